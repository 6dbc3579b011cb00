#include "MainWindow.h"

#include <vtkCamera.h>
#include <vtkRenderer.h>

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDir>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QImage>
#include <QKeySequence>
#include <QFontMetrics>
#include <QLabel>
#include <QLocale>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QSettings>
#include <QStatusBar>
#include <QStyle>
#include <QToolBar>
#include <QToolButton>
#include <QUndoStack>
#include <QUrl>
#include <array>
#include <cmath>
#include <exception>

#include "Autosave.h"
#include "BackgroundJob.h"
#include "DesignVariablePanel.h"
#include "Document.h"
#include "LatticeDialog.h"
#include "LatticeEditor.h"
#include "LatticeScene.h"
#include "MeshPanel.h"
#include "MeshPreviewer.h"
#include "MeshScene.h"
#include "ModelTree.h"
#include "OverlayScene.h"
#include "PatchScene.h"
#include "PropertyPanel.h"
#include "Selection.h"
#include "Text.h"
#include "VtkViewport.h"
#include "common/Error.h"
#include "io/CaseFile.h"

namespace aero::ui {

namespace {

const char* const kAppName = "Aeroform";
const char* const kRecentKey = "recentFiles";
constexpr int kMaxRecent = 8;
constexpr int kArrowSamples = 7;  // sensitivity arrows per patch and direction

bool supportedSuffix(const QString& path) {
    const QString s = QFileInfo(path).suffix().toLower();
    return s == QLatin1String("json") || s == QLatin1String("igs") || s == QLatin1String("iges") || s == QLatin1String("stp") ||
           s == QLatin1String("step");
}

}  // namespace

MainWindow::MainWindow(QWidget* parent) : MainWindow(Options{}, parent) {}

MainWindow::MainWindow(const Options& options, QWidget* parent) : QMainWindow(parent), options_(options) {
    document_ = new Document(this);
    selection_ = new Selection(this);
    jobs_ = new BackgroundJob(this);

    viewport_ = new VtkViewport(this);
    viewport_->setObjectName(QStringLiteral("viewport"));
    setCentralWidget(viewport_);
    scene_ = std::make_unique<PatchScene>(viewport_->renderer());
    lattices_ = std::make_unique<LatticeScene>(viewport_->renderer());
    overlay_ = std::make_unique<OverlayScene>(viewport_->renderer());
    meshScene_ = std::make_unique<MeshScene>(viewport_->renderer());
    editor_ = new LatticeEditor(viewport_, document_, selection_, lattices_.get(), this);

    createDocks();
    createStatusBar();
    // After the status bar: the previewer's messages about a finished job come after the
    // generic "done" of the job (same signal, later connection).
    previewer_ = new MeshPreviewer(document_, jobs_, viewport_, meshScene_.get(), meshPanel_, this);
    createMenus();
    connectDocument();
    if (options_.autosave) {
        autosaver_ = new Autosaver(document_,
                                   options_.autosaveDirectory.isEmpty() ? Autosaver::defaultDirectory()
                                                                        : options_.autosaveDirectory,
                                   options_.autosaveIntervalMs, this);
        connect(autosaver_, &Autosaver::failed, this, [this](const QString& m) { statusBar()->showMessage(m, 10000); });
    }
    setAcceptDrops(true);
    updateTitle();
    updateSummary();
    updateActions();
    resetCamera();
}

MainWindow::~MainWindow() {
    // Removing the scenes' actors releases their GL objects: do it in the viewport's context
    // (which is still alive; the viewport, a child widget, is destroyed after this body).
    viewport_->makeCurrent();
    meshScene_.reset();
    overlay_.reset();
    lattices_.reset();
    scene_.reset();
    viewport_->doneCurrent();
}

// ---- Layout -------------------------------------------------------------------------------------

void MainWindow::createDocks() {
    setDockOptions(QMainWindow::AnimatedDocks | QMainWindow::AllowTabbedDocks);
    tree_ = new ModelTree(document_, selection_, this);
    auto* treeDock = new QDockWidget(tr("Model"), this);
    treeDock->setObjectName(QStringLiteral("modelDock"));
    treeDock->setWidget(tree_);
    addDockWidget(Qt::LeftDockWidgetArea, treeDock);

    properties_ = new PropertyPanel(document_, selection_, this);
    auto* scroll = new QScrollArea(this);
    scroll->setWidget(properties_);
    scroll->setWidgetResizable(true);
    scroll->setFrameShape(QFrame::NoFrame);
    scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);  // the panel wraps to the dock's width
    auto* propDock = new QDockWidget(tr("Properties"), this);
    propDock->setObjectName(QStringLiteral("propertiesDock"));
    propDock->setWidget(scroll);
    addDockWidget(Qt::LeftDockWidgetArea, propDock);
    splitDockWidget(treeDock, propDock, Qt::Vertical);

    variables_ = new DesignVariablePanel(document_, this);
    auto* varDock = new QDockWidget(tr("Design Variables"), this);
    varDock->setObjectName(QStringLiteral("designVariablesDock"));
    varDock->setWidget(variables_);
    addDockWidget(Qt::RightDockWidgetArea, varDock);

    meshPanel_ = new MeshPanel(this);
    auto* meshScroll = new QScrollArea(this);
    meshScroll->setWidget(meshPanel_);
    meshScroll->setWidgetResizable(true);
    meshScroll->setFrameShape(QFrame::NoFrame);
    meshScroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    auto* meshDock = new QDockWidget(tr("Mesh Quality"), this);
    meshDock->setObjectName(QStringLiteral("meshQualityDock"));
    meshDock->setWidget(meshScroll);
    addDockWidget(Qt::RightDockWidgetArea, meshDock);
    tabifyDockWidget(varDock, meshDock);
    varDock->raise();

    resizeDocks({treeDock, varDock}, {260, 300}, Qt::Horizontal);
    resizeDocks({treeDock, propDock}, {200, 420}, Qt::Vertical);

