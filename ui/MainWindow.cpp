#include "MainWindow.h"

#include <vtkCamera.h>
#include <vtkRenderer.h>

#include <QAction>
#include <QApplication>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QImage>
#include <QKeySequence>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QStatusBar>
#include <array>
#include <exception>

#include "PatchScene.h"
#include "VtkViewport.h"
#include "cad/Iges.h"
#include "common/Error.h"
#include "geometry/HalfSphere.h"
#include "geometry/PatchSet.h"
#include "io/PatchSetJson.h"

namespace aero::ui {

namespace {

const char* const kAppName = "Aeroform";

}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
    viewport_ = new VtkViewport(this);
    viewport_->setObjectName(QStringLiteral("viewport"));
    setCentralWidget(viewport_);
    scene_ = std::make_unique<PatchScene>(viewport_->renderer());

    summaryLabel_ = new QLabel(this);
    summaryLabel_->setObjectName(QStringLiteral("summaryLabel"));
    statusBar()->addPermanentWidget(summaryLabel_);
    updateSummary();

    createMenus();
    setWindowTitle(QString::fromLatin1(kAppName));
    resetCamera();
}

MainWindow::~MainWindow() {
    // Removing the scene's actors releases their GL objects: do it in the viewport's context
    // (which is still alive; the viewport, a child widget, is destroyed after this body).
    viewport_->makeCurrent();
    scene_.reset();
    viewport_->doneCurrent();
}

void MainWindow::createMenus() {
    QMenu* file = menuBar()->addMenu(tr("&File"));
    QAction* open = file->addAction(tr("&Open..."), this, &MainWindow::chooseAndOpen);
    open->setObjectName(QStringLiteral("actionOpen"));
    open->setShortcut(QKeySequence::Open);
    QAction* sample =
        file->addAction(tr("Open &Sample (Half-Sphere)"), this, [this] { openSample(); });
    sample->setObjectName(QStringLiteral("actionOpenSample"));
    file->addSeparator();
    QAction* shot =
        file->addAction(tr("Save Screens&hot..."), this, &MainWindow::chooseAndSaveScreenshot);
    shot->setObjectName(QStringLiteral("actionSaveScreenshot"));
    shot->setShortcut(QKeySequence(tr("Ctrl+Shift+S")));
    file->addSeparator();
    QAction* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
    quit->setObjectName(QStringLiteral("actionQuit"));
    quit->setShortcut(QKeySequence::Quit);
    quit->setMenuRole(QAction::QuitRole);

    QMenu* view = menuBar()->addMenu(tr("&View"));
    auto toggle = [&](const QString& text, const char* name, bool on, auto apply) {
        QAction* a = view->addAction(text);
        a->setObjectName(QString::fromLatin1(name));
        a->setCheckable(true);
        a->setChecked(on);
        connect(a, &QAction::toggled, this, [this, apply](bool checked) {
            apply(checked);
            viewport_->requestRender();
        });
        return a;
    };
    toggle(tr("&Surfaces"), "actionSurfaces", scene_->surfacesVisible(),
           [this](bool on) { scene_->setSurfacesVisible(on); });
    toggle(tr("Patch &Edges"), "actionPatchEdges", scene_->edgesVisible(),
           [this](bool on) { scene_->setEdgesVisible(on); });
    toggle(tr("&Control Nets"), "actionControlNets", scene_->controlNetsVisible(),
           [this](bool on) { scene_->setControlNetsVisible(on); });
    toggle(tr("Orientation &Axes"), "actionOrientationAxes", viewport_->orientationAxesVisible(),
           [this](bool on) { viewport_->setOrientationAxesVisible(on); });
    view->addSeparator();
    QAction* reset = view->addAction(tr("&Reset Camera"), this, [this] {
        resetCamera();
        viewport_->requestRender();
    });
    reset->setObjectName(QStringLiteral("actionResetCamera"));
    reset->setShortcut(QKeySequence(tr("Ctrl+R")));
}

QString MainWindow::summary() const {
    if (scene_->empty()) return tr("No geometry");
    const int n = scene_->patchCount(), m = scene_->controlPointCount();
    return QStringLiteral("%1 %2, %3 %4")
        .arg(n)
        .arg(n == 1 ? tr("patch") : tr("patches"))
        .arg(m)
        .arg(m == 1 ? tr("control point") : tr("control points"));
}

void MainWindow::updateSummary() {
    summaryLabel_->setText(summary());
}

