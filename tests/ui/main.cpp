// test_ui: the GUI tests (Qt Test). Runs every test class in one process and returns non-zero
// if any failed. Classes that need OpenGL (a real X display, e.g. xvfb-run) skip themselves
// without one; the document and job tests run anywhere (offscreen platform).
#include <QApplication>
#include <QStandardPaths>
#include <QSurfaceFormat>

#include "VtkViewport.h"
#include "cli/Commands.h"

int runDocumentTest(int argc, char** argv);
int runJobRunnerTest(int argc, char** argv);
int runMainWindowTest(int argc, char** argv, bool canRender);
int runLatticeEditorTest(int argc, char** argv, bool canRender);
int runMeshPreviewTest(int argc, char** argv, bool canRender);
int runFlowSolveTest(int argc, char** argv, bool canRender);
int runPatchSceneTest(int argc, char** argv, bool canRender);
int runOptimizationWorkspaceTest(int argc, char** argv, bool canRender);
int runSensitivityTest(int argc, char** argv, bool canRender);

int main(int argc, char** argv) {
    // Flow solves run in the background here too: OpenMP must wait passively (as the
    // application does), or its spinning threads starve the GUI thread.
    aero::app::ensurePassiveOpenMpWaiting(argv);
    // Without an X display QApplication could not even start on xcb; start it offscreen then
    // (no OpenGL widget is created) and let the GL tests skip with a clear message.
    const QByteArray platform = qgetenv("QT_QPA_PLATFORM");
    const bool canRender = !qEnvironmentVariableIsEmpty("DISPLAY") && !platform.startsWith("offscreen") &&
                           !platform.startsWith("minimal");
    if (!canRender) qputenv("QT_QPA_PLATFORM", "offscreen");
    // Settings, autosaves and recent files go to test locations, never the user's.
    QStandardPaths::setTestModeEnabled(true);
    QSurfaceFormat::setDefaultFormat(aero::ui::VtkViewport::defaultFormat());
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("AeroformTest"));
    QApplication::setApplicationName(QStringLiteral("test_ui"));
    // AEROFORM_UI_TESTS=FlowSolveTest,JobRunnerTest runs only those classes (while developing).
    const QStringList only = qEnvironmentVariable("AEROFORM_UI_TESTS").split(QLatin1Char(','), Qt::SkipEmptyParts);
    auto wanted = [&only](const char* name) { return only.isEmpty() || only.contains(QLatin1String(name)); };
    int failed = 0;
    if (wanted("DocumentTest")) failed += runDocumentTest(argc, argv);
    if (wanted("JobRunnerTest")) failed += runJobRunnerTest(argc, argv);
    if (wanted("MainWindowTest")) failed += runMainWindowTest(argc, argv, canRender);
    if (wanted("LatticeEditorTest")) failed += runLatticeEditorTest(argc, argv, canRender);
    if (wanted("MeshPreviewTest")) failed += runMeshPreviewTest(argc, argv, canRender);
    if (wanted("FlowSolveTest")) failed += runFlowSolveTest(argc, argv, canRender);
    if (wanted("PatchSceneTest")) failed += runPatchSceneTest(argc, argv, canRender);
    if (wanted("OptimizationWorkspaceTest"))
        failed += runOptimizationWorkspaceTest(argc, argv, canRender);
    if (wanted("SensitivityTest")) failed += runSensitivityTest(argc, argv, canRender);
    return failed == 0 ? 0 : 1;
}