    connect(tree_, &ModelTree::geometryVisibilityChanged, this, [this](bool on) {
        if (!settingGeometry_) geometryHiddenForGrid_ = false;  // the user's choice from now on
        scene_->setSurfacesVisible(on);
        scene_->setEdgesVisible(on && findChild<QAction*>(QStringLiteral("actionPatchEdges"))->isChecked());
        findChild<QAction*>(QStringLiteral("actionSurfaces"))->setChecked(on);
        viewport_->requestRender();
    });
    connect(tree_, &ModelTree::patchVisibilityChanged, this, [this](int p, bool on) {
        scene_->setPatchVisible(p, on);
        updateSensitivity();
        viewport_->requestRender();
    });
    connect(tree_, &ModelTree::latticesVisibilityChanged, this, [this](bool on) { latticesAction_->setChecked(on); });
    connect(tree_, &ModelTree::latticeVisibilityChanged, this, [this](int l, bool on) {
        lattices_->setLatticeVisible(l, on);
        viewport_->requestRender();
    });
    connect(tree_, &ModelTree::gridVisibilityChanged, this, &MainWindow::applyGridVisibility);
}

void MainWindow::createStatusBar() {
    problemLabel_ = new QLabel(this);
    problemLabel_->setObjectName(QStringLiteral("problemLabel"));
    problemLabel_->setStyleSheet(QStringLiteral("QLabel { color: #b00020; font-weight: bold; }"));
    problemLabel_->setTextFormat(Qt::PlainText);
    problemLabel_->hide();
    statusBar()->addPermanentWidget(problemLabel_, 1);

    jobProgress_ = new QProgressBar(this);
    jobProgress_->setMaximumWidth(160);
    jobProgress_->setRange(0, 100);
    jobProgress_->hide();
    jobCancel_ = new QToolButton(this);
    jobCancel_->setText(tr("Cancel"));
    jobCancel_->hide();
    statusBar()->addPermanentWidget(jobProgress_);
    statusBar()->addPermanentWidget(jobCancel_);
    connect(jobCancel_, &QToolButton::clicked, jobs_, &BackgroundJob::cancel);
    connect(jobs_, &BackgroundJob::started, this, [this](const QString& title) {
        jobProgress_->setRange(0, 0);
        jobProgress_->setFormat(title);
        jobProgress_->show();
        jobCancel_->show();
        statusBar()->showMessage(title);
    });
    connect(jobs_, &BackgroundJob::progress, this, [this](double fraction, const QString& text) {
        if (fraction >= 0) {
            jobProgress_->setRange(0, 100);
            jobProgress_->setValue(static_cast<int>(std::lround(100 * std::min(1.0, fraction))));
        }
        if (!text.isEmpty()) statusBar()->showMessage(text);
    });
    connect(jobs_, &BackgroundJob::finished, this, [this](bool ok, bool cancelled, const QString& error) {
        jobProgress_->hide();
        jobCancel_->hide();
        statusBar()->showMessage(ok ? tr("%1: done").arg(jobs_->title())
                                    : cancelled ? tr("%1: cancelled").arg(jobs_->title())
                                                : tr("%1 failed: %2").arg(jobs_->title(), error),
                                 8000);
    });

    summaryLabel_ = new QLabel(this);
    summaryLabel_->setObjectName(QStringLiteral("summaryLabel"));
    statusBar()->addPermanentWidget(summaryLabel_);
    connect(editor_, &LatticeEditor::message, this, [this](const QString& text) {
        if (text.isEmpty())
            statusBar()->clearMessage();
        else
            statusBar()->showMessage(text, 6000);
    });
}

