#pragma once
// Long work off the GUI thread (design card: "long work runs on a worker thread; it reports
// through a progress callback and stops at a cancellation token; only the GUI thread touches
// Qt widgets or VTK objects").
//
// A JobRunner runs any number of jobs at once (a mesh preview while a flow solve runs), each on
// its own worker thread, each a Job object the GUI can watch and cancel. A job's work gets a
// JobContext<P> and reports two things, both delivered to the GUI thread in the order they were
// sent and before the job's finished():
//   status(fraction, text)  what every job has: for the status bar (Job::progressed);
//   report(P)               the job's own typed progress (a flow iteration with its residual,
//                           CFL and phase; a mesh stage), handed to the `progress` callback of
//                           its JobSpec<P> on the GUI thread: no strings to parse.
// cancelled() polls the job's atomic flag, which Job::cancel() sets; cancelFlag() hands the flag
// itself to libcore (CaseEvaluator::evaluate polls it between stages and iterations).
//
// When the work returns (or throws, or was cancelled) the job's `done` callback runs on the GUI
// thread (after a normal return only: that is where results are handed to the scenes), then
// Job::finished() and JobRunner::jobFinished(); the Job object is deleted afterwards
// (deleteLater: hold it in a QPointer). The work must not touch widgets, VTK objects or the
// Document: it gets copies of its inputs. Workers run at a lower CPU priority than the GUI
// thread (setting jobs/niceness), so the window stays responsive while they use every core.
#include <QList>
#include <QObject>
#include <QString>
#include <atomic>
#include <functional>
#include <memory>

class QThread;

namespace aero::ui {

class Job;

/// The worker's side of a job (copyable; valid while the work runs). P: the typed progress.
template <class P>
class JobContext {
  public:
    struct Channel {
        std::atomic<bool> cancel{false};
        Job* job = nullptr;  // lives until the worker thread has ended
        std::function<void(const P&)> handler;  // called on the GUI thread
    };

    explicit JobContext(std::shared_ptr<Channel> channel) : channel_(std::move(channel)) {}

    bool cancelled() const { return channel_->cancel.load(std::memory_order_relaxed); }
    /// The job's cancellation flag, for libcore routines that poll a `const std::atomic<bool>*`.
    const std::atomic<bool>* cancelFlag() const { return &channel_->cancel; }
    /// Sets that flag from the work itself, to stop at a point of its own choosing (an
    /// optimization pausing after a whole evaluation): the job then ends as Cancelled.
    void requestCancel() const { channel_->cancel.store(true, std::memory_order_relaxed); }
    /// fraction in [0, 1] (negative: unknown), text for the status bar. Thread-safe.
    void status(double fraction, const QString& text = {}) const;
    /// Typed progress for the job's owner (JobSpec::progress). Thread-safe.
    void report(P progress) const;

  private:
    std::shared_ptr<Channel> channel_;
};

/// What a job is: its work and the GUI-thread callbacks.
template <class P>
struct JobSpec {
    QString title;  // for people: "Flow solve", "Mesh preview"
    QString kind;   // for code: jobs of one kind are found by JobRunner::running(kind)
    std::function<void(const JobContext<P>&)> work;  // worker thread
    std::function<void(const P&)> progress;          // GUI thread, per report()
    std::function<void()> done;                      // GUI thread, after a normal return
};

/// No typed progress (status only).
struct NoProgress {};

class Job : public QObject {
    Q_OBJECT

  public:
    enum class State {
        Running,
        Finished,   // the work returned normally
        Cancelled,  // it returned after cancel() (whatever it did after)
        Failed      // it threw; error() says what
    };

    int id() const { return id_; }
    QString title() const { return title_; }
    QString kind() const { return kind_; }
    State state() const { return state_; }
    bool running() const { return state_ == State::Running; }
    QString error() const { return error_; }
    /// The last status: fraction (negative: unknown) and text.
    double fraction() const { return fraction_; }
    QString text() const { return text_; }

    /// Asks the work to stop (at its next cancelled() check). No-op once finished.
    void cancel();
    bool cancelRequested() const;
    /// Blocks the calling (GUI) thread until the worker thread has ended or `timeoutMs` passed;
    /// true if it ended. The finished() signal still comes from the event loop.
    bool wait(int timeoutMs);

  signals:
    void progressed(double fraction, const QString& text);
    /// The work ended: state() says how.
    void finished();

  private:
    friend class JobRunner;
    template <class P>
    friend class JobContext;
    Job(int id, QString title, QString kind, QObject* parent);
    /// Queues `call` to run on this job's (GUI) thread; called from the worker.
    void post(std::function<void()> call);
    void onThreadFinished();

    int id_;
    QString title_, kind_;
    State state_ = State::Running;
    QString error_;
    double fraction_ = -1;
    QString text_;
    QThread* thread_ = nullptr;
    std::atomic<bool>* cancel_ = nullptr;  // the channel's flag (the channel outlives the thread)
    std::shared_ptr<void> channel_;        // keeps it alive
    std::function<void()> done_;
    bool threw_ = false;                   // written by the worker, read after it ended
};

class JobRunner : public QObject {
    Q_OBJECT

  public:
    explicit JobRunner(QObject* parent = nullptr);
    ~JobRunner() override;  // cancels running jobs and waits for them

    /// Starts spec.work on a new worker thread and returns its Job (owned by the runner).
    template <class P>
    Job* start(JobSpec<P> spec);
    /// A job without typed progress.
    Job* start(const QString& title, const QString& kind, std::function<void(const JobContext<NoProgress>&)> work,
               std::function<void()> done = {});

    /// The running jobs, oldest first.
    QList<Job*> jobs() const;
    /// The running job of `kind`, or null.
    Job* running(const QString& kind) const;
    bool busy() const { return !jobs().isEmpty(); }
    void cancelAll();
    /// Waits for every running job's worker to end (see Job::wait); true if all did.
    bool waitAll(int timeoutMs);

  signals:
    void jobStarted(aero::ui::Job* job);
    void jobProgressed(aero::ui::Job* job);
    /// After the job's own finished(); the job is deleted later.
    void jobFinished(aero::ui::Job* job);

  private:
    Job* launch(const QString& title, const QString& kind, std::shared_ptr<void> channel, std::atomic<bool>* cancel,
                std::function<void(Job*)> bind, std::function<void()> work, std::function<void()> done);

    int nextId_ = 1;
    QList<Job*> jobs_;
};

// ---- Templates ------------------------------------------------------------------------------

template <class P>
void JobContext<P>::status(double fraction, const QString& text) const {
    Job* job = channel_->job;
    job->post([job, fraction, text] {
        job->fraction_ = fraction;
        if (!text.isEmpty()) job->text_ = text;
        emit job->progressed(fraction, text);
    });
}

template <class P>
void JobContext<P>::report(P progress) const {
    if (!channel_->handler) return;
    auto channel = channel_;
    channel_->job->post([channel, p = std::move(progress)] { channel->handler(p); });
}

template <class P>
Job* JobRunner::start(JobSpec<P> spec) {
    auto channel = std::make_shared<typename JobContext<P>::Channel>();
    channel->handler = std::move(spec.progress);
    JobContext<P> context(channel);
    auto work = [context, fn = std::move(spec.work)] { fn(context); };
    return launch(spec.title, spec.kind, channel, &channel->cancel, [channel](Job* job) { channel->job = job; },
                  std::move(work), std::move(spec.done));
}

}  // namespace aero::ui
