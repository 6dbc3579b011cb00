// Qt Test of the main window: renders the half-sphere sample through our QOpenGLWidget host,
// saves screenshots (build tree: tests/ui/screenshots/) and checks what the picture holds.
#include <vtkCamera.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include <QAction>
#include <QApplication>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QImage>
#include <QLabel>
#include <QMouseEvent>
#include <QOpenGLContext>
#include <QSurfaceFormat>
#include <QTemporaryDir>
#include <QTest>
#include <QVBoxLayout>
#include <QWheelEvent>
#include <QGroupBox>
#include <QMessageBox>
#include <QSpinBox>
#include <QMimeData>
#include <QPushButton>
#include <QProgressDialog>
#include <QElapsedTimer>
#include <QScreen>
#include <QTimer>
#include <QTreeWidgetItem>
#include <QUndoStack>
#include <QUrl>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "ActionSet.h"
#include "Document.h"
#include "Resources.h"
#include "LatticeScene.h"
#include "LatticeDialog.h"
#include "MainWindow.h"
#include "ModelTree.h"
#include "Selection.h"
#include "PatchScene.h"
#include "VtkViewport.h"
#include "cad/Iges.h"
#include "geometry/HalfSphere.h"
#include "io/PatchSetJson.h"
#include "UiTestSupport.h"

using aero::ui::MainWindow;
using namespace aero::uitest;

namespace {

std::array<double, 3> cameraPosition(MainWindow& w) {
    std::array<double, 3> p{};
    w.viewport()->renderer()->GetActiveCamera()->GetPosition(p.data());
    return p;
}

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace

class MainWindowTest : public QObject {
    Q_OBJECT

  public:
    explicit MainWindowTest(bool canRender) : canRender_(canRender) {}

  private slots:
    void initTestCase();
    void cleanupTestCase();
    void showsTwentyPatches();
    void rendersShadedSample();
    void controlNetsToggleChangesPicture();
    void mouseDragRotatesAndWheelZooms();
    void badFileKeepsScene();
    void opensJsonAndIges();
    void viewportSurvivesNewContext();
    void treeTogglesPatchVisibility();
    void droppedFileIsOpened();
    void closeAsksAboutUnsavedChanges();
    void meshActionsBeforeAPreview();
    void resourcesShipIconsSettingsAndADesktopEntry();
    void latticeDialogDescribesTheLattice();
    void aSlowCadFileShowsProgressAndCanBeCancelled();

  private:
    QImage renderNow() {
        const int before = window_->viewport()->renderedFrames();
        QImage image = window_->viewport()->grabImage();
        if (window_->viewport()->renderedFrames() == before) qWarning("grab did not render");
        return image;
    }
    QAction* action(const char* name) {
        return window_->findChild<QAction*>(QString::fromLatin1(name));
    }

