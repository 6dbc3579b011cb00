#include "BackgroundJob.h"

#include <QPointer>
#include <QThread>
#include <exception>

namespace aero::ui {

BackgroundJob::BackgroundJob(QObject* parent) : QObject(parent) {}

BackgroundJob::~BackgroundJob() {
    if (thread_) {
        token_->cancel();
        thread_->wait();
        delete thread_;
        thread_ = nullptr;
    }
}

bool BackgroundJob::start(const QString& title, Work work, std::function<void()> done) {
    if (thread_) return false;
    token_ = std::make_shared<CancelToken>();
    done_ = std::move(done);
    title_ = title;
    error_.clear();
    threw_ = false;
    QPointer<BackgroundJob> self(this);
    // Progress crosses to the GUI thread as a queued call; it is dropped if the job object is
    // gone by then.
    auto report = [self](double fraction, const QString& text) {
        QMetaObject::invokeMethod(
            self.data(),
            [self, fraction, text] {
                if (self) emit self->progress(fraction, text);
            },
            Qt::QueuedConnection);
    };
    JobContext context(token_, report);
    thread_ = QThread::create([this, work = std::move(work), context] {
        try {
            work(context);
        } catch (const std::exception& e) {
            threw_ = true;  // read by the GUI thread only after the thread finished
            error_ = QString::fromStdString(e.what());
        } catch (...) {
            threw_ = true;
            error_ = QStringLiteral("unknown error");
        }
    });
    thread_->setObjectName(QStringLiteral("aeroform-job"));
    connect(thread_, &QThread::finished, this, &BackgroundJob::onThreadFinished, Qt::QueuedConnection);
    emit started(title_);
    thread_->start();
    return true;
}

void BackgroundJob::cancel() {
    if (token_) token_->cancel();
}

void BackgroundJob::onThreadFinished() {
    if (!thread_) return;
    thread_->wait();
    thread_->deleteLater();
    thread_ = nullptr;
    const bool cancelled = token_->cancelled();
    const bool ok = !threw_ && !cancelled;
    auto done = std::move(done_);
    done_ = nullptr;
    if (ok && done) done();
    emit finished(ok, cancelled, error_);
}

}  // namespace aero::ui