void MainWindow::createMenus() {
    const QStyle* style = QApplication::style();
    auto named = [](QAction* a, const char* name) {
        a->setObjectName(QString::fromLatin1(name));
        return a;
    };

    // File.
    QMenu* file = menuBar()->addMenu(tr("&File"));
    file->setToolTipsVisible(true);
    QAction* open = named(file->addAction(style->standardIcon(QStyle::SP_DialogOpenButton), tr("&Open..."), this,
                                          &MainWindow::chooseAndOpen),
                          "actionOpen");
    open->setShortcut(QKeySequence::Open);
    open->setToolTip(tr("Open a project (.json case), an IGES or STEP file or a patch set"));
    recentMenu_ = file->addMenu(tr("Open &Recent"));
    recentMenu_->setObjectName(QStringLiteral("menuRecent"));
    connect(recentMenu_, &QMenu::aboutToShow, this, &MainWindow::fillRecentMenu);
    QMenu* samples = file->addMenu(tr("Open &Sample"));
    named(samples->addAction(tr("Half-Sphere with the Paper's &FFD Lattice"), this, [this] { openSample(true); }),
          "actionOpenSample");
    named(samples->addAction(tr("Half-Sphere &Geometry Only"), this, [this] { openSample(false); }),
          "actionOpenSampleGeometry");
    file->addSeparator();
    saveAction_ = named(file->addAction(style->standardIcon(QStyle::SP_DialogSaveButton), tr("&Save"), this,
                                        [this] { save(); }),
                        "actionSave");
    saveAction_->setShortcut(QKeySequence::Save);
    QAction* saveAsAction = named(file->addAction(tr("Save &As..."), this, [this] { saveAs(); }), "actionSaveAs");
    saveAsAction->setShortcut(QKeySequence::SaveAs);
    needsGeometry_.push_back(saveAsAction);
    QMenu* exportMenu = file->addMenu(tr("&Export"));
    exportMenu->setToolTipsVisible(true);
    needsGeometry_.push_back(named(exportMenu->addAction(tr("Deformed &Geometry (IGES, STEP, JSON)..."), this,
                                                         &MainWindow::exportGeometry),
                                   "actionExportGeometry"));
    needsGeometry_.push_back(named(exportMenu->addAction(tr("Geometry for &ParaView (VTK)..."), this, &MainWindow::exportVtk),
                                   "actionExportVtk"));
    exportGridAction_ = named(exportMenu->addAction(tr("G&rid (VTK, Plot3D)..."), this, &MainWindow::exportGrid),
                              "actionExportGrid");
    exportGridAction_->setToolTip(tr("The previewed grid: VTK multiblock with the quality fields, or Plot3D"));
    QAction* shot = named(exportMenu->addAction(tr("Screens&hot (PNG)..."), this, &MainWindow::chooseAndSaveScreenshot),
                          "actionSaveScreenshot");
    shot->setShortcut(QKeySequence(tr("Ctrl+Alt+S")));
    file->addSeparator();
    QAction* quit = named(file->addAction(tr("&Quit"), this, &QWidget::close), "actionQuit");
    quit->setShortcut(QKeySequence::Quit);
    quit->setMenuRole(QAction::QuitRole);

    // Edit.
    QMenu* edit = menuBar()->addMenu(tr("&Edit"));
    QAction* undo = named(document_->undoStack()->createUndoAction(this, tr("&Undo")), "actionUndo");
    undo->setShortcut(QKeySequence::Undo);
    undo->setIcon(style->standardIcon(QStyle::SP_ArrowBack));
    QAction* redo = named(document_->undoStack()->createRedoAction(this, tr("&Redo")), "actionRedo");
    redo->setShortcut(QKeySequence::Redo);
    redo->setIcon(style->standardIcon(QStyle::SP_ArrowForward));
    edit->addAction(undo);
    edit->addAction(redo);
    edit->addSeparator();
    named(edit->addAction(tr("Select All Lattice Points"), this,
                          [this] {
                              int l = selection_->lattice();
                              if (l < 0 && document_->latticeCount() > 0) l = 0;
                              if (l < 0) return;
                              std::vector<int> all(static_cast<std::size_t>(document_->lattices()[static_cast<std::size_t>(l)].controlCount()));
                              for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
                              selection_->selectPoints(l, std::move(all));
                          }),
          "actionSelectAllPoints")
        ->setShortcut(QKeySequence(tr("Ctrl+Shift+A")));
    resetPointsAction_ = named(edit->addAction(tr("Reset Selected Lattice Points"), this,
                                               [this] {
                                                   document_->resetLatticePoints(selection_->lattice(), selection_->points());
                                               }),
                               "actionResetPoints");
    resetPointsAction_->setShortcut(QKeySequence(Qt::Key_Delete));
    resetPointsAction_->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    viewport_->addAction(resetPointsAction_);
    named(edit->addAction(tr("Reset Design Variables"), document_, &Document::resetDesignValues), "actionResetVariables");

    // View.
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
    toggle(tr("&Surfaces"), "actionSurfaces", scene_->surfacesVisible(), [this](bool on) {
        scene_->setSurfacesVisible(on);
    });
    toggle(tr("Patch &Edges"), "actionPatchEdges", scene_->edgesVisible(), [this](bool on) { scene_->setEdgesVisible(on); });
    toggle(tr("&Control Nets"), "actionControlNets", scene_->controlNetsVisible(),
           [this](bool on) { scene_->setControlNetsVisible(on); });
    latticesAction_ = toggle(tr("FFD &Lattices"), "actionLattices", lattices_->visible(), [this](bool on) {
        lattices_->setVisible(on);
        if (tree_->latticesItem()->checkState(0) != (on ? Qt::Checked : Qt::Unchecked))
            tree_->latticesItem()->setCheckState(0, on ? Qt::Checked : Qt::Unchecked);
    });
    latticesAction_->setShortcut(QKeySequence(tr("Ctrl+L")));
    sensitivityAction_ = toggle(tr("Sensitivity &Arrows"), "actionSensitivity", false, [this](bool on) {
        variables_->setSensitivityShown(on);
        updateSensitivity();
    });
    sensitivityAction_->setToolTip(tr("Arrows dS/dv of the selected design variable"));
    toggle(tr("Orientation A&xes"), "actionOrientationAxes", viewport_->orientationAxesVisible(),
           [this](bool on) { viewport_->setOrientationAxesVisible(on); });
    view->addSeparator();
    QAction* reset = view->addAction(tr("&Reset Camera"), this, [this] {
        resetCamera();
        viewport_->requestRender();
    });
    reset->setObjectName(QStringLiteral("actionResetCamera"));
    reset->setShortcut(QKeySequence(tr("Ctrl+R")));
    auto viewAction = [&](const QString& text, const char* name, const char* key, std::array<double, 3> dir,
                          std::array<double, 3> up) {
        QAction* a = view->addAction(text, this, [this, dir, up] {
            setView(dir, up);
            viewport_->requestRender();
        });
        a->setObjectName(QString::fromLatin1(name));
        a->setShortcut(QKeySequence(QString::fromLatin1(key)));
    };
    viewAction(tr("&Front (from upstream)"), "actionViewFront", "Ctrl+1", {1, 0, 0}, {0, 0, 1});
    viewAction(tr("S&ide (from +Y)"), "actionViewSide", "Ctrl+2", {0, -1, 0}, {0, 0, 1});
    viewAction(tr("&Top (planform)"), "actionViewTop", "Ctrl+3", {0, 0, -1}, {0, 1, 0});
    view->addSeparator();
    QMenu* panels = view->addMenu(tr("&Panels"));
    for (QDockWidget* dock : findChildren<QDockWidget*>()) panels->addAction(dock->toggleViewAction());
    connect(sensitivityAction_, &QAction::toggled, variables_, &DesignVariablePanel::setSensitivityShown);
    connect(variables_, &DesignVariablePanel::sensitivityToggled, sensitivityAction_, &QAction::setChecked);
    connect(variables_, &DesignVariablePanel::sensitivityToggled, this, [this] {
        updateSensitivity();
        viewport_->requestRender();
    });
    connect(variables_, &DesignVariablePanel::currentVariableChanged, this, [this] {
        updateSensitivity();
        viewport_->requestRender();
    });

    // FFD.
    QMenu* ffdMenu = menuBar()->addMenu(tr("F&FD"));
    QAction* add = named(ffdMenu->addAction(tr("&Add Lattice..."), this, &MainWindow::addLattice), "actionAddLattice");
    add->setShortcut(QKeySequence(tr("Ctrl+Shift+L")));
    add->setToolTip(tr("Place an FFD lattice around the geometry or the selected patches"));
    needsGeometry_.push_back(add);
    removeLatticeAction_ = named(ffdMenu->addAction(tr("&Remove Selected Lattice"), this,
                                                    [this] { document_->removeLattice(selection_->lattice()); }),
                                 "actionRemoveLattice");

    // Mesh: the preview runs as a worker-thread job (jobs_); MeshPreviewer drives it.
    QMenu* mesh = menuBar()->addMenu(tr("&Mesh"));
    mesh->setToolTipsVisible(true);
    meshPreviewAction_ = named(mesh->addAction(tr("&Preview"), this, &MainWindow::startMeshPreview), "actionMeshPreview");
    meshPreviewAction_->setShortcut(QKeySequence(tr("Ctrl+M")));
    meshPreviewAction_->setIconText(tr("Mesh Preview"));
    meshPreviewAction_->setToolTip(tr("Generate the volume grid at the case's level, move it to the deformed geometry "
                                      "and check its cells"));
    meshCancelAction_ = named(mesh->addAction(tr("&Cancel Preview"), previewer_, &MeshPreviewer::cancel),
                              "actionMeshCancel");
    meshClearAction_ = named(mesh->addAction(tr("C&lear Preview"), previewer_, &MeshPreviewer::clear), "actionMeshClear");
    mesh->addSeparator();
    QAction* qualityPanel = findChild<QDockWidget*>(QStringLiteral("meshQualityDock"))->toggleViewAction();
    qualityPanel->setText(tr("Mesh &Quality Panel"));
    mesh->addAction(qualityPanel);
    mesh->addAction(exportGridAction_);

    // Help.
    QMenu* help = menuBar()->addMenu(tr("&Help"));
    help->addAction(tr("&Mouse and Keys"), this, [this] {
        QMessageBox::information(
            this, tr("Mouse and Keys"),
            tr("<p><b>View</b>: left drag rotates, middle drag (or Shift+left) pans, the wheel zooms; Ctrl+R "
               "resets the camera, Ctrl+1/2/3 look from the front, side and top.</p>"
               "<p><b>Lattice points</b>: click to select, Ctrl+click to add or remove, drag to move in the "
               "view plane, Shift+drag to move along X, Y or Z, Esc cancels a drag; Delete resets the "
               "selected points. Exact coordinates go in the Properties panel.</p>"
               "<p><b>Design variables</b>: sliders and spin boxes in the Design Variables panel; a slider "
               "drag is one undo step.</p>"
               "<p><b>Mesh preview</b>: Ctrl+M generates the grid (level and increments in the Mesh Quality "
               "panel); the model tree's Grid blocks toggle the control grid, wall, symmetry plane and slice; "
               "click a worst cell to fly the camera to it.</p>"));
    });
    help->addAction(tr("&About Aeroform"), this, [this] {
        QMessageBox::about(this, tr("About Aeroform"),
                           tr("<p><b>Aeroform</b> %1</p><p>Aerodynamic shape design with the two-level free-form "
                              "deformation of Gagnon &amp; Zingg.</p>")
                               .arg(QApplication::applicationVersion()));
    });

    // Tool bar.
    QToolBar* bar = addToolBar(tr("Main"));
    bar->setObjectName(QStringLiteral("mainToolBar"));
    bar->setMovable(false);
    bar->setToolButtonStyle(Qt::ToolButtonTextBesideIcon);
    bar->addAction(open);
    bar->addAction(saveAction_);
    bar->addSeparator();
    // The tool bar's undo/redo keep short labels (the menu's say what they undo); the command
    // goes into the tooltip.
    auto* stack = document_->undoStack();
    QAction* undoTool = named(new QAction(undo->icon(), tr("Undo"), this), "toolUndo");
    QAction* redoTool = named(new QAction(redo->icon(), tr("Redo"), this), "toolRedo");
    connect(undoTool, &QAction::triggered, stack, &QUndoStack::undo);
    connect(redoTool, &QAction::triggered, stack, &QUndoStack::redo);
    connect(stack, &QUndoStack::canUndoChanged, undoTool, &QAction::setEnabled);
    connect(stack, &QUndoStack::canRedoChanged, redoTool, &QAction::setEnabled);
    connect(stack, &QUndoStack::undoTextChanged, undoTool, [undoTool](const QString& t) {
        undoTool->setToolTip(t.isEmpty() ? tr("Undo") : tr("Undo %1").arg(t));
    });
    connect(stack, &QUndoStack::redoTextChanged, redoTool, [redoTool](const QString& t) {
        redoTool->setToolTip(t.isEmpty() ? tr("Redo") : tr("Redo %1").arg(t));
    });
    undoTool->setEnabled(stack->canUndo());
    redoTool->setEnabled(stack->canRedo());
    bar->addAction(undoTool);
    bar->addAction(redoTool);
    bar->addSeparator();
    bar->addAction(add);
    bar->addAction(latticesAction_);
    bar->addAction(sensitivityAction_);
    bar->addAction(meshPreviewAction_);
    bar->addSeparator();
    bar->addAction(reset);
}

