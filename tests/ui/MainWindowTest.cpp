// Qt Test of the main window: renders the half-sphere sample through our QOpenGLWidget host,
// saves screenshots (build tree: tests/ui/screenshots/) and checks what the picture holds.
#include <vtkCamera.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include <QAction>
#include <QApplication>
#include <QDir>
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
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "MainWindow.h"
#include "PatchScene.h"
#include "VtkViewport.h"
#include "cad/Iges.h"
#include "geometry/HalfSphere.h"
#include "io/PatchSetJson.h"

using aero::ui::MainWindow;

namespace {

const QString kScreenshotDir = QStringLiteral(AEROFORM_UI_SCREENSHOT_DIR);

struct PixelStats {
    double differingShare = 0;  // share of pixels that differ from the reference
    double meanLuma = 0;        // over the differing pixels
    double lumaStdDev = 0;      // over the differing pixels (shading varies across a sphere)
};

int luma(QRgb c) {
    return (299 * qRed(c) + 587 * qGreen(c) + 114 * qBlue(c)) / 1000;
}

// Compares two frames of the same size pixel by pixel; a pixel "differs" when any channel
// differs by more than `tolerance`.
PixelStats compare(const QImage& image, const QImage& reference, int tolerance = 24) {
    PixelStats s;
    const QImage a = image.convertToFormat(QImage::Format_RGB32);
    const QImage b = reference.convertToFormat(QImage::Format_RGB32);
    long long count = 0;
    double sum = 0, sum2 = 0;
    for (int y = 0; y < a.height(); ++y) {
        const auto* ra = reinterpret_cast<const QRgb*>(a.constScanLine(y));
        const auto* rb = reinterpret_cast<const QRgb*>(b.constScanLine(y));
        for (int x = 0; x < a.width(); ++x) {
            const int d = std::max({std::abs(qRed(ra[x]) - qRed(rb[x])),
                                    std::abs(qGreen(ra[x]) - qGreen(rb[x])),
                                    std::abs(qBlue(ra[x]) - qBlue(rb[x]))});
            if (d > tolerance) {
                ++count;
                const double l = luma(ra[x]);
                sum += l;
                sum2 += l * l;
            }
        }
    }
    const double n = static_cast<double>(a.width()) * a.height();
    s.differingShare = n > 0 ? static_cast<double>(count) / n : 0;
    if (count > 0) {
        s.meanLuma = sum / static_cast<double>(count);
        s.lumaStdDev =
            std::sqrt(std::max(0.0, sum2 / static_cast<double>(count) - s.meanLuma * s.meanLuma));
    }
    return s;
}

std::array<double, 3> cameraPosition(MainWindow& w) {
    std::array<double, 3> p{};
    w.viewport()->renderer()->GetActiveCamera()->GetPosition(p.data());
    return p;
}

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
}

void sendMouse(QWidget* w, QEvent::Type type, QPointF pos, Qt::MouseButton button,
               Qt::MouseButtons buttons) {
    QMouseEvent e(type, pos, w->mapToGlobal(pos), button, buttons, Qt::NoModifier);
    QApplication::sendEvent(w, &e);
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
    window_ = std::make_unique<MainWindow>();
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

int main(int argc, char** argv) {
    // Without an X display QApplication could not even start on xcb; start it offscreen then
    // (no OpenGL widget is created) and let initTestCase skip with a clear message.
    const QByteArray platform = qgetenv("QT_QPA_PLATFORM");
    const bool canRender = !qEnvironmentVariableIsEmpty("DISPLAY") &&
                           !platform.startsWith("offscreen") && !platform.startsWith("minimal");
    if (!canRender) qputenv("QT_QPA_PLATFORM", "offscreen");
    QSurfaceFormat::setDefaultFormat(aero::ui::VtkViewport::defaultFormat());
    QApplication app(argc, argv);
    MainWindowTest test(canRender);
    return QTest::qExec(&test, argc, argv);
}

#include "MainWindowTest.moc"
