// test_ui: the GUI tests (Qt Test). Runs every test class in one process and returns non-zero
// if any failed. Classes that need OpenGL (a real X display, e.g. xvfb-run) skip themselves
// without one; the document and job tests run anywhere (offscreen platform).
#include <QApplication>
#include <QStandardPaths>
#include <QSurfaceFormat>

#include "VtkViewport.h"

int runDocumentTest(int argc, char** argv);
int runBackgroundJobTest(int argc, char** argv);
int runMainWindowTest(int argc, char** argv, bool canRender);
int runLatticeEditorTest(int argc, char** argv, bool canRender);
int runMeshPreviewTest(int argc, char** argv, bool canRender);
int runPatchSceneTest(int argc, char** argv, bool canRender);

int main(int argc, char** argv) {
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
    int failed = 0;
    failed += runDocumentTest(argc, argv);
    failed += runBackgroundJobTest(argc, argv);
    failed += runMainWindowTest(argc, argv, canRender);
    failed += runLatticeEditorTest(argc, argv, canRender);
    failed += runMeshPreviewTest(argc, argv, canRender);
    failed += runPatchSceneTest(argc, argv, canRender);
    return failed == 0 ? 0 : 1;
}