void MainWindow::connectDocument() {
    connect(document_, &Document::reset, this, &MainWindow::onReset);
    connect(document_, &Document::shapeChanged, this, &MainWindow::onShapeChanged);
    connect(document_, &Document::latticesMoved, this, [this] {
        updateLatticeScene();
        viewport_->requestRender();
    });
    connect(document_, &Document::structureChanged, this, [this] {
        // Lattices may have been removed or re-specified: indices of a point selection are stale.
        const int l = selection_->lattice();
        if (l >= document_->latticeCount())
            selection_->clear();
        else if (selection_->kind() == Selection::Kind::LatticePoints)
            selection_->selectLattice(l);
        updateSummary();
        updateSensitivity();
        updateActions();
    });
    connect(document_, &Document::diagnosticsChanged, this, &MainWindow::updateDiagnostics);
    connect(document_, &Document::modifiedChanged, this, &MainWindow::updateTitle);
    connect(document_, &Document::titleChanged, this, &MainWindow::updateTitle);
    connect(document_, &Document::valuesChanged, this, &MainWindow::updateActions);

    // Mesh preview.
    auto showMeshOptions = [this] {
        const io::MeshCase& m = document_->caseFile().mesh;
        meshPanel_->setOptions(QString::fromStdString(m.level), m.elasticity.increments);
    };
    connect(document_, &Document::reset, this, showMeshOptions);
    connect(document_, &Document::meshOptionsChanged, this, showMeshOptions);
    showMeshOptions();
    connect(meshPanel_, &MeshPanel::previewRequested, this, &MainWindow::startMeshPreview);
    connect(meshPanel_, &MeshPanel::cancelRequested, previewer_, &MeshPreviewer::cancel);
    connect(meshPanel_, &MeshPanel::optionsEdited, this, [this, showMeshOptions](const QString& level, int increments) {
        QString error;
        if (!guarded([&] { document_->setMeshOptions(level.toStdString(), increments); }, &error)) {
            showMeshOptions();
            QMessageBox::critical(this, tr("Cannot change the mesh options"), error);
        }
    });
    connect(meshPanel_, &MeshPanel::metricChanged, this, [this](QualityMetric m) {
        meshScene_->setMetric(m);
        viewport_->requestRender();
    });
    connect(meshPanel_, &MeshPanel::sliceChanged, this, [this](int k) {
        meshScene_->setSlice(k);
        // Moving the slider means "show me the slice".
        tree_->gridPartItem(ModelTree::SlicePart)->setCheckState(0, Qt::Checked);
        if (tree_->gridItem()->checkState(0) != Qt::Checked) tree_->gridItem()->setCheckState(0, Qt::Checked);
        viewport_->requestRender();
    });
    connect(meshPanel_, &MeshPanel::worstCellActivated, this, [this](int index) { previewer_->flyToWorstCell(index); });
    connect(previewer_, &MeshPreviewer::stateChanged, this, &MainWindow::onMeshPreviewStateChanged);
    connect(previewer_, &MeshPreviewer::message, this, [this](const QString& text, int timeoutMs) {
        statusBar()->showMessage(text, timeoutMs);
    });
    connect(jobs_, &BackgroundJob::started, this, &MainWindow::updateActions);
    connect(jobs_, &BackgroundJob::finished, this, &MainWindow::updateActions);
    meshScene_->setMetric(meshPanel_->metric());
    applyGridVisibility();
    connect(selection_, &Selection::changed, this, [this] {
        const bool points = selection_->kind() == Selection::Kind::LatticePoints;
        lattices_->setSelection(points ? selection_->lattice() : -1, selection_->points());
        scene_->setHighlightedPatches(selection_->kind() == Selection::Kind::Patches ? selection_->patches()
                                                                                      : std::vector<int>{});
        updateActions();
        viewport_->requestRender();
    });
}