    bool canRender_;
    std::unique_ptr<MainWindow> window_;
};

void MainWindowTest::initTestCase() {
    if (!canRender_)
        QSKIP(
            "test_ui needs an X display: DISPLAY is not set (or QT_QPA_PLATFORM is offscreen). "
            "Run it under xvfb-run -a -s \"-screen 0 1280x800x24\".");
    QDir().mkpath(kScreenshotDir);
    MainWindow::Options options;
    options.autosave = false;
    options.recentFiles = false;
    window_ = std::make_unique<MainWindow>(options);
    window_->resize(1000, 700);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    QString error;
    QVERIFY2(window_->loadSample(&error), qPrintable(error));
    QTRY_VERIFY_WITH_TIMEOUT(window_->viewport()->renderedFrames() > 0, 10000);
}

void MainWindowTest::cleanupTestCase() {
    window_.reset();
}

void MainWindowTest::showsTwentyPatches() {
    QCOMPARE(window_->scene().patchCount(), 20);
    const auto* label = window_->findChild<QLabel*>(QStringLiteral("summaryLabel"));
    QVERIFY(label != nullptr);
    QVERIFY2(label->text().startsWith(QStringLiteral("20 patches, ")), qPrintable(label->text()));
    QCOMPARE(label->text(), window_->summary());
    // Not truncated once the status bar has been laid out again (posted layout requests).
    QTRY_VERIFY(label->width() >= label->sizeHint().width() &&
                label->geometry().right() < label->parentWidget()->width());
    QVERIFY2(window_->windowTitle().contains(QStringLiteral("Half-sphere")),
             qPrintable(window_->windowTitle()));
}

void MainWindowTest::rendersShadedSample() {
    const QImage frame = renderNow();
    QVERIFY(!frame.isNull());
    const qreal dpr = window_->viewport()->devicePixelRatioF();
    QCOMPARE(frame.width(), qRound(window_->viewport()->width() * dpr));
    QCOMPARE(frame.height(), qRound(window_->viewport()->height() * dpr));
    QVERIFY(frame.save(kScreenshotDir + QStringLiteral("/main_window_sample.png")));
    // The whole window too (menus, status bar): QWidget::grab() composes the GL widget.
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/main_window_full.png")));

    // The same view without the geometry: only the gradient background and the axes.
    action("actionSurfaces")->setChecked(false);
    action("actionPatchEdges")->setChecked(false);
    const QImage background = renderNow();
    action("actionSurfaces")->setChecked(true);
    action("actionPatchEdges")->setChecked(true);
    QVERIFY(background.save(kScreenshotDir + QStringLiteral("/main_window_background.png")));

    const PixelStats s = compare(frame, background);
    qInfo("geometry covers %.1f %% of the viewport; mean luma %.1f, std dev %.1f",
          100 * s.differingShare, s.meanLuma, s.lumaStdDev);
    QVERIFY2(s.differingShare > 0.05, "the half-sphere is missing or tiny");
    QVERIFY2(s.differingShare < 0.90, "the half-sphere fills the whole viewport");
    QVERIFY2(s.meanLuma > 60, "the surface is (nearly) black: lighting or blit broken");
    QVERIFY2(s.lumaStdDev > 4, "the surface is flat-coloured: no shading");

    // The background itself is not blank either (gradient: top lighter than bottom).
    const QImage bg = background.convertToFormat(QImage::Format_RGB32);
    const int w = bg.width(), h = bg.height();
    QVERIFY(luma(bg.pixel(w - 1, 0)) > luma(bg.pixel(w - 1, h - 1)));
    QVERIFY(luma(bg.pixel(w - 1, h - 1)) > 150);
}

void MainWindowTest::controlNetsToggleChangesPicture() {
    const QImage without = renderNow();
    QAction* nets = action("actionControlNets");
    QVERIFY(nets != nullptr);
    QVERIFY(!nets->isChecked());
    nets->setChecked(true);
    QVERIFY(window_->scene().controlNetsVisible());
    const QImage with = renderNow();
    QVERIFY(with.save(kScreenshotDir + QStringLiteral("/main_window_control_nets.png")));
    nets->setChecked(false);
    const PixelStats s = compare(with, without);
    QVERIFY2(s.differingShare > 0.002, "showing the control nets did not change the picture");
}

void MainWindowTest::mouseDragRotatesAndWheelZooms() {
    aero::ui::VtkViewport* vp = window_->viewport();
    renderNow();
    const auto home = cameraPosition(*window_);
    const int frames = vp->renderedFrames();

    const QPointF centre(vp->width() / 2.0, vp->height() / 2.0);
    sendMouse(vp, QEvent::MouseButtonPress, centre, Qt::LeftButton, Qt::LeftButton);
    for (int k = 1; k <= 10; ++k)
        sendMouse(vp, QEvent::MouseMove, centre + QPointF(12.0 * k, 4.0 * k), Qt::NoButton,
                  Qt::LeftButton);
    sendMouse(vp, QEvent::MouseButtonRelease, centre + QPointF(120, 40), Qt::LeftButton,
              Qt::NoButton);
    // Qt's logical pixels, origin top-left -> VTK's framebuffer pixels, origin bottom-left.
    const qreal dpr = vp->devicePixelRatioF();
    const int* at = vp->interactor()->GetEventPosition();
    QCOMPARE(at[0], qRound((centre.x() + 120) * dpr));
    QCOMPARE(at[1], vp->interactor()->GetSize()[1] - 1 - qRound((centre.y() + 40) * dpr));
    const auto rotated = cameraPosition(*window_);
    QVERIFY2(distance(home, rotated) > 0.1, "dragging with the left button did not rotate");
    // The interactor's render requests become widget updates, painted by the event loop.
    QTRY_VERIFY_WITH_TIMEOUT(vp->renderedFrames() > frames, 5000);
    QVERIFY(renderNow().save(kScreenshotDir + QStringLiteral("/main_window_rotated.png")));

    // Wheel forward zooms in (the camera moves towards the focal point).
    auto* cam = vp->renderer()->GetActiveCamera();
    const double before = cam->GetDistance();
    QWheelEvent wheel(centre, vp->mapToGlobal(centre), QPoint(), QPoint(0, 120), Qt::NoButton,
                      Qt::NoModifier, Qt::NoScrollPhase, false);
    QApplication::sendEvent(vp, &wheel);
    QVERIFY2(cam->GetDistance() < before, "the mouse wheel did not zoom");

    action("actionResetCamera")->trigger();
    QVERIFY(distance(home, cameraPosition(*window_)) < 1e-9);
}

void MainWindowTest::badFileKeepsScene() {
    QString error;
    QVERIFY(!window_->loadFile(QStringLiteral("/nonexistent/geometry.json"), &error));
    QVERIFY2(!error.isEmpty(), "no error message for a missing file");
    QVERIFY(!window_->loadFile(QStringLiteral("/tmp/geometry.stl"), &error));
    QVERIFY(error.contains(QStringLiteral("unsupported")));
    QCOMPARE(window_->scene().patchCount(), 20);
}

void MainWindowTest::opensJsonAndIges() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const aero::geometry::PatchSet sphere = aero::geometry::makeHalfSphere();
    const QString json = dir.filePath(QStringLiteral("half-sphere.json"));
    const QString iges = dir.filePath(QStringLiteral("half-sphere.igs"));
    aero::io::writePatchSetJson(sphere, json.toStdString());
    aero::cad::writeIges(sphere, iges.toStdString());

