// Qt Test of Mesh > Preview on the half-sphere sample with the paper's lattice: the job runs on
// the worker thread and ends with the coarse grid of the CLI (20 blocks, 6,252 control nodes,
// 98,260 grid nodes) and positive Jacobians, also after a lattice point moved; cancelling
// leaves a usable window; a worst-cell row flies the camera to the cell; edits make the
// preview outdated (and undo brings it back); tangled cells are reported and marked; the grid
// exports to VTK and Plot3D. Screenshots go to the build tree (tests/ui/screenshots/).
#include <vtkCamera.h>
#include <vtkRenderer.h>

#include <QAction>
#include <QComboBox>
#include <QDir>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QLabel>
#include <QLocale>
#include <QPushButton>
#include <QSignalSpy>
#include <QSlider>
#include <QSpinBox>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>
#include <QTreeWidgetItem>
#include <QUndoStack>
#include <array>
#include <cmath>
#include <memory>
#include <numeric>

#include "JobRunner.h"
#include "Document.h"
#include "MainWindow.h"
#include "MeshPanel.h"
#include "MeshPreviewer.h"
#include "MeshScene.h"
#include "ModelTree.h"
#include "PatchScene.h"
#include "QualityHistogram.h"
#include "UiTestSupport.h"
#include "VtkViewport.h"
#include "geometry/HalfSphere.h"
#include "io/PatchSetJson.h"
#include "mesh/Plot3d.h"

using aero::ui::MainWindow;
using aero::ui::MeshPreviewer;
using State = aero::ui::MeshPreviewer::State;
using namespace aero::uitest;

namespace {

constexpr int kJobTimeoutMs =
    120000;  // the coarse grid takes seconds; be generous on busy machines

const char* stateName(State s) {
    switch (s) {
        case State::None:
            return "None";
        case State::Running:
            return "Running";
        case State::Ready:
            return "Ready";
        case State::Outdated:
            return "Outdated";
        case State::Cancelled:
            return "Cancelled";
        case State::Failed:
            return "Failed";
    }
    return "?";
}

}  // namespace

class MeshPreviewTest : public QObject {
    Q_OBJECT

  public:
    explicit MeshPreviewTest(bool canRender) : canRender_(canRender) {}

  private slots:
    void initTestCase();
    void cleanupTestCase();
    void previewOfThePapersLatticeHasPositiveJacobians();
    void screenshotShowsTheGrid();
    void metricAndSliceChangeThePicture();
    void clickingAWorstCellFliesTheCameraThere();
    void movedLatticePointIsFollowedByTheGrid();
    void optionsAreUndoableCaseEdits();
    void exportWritesVtkAndPlot3d();
    void tangledCellsAreReportedAndMarked();
    void cancelStopsThePreviewAndKeepsTheWindowUsable();
    void failureIsReportedAndANewDocumentClearsThePreview();

  private:
    MeshPreviewer& previewer() { return window_->meshPreviewer(); }
    aero::ui::MeshPanel& panel() { return window_->meshPanel(); }
    QImage renderNow() { return window_->viewport()->grabImage(); }
    QAction* action(const char* name) {
        return window_->findChild<QAction*>(QString::fromLatin1(name));
    }
    // Starts the preview through the menu action and waits for it to end; returns the state.
    State runPreview() {
        action("actionMeshPreview")->trigger();
        if (previewer().state() != State::Running) return previewer().state();
        (void)QTest::qWaitFor([this] { return previewer().state() != State::Running; },
                              kJobTimeoutMs);
        (void)QTest::qWaitFor([this] { return !window_->jobs().busy(); }, 5000);
        return previewer().state();
    }

    bool canRender_;
    std::unique_ptr<MainWindow> window_;
};

void MeshPreviewTest::initTestCase() {
    if (!canRender_)
        QSKIP(
            "test_ui needs an X display: DISPLAY is not set (or QT_QPA_PLATFORM is offscreen). "
            "Run it under xvfb-run -a -s \"-screen 0 1280x800x24\".");
    QDir().mkpath(kScreenshotDir);
    MainWindow::Options options;
    options.autosave = false;
    options.recentFiles = false;
    window_ = std::make_unique<MainWindow>(options);
    window_->resize(1240, 780);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    QString error;
    QVERIFY2(window_->loadSample(&error), qPrintable(error));
    QTRY_VERIFY_WITH_TIMEOUT(window_->viewport()->renderedFrames() > 0, 10000);
}

