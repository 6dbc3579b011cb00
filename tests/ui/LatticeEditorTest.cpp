// Qt Test of editing in the main window under a real X display (xvfb-run): lattice points are
// picked and dragged through the same event path as the mouse (QMouseEvents sent to the
// viewport), the patches follow as the FFD says, undo restores them exactly, the property
// panel and design-variable sliders edit, projects round-trip through save and open, and the
// window's screenshots (build tree: tests/ui/screenshots/) are not blank.
#include <QAction>
#include <QApplication>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QLabel>
#include <QSlider>
#include <QTemporaryDir>
#include <QTest>
#include <QUndoStack>
#include <cmath>
#include <memory>

#include "DesignVariablePanel.h"
#include "Document.h"
#include "LatticeEditor.h"
#include "LatticeScene.h"
#include "MainWindow.h"
#include "OverlayScene.h"
#include "PropertyPanel.h"
#include "Selection.h"
#include "UiTestSupport.h"
#include "VtkViewport.h"
#include "geometry/HalfSphere.h"
#include "io/CaseWriter.h"

using aero::ui::MainWindow;
using namespace aero::uitest;

namespace {

using V3 = std::array<double, 3>;

bool samePoints(const aero::geometry::PatchSet& a, const aero::geometry::PatchSet& b) {
    if (a.size() != b.size()) return false;
    for (int p = 0; p < a.size(); ++p)
        if (a.patches[static_cast<std::size_t>(p)].points != b.patches[static_cast<std::size_t>(p)].points) return false;
    return true;
}

std::string caseText(const aero::io::CaseFile& c) {
    aero::io::CaseFile k = c;
    k.path.clear();
    k.geometry.clear();
    return aero::io::formatCase(k);
}

double norm(const V3& v) {
    return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

}  // namespace

class LatticeEditorTest : public QObject {
    Q_OBJECT

  public:
    explicit LatticeEditorTest(bool canRender) : canRender_(canRender) {}

  private slots:
    void initTestCase();
    void cleanupTestCase();
    void init();
    void dragMovesPointInTheViewPlaneAsTheFfdSays();
    void shiftDragMovesAlongOneAxis();
    void ctrlClickSelectsSeveralThatMoveTogether();
    void escapeCancelsADrag();
    void typedCoordinatesMoveThePoint();
    void sliderDragIsOneUndoStep();
    void sensitivityArrowsFollowTheSelectedVariable();
    void nonInjectiveLatticeIsHighlightedAndExplained();
    void saveAndReopenRestoreExactly();
    void windowScreenshotsAreNotBlank();
    void dragIsInteractive();
    void documentationScreenshots();

  private:
    aero::ui::Document& doc() { return window_->document(); }
    aero::ui::VtkViewport* view() { return window_->viewport(); }
    QAction* action(const char* name) { return window_->findChild<QAction*>(QString::fromLatin1(name)); }
    QPointF screenOf(int l, int a) {
        const double* x = &doc().lattices()[static_cast<std::size_t>(l)].points[3 * static_cast<std::size_t>(a)];
        QPointF w;
        if (!view()->project({x[0], x[1], x[2]}, &w)) return {-1, -1};
        return w;
    }
    // A point of lattice 0 that the editor picks at its own screen position (not hidden by a
    // nearer one), well inside the viewport; candidates by (i, j, k).
    int pickable(std::initializer_list<std::array<int, 3>> candidates) {
        const auto& L = doc().lattices()[0];
        for (const auto& c : candidates) {
            const int a = L.index(c[0], c[1], c[2]);
            const QPointF p = screenOf(0, a);
            const QRectF inner = QRectF(view()->rect()).adjusted(40, 40, -40, -40);
            if (!inner.contains(p)) continue;
            const auto hit = window_->latticeEditor().pointAt(p);
            if (hit.lattice == 0 && hit.point == a) return a;
        }
        return -1;
    }
    QImage frame() { return view()->grabImage(); }