    for (const QString& path : {json, iges}) {
        QString error;
        QVERIFY2(window_->loadFile(path, &error), qPrintable(path + QStringLiteral(": ") + error));
        QCOMPARE(window_->scene().patchCount(), sphere.size());
        QCOMPARE(window_->scene().controlPointCount(), sphere.controlPointCount());
        QVERIFY(window_->windowTitle().startsWith(QFileInfo(path).fileName()));
    }
    QString error;
    QVERIFY2(window_->loadSample(&error), qPrintable(error));
}

// A QOpenGLWidget gets a new OpenGL context when it moves to another top-level window; VTK
// must release its GL objects with the old context and initialize again in the new one.
void MainWindowTest::viewportSurvivesNewContext() {
    auto first = std::make_unique<QWidget>();
    auto* vp = new aero::ui::VtkViewport;
    (new QVBoxLayout(first.get()))->addWidget(vp);
    auto scene = std::make_unique<aero::ui::PatchScene>(vp->renderer());
    scene->setPatchSet(aero::geometry::makeHalfSphere());
    vp->renderer()->ResetCamera();
    first->resize(500, 400);
    first->show();
    QVERIFY(QTest::qWaitForWindowExposed(first.get()));

    auto coverage = [&] {
        const QImage with = vp->grabImage();
        scene->setSurfacesVisible(false);
        scene->setEdgesVisible(false);
        const QImage without = vp->grabImage();
        scene->setSurfacesVisible(true);
        scene->setEdgesVisible(true);
        return compare(with, without).differingShare;
    };
    const double before = coverage();
    QVERIFY2(before > 0.05, "standalone viewport renders nothing");
    const QOpenGLContext* firstContext = vp->context();
    QVERIFY(firstContext != nullptr);

    auto second = std::make_unique<QWidget>();
    (new QVBoxLayout(second.get()))->addWidget(vp);  // reparent: new top level, new context
    second->resize(500, 400);
    second->show();
    QVERIFY(QTest::qWaitForWindowExposed(second.get()));
    first.reset();
    QVERIFY2(vp->context() != firstContext, "reparenting did not recreate the GL context");
    const double after = coverage();
    QVERIFY(vp->grabImage().save(kScreenshotDir + QStringLiteral("/viewport_new_context.png")));
    QVERIFY2(after > 0.05, "nothing rendered after the context was recreated");

    vp->makeCurrent();  // actors release GL objects when removed
    scene.reset();
    vp->doneCurrent();
}