void MeshPreviewTest::cleanupTestCase() {
    window_.reset();
}

void MeshPreviewTest::previewOfThePapersLatticeHasPositiveJacobians() {
    QVERIFY(action("actionMeshPreview")->isEnabled());
    QVERIFY2(!action("actionExportGrid")->isEnabled(), "grid export before any preview");
    QCOMPARE(previewer().state(), State::None);
    QCOMPARE(window_->modelTree().gridPartItem(aero::ui::ModelTree::WallPart)->isDisabled(), true);

    QSignalSpy progress(&window_->jobs(), &aero::ui::JobRunner::jobProgressed);
    const State s = runPreview();
    QVERIFY2(s == State::Ready, stateName(s));
    QVERIFY(progress.count() > 0);

    const auto r = previewer().result();
    QVERIFY(r != nullptr);
    QCOMPARE(r->level, std::string("coarse"));
    QCOMPARE(r->grids.size(), std::size_t{20});
    QCOMPARE(r->mesh.controlCount(), 6252);
    QCOMPARE(r->gridNodes(), 98260L);
    QVERIFY2(!r->moved, "the paper's lattice at its baseline values does not move the wall");
    qInfo("coarse preview: min Jacobian %.3e, min scaled Jacobian %.3f, %.2f s",
          r->summary.minJacobian.min, r->summary.scaledJacobian.min, r->seconds);
    QVERIFY(r->summary.minJacobian.min > 0);
    QCOMPARE(r->summary.nonPositiveJacobian, 0L);
    QVERIFY(previewer().problem().isEmpty());

    // What the window says about it.
    QVERIFY(action("actionExportGrid")->isEnabled());
    QVERIFY(!window_->meshScene().empty());
    QVERIFY(window_->meshScene().partVisible(aero::ui::MeshPart::Wall));
    QVERIFY(!window_->meshScene().partVisible(aero::ui::MeshPart::Slice));
    QVERIFY2(!window_->scene().surfacesVisible(),
             "the geometry's surfaces stay under the grid's wall");
    const QString gridText = window_->modelTree().gridItem()->text(0);
    QVERIFY2(gridText.contains(QStringLiteral("20 blocks")), qPrintable(gridText));
    QVERIFY(window_->modelTree().gridItem()->toolTip(0).contains(QLocale().toString(98260)));
    QVERIFY(!window_->modelTree().gridPartItem(aero::ui::ModelTree::WallPart)->isDisabled());
    QVERIFY2(panel().statusText().contains(QStringLiteral("20 blocks")),
             qPrintable(panel().statusText()));
    QVERIFY2(panel().summaryLabel()->text().contains(
                 QStringLiteral("No cell with a non-positive Jacobian")),
             qPrintable(panel().summaryLabel()->text()));
    // The sphere's wall turns by about 3 degrees per grid node: said, not warned about.
    QVERIFY(r->wallBend.degrees > 1 && r->wallBend.degrees < 5);
    QVERIFY2(panel().summaryLabel()->text().contains(QStringLiteral("Sharpest wall bend")),
             qPrintable(panel().summaryLabel()->text()));
    QCOMPARE(panel().worstCellTable()->rowCount(), static_cast<int>(r->summary.worst.size()));
    QVERIFY(panel().worstCellTable()->rowCount() > 5);
    const auto& counts = panel().histogram()->counts();
    QCOMPARE(std::accumulate(counts.begin(), counts.end(), 0L), r->summary.cellCount);
}

void MeshPreviewTest::screenshotShowsTheGrid() {
    QCOMPARE(previewer().state(), State::Ready);
    const QImage with = renderNow();
    QVERIFY(with.save(kScreenshotDir + QStringLiteral("/mesh_preview.png")));
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/mesh_preview_window.png")));
    QVERIFY2(distinctColours(with) > 200, "the mesh preview looks blank");

    // Without the grid (Grid blocks unchecked) the geometry comes back: a different picture.
    aero::ui::ModelTree& tree = window_->modelTree();
    tree.gridItem()->setCheckState(0, Qt::Unchecked);
    QVERIFY(!tree.gridPartShown(aero::ui::ModelTree::WallPart));
    QVERIFY(!window_->meshScene().anythingVisible());
    QVERIFY(window_->scene().surfacesVisible());
    const QImage without = renderNow();
    tree.gridItem()->setCheckState(0, Qt::Checked);
    QVERIFY(!window_->scene().surfacesVisible());
    const PixelStats s = compare(with, without);
    qInfo("the grid changes %.1f %% of the viewport", 100 * s.differingShare);
    QVERIFY2(s.differingShare > 0.05, "showing the grid hardly changed the picture");
}

