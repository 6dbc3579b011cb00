#include "JobRunner.h"

#include <QDeadlineTimer>
#include <QThread>
#include <algorithm>
#include <exception>

#include "Resources.h"

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace aero::ui {

namespace {

// Lowers the calling (worker) thread's CPU priority by `niceness` (Linux: nice is per thread,
// and the OpenMP threads the worker starts inherit it), so that on a machine with few cores the
// GUI thread keeps its share while a solve keeps every core busy. Costs nothing on an idle
// machine: priorities only matter when threads compete.
void lowerPriority(int niceness) {
#ifdef __linux__
    if (niceness > 0) (void)setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), niceness);
#else
    (void)niceness;
#endif
}

}  // namespace

// ---- Job ----------------------------------------------------------------------------------------

Job::Job(int id, QString title, QString kind, QObject* parent)
    : QObject(parent), id_(id), title_(std::move(title)), kind_(std::move(kind)) {}

void Job::cancel() {
    if (running() && cancel_) cancel_->store(true, std::memory_order_relaxed);
}

bool Job::cancelRequested() const {
    return cancel_ && cancel_->load(std::memory_order_relaxed);
}

bool Job::wait(int timeoutMs) {
    if (!thread_) return true;
    return thread_->wait(QDeadlineTimer(timeoutMs));
}

void Job::post(std::function<void()> call) {
    // Queued to this object: runs on the GUI thread in the order posted, and is dropped if the
    // job object is gone by then (it is deleted only after the worker thread ended).
    QMetaObject::invokeMethod(this, std::move(call), Qt::QueuedConnection);
}

void Job::onThreadFinished() {
    if (!thread_) return;
    thread_->wait();
    thread_->deleteLater();
    thread_ = nullptr;
    if (threw_)
        state_ = State::Failed;
    else if (cancelRequested())
        state_ = State::Cancelled;
    else
        state_ = State::Finished;
    auto done = std::move(done_);
    done_ = nullptr;
    if (state_ == State::Finished && done) done();
    emit finished();
}

// ---- JobRunner ------------------------------------------------------------------------------------

JobRunner::JobRunner(QObject* parent) : QObject(parent) {}

JobRunner::~JobRunner() {
    cancelAll();
    for (Job* job : jobs_) {
        if (job->thread_) {
            job->thread_->wait();
            delete job->thread_;
            job->thread_ = nullptr;
        }
    }
}

Job* JobRunner::start(const QString& title, const QString& kind,
                      std::function<void(const JobContext<NoProgress>&)> work, std::function<void()> done) {
    JobSpec<NoProgress> spec;
    spec.title = title;
    spec.kind = kind;
    spec.work = std::move(work);
    spec.done = std::move(done);
    return start(std::move(spec));
}

Job* JobRunner::launch(const QString& title, const QString& kind, std::shared_ptr<void> channel,
                       std::atomic<bool>* cancel, std::function<void(Job*)> bind, std::function<void()> work,
                       std::function<void()> done) {
    auto* job = new Job(nextId_++, title, kind, this);
    job->channel_ = std::move(channel);
    job->cancel_ = cancel;
    job->done_ = std::move(done);
    bind(job);
    const int niceness = std::max(0, setting(QStringLiteral("jobs/niceness")).toInt());
    job->thread_ = QThread::create([job, niceness, work = std::move(work)] {
        lowerPriority(niceness);
        try {
            work();
        } catch (const std::exception& e) {
            job->threw_ = true;  // read on the GUI thread only after the thread ended
            job->error_ = QString::fromStdString(e.what());
        } catch (...) {
            job->threw_ = true;
            job->error_ = QStringLiteral("unknown error");
        }
    });
    job->thread_->setObjectName(QStringLiteral("aeroform-job-%1").arg(job->id()));
    connect(job->thread_, &QThread::finished, job, &Job::onThreadFinished, Qt::QueuedConnection);
    connect(job, &Job::progressed, this, [this, job] { emit jobProgressed(job); });
    connect(job, &Job::finished, this, [this, job] {
        jobs_.removeOne(job);
        emit jobFinished(job);
        job->deleteLater();
    });
    jobs_.append(job);
    emit jobStarted(job);
    job->thread_->start();
    return job;
}

QList<Job*> JobRunner::jobs() const {
    return jobs_;
}

Job* JobRunner::running(const QString& kind) const {
    for (Job* job : jobs_)
        if (job->kind() == kind) return job;
    return nullptr;
}

void JobRunner::cancelAll() {
    for (Job* job : jobs_) job->cancel();
}

bool JobRunner::waitAll(int timeoutMs) {
    QDeadlineTimer deadline(timeoutMs);
    bool all = true;
    for (Job* job : jobs_)
        if (job->thread_) all = job->thread_->wait(deadline) && all;
    return all;
}

}  // namespace aero::ui