void MainWindowTest::treeTogglesPatchVisibility() {
    QString error;
    QVERIFY2(window_->loadSample(&error), qPrintable(error));
    aero::ui::ModelTree& tree = window_->modelTree();
    QCOMPARE(tree.geometryItem()->childCount(), 20);
    QCOMPARE(tree.latticesItem()->childCount(), 1);
    QVERIFY(tree.gridItem() != nullptr);
    const QImage all = renderNow();
    for (int p = 0; p < 8; ++p) tree.patchItem(p)->setCheckState(0, Qt::Unchecked);
    QVERIFY(!window_->scene().patchVisible(0));
    QVERIFY(window_->scene().patchVisible(8));
    const QImage some = renderNow();
    QVERIFY(some.save(kScreenshotDir + QStringLiteral("/main_window_patches_hidden.png")));
    QVERIFY2(compare(some, all).differingShare > 0.01, "hiding patches did not change the picture");
    for (int p = 0; p < 8; ++p) tree.patchItem(p)->setCheckState(0, Qt::Checked);
    QVERIFY(compare(renderNow(), all).differingShare < 0.001);
    // The lattice check box hides the lattice (and the View action follows the whole group).
    tree.latticesItem()->setCheckState(0, Qt::Unchecked);
    QVERIFY(!window_->latticeScene().visible());
    QVERIFY(!action("actionLattices")->isChecked());
    action("actionLattices")->setChecked(true);
    QCOMPARE(tree.latticesItem()->checkState(0), Qt::Checked);
    // Selecting patches in the tree selects them (and tints them in the view).
    tree.clearSelection();
    tree.patchItem(2)->setSelected(true);
    tree.patchItem(3)->setSelected(true);
    QCOMPARE(window_->selection().kind(), aero::ui::Selection::Kind::Patches);
    QCOMPARE(window_->selection().patches(), (std::vector<int>{2, 3}));
    tree.clearSelection();
}