// ---- Document -> scenes -------------------------------------------------------------------------

void MainWindow::onReset() {
    selection_->clear();
    try {
        if (document_->hasGeometry())
            scene_->setPatchSet(document_->shape());
        else
            scene_->clear();
    } catch (const aero::Error& e) {
        scene_->clear();
        statusBar()->showMessage(QString::fromStdString(e.what()), 10000);
    }
    for (int p = 0; p < scene_->patchCount(); ++p) scene_->setPatchVisible(p, true);
    updateLatticeScene();
    updateDiagnostics();
    updateSensitivity();
    updateSummary();
    updateTitle();
    updateActions();
    resetCamera();
    if (!document_->loadMessage().isEmpty()) statusBar()->showMessage(document_->loadMessage(), 10000);
    viewport_->requestRender();
}

void MainWindow::onShapeChanged(const QVector<int>& patches) {
    scene_->updatePatches(document_->shape(), std::vector<int>(patches.begin(), patches.end()));
    if (sensitivityAction_->isChecked()) updateSensitivity();
    viewport_->requestRender();
}

void MainWindow::updateLatticeScene() {
    const auto& moved = document_->lattices();
    const auto& reports = document_->injectivity();
    std::vector<LatticeView> views(moved.size());
    for (std::size_t l = 0; l < moved.size(); ++l) {
        views[l].lattice = moved[l];
        if (l < reports.size()) {
            views[l].injective = reports[l].injective;
            views[l].foldAt = reports[l].minPoint;
        }
    }
    for (const auto& d : document_->caseFile().displacements) {
        if (d.lattice < 0 || d.lattice >= static_cast<int>(views.size())) continue;
        const ffd::Lattice& L = views[static_cast<std::size_t>(d.lattice)].lattice;
        views[static_cast<std::size_t>(d.lattice)].displaced.push_back(L.index(d.index[0], d.index[1], d.index[2]));
    }
    lattices_->setLattices(std::move(views));
    const bool points = selection_->kind() == Selection::Kind::LatticePoints;
    lattices_->setSelection(points ? selection_->lattice() : -1, selection_->points());
    for (int l = 0; l < lattices_->latticeCount(); ++l) {
        const QTreeWidgetItem* item = tree_->latticeItem(l);
        if (item) lattices_->setLatticeVisible(l, item->checkState(0) == Qt::Checked);
    }
}

void MainWindow::updateDiagnostics() {
    overlay_->setFailedPoints(document_->failedPoints());
    QStringList problems = document_->problems();
    if (previewer_ && !previewer_->problem().isEmpty()) problems << previewer_->problem();
    if (problems.isEmpty()) {
        problemLabel_->clear();
        problemLabel_->setToolTip(QString());
        problemLabel_->hide();
    } else {
        QString text = QStringLiteral("\u26a0 ") + problems.front();
        if (problems.size() > 1) text += tr(" (+%1 more)").arg(problems.size() - 1);
        const QFontMetrics fm(problemLabel_->font());
        problemLabel_->setText(fm.elidedText(text, Qt::ElideRight, std::max(300, width() - 420)));
        problemLabel_->setToolTip(problems.join(QStringLiteral("\n\n")));
        problemLabel_->show();
    }
    viewport_->requestRender();
}

QString MainWindow::problemText() const {
    return document_->problems().join(QLatin1Char('\n'));
}

void MainWindow::updateSensitivity() {
    const int var = variables_->currentVariable();
    const ffd::FfdModel* model = document_->model();
    if (!sensitivityAction_->isChecked() || !model || var < 0 || var >= model->design().size()) {
        overlay_->clearArrows();
        variables_->setSensitivityNote(sensitivityAction_->isChecked() && model ? tr("Select a variable to see its arrows.")
                                                                                : QString());
        return;
    }
    const geometry::PatchSet derivative = document_->shapeDerivative(var);
    std::vector<char> hidden(static_cast<std::size_t>(scene_->patchCount()), 0);
    for (int p = 0; p < scene_->patchCount(); ++p) hidden[static_cast<std::size_t>(p)] = scene_->patchVisible(p) ? 0 : 1;
    std::vector<double> points, vectors;
    const double largest = sensitivityField(document_->shape(), derivative, kArrowSamples, hidden, points, vectors);
    const auto b = scene_->bounds();
    const double size = std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) + (b[5] - b[4]) * (b[5] - b[4]));
    const double length = 0.1 * size;
    overlay_->setArrows(points, vectors, length);
    const QString name = QString::fromStdString(model->design().variables()[static_cast<std::size_t>(var)].name);
    variables_->setSensitivityNote(
        largest > 0 ? tr("Arrows: dS/dv of %1; the longest is %2 (drawn %3 long).").arg(name).arg(largest, 0, 'g', 3).arg(length, 0, 'g', 2)
                    : tr("%1 does not move the surface.").arg(name));
}