void MeshPreviewTest::metricAndSliceChangeThePicture() {
    const QImage scaled = renderNow();
    panel().metricBox()->setCurrentIndex(static_cast<int>(aero::ui::QualityMetric::AspectRatio));
    QCOMPARE(window_->meshScene().metric(), aero::ui::QualityMetric::AspectRatio);
    QVERIFY(!panel().worstCellTable()->isColumnHidden(3));  // the chosen metric's column
    const QImage aspect = renderNow();
    QVERIFY(aspect.save(kScreenshotDir + QStringLiteral("/mesh_preview_aspect_ratio.png")));
    QVERIFY2(compare(aspect, scaled).differingShare > 0.01, "another metric, the same colours");
    panel().metricBox()->setCurrentIndex(static_cast<int>(aero::ui::QualityMetric::ScaledJacobian));

    // Moving the slice slider shows the slice at that layer.
    aero::ui::ModelTree& tree = window_->modelTree();
    QVERIFY(!tree.gridPartShown(aero::ui::ModelTree::SlicePart));
    QCOMPARE(window_->meshScene().sliceLayers(), 16);
    panel().sliceSlider()->setValue(4);
    QCOMPARE(window_->meshScene().slice(), 4);
    QVERIFY(tree.gridPartShown(aero::ui::ModelTree::SlicePart));
    QVERIFY(window_->meshScene().partVisible(aero::ui::MeshPart::Slice));
    const QImage slice = renderNow();
    QVERIFY(slice.save(kScreenshotDir + QStringLiteral("/mesh_preview_slice.png")));
    QVERIFY2(compare(slice, scaled).differingShare > 0.01, "the slice is not drawn");
    tree.gridPartItem(aero::ui::ModelTree::SlicePart)->setCheckState(0, Qt::Unchecked);
    QVERIFY(!window_->meshScene().partVisible(aero::ui::MeshPart::Slice));
    QVERIFY(compare(renderNow(), scaled).differingShare < 0.001);

    // The control grid's wireframe.
    tree.gridPartItem(aero::ui::ModelTree::ControlGridPart)->setCheckState(0, Qt::Checked);
    QVERIFY(window_->meshScene().partVisible(aero::ui::MeshPart::ControlGrid));
    const QImage control = renderNow();
    QVERIFY(control.save(kScreenshotDir + QStringLiteral("/mesh_preview_control_grid.png")));
    QVERIFY2(compare(control, scaled).differingShare > 0.01, "the control grid is not drawn");
    tree.gridPartItem(aero::ui::ModelTree::ControlGridPart)->setCheckState(0, Qt::Unchecked);
}

void MeshPreviewTest::clickingAWorstCellFliesTheCameraThere() {
    const auto r = previewer().result();
    QVERIFY(r && r->summary.worst.size() > 3);
    QTableWidget* table = panel().worstCellTable();
    const int row = 3;
    table->scrollToItem(table->item(row, 1));
    const QRect rect = table->visualItemRect(table->item(row, 1));
    QVERIFY(rect.isValid());
    QTest::mouseClick(table->viewport(), Qt::LeftButton, Qt::NoModifier, rect.center());
    QCOMPARE(table->currentRow(), row);
    QVERIFY(previewer().flying());
    QTRY_VERIFY_WITH_TIMEOUT(!previewer().flying(), 5000);

    const auto& w = r->summary.worst[static_cast<std::size_t>(row)];
    std::array<double, 3> focal{};
    window_->viewport()->renderer()->GetActiveCamera()->GetFocalPoint(focal.data());
    for (int k = 0; k < 3; ++k) QVERIFY(std::abs(focal[k] - w.centroid[k]) < 1e-9);
    QCOMPARE(window_->meshScene().focusCell(), (aero::ui::GridCell{w.block, w.cell}));
    // Close enough to see the cell: a few cell sizes away, not the whole-body distance.
    std::array<double, 3> centre{};
    double size = 0;
    QVERIFY(window_->meshScene().cellCentre({w.block, w.cell}, centre, size));
    const double dist = window_->viewport()->renderer()->GetActiveCamera()->GetDistance();
    QVERIFY2(
        dist < 40 * size + 0.2,
        qPrintable(QStringLiteral("camera %1 away from a cell of size %2").arg(dist).arg(size)));
    const QImage shot = renderNow();
    QVERIFY(shot.save(kScreenshotDir + QStringLiteral("/mesh_preview_worst_cell.png")));
    // The focused cell is drawn in yellow on top.
    int yellow = 0;
    const QImage img = shot.convertToFormat(QImage::Format_RGB32);
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            const QRgb c = img.pixel(x, y);
            if (qRed(c) > 220 && qGreen(c) > 180 && qBlue(c) < 60) ++yellow;
        }
    QVERIFY2(yellow > 20, "the focused cell is not highlighted");
    // The same row again flies back there after the view was changed.
    window_->resetCamera();
    QTest::mouseClick(table->viewport(), Qt::LeftButton, Qt::NoModifier, rect.center());
    QTRY_VERIFY_WITH_TIMEOUT(!previewer().flying(), 5000);
    window_->viewport()->renderer()->GetActiveCamera()->GetFocalPoint(focal.data());
    for (int k = 0; k < 3; ++k) QVERIFY(std::abs(focal[k] - w.centroid[k]) < 1e-9);
    window_->resetCamera();
}

