// The patch scene with trimmed patches: IGES and STEP files opened through the window show a
// trimmed patch only inside its trim loops (no triangle in its hole, the drawn area that of the
// trimmed surface, the trim loops as its edges), an untrimmed one as its full grid; a
// deformation moves the points of a trimmed patch without changing its tessellation.
#include <vtkRenderer.h>

#include <QDir>
#include <QImage>
#include <QTemporaryDir>
#include <QTest>
#include <cmath>
#include <memory>
#include <numbers>

#include "Document.h"
#include "MainWindow.h"
#include "PatchScene.h"
#include "UiTestSupport.h"
#include "VtkViewport.h"
#include "cad/Iges.h"
#include "cad/Step.h"
#include "geometry/PatchSet.h"
#include "geometry/Trim.h"

using aero::ui::MainWindow;
using namespace aero::uitest;

namespace {

/// The plane z = 0 over [x0, x0 + 2] x [0, 1], parameters [0, 1]^2 (x = x0 + 2u, y = v).
aero::geometry::Patch plane(double x0) {
    aero::geometry::Patch p;
    p.degreeU = p.degreeV = 1;
    p.countU = p.countV = 2;
    p.knotsU = p.knotsV = {0, 0, 1, 1};
    p.points = {x0, 0, 0, x0 + 2, 0, 0, x0, 1, 0, x0 + 2, 1, 0};
    return p;
}

/// A circle of radius r about (0.5, 0.5) in parameter space, clockwise (a hole).
aero::geometry::TrimCurve hole(double r) {
    aero::geometry::TrimCurve t;
    t.curve.degree = 2;
    t.curve.knots = {0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4};
    const double w = std::sqrt(0.5);
    const double px[] = {1, 1, 0, -1, -1, -1, 0, 1, 1}, py[] = {0, -1, -1, -1, 0, 1, 1, 1, 0};
    for (int k = 0; k < 9; ++k) {
        t.curve.points.insert(t.curve.points.end(), {0.5 + r * px[k], 0.5 + r * py[k], 0.0});
        t.curve.weights.push_back(k % 2 ? w : 1.0);
    }
    t.first = 0;
    t.last = 4;
    return t;
}

/// Patch 1: the plane trimmed to [0.1, 0.9]^2 minus a circle of radius 0.2; patch 2: an untrimmed
/// plane beside it. In metres.
aero::geometry::PatchSet trimmedPlanes() {
    aero::geometry::PatchSet set;
    set.unit = "m";
    set.patches = {plane(0), plane(3)};
    set.names = {"trimmed", "whole"};
    set.trims.resize(2);
    set.trims[0].outer = aero::geometry::rectangleLoop(0.1, 0.9, 0.1, 0.9);
    set.trims[0].holes.push_back({{hole(0.2)}});
    aero::geometry::validate(set);
    return set;
}

double triangleArea(const std::vector<double>& x, int a, int b, int c) {
    const double ux = x[3 * b] - x[3 * a], uy = x[3 * b + 1] - x[3 * a + 1],
                 uz = x[3 * b + 2] - x[3 * a + 2];
    const double vx = x[3 * c] - x[3 * a], vy = x[3 * c + 1] - x[3 * a + 1],
                 vz = x[3 * c + 2] - x[3 * a + 2];
    return 0.5 * std::sqrt(std::pow(uy * vz - uz * vy, 2) + std::pow(uz * vx - ux * vz, 2) +
                           std::pow(ux * vy - uy * vx, 2));
}

}  // namespace

class PatchSceneTest : public QObject {
    Q_OBJECT

  public:
    explicit PatchSceneTest(bool canRender) : canRender_(canRender) {}

  private slots:
    void initTestCase() {
        if (!canRender_)
            QSKIP(
                "test_ui needs an X display: DISPLAY is not set (or QT_QPA_PLATFORM is offscreen). "
                "Run it under xvfb-run -a -s \"-screen 0 1280x800x24\".");
        MainWindow::Options options;
        options.autosave = false;
        options.recentFiles = false;
        window_ = std::make_unique<MainWindow>(options);
        window_->resize(900, 600);
        window_->show();
        QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    }
    void cleanupTestCase() { window_.reset(); }