void MainWindow::updateSummary() {
    summaryLabel_->setText(summary());
}

QString MainWindow::summary() const {
    if (scene_->empty()) return tr("No geometry");
    const int n = scene_->patchCount(), m = scene_->controlPointCount();
    QString s = QStringLiteral("%1 %2, %3 %4")
                    .arg(n)
                    .arg(n == 1 ? tr("patch") : tr("patches"))
                    .arg(m)
                    .arg(m == 1 ? tr("control point") : tr("control points"));
    const int lattices = document_->latticeCount();
    if (lattices > 0) {
        s += QStringLiteral(" \u00b7 ") + counted(lattices, tr("lattice"), tr("lattices"));
        if (const ffd::FfdModel* model = document_->model())
            s += QStringLiteral(", ") + counted(model->design().size(), tr("design variable"), tr("design variables"));
    }
    return s;
}

void MainWindow::updateTitle() {
    const QString title = document_->hasGeometry() ? document_->title() : QString();
    setWindowTitle(title.isEmpty() ? QString::fromLatin1(kAppName)
                                   : QStringLiteral("%1[*] \u2014 %2").arg(title, QString::fromLatin1(kAppName)));
    setWindowModified(document_->isModified());
}

void MainWindow::updateActions() {
    const bool geometry = document_->hasGeometry();
    for (QAction* a : needsGeometry_) a->setEnabled(geometry);
    saveAction_->setEnabled(geometry);
    removeLatticeAction_->setEnabled(selection_->kind() == Selection::Kind::Lattice ||
                                     selection_->kind() == Selection::Kind::LatticePoints);
    resetPointsAction_->setEnabled(selection_->kind() == Selection::Kind::LatticePoints);
    const MeshPreviewer::State mesh = previewer_->state();
    meshPreviewAction_->setEnabled(geometry && !jobs_->running());
    meshCancelAction_->setEnabled(mesh == MeshPreviewer::State::Running);
    meshClearAction_->setEnabled(previewer_->result() != nullptr);
    exportGridAction_->setEnabled(mesh == MeshPreviewer::State::Ready);
    exportGridAction_->setStatusTip(mesh == MeshPreviewer::State::Ready ? QString()
                                                                        : tr("Run Mesh > Preview first (Ctrl+M)"));
    meshPanel_->previewButton()->setEnabled(geometry && (!jobs_->running() || mesh == MeshPreviewer::State::Running));
}

// ---- Camera ---------------------------------------------------------------------------------------

void MainWindow::resetCamera() {
    // Oblique view from upstream (-X), the +Y side and above; X streamwise, Z up.
    setView({1.0, -1.35, -0.75}, {0.0, 0.0, 1.0});
}

void MainWindow::setView(const std::array<double, 3>& direction, const std::array<double, 3>& up) {
    vtkRenderer* ren = viewport_->renderer();
    vtkCamera* cam = ren->GetActiveCamera();
    cam->SetViewAngle(30.0);
    if (scene_->empty()) {
        cam->SetFocalPoint(0, 0, 0);
        cam->SetPosition(-direction[0] * 4, -direction[1] * 4, -direction[2] * 4);
        cam->SetViewUp(up.data());
    } else {
        const double aspect = viewport_->height() > 0 ? double(viewport_->width()) / viewport_->height() : 1.0;
        const std::vector<double> extra = lattices_->allPoints();
        scene_->fitCamera(cam, aspect, direction, up, 0.9, &extra);
    }
    ren->ResetCameraClippingRange();
}

// ---- Files ------------------------------------------------------------------------------------------

bool MainWindow::guarded(const std::function<void()>& work, QString* error) {
    try {
        work();
        return true;
    } catch (const aero::Error& e) {
        if (error) *error = QString::fromStdString(e.what());
    } catch (const std::exception& e) {  // not expected from libcore, but never let it escape
        if (error) *error = tr("Unexpected error: %1").arg(QString::fromStdString(e.what()));
    }
    return false;
}

bool MainWindow::loadFile(const QString& path, QString* error) {
    const QFileInfo info(path);
    const QString suffix = info.suffix().toLower();
    const std::string file = QFile::encodeName(path).toStdString();
    bool project = false;
    if (suffix == QLatin1String("json")) {
        project = io::looksLikeCase(file);
    } else if (!supportedSuffix(path)) {
        if (error)
            *error = tr("'%1': unsupported file type (expected a project .json, a patch set .json, .igs, .iges, .stp or .step)").arg(path);
        return false;
    }
    if (!guarded([&] { project ? document_->openProject(path) : document_->newFromGeometry(path); }, error)) return false;
    lastDirectory_ = info.absolutePath();
    addRecentFile(info.absoluteFilePath());
    return true;
}

bool MainWindow::loadSample(QString* error, bool withPaperLattice) {
    return guarded([&] { document_->newFromSample(withPaperLattice); }, error);
}

bool MainWindow::saveProject(const QString& path, QString* error) {
    if (!guarded([&] { document_->saveProject(path); }, error)) return false;
    lastDirectory_ = QFileInfo(path).absolutePath();
    addRecentFile(QFileInfo(path).absoluteFilePath());
    statusBar()->showMessage(document_->loadMessage().isEmpty() ? tr("Saved %1").arg(path) : document_->loadMessage(), 8000);
    return true;
}

bool MainWindow::openFile(const QString& path) {
    if (!maybeSave()) return false;
    QString error;
    if (loadFile(path, &error)) return true;
    QMessageBox::critical(this, tr("Cannot open file"), error);
    return false;
}

bool MainWindow::openSample(bool withPaperLattice) {
    if (!maybeSave()) return false;
    QString error;
    if (loadSample(&error, withPaperLattice)) return true;
    QMessageBox::critical(this, tr("Cannot create the sample"), error);
    return false;
}

