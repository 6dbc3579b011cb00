// Qt Test of ui/JobRunner: work runs off the GUI thread, status and typed progress arrive on the
// GUI thread in order and before the end, several jobs run at once and are cancelled one by one,
// errors are reported, the runner's destructor cancels and waits.
#include <QPointer>
#include <QSignalSpy>
#include <QTest>
#include <QThread>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "JobRunner.h"

using aero::ui::Job;
using aero::ui::JobContext;
using aero::ui::JobRunner;
using aero::ui::JobSpec;
using aero::ui::NoProgress;

namespace {

// The job's end as it was announced (the Job object is deleted soon after its finished()).
struct Ending {
    int count = 0;
    Job::State state = Job::State::Running;
    QString error;
    void watch(Job* job) {
        QObject::connect(job, &Job::finished, job, [this, job] {
            ++count;
            state = job->state();
            error = job->error();
        });
    }
};

// A typed progress record, as a flow iteration would be.
struct Step {
    int index = 0;
    double residual = 0;
};

}  // namespace

class JobRunnerTest : public QObject {
    Q_OBJECT

  private slots:
    void runsOffTheGuiThreadWithTypedProgress();
    void severalJobsRunAtOnceAndCancelOneByOne();
    void cancelStopsTheWorkAndSkipsDone();
    void errorsAreReported();
    void destructorCancelsAndWaits();
};

void JobRunnerTest::runsOffTheGuiThreadWithTypedProgress() {
    JobRunner runner;
    QSignalSpy started(&runner, &JobRunner::jobStarted);
    QSignalSpy finished(&runner, &JobRunner::jobFinished);
    std::atomic<bool> offGuiThread{false};
    QThread* gui = QThread::currentThread();
    std::vector<Step> received;
    bool progressOnGuiThread = true, doneOnGuiThread = false, finishedAfterProgress = false;
    auto sum = std::make_shared<int>(0);
    int result = 0;

    JobSpec<Step> spec;
    spec.title = QStringLiteral("Counting");
    spec.kind = QStringLiteral("count");
    spec.work = [&, sum](const JobContext<Step>& ctx) {
        offGuiThread = QThread::currentThread() != gui;
        for (int i = 1; i <= 10; ++i) {
            *sum += i;
            ctx.status(i / 10.0, QStringLiteral("step %1").arg(i));
            ctx.report({i, std::pow(10.0, -i)});
        }
    };
    spec.progress = [&](const Step& s) {
        progressOnGuiThread = progressOnGuiThread && QThread::currentThread() == gui;
        received.push_back(s);
    };
    spec.done = [&, sum] {
        doneOnGuiThread = QThread::currentThread() == gui;
        result = *sum;
    };
    QPointer<Job> job = runner.start(std::move(spec));
    QVERIFY(job);
    QSignalSpy statuses(job.data(), &Job::progressed);
    connect(job.data(), &Job::finished, this, [&] { finishedAfterProgress = received.size() == 10; });
    QCOMPARE(started.count(), 1);
    QCOMPARE(runner.running(QStringLiteral("count")), job.data());
    QVERIFY(runner.busy());
    QTRY_COMPARE_WITH_TIMEOUT(finished.count(), 1, 10000);
    QVERIFY(!runner.busy());
    QVERIFY(offGuiThread);
    QVERIFY(progressOnGuiThread);
    QVERIFY(doneOnGuiThread);
    QVERIFY2(finishedAfterProgress, "every report arrives before the job's end");
    QCOMPARE(result, 55);
    QCOMPARE(static_cast<int>(received.size()), 10);
    for (int i = 0; i < 10; ++i) QCOMPARE(received[static_cast<std::size_t>(i)].index, i + 1);  // in order
    QCOMPARE(received.back().residual, 1e-10);
    QCOMPARE(statuses.count(), 10);
    QCOMPARE(statuses.back().at(0).toDouble(), 1.0);
    QCOMPARE(statuses.front().at(1).toString(), QStringLiteral("step 1"));
    QTRY_VERIFY(job.isNull());  // deleted after its end
}