void MeshPreviewTest::movedLatticePointIsFollowedByTheGrid() {
    aero::ui::Document& doc = window_->document();
    // A top point of the lattice (i = 2, j = 3, k = 1 of 6 x 6 x 2) moved up and outwards.
    const int point = 2 + 6 * (3 + 6 * 1);
    doc.moveLatticePoints(0, {point}, {0.05, 0.1, 0.25});
    QCOMPARE(previewer().state(), State::Outdated);
    QVERIFY(window_->meshScene().empty());
    QVERIFY2(window_->scene().surfacesVisible(), "the geometry is back while the grid is outdated");
    QVERIFY(!action("actionExportGrid")->isEnabled());
    QVERIFY(panel().statusText().contains(QStringLiteral("Outdated")));
    QVERIFY(
        window_->grab().save(kScreenshotDir + QStringLiteral("/mesh_preview_outdated_window.png")));

    const State s = runPreview();
    QVERIFY2(s == State::Ready, stateName(s));
    const auto r = previewer().result();
    QVERIFY(r->moved);
    QCOMPARE(r->move.cgIterations.size(), std::size_t{6});
    QCOMPARE(r->mesh.controlCount(), 6252);
    QCOMPARE(r->gridNodes(), 98260L);
    qInfo("moved preview: min Jacobian %.3e, %d PCG iterations, %.2f s", r->summary.minJacobian.min,
          r->move.totalIterations, r->seconds);
    QVERIFY(r->summary.minJacobian.min > 0);
    QCOMPARE(r->summary.nonPositiveJacobian, 0L);
    // The wall follows the deformed geometry: its control nodes are the document's points.
    const std::vector<double> wall = doc.uniquePoints();
    for (std::size_t u = 0; u < r->mesh.surfaceNode.size(); ++u)
        for (std::size_t c = 0; c < 3; ++c)
            QCOMPARE(r->mesh.control[3 * static_cast<std::size_t>(r->mesh.surfaceNode[u]) + c],
                     wall[3 * u + c]);
    QVERIFY(
        window_->grab().save(kScreenshotDir + QStringLiteral("/mesh_preview_moved_window.png")));

    // Undo makes it outdated, redo brings it back without running again.
    doc.undoStack()->undo();
    QCOMPARE(previewer().state(), State::Outdated);
    doc.undoStack()->redo();
    QCOMPARE(previewer().state(), State::Ready);
    QVERIFY(!window_->meshScene().empty());
    QCOMPARE(previewer().result(), r);
}

