#pragma once
// Long work off the GUI thread (design card: "long work runs on a worker thread; it reports
// through a progress callback and stops at a cancellation token; only the GUI thread touches
// Qt widgets or VTK objects").
//
// A BackgroundJob runs one function at a time on its own worker thread. The function gets a
// JobContext: progress(fraction, text) is delivered to the GUI thread as the progress()
// signal (queued), cancelled() polls the token that cancel() sets. When the function returns
// (or throws, or was cancelled), finished() is emitted on the GUI thread and, on success, the
// `done` callback runs there too: that is where results are handed to the document and the
// scenes. The function itself must not touch widgets, VTK objects or the Document.
//
// The mesh preview (Mesh > Preview, ui/MeshPreviewer) is its first user.
#include <QObject>
#include <QString>
#include <atomic>
#include <functional>
#include <memory>

class QThread;

namespace aero::ui {

/// Set by the GUI thread, polled by the worker.
class CancelToken {
  public:
    void cancel() { flag_.store(true, std::memory_order_relaxed); }
    bool cancelled() const { return flag_.load(std::memory_order_relaxed); }
    /// The flag itself, for libcore routines that poll a `const std::atomic<bool>*`.
    const std::atomic<bool>* flag() const { return &flag_; }

  private:
    std::atomic<bool> flag_{false};
};

class JobContext {
  public:
    JobContext(std::shared_ptr<const CancelToken> token, std::function<void(double, const QString&)> progress)
        : token_(std::move(token)), progress_(std::move(progress)) {}
    bool cancelled() const { return token_->cancelled(); }
    /// The token's flag (valid while the work runs), e.g. for mesh::moveControlGrid.
    const std::atomic<bool>* cancelFlag() const { return token_->flag(); }
    /// fraction in [0, 1] (negative: unknown), text for the status bar. Thread-safe.
    void progress(double fraction, const QString& text = {}) const { progress_(fraction, text); }

  private:
    std::shared_ptr<const CancelToken> token_;
    std::function<void(double, const QString&)> progress_;
};

class BackgroundJob : public QObject {
    Q_OBJECT

  public:
    using Work = std::function<void(const JobContext&)>;

    explicit BackgroundJob(QObject* parent = nullptr);
    ~BackgroundJob() override;  // cancels a running job and waits for it

    /// Starts `work` on the worker thread; false if a job is running already.
    bool start(const QString& title, Work work, std::function<void()> done = {});
    /// Asks the running job to stop (it stops at its next cancelled() check).
    void cancel();
    bool running() const { return thread_ != nullptr; }
    QString title() const { return title_; }

  signals:
    void started(const QString& title);
    void progress(double fraction, const QString& text);
    /// ok: the work returned normally and was not cancelled; error: what it threw.
    void finished(bool ok, bool cancelled, const QString& error);

  private:
    void onThreadFinished();

    QThread* thread_ = nullptr;
    std::shared_ptr<CancelToken> token_;
    std::function<void()> done_;
    QString title_;
    QString error_;
    bool threw_ = false;
};

}  // namespace aero::ui
