// test_job_runner: JobRunnerTest alone, for the ThreadSanitizer build (the `tsan` preset), where
// building the whole GUI suite with libcore would take longer than CI allows. The same class runs
// in test_ui in every other build. Offscreen: the jobs need an event loop, not a display.
#include <QApplication>
#include <QStandardPaths>

int runJobRunnerTest(int argc, char** argv);

int main(int argc, char** argv) {
    if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
    QStandardPaths::setTestModeEnabled(true);
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("AeroformTest"));
    QApplication::setApplicationName(QStringLiteral("test_job_runner"));
    return runJobRunnerTest(argc, argv) == 0 ? 0 : 1;
}