void JobRunnerTest::severalJobsRunAtOnceAndCancelOneByOne() {
    JobRunner runner;
    std::atomic<int> a{0}, b{0};
    auto spin = [](std::atomic<int>& counter) {
        return [&counter](const JobContext<NoProgress>& ctx) {
            while (!ctx.cancelled()) {
                ++counter;
                QThread::msleep(1);
            }
        };
    };
    QPointer<Job> first = runner.start(QStringLiteral("Mesh preview"), QStringLiteral("mesh"), spin(a));
    QPointer<Job> second = runner.start(QStringLiteral("Flow solve"), QStringLiteral("flow"), spin(b));
    QCOMPARE(runner.jobs().size(), 2);
    QVERIFY(first->id() != second->id());
    QTRY_VERIFY_WITH_TIMEOUT(a > 3 && b > 3, 5000);  // both run at the same time
    Ending firstEnd;
    firstEnd.watch(first);
    first->cancel();
    QTRY_COMPARE_WITH_TIMEOUT(firstEnd.count, 1, 5000);
    QCOMPARE(firstEnd.state, Job::State::Cancelled);
    QCOMPARE(runner.jobs().size(), 1);
    QCOMPARE(runner.running(QStringLiteral("flow")), second.data());
    QVERIFY(runner.running(QStringLiteral("mesh")) == nullptr);
    const int before = b;
    QTRY_VERIFY_WITH_TIMEOUT(b > before + 3, 5000);  // the other one goes on
    QCOMPARE(second->state(), Job::State::Running);
    runner.cancelAll();
    QVERIFY(runner.waitAll(5000));
    QTRY_VERIFY_WITH_TIMEOUT(!runner.busy(), 5000);
}

void JobRunnerTest::cancelStopsTheWorkAndSkipsDone() {
    JobRunner runner;
    std::atomic<int> iterations{0};
    bool done = false;
    QPointer<Job> job = runner.start(
        QStringLiteral("Forever"), QStringLiteral("x"),
        [&](const JobContext<NoProgress>& ctx) {
            while (!ctx.cancelled()) {
                ++iterations;
                QThread::msleep(1);
            }
        },
        [&] { done = true; });
    Ending end;
    end.watch(job);
    QTRY_VERIFY_WITH_TIMEOUT(iterations > 3, 5000);
    job->cancel();
    QVERIFY(job->cancelRequested());
    QTRY_COMPARE_WITH_TIMEOUT(end.count, 1, 5000);
    QCOMPARE(end.state, Job::State::Cancelled);
    QVERIFY(!done);  // a cancelled job hands nothing over
}

void JobRunnerTest::errorsAreReported() {
    JobRunner runner;
    QPointer<Job> job = runner.start(QStringLiteral("Failing"), QStringLiteral("x"),
                                     [](const JobContext<NoProgress>&) { throw std::runtime_error("mesh is tangled"); });
    Ending end;
    end.watch(job);
    QTRY_COMPARE_WITH_TIMEOUT(end.count, 1, 5000);
    QCOMPARE(end.state, Job::State::Failed);
    QCOMPARE(end.error, QStringLiteral("mesh is tangled"));
    // Another job of the kind can run afterwards.
    QPointer<Job> again = runner.start(QStringLiteral("Again"), QStringLiteral("x"), [](const JobContext<NoProgress>&) {});
    Ending endAgain;
    endAgain.watch(again);
    QTRY_COMPARE_WITH_TIMEOUT(endAgain.count, 1, 5000);
    QCOMPARE(endAgain.state, Job::State::Finished);
}

void JobRunnerTest::destructorCancelsAndWaits() {
    std::atomic<bool> stopped{false};
    {
        JobRunner runner;
        runner.start(QStringLiteral("Long"), QStringLiteral("x"), [&](const JobContext<NoProgress>& ctx) {
            while (!ctx.cancelled()) QThread::msleep(1);
            stopped = true;
        });
        QThread::msleep(5);
    }
    QVERIFY(stopped);
}

int runJobRunnerTest(int argc, char** argv) {
    JobRunnerTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "JobRunnerTest.moc"
