// Qt Test of ui/BackgroundJob: work runs off the GUI thread, progress arrives on the GUI
// thread in order, cancellation stops the work, results are handed over on the GUI thread.
#include <QSignalSpy>
#include <QTest>
#include <QThread>
#include <atomic>
#include <stdexcept>

#include "BackgroundJob.h"

using aero::ui::BackgroundJob;
using aero::ui::JobContext;

class BackgroundJobTest : public QObject {
    Q_OBJECT

  private slots:
    void runsOffTheGuiThreadAndReportsProgress();
    void cancelStopsTheWork();
    void errorsAreReported();
    void destructorCancelsAndWaits();
};

void BackgroundJobTest::runsOffTheGuiThreadAndReportsProgress() {
    BackgroundJob job;
    QSignalSpy progress(&job, &BackgroundJob::progress);
    QSignalSpy finished(&job, &BackgroundJob::finished);
    std::atomic<bool> offGuiThread{false};
    QThread* gui = QThread::currentThread();
    int result = 0;
    auto shared = std::make_shared<int>(0);
    bool doneOnGuiThread = false;
    QVERIFY(job.start(
        QStringLiteral("Counting"),
        [&, shared](const JobContext& ctx) {
            offGuiThread = QThread::currentThread() != gui;
            for (int i = 1; i <= 10; ++i) {
                *shared += i;
                ctx.progress(i / 10.0, QStringLiteral("step %1").arg(i));
            }
        },
        [&, shared] {
            doneOnGuiThread = QThread::currentThread() == gui;
            result = *shared;
        }));
    QVERIFY(job.running());
    QVERIFY(!job.start(QStringLiteral("second"), [](const JobContext&) {}));  // one at a time
    QTRY_COMPARE_WITH_TIMEOUT(finished.count(), 1, 10000);
    QVERIFY(!job.running());
    QVERIFY(offGuiThread);
    QVERIFY(doneOnGuiThread);
    QCOMPARE(result, 55);
    QCOMPARE(finished.front().at(0).toBool(), true);   // ok
    QCOMPARE(finished.front().at(1).toBool(), false);  // not cancelled
    QCOMPARE(progress.count(), 10);                    // all delivered before finished, in order
    QCOMPARE(progress.back().at(0).toDouble(), 1.0);
    QCOMPARE(progress.front().at(1).toString(), QStringLiteral("step 1"));
}

void BackgroundJobTest::cancelStopsTheWork() {
    BackgroundJob job;
    QSignalSpy finished(&job, &BackgroundJob::finished);
    std::atomic<int> iterations{0};
    bool done = false;
    job.start(
        QStringLiteral("Forever"),
        [&](const JobContext& ctx) {
            while (!ctx.cancelled()) {
                ++iterations;
                QThread::msleep(1);
            }
        },
        [&] { done = true; });
    QTRY_VERIFY_WITH_TIMEOUT(iterations > 3, 5000);
    job.cancel();
    QTRY_COMPARE_WITH_TIMEOUT(finished.count(), 1, 5000);
    QCOMPARE(finished.front().at(0).toBool(), false);
    QCOMPARE(finished.front().at(1).toBool(), true);
    QVERIFY(!done);  // a cancelled job hands nothing over
}

void BackgroundJobTest::errorsAreReported() {
    BackgroundJob job;
    QSignalSpy finished(&job, &BackgroundJob::finished);
    job.start(QStringLiteral("Failing"), [](const JobContext&) { throw std::runtime_error("mesh is tangled"); });
    QTRY_COMPARE_WITH_TIMEOUT(finished.count(), 1, 5000);
    QCOMPARE(finished.front().at(0).toBool(), false);
    QCOMPARE(finished.front().at(2).toString(), QStringLiteral("mesh is tangled"));
    // The job can run again afterwards.
    QVERIFY(job.start(QStringLiteral("Again"), [](const JobContext&) {}));
    QTRY_COMPARE_WITH_TIMEOUT(finished.count(), 2, 5000);
}

void BackgroundJobTest::destructorCancelsAndWaits() {
    std::atomic<bool> stopped{false};
    {
        BackgroundJob job;
        job.start(QStringLiteral("Long"), [&](const JobContext& ctx) {
            while (!ctx.cancelled()) QThread::msleep(1);
            stopped = true;
        });
        QThread::msleep(5);
    }
    QVERIFY(stopped);
}

int runBackgroundJobTest(int argc, char** argv) {
    BackgroundJobTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "BackgroundJobTest.moc"