void MainWindow::offerRecovery() {
    if (!autosaver_) return;
    const auto sessions = Autosaver::findRecoverable(autosaver_->directory());
    if (sessions.isEmpty()) return;
    const Autosaver::Recoverable& r = sessions.front();  // the most recent
    QMessageBox box(QMessageBox::Question, tr("Recover Unsaved Work"),
                    tr("Aeroform did not close normally. Unsaved work on \u201c%1\u201d was autosaved at %2.")
                        .arg(r.title.isEmpty() ? tr("an unsaved project") : r.title,
                             QLocale().toString(r.saved, QLocale::ShortFormat)),
                    QMessageBox::NoButton, this);
    box.setInformativeText(tr("Recover it now? Discard deletes the autosaved copy."));
    QPushButton* recover = box.addButton(tr("Recover"), QMessageBox::AcceptRole);
    QPushButton* discard = box.addButton(tr("Discard"), QMessageBox::DestructiveRole);
    box.addButton(tr("Not Now"), QMessageBox::RejectRole);
    box.setDefaultButton(recover);
    box.exec();
    if (box.clickedButton() == discard) {
        Autosaver::discard(r);
    } else if (box.clickedButton() == recover) {
        QString error;
        if (guarded([&] { document_->recover(r.casePath, r.projectPath, r.generated, r.title); }, &error)) {
            autosaver_->saveNow();  // our own session holds it now
            Autosaver::discard(r);
            statusBar()->showMessage(tr("Recovered the autosaved work; save it to keep it."), 10000);
        } else {
            QMessageBox::critical(this, tr("Cannot recover"), error);
        }
    }
}