    bool canRender_;
    std::unique_ptr<QTemporaryDir> dir_;
    std::unique_ptr<MainWindow> window_;
};

void LatticeEditorTest::initTestCase() {
    if (!canRender_)
        QSKIP("test_ui needs an X display: DISPLAY is not set (or QT_QPA_PLATFORM is offscreen). "
              "Run it under xvfb-run -a -s \"-screen 0 1280x800x24\".");
    QDir().mkpath(kScreenshotDir);
    dir_ = std::make_unique<QTemporaryDir>();
    MainWindow::Options options;
    options.autosaveDirectory = dir_->filePath(QStringLiteral("autosave"));
    options.autosaveIntervalMs = 3600000;
    options.recentFiles = false;
    window_ = std::make_unique<MainWindow>(options);
    window_->resize(1240, 780);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
}

void LatticeEditorTest::cleanupTestCase() {
    window_.reset();
    dir_.reset();
}

void LatticeEditorTest::init() {
    // Every test starts from the paper's sample, default camera, nothing selected.
    QString error;
    QVERIFY2(window_->loadSample(&error, true), qPrintable(error));
    QCOMPARE(doc().latticeCount(), 1);
    QTRY_VERIFY_WITH_TIMEOUT(view()->renderedFrames() > 0, 10000);
    frame();  // renders with the final camera (projection uses it)
}

void LatticeEditorTest::dragMovesPointInTheViewPlaneAsTheFfdSays() {
    const aero::geometry::PatchSet before = doc().shape();
    const int a = pickable({{2, 3, 1}, {3, 3, 1}, {2, 2, 1}, {3, 4, 1}, {1, 3, 1}});
    QVERIFY2(a >= 0, "no lattice point can be picked");
    const QPointF from = screenOf(0, a);
    const QPointF to = from + QPointF(45, -30);
    const V3 viewDir = view()->viewDirection();
    drag(view(), from, to);

    // One edit: a displacement of exactly that lattice point.
    QCOMPARE(doc().undoStack()->count(), 1);
    QCOMPARE(doc().caseFile().displacements.size(), std::size_t(1));
    const auto& L = doc().lattices()[0];
    QCOMPARE(doc().caseFile().displacements[0].index,
             (std::array<int, 3>{a % L.count[0], (a / L.count[0]) % L.count[1], a / (L.count[0] * L.count[1])}));
    const V3 delta = doc().displacement(0, a);
    QVERIFY(norm(delta) > 1e-3);
    // In the plane parallel to the view plane, and the point ends up under the cursor.
    QVERIFY2(std::abs(delta[0] * viewDir[0] + delta[1] * viewDir[1] + delta[2] * viewDir[2]) < 1e-9 * norm(delta),
             "the drag left the view plane");
    const QPointF now = screenOf(0, a);
    QVERIFY2(std::hypot(now.x() - to.x(), now.y() - to.y()) < 0.5,
             qPrintable(QStringLiteral("point at (%1, %2), cursor at (%3, %4)").arg(now.x()).arg(now.y()).arg(to.x()).arg(to.y())));
    QVERIFY(window_->selection().hasPoint(0, a));

    // The patches moved as the FFD says: the baseline model with that point displaced.
    const aero::ffd::FfdModel reference = aero::io::buildModel(doc().caseFile(), aero::geometry::makeHalfSphere());
    aero::ffd::Lattice moved = reference.design().lattice(0, reference.design().baselineValues());
    for (int k = 0; k < 3; ++k) moved.points[3 * static_cast<std::size_t>(a) + k] += delta[static_cast<std::size_t>(k)];
    const aero::geometry::PatchSet expected = reference.deformWith({moved});
    QVERIFY(samePoints(doc().shape(), expected));
    QVERIFY(!samePoints(doc().shape(), before));
    QVERIFY(window_->isWindowModified());

    // Undo (the Edit menu's action) restores every control point exactly; redo re-applies.
    action("actionUndo")->trigger();
    QVERIFY(samePoints(doc().shape(), before));
    QVERIFY(doc().caseFile().displacements.empty());
    QVERIFY(!window_->isWindowModified());
    action("actionRedo")->trigger();
    QVERIFY(samePoints(doc().shape(), expected));
}

void LatticeEditorTest::shiftDragMovesAlongOneAxis() {
    const int a = pickable({{3, 3, 1}, {2, 3, 1}, {3, 2, 1}, {2, 4, 1}});
    QVERIFY(a >= 0);
    const QPointF from = screenOf(0, a);
    drag(view(), from, from + QPointF(0, -50), 10, Qt::ShiftModifier);  // upwards on screen: Z
    const V3 delta = doc().displacement(0, a);
    int moving = 0;
    for (double c : delta) moving += c != 0 ? 1 : 0;
    QCOMPARE(moving, 1);
    QVERIFY2(delta[2] > 0, "dragging up with Shift should raise the point along Z");
}

void LatticeEditorTest::ctrlClickSelectsSeveralThatMoveTogether() {
    const int a = pickable({{2, 3, 1}, {3, 3, 1}});
    const int b = pickable({{2, 4, 1}, {3, 4, 1}, {2, 2, 1}});
    QVERIFY(a >= 0 && b >= 0 && a != b);
    click(view(), screenOf(0, a));
    click(view(), screenOf(0, b), Qt::ControlModifier);
    QCOMPARE(window_->selection().points().size(), std::size_t(2));
    QCOMPARE(doc().undoStack()->count(), 0);  // selecting is not an edit
    const QPointF from = screenOf(0, b);
    drag(view(), from, from + QPointF(-20, -35));
    QCOMPARE(doc().undoStack()->count(), 1);
    QCOMPARE(doc().caseFile().displacements.size(), std::size_t(2));
    QCOMPARE(doc().displacement(0, a), doc().displacement(0, b));
    // Esc drops the point selection (the lattice stays selected).
    QTest::keyClick(view(), Qt::Key_Escape);
    QCOMPARE(window_->selection().kind(), aero::ui::Selection::Kind::Lattice);
}

void LatticeEditorTest::escapeCancelsADrag() {
    const aero::geometry::PatchSet before = doc().shape();
    const int a = pickable({{2, 3, 1}, {3, 3, 1}});
    QVERIFY(a >= 0);
    const QPointF from = screenOf(0, a);
    sendMouse(view(), QEvent::MouseButtonPress, from, Qt::LeftButton, Qt::LeftButton);
    sendMouse(view(), QEvent::MouseMove, from + QPointF(30, 30), Qt::NoButton, Qt::LeftButton);
    QVERIFY(window_->latticeEditor().dragging());
    QVERIFY(doc().previewing());
    QVERIFY(!samePoints(doc().shape(), before));  // the geometry follows live
    QTest::keyClick(view(), Qt::Key_Escape);
    QVERIFY(!doc().previewing());
    QVERIFY(samePoints(doc().shape(), before));
    sendMouse(view(), QEvent::MouseMove, from + QPointF(60, 30), Qt::NoButton, Qt::LeftButton);
    sendMouse(view(), QEvent::MouseButtonRelease, from + QPointF(60, 30), Qt::LeftButton, Qt::NoButton);
    QVERIFY(samePoints(doc().shape(), before));
    QCOMPARE(doc().undoStack()->count(), 0);
}

void LatticeEditorTest::typedCoordinatesMoveThePoint() {
    const int a = pickable({{2, 3, 1}, {3, 3, 1}});
    QVERIFY(a >= 0);
    click(view(), screenOf(0, a));
    QVERIFY(window_->selection().hasPoint(0, a));
    const auto editors = window_->properties().coordinateEditors();
    QDoubleSpinBox* z = editors[2];
    const double z0 = doc().lattices()[0].points[3 * static_cast<std::size_t>(a) + 2];
    QCOMPARE(z->value(), std::round(z0 * 1e6) / 1e6);
    z->setValue(z0 + 0.25);
    const double typed = z->value();
    QVERIFY(std::abs(doc().lattices()[0].points[3 * static_cast<std::size_t>(a) + 2] - typed) < 1e-12);
    QCOMPARE(doc().undoStack()->count(), 1);
    action("actionUndo")->trigger();
    QCOMPARE(doc().lattices()[0].points[3 * static_cast<std::size_t>(a) + 2], z0);
}

void LatticeEditorTest::sliderDragIsOneUndoStep() {
    auto& panel = window_->designVariables();
    const int var = doc().model()->design().find("body.S4.ty");
    QVERIFY(var >= 0);
    QSlider* slider = panel.slider(var);
    QVERIFY(slider != nullptr);
    const aero::geometry::PatchSet before = doc().shape();
    slider->setSliderDown(true);  // the user grabs the handle...
    for (int pos = 510; pos <= 700; pos += 38) slider->setValue(pos);
    slider->setSliderDown(false);  // ...and lets go
    QCOMPARE(doc().undoStack()->count(), 1);
    const auto& v = doc().model()->design().variables()[static_cast<std::size_t>(var)];
    const double expected = std::round((v.lower + (v.upper - v.lower) * slider->value() / 1000.0) * 1e4) / 1e4;
    QCOMPARE(doc().values()[static_cast<std::size_t>(var)], expected);
    QCOMPARE(panel.spinBox(var)->value(), expected);
    QCOMPARE(panel.currentVariable(), var);
    QVERIFY(!samePoints(doc().shape(), before));
    action("actionUndo")->trigger();
    QVERIFY(samePoints(doc().shape(), before));
    QCOMPARE(slider->value(), 500);  // the panel follows undo (baseline 0 in [-3, 3])
}

void LatticeEditorTest::sensitivityArrowsFollowTheSelectedVariable() {
    auto& panel = window_->designVariables();
    const int var = doc().model()->design().find("body.S3.ty");
    panel.setCurrentVariable(var);
    const QImage without = frame();
    action("actionSensitivity")->setChecked(true);
    QVERIFY(panel.sensitivityShown());
    QVERIFY(window_->overlayScene().arrowCount() > 20);
    const QImage with = frame();
    QVERIFY(with.save(kScreenshotDir + QStringLiteral("/sensitivity_S3_ty.png")));
    QVERIFY2(redShare(with) > redShare(without) + 0.002, "no red arrows in the picture");
    // Another variable, other arrows (a taper moves the surface fore and aft); off again, none.
    panel.setCurrentVariable(doc().model()->design().find("body.S0.taperx"));
    QVERIFY(window_->overlayScene().arrowCount() > 0);
    QVERIFY(panel.findChildren<QLabel*>().size() > 0);
    action("actionSensitivity")->setChecked(false);
    QCOMPARE(window_->overlayScene().arrowCount(), 0);
}

void LatticeEditorTest::nonInjectiveLatticeIsHighlightedAndExplained() {
    const auto* label = window_->findChild<QLabel*>(QStringLiteral("problemLabel"));
    QVERIFY(label != nullptr);
    QVERIFY(label->isHidden());
    const QImage fine = frame();
    const auto& L = doc().lattices()[0];
    const int a = L.index(2, 3, 1);
    const double height = L.points[3 * static_cast<std::size_t>(a) + 2] - L.points[3 * static_cast<std::size_t>(L.index(2, 3, 0)) + 2];
    doc().moveLatticePoints(0, {a}, {0, 0, -5.0 * height});
    QVERIFY(!doc().injectivity()[0].injective);
    QVERIFY(label->isVisible());
    QVERIFY2(label->text().contains(QStringLiteral("not injective")), qPrintable(label->text()));
    QVERIFY(label->toolTip().contains(QStringLiteral("fold")));
    const QImage folded = frame();
    QVERIFY(folded.save(kScreenshotDir + QStringLiteral("/non_injective.png")));
    QVERIFY2(redShare(folded) > redShare(fine) + 0.001, "the folded lattice is not highlighted in red");
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/non_injective_window.png")));
    action("actionUndo")->trigger();
    QVERIFY(label->isHidden());
}

void LatticeEditorTest::saveAndReopenRestoreExactly() {
    const int a = pickable({{2, 3, 1}, {3, 3, 1}});
    QVERIFY(a >= 0);
    const QPointF from = screenOf(0, a);
    drag(view(), from, from + QPointF(25, -40));
    doc().setDesignValue(doc().model()->design().find("body.S5.taperx"), 0.6);
    const aero::geometry::PatchSet shape = doc().shape();
    const std::string text = caseText(doc().caseFile());
    QVERIFY(window_->isWindowModified());
    QVERIFY(window_->windowTitle().contains(QStringLiteral("[*]")));

    const QString path = dir_->filePath(QStringLiteral("edited.json"));
    QString error;
    QVERIFY2(window_->saveProject(path, &error), qPrintable(error));
    QVERIFY(!window_->isWindowModified());
    QVERIFY(window_->windowTitle().startsWith(QStringLiteral("edited.json")));

    QVERIFY2(window_->loadSample(&error, false), qPrintable(error));  // something else in between
    QVERIFY2(window_->loadFile(path, &error), qPrintable(error));
    QCOMPARE(caseText(doc().caseFile()), text);
    QVERIFY(samePoints(doc().shape(), shape));
    QVERIFY(!window_->isWindowModified());
    QCOMPARE(doc().undoStack()->count(), 0);
    // What the GUI saved is a case the CLI reads (aeroform-cli deform edited.json).
    const aero::io::CaseFile c = aero::io::readCase(path.toStdString());
    QCOMPARE(c.displacements.size(), std::size_t(1));
    // A copy in the build tree (next to the screenshots) to try with the CLI.
    const QString kept = kScreenshotDir + QStringLiteral("/../projects/edited_sphere.json");
    QDir().mkpath(QFileInfo(kept).absolutePath());
    QVERIFY2(window_->saveProject(kept, &error), qPrintable(error));
}

void LatticeEditorTest::windowScreenshotsAreNotBlank() {
    // A scene worth looking at: two stations pulled out, one point selected.
    auto& d = doc();
    d.setDesignValue(d.model()->design().find("body.S5.ty"), 1.2);
    d.setDesignValue(d.model()->design().find("body.S4.ty"), 0.6);
    const int a = pickable({{3, 5, 1}, {2, 5, 1}, {3, 4, 1}});
    QVERIFY(a >= 0);
    const QPointF from = screenOf(0, a);
    drag(view(), from, from + QPointF(0, -45), 10, Qt::ShiftModifier);
    QVERIFY(window_->selection().hasPoint(0, a));
    window_->designVariables().setCurrentVariable(d.model()->design().find("body.S5.ty"));
    QApplication::processEvents();

    const QImage viewport = frame();
    QVERIFY(viewport.save(kScreenshotDir + QStringLiteral("/lattice_edit_viewport.png")));
    const QImage window = window_->grab().toImage();
    QVERIFY(window.save(kScreenshotDir + QStringLiteral("/lattice_edit.png")));
    QVERIFY2(distinctColours(window) > 300, "the window screenshot looks blank");
    // The viewport part of the window grab holds the rendered scene, not a blank rectangle.
    const QRect vr(view()->mapTo(window_.get(), QPoint(0, 0)), view()->size());
    const QImage inWindow = window.copy(vr);
    QVERIFY(distinctColours(inWindow) > 100);
    QVERIFY(compare(inWindow.scaled(viewport.size()), viewport, 40).differingShare < 0.2);

    // And the sensitivity view for the documentation.
    action("actionSensitivity")->setChecked(true);
    QApplication::processEvents();
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/sensitivity_window.png")));
    action("actionSensitivity")->setChecked(false);
}

void LatticeEditorTest::dragIsInteractive() {
    // Not a timed test (no threshold): reports what a drag frame costs on this machine.
    const int a = pickable({{2, 3, 1}, {3, 3, 1}});
    QVERIFY(a >= 0);
    const QPointF from = screenOf(0, a);
    sendMouse(view(), QEvent::MouseButtonPress, from, Qt::LeftButton, Qt::LeftButton);
    QElapsedTimer timer;
    qint64 update = 0, render = 0;
    const int frames = 20;
    for (int k = 1; k <= frames; ++k) {
        timer.start();
        sendMouse(view(), QEvent::MouseMove, from + QPointF(2.0 * k, -1.5 * k), Qt::NoButton, Qt::LeftButton);
        update += timer.nsecsElapsed();
        timer.start();
        view()->grabImage();  // one full frame
        render += timer.nsecsElapsed();
    }
    sendMouse(view(), QEvent::MouseButtonRelease, from + QPointF(2.0 * frames, -1.5 * frames), Qt::LeftButton, Qt::NoButton);
    qInfo("drag frame: %.2f ms deform + scene update (20 patches re-sampled at most), %.2f ms render (llvmpipe)",
          update / 1e6 / frames, render / 1e6 / frames);
    QCOMPARE(doc().undoStack()->count(), 1);
}

void LatticeEditorTest::documentationScreenshots() {
    // docs/images/ takes its pictures from these (copied by hand, never written by tests).
    window_->selection().selectLattice(0);
    QApplication::processEvents();
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/doc_main_window.png")));

    // Towards the blended-wing body of the paper's Figure 2, then the tip points pulled up.
    QString error;
    QVERIFY2(window_->loadFile(QStringLiteral(AEROFORM_SAMPLES_DIR "/bwb_deform.json"), &error), qPrintable(error));
    frame();
    const auto& L = doc().lattices()[0];
    std::vector<int> tip;
    for (int i = 0; i < L.count[0]; ++i) tip.push_back(L.index(i, L.count[1] - 1, 1));
    const int grab = pickable({{2, 5, 1}, {3, 5, 1}, {1, 5, 1}, {4, 5, 1}});
    QVERIFY(grab >= 0);
    window_->selection().selectPoints(0, tip);
    const QPointF from = screenOf(0, grab);
    sendMouse(view(), QEvent::MouseButtonPress, from, Qt::LeftButton, Qt::LeftButton);
    for (int k = 1; k <= 10; ++k)
        sendMouse(view(), QEvent::MouseMove, from + QPointF(0, -5.0 * k), Qt::NoButton, Qt::LeftButton, Qt::ShiftModifier);
    QApplication::processEvents();
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/doc_lattice_edit.png")));
    sendMouse(view(), QEvent::MouseButtonRelease, from + QPointF(0, -50), Qt::LeftButton, Qt::NoButton, Qt::ShiftModifier);
    QCOMPARE(doc().caseFile().displacements.size(), tip.size());

    // The paper's Figure 1: arrows dS/dv of one variable on the sphere.
    QVERIFY2(window_->loadSample(&error, true), qPrintable(error));
    frame();
    window_->designVariables().setCurrentVariable(doc().model()->design().find("body.S3.taperx"));
    action("actionSensitivity")->setChecked(true);
    QApplication::processEvents();
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/doc_sensitivity.png")));
    action("actionSensitivity")->setChecked(false);
}

int runLatticeEditorTest(int argc, char** argv, bool canRender) {
    LatticeEditorTest test(canRender);
    return QTest::qExec(&test, argc, argv);
}

#include "LatticeEditorTest.moc"