void MainWindowTest::droppedFileIsOpened() {
    QTemporaryDir dir;
    const QString path = dir.filePath(QStringLiteral("dropped.json"));
    aero::io::writePatchSetJson(aero::geometry::makeHalfSphere(), path.toStdString());
    QMimeData mime;
    mime.setUrls({QUrl::fromLocalFile(path)});
    const QPoint at(window_->width() / 2, window_->height() / 2);
    QDragEnterEvent enter(at, Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(window_.get(), &enter);
    QVERIFY(enter.isAccepted());
    QDropEvent drop(QPointF(at), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(window_.get(), &drop);
    QTRY_VERIFY(window_->windowTitle().startsWith(QStringLiteral("dropped.json")));
    QCOMPARE(window_->document().latticeCount(), 0);
    // Other files are refused.
    QMimeData other;
    other.setUrls({QUrl::fromLocalFile(dir.filePath(QStringLiteral("mesh.stl")))});
    QDragEnterEvent refused(at, Qt::CopyAction, &other, Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(window_.get(), &refused);
    QVERIFY(!refused.isAccepted());
    QString error;
    QVERIFY2(window_->loadSample(&error), qPrintable(error));
}

void MainWindowTest::closeAsksAboutUnsavedChanges() {
    aero::ui::Document& doc = window_->document();
    doc.setDesignValue(doc.model()->design().find("body.S2.tx"), 0.2);
    QVERIFY(window_->isWindowModified());
    QString asked;
    QTimer::singleShot(0, this, [&asked] {
        auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget());
        if (!box) return;
        asked = box->text();
        box->button(QMessageBox::Cancel)->click();
    });
    QVERIFY2(!window_->close(), "the window closed with unsaved changes");
    QVERIFY2(asked.contains(QStringLiteral("unsaved changes")), qPrintable(asked));
    QVERIFY(window_->isVisible());
    doc.undoStack()->undo();
    QVERIFY(!window_->isWindowModified());
}

void MainWindowTest::resourcesShipIconsSettingsAndADesktopEntry() {
    // The compiled-in resource file (resources/aeroform.qrc).
    for (const char* icon : {"aeroform", "open", "save", "flow-solve", "flow-stop", "mesh-preview", "lattices"})
        QVERIFY2(QFile::exists(QStringLiteral(":/icons/%1.svg").arg(QLatin1String(icon))), icon);
    QVERIFY(QFile::exists(QStringLiteral(":/settings/defaults.ini")));
    // Default settings where the user has none (the tests' settings are their own).
    QCOMPARE(aero::ui::setting(QStringLiteral("flow/field")).toString(), QStringLiteral("entropy"));
    QCOMPARE(aero::ui::setting(QStringLiteral("sections/spacing")).toDouble(), 0.5);
    QCOMPARE(aero::ui::setting(QStringLiteral("autosave/intervalSeconds")).toInt(), 30);
    QVERIFY(aero::ui::setting(QStringLiteral("jobs/niceness")).toInt() >= 0);
    QVERIFY(!aero::ui::setting(QStringLiteral("no/such/key")).isValid());
    // The actions carry icons (SVG through Qt's icon engine, or the style's when it is missing).
    const aero::ui::ActionSet& a = window_->actions();
    for (QAction* action : {a.open, a.save, a.flowSolve, a.flowStop, a.meshPreview})
        QVERIFY2(!action->icon().pixmap(16, 16).isNull(), qPrintable(action->objectName()));
    QVERIFY(!window_->windowIcon().isNull() || aero::ui::appIcon(QStringLiteral("aeroform")).isNull());
    if (aero::ui::appIcon(QStringLiteral("flow-solve")).pixmap(16, 16).isNull())
        qWarning("no SVG icon engine (Debian: libqt6svg6): the style's icons are used");
    // The desktop entry runs the application with its icon.
    QFile desktop(QStringLiteral(AEROFORM_SAMPLES_DIR "/../resources/aeroform.desktop"));
    QVERIFY(desktop.open(QIODevice::ReadOnly | QIODevice::Text));
    const QString entry = QString::fromUtf8(desktop.readAll());
    QVERIFY(entry.startsWith(QStringLiteral("[Desktop Entry]")));
    for (const char* line : {"Type=Application", "Exec=aeroform %f", "Icon=aeroform", "Name=Aeroform"})
        QVERIFY2(entry.contains(QLatin1String(line)), line);
}

void MainWindowTest::meshActionsBeforeAPreview() {
    // The preview itself is tested in MeshPreviewTest; here: what the menus offer before it.
    QAction* preview = action("actionMeshPreview");
    QVERIFY(preview != nullptr);
    QVERIFY(preview->isEnabled());
    QVERIFY(!action("actionMeshCancel")->isEnabled());
    QVERIFY(!action("actionExportGrid")->isEnabled());
    QVERIFY(window_->modelTree().gridItem()->child(0)->isDisabled());
}

void MainWindowTest::latticeDialogDescribesTheLattice() {
    aero::ui::LatticeDialog dialog(QStringLiteral("wing"), {4, 5, 6});
    dialog.show();
    QVERIFY(QTest::qWaitForWindowExposed(&dialog));
    QVERIFY(dialog.grab().save(kScreenshotDir + QStringLiteral("/lattice_dialog.png")));
    const QList<QSpinBox*> ints = dialog.findChildren<QSpinBox*>();
    QCOMPARE(ints.size(), 6);  // counts x3, degrees x3
    auto lattice = dialog.lattice();
    QCOMPARE(lattice.name, std::string("wing"));
    QCOMPARE(lattice.counts, (std::array<int, 3>{6, 6, 2}));  // the paper's default
    QCOMPARE(lattice.degrees, (std::array<int, 3>{3, 3, 1}));
    QCOMPARE(lattice.patches, (std::vector<int>{4, 5, 6}));   // the selection is offered first
    QVERIFY(!dialog.stations().has_value());
    auto* stations = dialog.findChild<QGroupBox*>();
    for (QGroupBox* box : dialog.findChildren<QGroupBox*>())
        if (box->isCheckable()) stations = box;
    stations->setChecked(true);
    const auto spec = dialog.stations();
    QVERIFY(spec.has_value());
    QCOMPARE(spec->direction, 1);
    QCOMPARE(spec->bits, std::vector<std::string>(6, "011"));  // X and Y translations, 6 stations
    // Raising a degree raises the minimum count with it.
    ints[3]->setValue(5);  // degree in X
    QCOMPARE(ints[0]->minimum(), 6);
    ints[3]->setValue(6);
    QCOMPARE(ints[0]->value(), 7);
}

// A CAD file whose conversion takes long (here a stand-in helper that never finishes): the window
// stays live, a progress dialog appears and its Cancel stops the read at once; the open document
// stays as it was. Then the real helper opens the same file.
void MainWindowTest::aSlowCadFileShowsProgressAndCanBeCancelled() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString hang = dir.filePath(QStringLiteral("hang.sh"));
    {
        QFile f(hang);
        QVERIFY(f.open(QIODevice::WriteOnly));
        f.write("#!/bin/sh\nexec sleep 60\n");
    }
    QFile::setPermissions(hang, QFile::ReadOwner | QFile::WriteOwner | QFile::ExeOwner);
    const QString step = QStringLiteral(AEROFORM_FUZZ_CORPUS_DIR "/step/occt_trimmed.stp");
    const QByteArray previousHelper = qgetenv("AEROFORM_OCCT_HELPER");
    const bool hadHelper = qEnvironmentVariableIsSet("AEROFORM_OCCT_HELPER");
    qputenv("AEROFORM_OCCT_HELPER", hang.toLocal8Bit());
    const QString titleBefore = window_->windowTitle();
    const int patchesBefore = window_->scene().patchCount();

    bool dialogShown = false;
    int framesWhileReading = -1;
    const int framesBefore = window_->viewport()->renderedFrames();
    QTimer::singleShot(1500, window_.get(), [&] {
        auto* progress = window_->findChild<QProgressDialog*>(QStringLiteral("openProgress"));
        if (!progress) return;
        dialogShown = progress->isVisible();
        window_->viewport()->update();  // the window still paints while the file is read
        for (int i = 0; i < 50 && window_->viewport()->renderedFrames() == framesBefore; ++i) QTest::qWait(100);
        framesWhileReading = window_->viewport()->renderedFrames() - framesBefore;
        const QImage shot = window_->screen()->grabWindow(0).toImage();
        shot.save(kScreenshotDir + QStringLiteral("/open_progress.png"));
        for (QPushButton* b : progress->findChildren<QPushButton*>()) b->click();
    });
    QElapsedTimer clock;
    clock.start();
    QString error;
    const bool opened = window_->loadFile(step, &error);
    const qint64 ms = clock.elapsed();
    if (hadHelper)
        qputenv("AEROFORM_OCCT_HELPER", previousHelper);
    else
        qunsetenv("AEROFORM_OCCT_HELPER");
    QVERIFY(!opened);
    QVERIFY2(dialogShown, "no progress dialog after 1.5 s of reading");
    QVERIFY2(framesWhileReading > 0, "the viewport did not render while the file was read");
    QVERIFY2(error.contains(QStringLiteral("was cancelled")), qPrintable(error));
    QVERIFY2(ms < 15000, qPrintable(QStringLiteral("the cancel took %1 ms").arg(ms)));
    QCOMPARE(window_->windowTitle(), titleBefore);
    QCOMPARE(window_->scene().patchCount(), patchesBefore);
    QVERIFY(!window_->findChild<QProgressDialog*>(QStringLiteral("openProgress")));

    // The real helper converts it.
    QVERIFY2(window_->loadFile(step, &error), qPrintable(error));
    QVERIFY(window_->scene().patchCount() > 0);
    QVERIFY(window_->windowTitle().startsWith(QStringLiteral("occt_trimmed.stp")));
    QVERIFY2(window_->loadSample(&error), qPrintable(error));
}

int runMainWindowTest(int argc, char** argv, bool canRender) {
    MainWindowTest test(canRender);
    return QTest::qExec(&test, argc, argv);
}

#include "MainWindowTest.moc"