    void trimmedIgesAndStepAreShownTrimmed() {
        QTemporaryDir dir;
        QVERIFY(dir.isValid());
        const aero::geometry::PatchSet set = trimmedPlanes();
        const QString iges = dir.filePath(QStringLiteral("trimmed.igs")),
                      step = dir.filePath(QStringLiteral("trimmed.step"));
        aero::cad::writeIges(set, iges.toStdString());
        aero::cad::writeStep(set, step.toStdString());
        for (const QString& path : {iges, step}) {
            QString error;
            QVERIFY2(window_->loadFile(path, &error),
                     qPrintable(path + QStringLiteral(": ") + error));
            const aero::ui::PatchScene& scene = window_->scene();
            QCOMPARE(scene.patchCount(), 2);
            // The trimmed patch: every drawn point inside the outer loop and outside the hole
            // (up to the bisection's and the loops' polygon tolerance), the drawn area that of
            // the trimmed surface: 2 (0.8^2 - pi 0.2^2).
            const auto mesh = scene.surfaceMesh(0);
            QVERIFY(!mesh.triangles.empty());
            for (std::size_t k = 0; k < mesh.uv.size(); k += 2) {
                const double u = mesh.uv[k], v = mesh.uv[k + 1];
                QVERIFY2(u > 0.1 - 1e-9 && u < 0.9 + 1e-9 && v > 0.1 - 1e-9 && v < 0.9 + 1e-9,
                         "a point outside the outer loop");
                QVERIFY2(std::hypot(u - 0.5, v - 0.5) > 0.2 - 1e-3, "a point in the hole");
                QVERIFY(std::abs(mesh.points[3 * (k / 2)] - 2 * u) <
                        1e-6);  // the plane: x = 2u (VTK keeps floats)
            }
            double area = 0;
            for (std::size_t t = 0; t < mesh.triangles.size(); t += 3)
                area += triangleArea(mesh.points, mesh.triangles[t], mesh.triangles[t + 1],
                                     mesh.triangles[t + 2]);
            const double exact = 2 * (0.64 - std::numbers::pi * 0.04);
            QVERIFY2(std::abs(area - exact) < 2e-3 * exact,
                     qPrintable(QStringLiteral("area %1, expected %2").arg(area).arg(exact)));
            // Its edges are the two trim loops, the hole's on the circle.
            QCOMPARE(static_cast<int>(mesh.edges.size()), 2);
            for (std::size_t k = 0; k < mesh.edges[1].size(); k += 3) {
                const double u = mesh.edges[1][k] / 2, v = mesh.edges[1][k + 1];
                QVERIFY(std::abs(std::hypot(u - 0.5, v - 0.5) - 0.2) < 1e-6);
            }
            // The untrimmed patch: the full 33 x 33 grid and its four edges.
            const auto whole = scene.surfaceMesh(1);
            QCOMPARE(static_cast<int>(whole.points.size()), 3 * 33 * 33);
            QCOMPARE(static_cast<int>(whole.triangles.size()), 3 * 2 * 32 * 32);
            QCOMPARE(static_cast<int>(whole.edges.size()), 4);
        }
        const QImage shot = window_->viewport()->grabImage();
        QVERIFY(shot.save(kScreenshotDir + QStringLiteral("/trimmed_patches.png")));

        // Exported from the window's document to STEP and read back: the unit and the trim kept.
        const QString exported = dir.filePath(QStringLiteral("exported.stp"));
        window_->document().exportGeometry(exported);
        const aero::geometry::PatchSet back = aero::cad::readStep(exported.toStdString());
        QCOMPARE(back.unit, std::string("m"));
        QCOMPARE(back.size(), 2);
        QVERIFY(back.trimmed(0));
        QVERIFY(!back.trimmed(1));
        QCOMPARE(back.patches[1].points, set.patches[1].points);
    }

    void deformationKeepsTheTessellation() {
        const auto viewport = std::make_unique<aero::ui::VtkViewport>();
        aero::ui::PatchScene scene(viewport->renderer());
        aero::geometry::PatchSet set = trimmedPlanes();
        scene.setPatchSet(set);
        const auto before = scene.surfaceMesh(0);
        for (std::size_t k = 2; k < set.patches[0].points.size(); k += 3)
            set.patches[0].points[k] += 0.5;  // lift it
        scene.updatePatches(set, {0});
        const auto after = scene.surfaceMesh(0);
        QCOMPARE(after.uv, before.uv);
        QCOMPARE(after.triangles, before.triangles);
        for (std::size_t k = 2; k < after.points.size(); k += 3) QCOMPARE(after.points[k], 0.5);
        // Another trim is another layout: the scene is rebuilt.
        set.trims[0].holes.clear();
        scene.updatePatches(set, {0});
        QVERIFY(scene.surfaceMesh(0).triangles.size() > before.triangles.size());
    }

  private:
    bool canRender_;
    std::unique_ptr<MainWindow> window_;
};

int runPatchSceneTest(int argc, char** argv, bool canRender) {
    PatchSceneTest test(canRender);
    return QTest::qExec(&test, argc, argv);
}

#include "PatchSceneTest.moc"