void MeshPreviewTest::optionsAreUndoableCaseEdits() {
    aero::ui::Document& doc = window_->document();
    QCOMPARE(panel().level(), QStringLiteral("coarse"));
    QCOMPARE(panel().increments(), 6);
    QComboBox* level = panel().levelBox();
    level->setCurrentIndex(level->findData(QStringLiteral("medium")));
    emit level->activated(level->currentIndex());
    QCOMPARE(doc.caseFile().mesh.level, std::string("medium"));
    QVERIFY(doc.caseFile().mesh.present);
    QCOMPARE(doc.caseFile().mesh.extrusion.surfaceNodes, 23);
    QVERIFY2(doc.undoStack()->undoText().contains(QStringLiteral("medium")),
             qPrintable(doc.undoStack()->undoText()));
    QCOMPARE(previewer().state(), State::Outdated);  // made with other options
    panel().incrementsBox()->setValue(9);
    QCOMPARE(doc.caseFile().mesh.elasticity.increments, 9);
    doc.undoStack()->undo();
    QCOMPARE(panel().increments(), 6);
    doc.undoStack()->undo();
    QCOMPARE(doc.caseFile().mesh.level, std::string("coarse"));
    QCOMPARE(panel().level(), QStringLiteral("coarse"));
    QCOMPARE(previewer().state(), State::Ready);
}

void MeshPreviewTest::exportWritesVtkAndPlot3d() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const QString vtm = dir.filePath(QStringLiteral("grid.vtm"));
    const QString xyz = dir.filePath(QStringLiteral("grid.xyz"));
    previewer().exportGrid(vtm);
    previewer().exportGrid(xyz);
    QVERIFY(QFileInfo::exists(vtm));
    QVERIFY(QFileInfo(dir.filePath(QStringLiteral("grid"))).isDir());
    QFile f(vtm);
    QVERIFY(f.open(QIODevice::ReadOnly));
    const QByteArray text = f.readAll();
    QVERIFY(text.contains("control_grid"));
    QFile piece(QDir(dir.filePath(QStringLiteral("grid")))
                    .filePath(QDir(dir.filePath(QStringLiteral("grid")))
                                  .entryList({QStringLiteral("grid_*.vts")})
                                  .value(0)));
    QVERIFY(piece.open(QIODevice::ReadOnly));
    const QByteArray vts = piece.readAll();
    QVERIFY(vts.contains("scaled_jacobian") && vts.contains("aspect_ratio"));
    const auto blocks = aero::mesh::readPlot3d(xyz.toStdString());
    QCOMPARE(blocks.size(), std::size_t{20});
    long nodes = 0;
    for (const auto& b : blocks) nodes += b.nodeCount();
    QCOMPARE(nodes, 98260L);
    QVERIFY(blocks[0].xyz == previewer().result()->grids[0].xyz);  // binary: bitwise
}

void MeshPreviewTest::tangledCellsAreReportedAndMarked() {
    // One elasticity increment for a large spanwise move of the outer station tangles cells
    // near the body (the CLI reports 44 of them): the preview must say so and mark them.
    aero::ui::Document& doc = window_->document();
    doc.undoStack()->undo();  // the moved lattice point
    panel().incrementsBox()->setValue(1);
    doc.setDesignValue(doc.model()->design().find("body.S5.ty"), 2.5);
    const State s = runPreview();
    QVERIFY2(s == State::Ready, stateName(s));
    const auto r = previewer().result();
    qInfo("tangled preview: %ld bad cells, min Jacobian %.3e", r->summary.nonPositiveJacobian,
          r->summary.minJacobian.min);
    QVERIFY(r->summary.nonPositiveJacobian > 0);
    QCOMPARE(window_->meshScene().markedCellCount(),
             static_cast<int>(r->summary.nonPositiveJacobian));
    QVERIFY(previewer().problem().contains(QStringLiteral("non-positive Jacobian")));
    const auto* problem = window_->findChild<QLabel*>(QStringLiteral("problemLabel"));
    QVERIFY(problem->isVisible());
    QVERIFY2(problem->text().contains(QStringLiteral("non-positive")), qPrintable(problem->text()));
    QVERIFY(panel().summaryLabel()->text().contains(QStringLiteral("non-positive Jacobian")));
    QCOMPARE(panel().worstCellTable()->item(0, 2)->foreground().color(), QColor(0xb0, 0x00, 0x20));
    const QImage shot = renderNow();
    QVERIFY(shot.save(kScreenshotDir + QStringLiteral("/mesh_preview_tangled.png")));
    QVERIFY(
        window_->grab().save(kScreenshotDir + QStringLiteral("/mesh_preview_tangled_window.png")));
    QVERIFY2(redShare(shot) > 0.0002, "the tangled cells are not marked in red");

    // Back to a valid state: the problem goes away with the preview.
    doc.undoStack()->undo();
    doc.undoStack()->undo();
    QCOMPARE(doc.caseFile().mesh.elasticity.increments, 6);
    QCOMPARE(previewer().state(), State::Outdated);
    QVERIFY(previewer().problem().isEmpty());
    QVERIFY(!problem->text().contains(QStringLiteral("non-positive")) || !problem->isVisible());
}