bool MainWindow::maybeSave() {
    if (!document_->isModified()) return true;
    const auto answer = QMessageBox::warning(
        this, tr("Unsaved Changes"),
        tr("\u201c%1\u201d has unsaved changes. Save them first?").arg(document_->title()),
        QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
    if (answer == QMessageBox::Save) return save();
    return answer == QMessageBox::Discard;
}

bool MainWindow::save() {
    if (document_->projectPath().isEmpty()) return saveAs();
    QString error;
    if (saveProject(document_->projectPath(), &error)) return true;
    QMessageBox::critical(this, tr("Cannot save"), error);
    return false;
}

bool MainWindow::saveAs() {
    QString suggestion = document_->projectPath();
    if (suggestion.isEmpty())
        suggestion = QDir(lastDirectory_.isEmpty() ? QDir::homePath() : lastDirectory_)
                         .filePath(QFileInfo(document_->title()).completeBaseName().replace(QLatin1Char(' '), QLatin1Char('_')) +
                                   QStringLiteral("_project.json"));
    QString path = QFileDialog::getSaveFileName(this, tr("Save Project"), suggestion,
                                                tr("Aeroform project (*.json)"));
    if (path.isEmpty()) return false;
    if (QFileInfo(path).suffix().isEmpty()) path += QStringLiteral(".json");
    QString error;
    if (saveProject(path, &error)) return true;
    QMessageBox::critical(this, tr("Cannot save"), error);
    return false;
}

void MainWindow::chooseAndOpen() {
    if (!maybeSave()) return;
    const QString path = QFileDialog::getOpenFileName(
        this, tr("Open"), lastDirectory_,
        tr("Projects and geometry (*.json *.igs *.iges *.IGS *.IGES *.stp *.step *.STP *.STEP);;Aeroform project or patch set (*.json);;"
           "IGES (*.igs *.iges *.IGS *.IGES);;STEP (*.stp *.step *.STP *.STEP);;All files (*)"));
    if (path.isEmpty()) return;
    QString error;
    if (!loadFile(path, &error)) QMessageBox::critical(this, tr("Cannot open file"), error);
}

void MainWindow::addRecentFile(const QString& path) {
    if (!options_.recentFiles) return;
    QSettings settings;
    QStringList list = settings.value(QLatin1String(kRecentKey)).toStringList();
    list.removeAll(path);
    list.prepend(path);
    while (list.size() > kMaxRecent) list.removeLast();
    settings.setValue(QLatin1String(kRecentKey), list);
}

void MainWindow::fillRecentMenu() {
    recentMenu_->clear();
    const QStringList list = options_.recentFiles ? QSettings().value(QLatin1String(kRecentKey)).toStringList() : QStringList();
    int n = 0;
    for (const QString& path : list) {
        if (!QFileInfo::exists(path)) continue;
        QAction* a = recentMenu_->addAction(QStringLiteral("&%1 %2").arg(++n).arg(QFileInfo(path).fileName()), this,
                                            [this, path] { openFile(path); });
        a->setToolTip(path);
        a->setStatusTip(path);
    }
    if (n == 0) recentMenu_->addAction(tr("(none)"))->setEnabled(false);
    recentMenu_->addSeparator();
    recentMenu_->addAction(tr("Clear List"), this, [] { QSettings().remove(QLatin1String(kRecentKey)); });
}

void MainWindow::dragEnterEvent(QDragEnterEvent* e) {
    const QMimeData* mime = e->mimeData();
    if (mime->hasUrls() && !mime->urls().isEmpty() && mime->urls().front().isLocalFile() &&
        supportedSuffix(mime->urls().front().toLocalFile()))
        e->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* e) {
    const QList<QUrl> urls = e->mimeData()->urls();
    if (urls.isEmpty() || !urls.front().isLocalFile()) return;
    e->acceptProposedAction();
    const QString path = urls.front().toLocalFile();
    // Open after the drop returns (the source application waits for it).
    QMetaObject::invokeMethod(this, [this, path] { openFile(path); }, Qt::QueuedConnection);
}

void MainWindow::closeEvent(QCloseEvent* e) {
    if (maybeSave())
        e->accept();
    else
        e->ignore();
}

// ---- Export -------------------------------------------------------------------------------------

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

void MainWindow::exportGeometry() {
    if (!document_->problems().isEmpty()) {
        const auto answer = QMessageBox::warning(this, tr("Export Deformed Geometry"),
                                                 tr("The current state has problems:\n\n%1\n\nExport anyway?").arg(problemText()),
                                                 QMessageBox::Yes | QMessageBox::Cancel, QMessageBox::Cancel);
        if (answer != QMessageBox::Yes) return;
    }
    const QString path = QFileDialog::getSaveFileName(this, tr("Export Deformed Geometry"), lastDirectory_,
                                                      tr("IGES (*.igs *.iges);;STEP (*.stp *.step);;Aeroform patch set (*.json)"));
    if (path.isEmpty()) return;
    QString error;
    if (guarded([&] { document_->exportGeometry(path); }, &error))
        statusBar()->showMessage(tr("Exported %1").arg(path), 5000);
    else
        QMessageBox::critical(this, tr("Cannot export"), error);
}

void MainWindow::exportVtk() {
    QString path = QFileDialog::getSaveFileName(this, tr("Export for ParaView"), lastDirectory_,
                                                tr("VTK multiblock (*.vtm)"));
    if (path.isEmpty()) return;
    if (QFileInfo(path).suffix().toLower() != QLatin1String("vtm")) path += QStringLiteral(".vtm");
    QString error;
    if (guarded([&] { document_->exportVtk(path); }, &error))
        statusBar()->showMessage(tr("Exported %1").arg(path), 5000);
    else
        QMessageBox::critical(this, tr("Cannot export"), error);
}

void MainWindow::exportGrid() {
    QString filter;
    QString path = QFileDialog::getSaveFileName(
        this, tr("Export Grid"), lastDirectory_,
        tr("VTK multiblock with quality fields (*.vtm);;Plot3D binary (*.xyz);;Plot3D ASCII (*.p3d)"), &filter);
    if (path.isEmpty()) return;
    if (QFileInfo(path).suffix().isEmpty())
        path += filter.contains(QLatin1String("*.xyz")) ? QStringLiteral(".xyz")
                : filter.contains(QLatin1String("*.p3d")) ? QStringLiteral(".p3d")
                                                           : QStringLiteral(".vtm");
    QString error;
    QApplication::setOverrideCursor(Qt::WaitCursor);
    const bool ok = guarded([&] { previewer_->exportGrid(path); }, &error);
    QApplication::restoreOverrideCursor();
    if (ok)
        statusBar()->showMessage(tr("Exported %1").arg(path), 5000);
    else
        QMessageBox::critical(this, tr("Cannot export the grid"), error);
}

// ---- Mesh preview -------------------------------------------------------------------------------

void MainWindow::startMeshPreview() {
    if (!document_->problems().isEmpty()) {
        const auto answer = QMessageBox::warning(this, tr("Mesh Preview"),
                                                 tr("The current state has problems:\n\n%1\n\nPreview the mesh anyway?").arg(problemText()),
                                                 QMessageBox::Yes | QMessageBox::Cancel, QMessageBox::Cancel);
        if (answer != QMessageBox::Yes) return;
    }
    QString error;
    if (!previewer_->start(&error)) {
        statusBar()->showMessage(error, 8000);
        return;
    }
    if (auto* dock = findChild<QDockWidget*>(QStringLiteral("meshQualityDock"))) {
        dock->show();
        dock->raise();
    }
}

void MainWindow::onMeshPreviewStateChanged() {
    using State = MeshPreviewer::State;
    const State state = previewer_->state();
    switch (state) {
        case State::Ready:
            tree_->setGridState(counted(static_cast<long long>(previewer_->result()->grids.size()), tr("block"), tr("blocks")), true,
                                tr("The mesh preview's grid: %1").arg(previewer_->description()));
            break;
        case State::Outdated:
            tree_->setGridState(tr("outdated"), false,
                                tr("The geometry or the mesh options changed after the preview: run Mesh > Preview again"));
            break;
        case State::Running:
            tree_->setGridState(tr("generating..."), false);
            break;
        default:
            tree_->setGridState({}, false);
            break;
    }
    applyGridVisibility();
    updateActions();
    updateDiagnostics();
}

void MainWindow::applyGridVisibility() {
    for (int p = 0; p < ModelTree::GridPartCount; ++p) meshScene_->setPartVisible(static_cast<MeshPart>(p), tree_->gridPartShown(p));
    // The grid's wall lies on the geometry's surfaces: hide those while it is shown.
    const bool wall = previewer_ && previewer_->state() == MeshPreviewer::State::Ready && tree_->gridPartShown(ModelTree::WallPart);
    const bool geometryShown = tree_->geometryItem()->checkState(0) == Qt::Checked;
    settingGeometry_ = true;
    if (wall && geometryShown) {
        tree_->geometryItem()->setCheckState(0, Qt::Unchecked);
        geometryHiddenForGrid_ = true;
    } else if (!wall && geometryHiddenForGrid_) {
        geometryHiddenForGrid_ = false;
        if (!geometryShown) {
            tree_->geometryItem()->setCheckState(0, Qt::Checked);
        } else {  // checked again without a signal (a new document): show the surfaces ourselves
            scene_->setSurfacesVisible(true);
            scene_->setEdgesVisible(findChild<QAction*>(QStringLiteral("actionPatchEdges"))->isChecked());
            findChild<QAction*>(QStringLiteral("actionSurfaces"))->setChecked(true);
        }
    }
    settingGeometry_ = false;
    viewport_->requestRender();
}

// ---- FFD ----------------------------------------------------------------------------------------

void MainWindow::addLattice() {
    if (!document_->hasGeometry()) return;
    QString name = QStringLiteral("L%1").arg(document_->latticeCount());
    for (int k = document_->latticeCount(); ; ++k) {
        name = k == 0 ? QStringLiteral("body") : QStringLiteral("L%1").arg(k);
        bool taken = false;
        for (const auto& l : document_->caseFile().lattices) taken = taken || QString::fromStdString(l.name) == name;
        if (!taken) break;
    }
    const std::vector<int> patches =
        selection_->kind() == Selection::Kind::Patches ? selection_->patches() : std::vector<int>{};
    LatticeDialog dialog(name, patches, this);
    if (dialog.exec() != QDialog::Accepted) return;
    QString error;
    if (!guarded([&] { document_->addLattice(dialog.lattice(), dialog.stations()); }, &error)) {
        QMessageBox::critical(this, tr("Cannot add the lattice"), error);
        return;
    }
    selection_->selectLattice(document_->latticeCount() - 1);
    latticesAction_->setChecked(true);
    resetCamera();
    viewport_->requestRender();
}

}  // namespace aero::ui