bool MainWindow::load(const std::function<geometry::PatchSet()>& read, const QString& title,
                      QString* error) {
    try {
        const geometry::PatchSet set = read();
        scene_->setPatchSet(set);
    } catch (const aero::Error& e) {
        if (error) *error = QString::fromStdString(e.what());
        return false;
    } catch (const std::exception& e) {  // not expected from libcore, but never let it escape
        if (error) *error = tr("Unexpected error: %1").arg(QString::fromStdString(e.what()));
        return false;
    }
    setWindowTitle(QStringLiteral("%1 \u2014 %2").arg(title, QString::fromLatin1(kAppName)));
    updateSummary();
    resetCamera();
    viewport_->requestRender();
    return true;
}

bool MainWindow::loadFile(const QString& path, QString* error) {
    const QFileInfo info(path);
    const QString suffix = info.suffix().toLower();
    const std::string file = QFile::encodeName(path).toStdString();
    std::function<geometry::PatchSet()> read;
    if (suffix == QLatin1String("json")) {
        read = [file] { return io::readPatchSetJson(file); };
    } else if (suffix == QLatin1String("igs") || suffix == QLatin1String("iges")) {
        read = [this, file] {
            cad::IgesReadReport report;
            geometry::PatchSet set = cad::readIges(file, &report);
            if (!report.warnings.empty() || report.converted > 0 || report.trimmed > 0)
                statusBar()->showMessage(
                    tr("IGES: %1 faces, %2 converted to B-splines, %3 trimmed (untrimmed "
                       "surface shown), %4 warnings")
                        .arg(report.faces)
                        .arg(report.converted)
                        .arg(report.trimmed)
                        .arg(static_cast<int>(report.warnings.size())),
                    10000);
            return set;
        };
    } else {
        if (error)
            *error = tr("'%1': unsupported file type (expected .json, .igs or .iges)").arg(path);
        return false;
    }
    if (!load(read, info.fileName(), error)) return false;
    lastDirectory_ = info.absolutePath();
    return true;
}

bool MainWindow::loadSample(QString* error) {
    return load([] { return geometry::makeHalfSphere(); }, tr("Half-sphere (sample)"), error);
}

bool MainWindow::openFile(const QString& path) {
    QString error;
    if (loadFile(path, &error)) return true;
    QMessageBox::critical(this, tr("Cannot open file"), error);
    return false;
}

bool MainWindow::openSample() {
    QString error;
    if (loadSample(&error)) return true;
    QMessageBox::critical(this, tr("Cannot create the sample"), error);
    return false;
}

void MainWindow::chooseAndOpen() {
    const QString path = QFileDialog::getOpenFileName(
        this, tr("Open Patch Set"), lastDirectory_,
        tr("Patch sets (*.json *.igs *.iges *.IGS *.IGES);;Aeroform JSON (*.json);;"
           "IGES (*.igs *.iges *.IGS *.IGES);;All files (*)"));
    if (!path.isEmpty()) openFile(path);
}

bool MainWindow::saveScreenshot(const QString& path, QString* error) {
    const QImage image = viewport_->grabImage();
    if (image.isNull()) {
        if (error) *error = tr("The viewport has not been rendered yet.");
        return false;
    }
    if (!image.save(path)) {
        if (error) *error = tr("Cannot write '%1'.").arg(path);
        return false;
    }
    return true;
}

void MainWindow::chooseAndSaveScreenshot() {
    const QString path =
        QFileDialog::getSaveFileName(this, tr("Save Screenshot"), lastDirectory_,
                                     tr("PNG image (*.png);;JPEG image (*.jpg *.jpeg)"));
    if (path.isEmpty()) return;
    QString error;
    if (saveScreenshot(path, &error))
        statusBar()->showMessage(tr("Saved %1").arg(path), 5000);
    else
        QMessageBox::critical(this, tr("Cannot save screenshot"), error);
}

void MainWindow::resetCamera() {
    vtkRenderer* ren = viewport_->renderer();
    vtkCamera* cam = ren->GetActiveCamera();
    // Oblique view from upstream (-X), the +Y side and above; X streamwise, Z up.
    const std::array<double, 3> direction{1.0, -1.35, -0.75}, up{0.0, 0.0, 1.0};
    cam->SetViewAngle(30.0);
    if (scene_->empty()) {
        cam->SetFocalPoint(0, 0, 0);
        cam->SetPosition(-direction[0] * 4, -direction[1] * 4, -direction[2] * 4);
        cam->SetViewUp(up.data());
    } else {
        const double aspect =
            viewport_->height() > 0 ? double(viewport_->width()) / viewport_->height() : 1.0;
        scene_->fitCamera(cam, aspect, direction, up, 0.9);
    }
    ren->ResetCameraClippingRange();
}

}  // namespace aero::ui