void MeshPreviewTest::cancelStopsThePreviewAndKeepsTheWindowUsable() {
    aero::ui::Document& doc = window_->document();
    // Something to move, in many increments so that the move is still running when cancelled.
    panel().incrementsBox()->setValue(30);
    doc.setDesignValue(doc.model()->design().find("body.S2.tx"), 0.2);
    action("actionMeshPreview")->trigger();
    QCOMPARE(previewer().state(), State::Running);
    QVERIFY(action("actionMeshCancel")->isEnabled());
    QCOMPARE(panel().previewButton()->text(), QStringLiteral("Cancel"));
    QVERIFY(!action("actionMeshPreview")->isEnabled());
    // Cancel during the elasticity move (the job reports its increments).
    QTRY_VERIFY_WITH_TIMEOUT(panel().statusText().contains(QStringLiteral("increment")), 30000);
    QVERIFY(
        window_->grab().save(kScreenshotDir + QStringLiteral("/mesh_preview_running_window.png")));
    QElapsedTimer latency;
    latency.start();
    QTest::mouseClick(panel().previewButton(), Qt::LeftButton);
    QTRY_COMPARE_WITH_TIMEOUT(previewer().state(), State::Cancelled, 30000);
    qInfo("cancelled %lld ms after the click", static_cast<long long>(latency.elapsed()));
    QVERIFY(!window_->jobs().busy());
    QVERIFY(previewer().result() == nullptr);
    QVERIFY(window_->meshScene().empty());
    QVERIFY(panel().statusText().contains(QStringLiteral("Cancelled")));
    QCOMPARE(panel().previewButton()->text(), QStringLiteral("Preview Mesh"));

    // The window goes on: actions, edits, undo and rendering.
    QVERIFY(action("actionMeshPreview")->isEnabled());
    QVERIFY(!action("actionExportGrid")->isEnabled());
    QVERIFY(window_->scene().surfacesVisible());
    doc.undoStack()->undo();
    QCOMPARE(doc.values()[static_cast<std::size_t>(doc.model()->design().find("body.S2.tx"))], 0.0);
    doc.undoStack()->undo();
    QCOMPARE(panel().increments(), 6);
    const int frames = window_->viewport()->renderedFrames();
    QVERIFY(!renderNow().isNull());
    QVERIFY(window_->viewport()->renderedFrames() > frames);
}

void MeshPreviewTest::failureIsReportedAndANewDocumentClearsThePreview() {
    // One patch of the half-sphere alone: its edges are neither shared nor on the symmetry
    // plane, so the grid cannot be generated (libcore throws; the job reports it).
    QTemporaryDir dir;
    aero::geometry::PatchSet one = aero::geometry::makeHalfSphere();
    one.patches.resize(1);
    one.names.resize(1);
    const QString path = dir.filePath(QStringLiteral("one_patch.json"));
    aero::io::writePatchSetJson(one, path.toStdString());
    QString error;
    QVERIFY2(window_->loadFile(path, &error), qPrintable(error));
    QCOMPARE(previewer().state(), State::None);
    const State s = runPreview();
    QVERIFY2(s == State::Failed, stateName(s));
    qInfo("failure: %s", qPrintable(previewer().error()));
    QVERIFY(!previewer().error().isEmpty());
    QVERIFY(panel().statusText().startsWith(QStringLiteral("Failed")));
    QVERIFY(window_->meshScene().empty());
    QVERIFY(action("actionMeshPreview")->isEnabled());

    // A ready preview goes away with its document.
    QVERIFY2(window_->loadSample(&error), qPrintable(error));
    QCOMPARE(runPreview(), State::Ready);
    QVERIFY(!window_->scene().surfacesVisible());
    QVERIFY2(window_->loadSample(&error), qPrintable(error));
    QCOMPARE(previewer().state(), State::None);
    QVERIFY(window_->meshScene().empty());
    QVERIFY2(window_->scene().surfacesVisible(), "the geometry is shown again without a grid");
    QCOMPARE(window_->modelTree().geometryItem()->checkState(0), Qt::Checked);
}

int runMeshPreviewTest(int argc, char** argv, bool canRender) {
    MeshPreviewTest test(canRender);
    return QTest::qExec(&test, argc, argv);
}

#include "MeshPreviewTest.moc"
