#include "MainWindow.h"

#include <vtkCamera.h>
#include <vtkRenderer.h>

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileInfo>
#include <QFontMetrics>
#include <QImage>
#include <QLabel>
#include <QMenu>
#include <QMessageBox>
#include <QMimeData>
#include <QPushButton>
#include <QScrollArea>
#include <QStatusBar>
#include <QTreeWidgetItem>
#include <QUndoStack>
#include <QUrl>

#include "ActionSet.h"
#include "Autosave.h"
#include "DesignVariablePanel.h"
#include "Document.h"
#include "Exports.h"
#include "FlowPanel.h"
#include "FlowRunner.h"
#include "FlowScene.h"
#include "FlowWorkspace.h"
#include "Help.h"
#include "JobRunner.h"
#include "JobStatusBar.h"
#include "LatticeDialog.h"
#include "LatticeEditor.h"
#include "LatticeScene.h"
#include "Menus.h"
#include "MeshPanel.h"
#include "MeshPreviewer.h"
#include "MeshScene.h"
#include "ModelTree.h"
#include "OptimizationPanel.h"
#include "OptimizationPlots.h"
#include "OptimizationRunner.h"
#include "OptimizationScene.h"
#include "OptimizationWorkspace.h"
#include "OverlayScene.h"
#include "PatchScene.h"
#include "ProjectFiles.h"
#include "PropertyPanel.h"
#include "ResidualPlot.h"
#include "Resources.h"
#include "SectionView.h"
#include "Selection.h"
#include "SensitivityRunner.h"
#include "SensitivityWorkspace.h"
#include "SurfaceFieldScene.h"
#include "Text.h"
#include "VtkViewport.h"
#include "common/Error.h"
#include "io/CaseFile.h"

namespace aero::ui {

namespace {

const char* const kAppName = "Aeroform";
constexpr int kQuitWaitMs = 120000;     // how long quitting waits for stopped jobs

QDockWidget* dock(QMainWindow* window, const QString& title, const char* name, QWidget* content, bool scroll) {
    auto* d = new QDockWidget(title, window);
    d->setObjectName(QString::fromLatin1(name));
    if (scroll) {
        auto* area = new QScrollArea(window);
        area->setWidget(content);
        area->setWidgetResizable(true);
        area->setFrameShape(QFrame::NoFrame);
        area->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);  // the panel wraps to the dock's width
        d->setWidget(area);
    } else {
        d->setWidget(content);
    }
    return d;
}

}  // namespace

MainWindow::Options MainWindow::defaultOptions() {
    Options o;
    const int seconds = setting(QStringLiteral("autosave/intervalSeconds")).toInt();
    if (seconds > 0) o.autosaveIntervalMs = 1000 * seconds;
    return o;
}

MainWindow::MainWindow(QWidget* parent) : MainWindow(defaultOptions(), parent) {}

MainWindow::MainWindow(const Options& options, QWidget* parent) : QMainWindow(parent), options_(options) {
    initResources();
    setWindowIcon(appIcon(QStringLiteral("aeroform")));
    document_ = new Document(this);
    selection_ = new Selection(this);
    jobs_ = new JobRunner(this);
    actions_ = std::make_unique<ActionSet>(this, document_->undoStack());
    files_ = new ProjectFiles(document_, this, options_.recentFiles, this);

    viewport_ = new VtkViewport(this);
    viewport_->setObjectName(QStringLiteral("viewport"));
    setCentralWidget(viewport_);
    scene_ = std::make_unique<PatchScene>(viewport_->renderer());
    lattices_ = std::make_unique<LatticeScene>(viewport_->renderer());
    overlay_ = std::make_unique<OverlayScene>(viewport_->renderer());
    gradientArrows_ = std::make_unique<OverlayScene>(viewport_->renderer(), std::array<double, 3>{0.10, 0.62, 0.25});
    surfaceField_ = std::make_unique<SurfaceFieldScene>(viewport_->renderer());
    meshScene_ = std::make_unique<MeshScene>(viewport_->renderer());
    flowScene_ = std::make_unique<FlowScene>(viewport_->renderer());
    optimizationScene_ = std::make_unique<OptimizationScene>(viewport_->renderer());
    editor_ = new LatticeEditor(viewport_, document_, selection_, lattices_.get(), this);

    meshPanel_ = new MeshPanel(this);
    previewer_ = new MeshPreviewer(document_, jobs_, viewport_, meshScene_.get(), meshPanel_, this);
    flow_ = new FlowWorkspace(document_, jobs_, viewport_, flowScene_.get(), this, this);
    optimization_ = new OptimizationWorkspace(document_, jobs_, viewport_, optimizationScene_.get(),
                                              this, this);
    sensitivities_ = new SensitivityRunner(document_, jobs_, &flow_->runner(), this);
    exports_ = new Exports(
        document_, files_, previewer_, &flow_->runner(), this,
        [this](const QString& path, QString* error) { return saveScreenshot(path, error); },
        [this] { return problemText(); }, this);

    createDocks();
    createStatusBar();
    menus_ = std::make_unique<MenuRefs>(buildMenus(this, *actions_));
    buildToolBar(this, *actions_);
    for (QDockWidget* d : findChildren<QDockWidget*>()) menus_->panels->addAction(d->toggleViewAction());
    QAction* qualityPanel = findChild<QDockWidget*>(QStringLiteral("meshQualityDock"))->toggleViewAction();
    menus_->mesh->addAction(qualityPanel);
    for (const char* name : {"flowDock", "residualsDock", "sectionsDock"})
        menus_->flow->addAction(findChild<QDockWidget*>(QString::fromLatin1(name))->toggleViewAction());
    for (const char* name : {"optimizationDock", "optimizationPlotsDock"})
        menus_->optimize->addAction(
            findChild<QDockWidget*>(QString::fromLatin1(name))->toggleViewAction());
    connectActions();
    connectDocument();
    sensitivity_ = new SensitivityWorkspace(document_, sensitivities_, &flow_->runner(), optimization_, *actions_,
                                            {viewport_, scene_.get(), lattices_.get(), overlay_.get(),
                                             gradientArrows_.get(), surfaceField_.get(), variables_, tree_,
                                             predictionLabel_},
                                            this);
    connect(sensitivity_, &SensitivityWorkspace::message, this,
            [this](const QString& text, int timeoutMs) { statusBar()->showMessage(text, timeoutMs); });
    connect(sensitivities_, &SensitivityRunner::stateChanged, this, &MainWindow::updateActions);
    connect(sensitivities_, &SensitivityRunner::resultChanged, this, &MainWindow::updateActions);
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
    // Jobs first: their results must not arrive in half-destroyed panels.
    jobs_->cancelAll();
    jobs_->waitAll(kQuitWaitMs);
    // Removing the scenes' actors releases their GL objects: do it in the viewport's context
    // (which is still alive; the viewport, a child widget, is destroyed after this body).
    viewport_->makeCurrent();
    optimizationScene_.reset();
    flowScene_.reset();
    meshScene_.reset();
    surfaceField_.reset();
    gradientArrows_.reset();
    overlay_.reset();
    lattices_.reset();
    scene_.reset();
    viewport_->doneCurrent();
}

// ---- Layout -------------------------------------------------------------------------------------

void MainWindow::createDocks() {
    setDockOptions(QMainWindow::AnimatedDocks | QMainWindow::AllowTabbedDocks);
    setCorner(Qt::BottomLeftCorner, Qt::LeftDockWidgetArea);
    setCorner(Qt::BottomRightCorner, Qt::RightDockWidgetArea);
    tree_ = new ModelTree(document_, selection_, this);
    QDockWidget* treeDock = dock(this, tr("Model"), "modelDock", tree_, false);
    addDockWidget(Qt::LeftDockWidgetArea, treeDock);
    properties_ = new PropertyPanel(document_, selection_, this);
    QDockWidget* propDock = dock(this, tr("Properties"), "propertiesDock", properties_, true);
    addDockWidget(Qt::LeftDockWidgetArea, propDock);
    splitDockWidget(treeDock, propDock, Qt::Vertical);

    variables_ = new DesignVariablePanel(document_, this);
    QDockWidget* varDock = dock(this, tr("Design Variables"), "designVariablesDock", variables_, false);
    addDockWidget(Qt::RightDockWidgetArea, varDock);
    QDockWidget* meshDock = dock(this, tr("Mesh Quality"), "meshQualityDock", meshPanel_, true);
    addDockWidget(Qt::RightDockWidgetArea, meshDock);
    tabifyDockWidget(varDock, meshDock);
    QDockWidget* flowDock = dock(this, tr("Flow"), "flowDock", flow_->panel(), true);
    addDockWidget(Qt::RightDockWidgetArea, flowDock);
    tabifyDockWidget(meshDock, flowDock);
    QDockWidget* optimizationDock =
        dock(this, tr("Optimization"), "optimizationDock", optimization_->panel(), true);
    addDockWidget(Qt::RightDockWidgetArea, optimizationDock);
    tabifyDockWidget(flowDock, optimizationDock);
    varDock->raise();

    // The plots below the view, shown when a solve starts.
    QDockWidget* residualDock = dock(this, tr("Residuals"), "residualsDock", flow_->residualPlot(), false);
    addDockWidget(Qt::BottomDockWidgetArea, residualDock);
    QDockWidget* sectionDock = dock(this, tr("Sections"), "sectionsDock", flow_->sections(), false);
    addDockWidget(Qt::BottomDockWidgetArea, sectionDock);
    tabifyDockWidget(residualDock, sectionDock);
    // The optimization's plots, shown when a run starts or a history is read back.
    QDockWidget* plotsDock = dock(this, tr("Optimization Plots"), "optimizationPlotsDock",
                                  optimization_->plots(), false);
    addDockWidget(Qt::BottomDockWidgetArea, plotsDock);
    tabifyDockWidget(sectionDock, plotsDock);
    residualDock->raise();
    residualDock->hide();
    sectionDock->hide();
    plotsDock->hide();

    resizeDocks({treeDock, varDock}, {250, 380}, Qt::Horizontal);
    resizeDocks({treeDock, propDock}, {200, 420}, Qt::Vertical);

    connect(tree_, &ModelTree::geometryVisibilityChanged, this, [this](bool on) {
        if (!settingGeometry_) geometryHiddenForResults_ = false;  // the user's choice from now on
        scene_->setSurfacesVisible(on);
        scene_->setEdgesVisible(on && actions_->patchEdges->isChecked());
        actions_->surfaces->setChecked(on);
        viewport_->requestRender();
    });
    connect(tree_, &ModelTree::patchVisibilityChanged, this, [this](int p, bool on) {
        scene_->setPatchVisible(p, on);
        sensitivity_->updateShapeArrows();
        viewport_->requestRender();
    });
    connect(tree_, &ModelTree::latticesVisibilityChanged, this, [this](bool on) { actions_->lattices->setChecked(on); });
    connect(tree_, &ModelTree::latticeVisibilityChanged, this, [this](int l, bool on) {
        lattices_->setLatticeVisible(l, on);
        viewport_->requestRender();
    });
    connect(tree_, &ModelTree::gridVisibilityChanged, this, &MainWindow::applyResultVisibility);
}

void MainWindow::createStatusBar() {
    problemLabel_ = new QLabel(this);
    problemLabel_->setObjectName(QStringLiteral("problemLabel"));
    problemLabel_->setStyleSheet(QStringLiteral("QLabel { color: #b00020; font-weight: bold; }"));
    problemLabel_->setTextFormat(Qt::PlainText);
    problemLabel_->hide();
    statusBar()->addPermanentWidget(problemLabel_, 1);
    jobStatus_ = new JobStatusBar(jobs_, statusBar(), this);
    statusBar()->addPermanentWidget(jobStatus_);
    predictionLabel_ = new QLabel(this);
    predictionLabel_->setObjectName(QStringLiteral("predictionStatus"));
    predictionLabel_->setToolTip(tr("First-order change of the objective since the gradient (Flow \u25b8 Compute "
                                    "Sensitivities): the sum of dJ/dB . \u0394B over the lattice points"));
    predictionLabel_->hide();
    statusBar()->addPermanentWidget(predictionLabel_);
    summaryLabel_ = new QLabel(this);
    summaryLabel_->setObjectName(QStringLiteral("summaryLabel"));
    statusBar()->addPermanentWidget(summaryLabel_);
    auto show = [this](const QString& text, int timeoutMs) { statusBar()->showMessage(text, timeoutMs); };
    connect(editor_, &LatticeEditor::message, this, [this](const QString& text) {
        if (text.isEmpty())
            statusBar()->clearMessage();
        else
            statusBar()->showMessage(text, 6000);
    });
    connect(files_, &ProjectFiles::message, this, show);
    connect(exports_, &Exports::message, this, show);
    connect(previewer_, &MeshPreviewer::message, this, show);
    connect(flow_, &FlowWorkspace::message, this, show);
    connect(optimization_, &OptimizationWorkspace::message, this, show);
}

void MainWindow::connectActions() {
    const ActionSet& a = *actions_;
    // File.
    connect(a.open, &QAction::triggered, files_, &ProjectFiles::chooseAndOpen);
    connect(menus_->recent, &QMenu::aboutToShow, this, [this] { files_->fillRecentMenu(menus_->recent); });
    connect(a.openSample, &QAction::triggered, this, [this] { openSample(true); });
    connect(a.openSampleGeometry, &QAction::triggered, this, [this] { openSample(false); });
    connect(a.save, &QAction::triggered, files_, &ProjectFiles::save);
    connect(a.saveAs, &QAction::triggered, files_, &ProjectFiles::saveAs);
    connect(a.exportGeometry, &QAction::triggered, exports_, &Exports::exportGeometry);
    connect(a.exportVtk, &QAction::triggered, exports_, &Exports::exportVtk);
    connect(a.exportGrid, &QAction::triggered, exports_, &Exports::exportGrid);
    connect(a.exportFlow, &QAction::triggered, exports_, &Exports::exportFlow);
    connect(a.screenshot, &QAction::triggered, exports_, &Exports::saveScreenshot);
    connect(a.quit, &QAction::triggered, this, &QWidget::close);

    // Edit.
    QUndoStack* stack = document_->undoStack();
    connect(a.undoTool, &QAction::triggered, stack, &QUndoStack::undo);
    connect(a.redoTool, &QAction::triggered, stack, &QUndoStack::redo);
    connect(stack, &QUndoStack::canUndoChanged, a.undoTool, &QAction::setEnabled);
    connect(stack, &QUndoStack::canRedoChanged, a.redoTool, &QAction::setEnabled);
    QAction* undoTool = a.undoTool;
    QAction* redoTool = a.redoTool;
    connect(stack, &QUndoStack::undoTextChanged, undoTool, [undoTool](const QString& t) {
        undoTool->setToolTip(t.isEmpty() ? tr("Undo") : tr("Undo %1").arg(t));
    });
    connect(stack, &QUndoStack::redoTextChanged, redoTool, [redoTool](const QString& t) {
        redoTool->setToolTip(t.isEmpty() ? tr("Redo") : tr("Redo %1").arg(t));
    });
    a.undoTool->setEnabled(stack->canUndo());
    a.redoTool->setEnabled(stack->canRedo());
    connect(a.selectAllPoints, &QAction::triggered, this, &MainWindow::selectAllLatticePoints);
    connect(a.resetPoints, &QAction::triggered, this,
            [this] { document_->resetLatticePoints(selection_->lattice(), selection_->points()); });
    viewport_->addAction(a.resetPoints);
    connect(a.resetVariables, &QAction::triggered, document_, &Document::resetDesignValues);

    // View: the toggles start as the scenes are.
    auto toggle = [this](QAction* action, bool on, auto apply) {
        action->setChecked(on);
        connect(action, &QAction::toggled, this, [this, apply](bool checked) {
            apply(checked);
            viewport_->requestRender();
        });
    };
    toggle(a.surfaces, scene_->surfacesVisible(), [this](bool on) { scene_->setSurfacesVisible(on); });
    toggle(a.patchEdges, scene_->edgesVisible(), [this](bool on) { scene_->setEdgesVisible(on); });
    toggle(a.controlNets, scene_->controlNetsVisible(), [this](bool on) { scene_->setControlNetsVisible(on); });
    toggle(a.lattices, lattices_->visible(), [this](bool on) {
        lattices_->setVisible(
            on && !optimization_->viewShown());  // an evaluation's lattices replace the design's
        optimizationScene_->setLatticesVisible(on);
        if (tree_->latticesItem()->checkState(0) != (on ? Qt::Checked : Qt::Unchecked))
            tree_->latticesItem()->setCheckState(0, on ? Qt::Checked : Qt::Unchecked);
    });
    toggle(a.sensitivity, false, [this](bool on) {
        variables_->setSensitivityShown(on);
        sensitivity_->updateShapeArrows();
    });
    toggle(a.orientationAxes, viewport_->orientationAxesVisible(), [this](bool on) { viewport_->setOrientationAxesVisible(on); });
    connect(a.resetCamera, &QAction::triggered, this, [this] {
        resetCamera();
        viewport_->requestRender();
    });
    auto view = [this](QAction* action, std::array<double, 3> dir, std::array<double, 3> up) {
        connect(action, &QAction::triggered, this, [this, dir, up] {
            setView(dir, up);
            viewport_->requestRender();
        });
    };
    view(a.viewFront, {1, 0, 0}, {0, 0, 1});
    view(a.viewSide, {0, -1, 0}, {0, 0, 1});
    view(a.viewTop, {0, 0, -1}, {0, 1, 0});
    QAction* sensitivity = a.sensitivity;
    connect(variables_, &DesignVariablePanel::sensitivityToggled, sensitivity, &QAction::setChecked);
    connect(variables_, &DesignVariablePanel::sensitivityToggled, this, [this] {
        sensitivity_->updateShapeArrows();
        viewport_->requestRender();
    });
    connect(variables_, &DesignVariablePanel::currentVariableChanged, this, [this] {
        sensitivity_->updateShapeArrows();
        viewport_->requestRender();
    });

    // FFD.
    connect(a.addLattice, &QAction::triggered, this, &MainWindow::addLattice);
    connect(a.removeLattice, &QAction::triggered, this, [this] { document_->removeLattice(selection_->lattice()); });

    // Mesh.
    connect(a.meshPreview, &QAction::triggered, this, &MainWindow::startMeshPreview);
    connect(a.meshCancel, &QAction::triggered, previewer_, &MeshPreviewer::cancel);
    connect(a.meshClear, &QAction::triggered, previewer_, &MeshPreviewer::clear);

    // Flow.
    connect(a.flowSolve, &QAction::triggered, this, [this] { startFlowSolve(false); });
    connect(a.flowContinue, &QAction::triggered, this, [this] { startFlowSolve(true); });
    connect(a.flowStop, &QAction::triggered, flow_, &FlowWorkspace::stop);
    // A solve, however started (the panel's buttons too), brings its panel and plot forward.
    connect(&flow_->runner(), &FlowRunner::started, this, [this] {
        for (const char* name : {"flowDock", "residualsDock"}) {
            if (auto* d = findChild<QDockWidget*>(QString::fromLatin1(name))) {
                d->show();
                d->raise();
            }
        }
    });

    // Optimize.
    connect(a.optimizeStart, &QAction::triggered, optimization_, &OptimizationWorkspace::start);
    connect(a.optimizePause, &QAction::triggered, optimization_, &OptimizationWorkspace::pause);
    connect(a.optimizeStop, &QAction::triggered, optimization_, &OptimizationWorkspace::stop);
    connect(a.optimizeResume, &QAction::triggered, optimization_, &OptimizationWorkspace::resume);
    connect(a.optimizeExportShape, &QAction::triggered, optimization_,
            &OptimizationWorkspace::chooseAndExportShape);
    connect(a.optimizeExportHistory, &QAction::triggered, optimization_,
            &OptimizationWorkspace::chooseAndExportHistory);
    // A run, however started, and a history read back bring the panel and the plots forward.
    auto showOptimization = [this] {
        for (const char* name : {"optimizationDock", "optimizationPlotsDock"}) {
            if (auto* d = findChild<QDockWidget*>(QString::fromLatin1(name))) {
                d->show();
                d->raise();
            }
        }
    };
    connect(&optimization_->runner(), &OptimizationRunner::started, this, showOptimization);
    connect(&optimization_->runner(), &OptimizationRunner::stateChanged, this,
            [this, showOptimization] {
                if (optimization_->runner().state() == OptimizationRunner::State::Recorded)
                    showOptimization();
            });

    // Help.
    connect(a.mouseAndKeys, &QAction::triggered, this, [this] { showMouseAndKeys(this); });
    connect(a.about, &QAction::triggered, this, [this] { showAbout(this); });
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
        sensitivity_->updateShapeArrows();
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
        if (!ProjectFiles::guarded([&] { document_->setMeshOptions(level.toStdString(), increments); }, &error)) {
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
    meshScene_->setMetric(meshPanel_->metric());

    // Flow: a shown solution takes the place of the geometry (and of a grid preview's wall).
    connect(flow_, &FlowWorkspace::solutionShownChanged, this, [this](bool shown) {
        if (shown && tree_->gridPartShown(ModelTree::WallPart)) tree_->gridItem()->setCheckState(0, Qt::Unchecked);
        applyResultVisibility();
        updateActions();
    });
    connect(&flow_->runner(), &FlowRunner::stateChanged, this, &MainWindow::updateActions);

    // Optimization: an evaluation in the 3D view takes the design's place; a flow solve of the
    // design or an edit of it gives the view back.
    connect(optimization_, &OptimizationWorkspace::viewShownChanged, this,
            &MainWindow::applyOptimizationView);
    connect(&optimization_->runner(), &OptimizationRunner::stateChanged, this,
            &MainWindow::updateActions);
    connect(&optimization_->runner(), &OptimizationRunner::recordAdded, this,
            &MainWindow::updateActions);
    connect(&flow_->runner(), &FlowRunner::started, this,
            [this] { optimization_->setViewShown(false); });
    connect(document_, &Document::shapeChanged, this, [this](const QVector<int>& patches) {
        if (!patches.isEmpty() && optimization_->viewShown()) optimization_->setViewShown(false);
    });

    connect(jobs_, &JobRunner::jobStarted, this, &MainWindow::updateActions);
    connect(jobs_, &JobRunner::jobFinished, this, &MainWindow::updateActions);
    applyResultVisibility();
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
    sensitivity_->updateShapeArrows();
    updateSummary();
    updateTitle();
    updateActions();
    resetCamera();
    if (!document_->loadMessage().isEmpty()) statusBar()->showMessage(document_->loadMessage(), 10000);
    viewport_->requestRender();
}

void MainWindow::onShapeChanged(const QVector<int>& patches) {
    scene_->updatePatches(document_->shape(), std::vector<int>(patches.begin(), patches.end()));
    if (actions_->sensitivity->isChecked()) sensitivity_->updateShapeArrows();
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
    const ActionSet& a = *actions_;
    const bool geometry = document_->hasGeometry();
    for (QAction* action : {a.saveAs, a.exportGeometry, a.exportVtk, a.addLattice}) action->setEnabled(geometry);
    a.save->setEnabled(geometry);
    a.removeLattice->setEnabled(selection_->kind() == Selection::Kind::Lattice ||
                                selection_->kind() == Selection::Kind::LatticePoints);
    a.resetPoints->setEnabled(selection_->kind() == Selection::Kind::LatticePoints);
    const MeshPreviewer::State mesh = previewer_->state();
    const bool meshRunning = mesh == MeshPreviewer::State::Running;
    a.meshPreview->setEnabled(geometry && !meshRunning);
    a.meshCancel->setEnabled(meshRunning);
    a.meshClear->setEnabled(previewer_->result() != nullptr);
    a.exportGrid->setEnabled(mesh == MeshPreviewer::State::Ready);
    a.exportGrid->setStatusTip(mesh == MeshPreviewer::State::Ready ? QString() : tr("Run Mesh > Preview first (Ctrl+M)"));
    meshPanel_->previewButton()->setEnabled(geometry);
    const FlowRunner& flow = flow_->runner();
    a.flowSolve->setEnabled(geometry && !flow.running());
    a.flowStop->setEnabled(flow.running());
    a.flowContinue->setEnabled(geometry && !flow.running() && flow.canContinue());
    a.exportFlow->setEnabled(flow.result() != nullptr);
    const bool gradientRunning = sensitivities_->running();
    a.computeSensitivities->setEnabled(geometry && document_->model() && !gradientRunning);
    a.cancelSensitivities->setEnabled(gradientRunning);
    a.confirmPrediction->setEnabled(sensitivities_->result() != nullptr && !flow.running());
    variables_->setCanComputeGradient(!gradientRunning);
    flow_->panel()->solveButton()->setEnabled(geometry);
    const OptimizationRunner& opt = optimization_->runner();
    const bool optBusy = opt.running() || opt.loading();
    a.optimizeStart->setEnabled(geometry && !optBusy);
    a.optimizeStart->setText(opt.historyExists() ? tr("&Start Over...") : tr("&Start"));
    a.optimizePause->setEnabled(opt.state() == OptimizationRunner::State::Running);
    a.optimizeStop->setEnabled(opt.running());
    a.optimizeResume->setEnabled(geometry && !optBusy && opt.historyExists());
    a.optimizeExportShape->setEnabled(optimization_->shownEvaluation() > 0);
    a.optimizeExportHistory->setEnabled(opt.historyExists());
}

void MainWindow::applyOptimizationView() {
    const bool on = optimization_->viewShown();
    flowScene_->setShown(!on);
    lattices_->setVisible(!on && actions_->lattices->isChecked());
    optimizationScene_->setLatticesVisible(actions_->lattices->isChecked());
    applyResultVisibility();
    updateActions();
    viewport_->requestRender();
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
        std::vector<double> extra = lattices_->allPoints();
        const std::vector<double> evaluations =
            optimizationScene_->viewPoints();  // empty unless shown
        extra.insert(extra.end(), evaluations.begin(), evaluations.end());
        scene_->fitCamera(cam, aspect, direction, up, 0.9, &extra);
    }
    ren->ResetCameraClippingRange();
}

// ---- Files ------------------------------------------------------------------------------------------

bool MainWindow::loadFile(const QString& path, QString* error) {
    return files_->load(path, error);
}

bool MainWindow::loadSample(QString* error, bool withPaperLattice) {
    return files_->loadSample(error, withPaperLattice);
}

bool MainWindow::saveProject(const QString& path, QString* error) {
    return files_->saveTo(path, error);
}

bool MainWindow::openFile(const QString& path) {
    return files_->open(path);
}

bool MainWindow::openSample(bool withPaperLattice) {
    return files_->openSample(withPaperLattice);
}

void MainWindow::offerRecovery() {
    files_->offerRecovery(autosaver_);
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

void MainWindow::dragEnterEvent(QDragEnterEvent* e) {
    const QMimeData* mime = e->mimeData();
    if (mime->hasUrls() && !mime->urls().isEmpty() && mime->urls().front().isLocalFile() &&
        ProjectFiles::supported(mime->urls().front().toLocalFile()))
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
    if (!jobs_->busy()) {
        if (files_->maybeSave())
            e->accept();
        else
            e->ignore();
        return;
    }
    // Ask about the running work first, then about unsaved changes; stop the work only when
    // both said yes (a Cancel anywhere keeps everything running).
    if (!confirmQuitWhileWorking() || !files_->maybeSave()) {
        e->ignore();
        return;
    }
    QApplication::setOverrideCursor(Qt::WaitCursor);
    statusBar()->showMessage(tr("Stopping the background work..."));
    jobs_->cancelAll();
    jobs_->waitAll(kQuitWaitMs);
    QApplication::restoreOverrideCursor();
    // Deliver the jobs' endings (the flow keeps its restart file on the worker already).
    QCoreApplication::sendPostedEvents();
    e->accept();
}

bool MainWindow::confirmQuitWhileWorking() {
    QStringList running;
    for (Job* job : jobs_->jobs()) running << job->title();
    QString detail;
    if (flow_->runner().running()) {
        const QString restart = flow_->runner().restartPath();
        detail = restart.isEmpty()
                     ? tr("The flow solve's state is lost: the project has not been saved, so there is no place to keep "
                          "it (save the project first to be able to continue the run later).")
                     : tr("The flow solve stops at its next iteration and keeps its state in %1; Flow > Continue resumes "
                          "it when you open the project again.")
                           .arg(restart);
    }
    if (optimization_->runner().running()) {
        if (!detail.isEmpty()) detail += QStringLiteral("\n\n");
        detail += tr("The optimization stops within its current flow iteration. Its history (%1) "
                     "keeps every evaluation "
                     "finished so far; Optimize > Resume continues it, also after the project is "
                     "opened again (the "
                     "interrupted evaluation is solved again).")
                      .arg(optimization_->runner().historyJsonlPath());
    }
    QMessageBox box(QMessageBox::Question, tr("Quit While Working"),
                    tr("%1 still running. Stop and quit?").arg(running.join(tr(" and ")) +
                                                              (running.size() == 1 ? tr(" is") : tr(" are"))),
                    QMessageBox::NoButton, this);
    box.setObjectName(QStringLiteral("quitWhileWorking"));
    if (!detail.isEmpty()) box.setInformativeText(detail);
    QPushButton* stop = box.addButton(tr("Stop and Quit"), QMessageBox::AcceptRole);
    stop->setObjectName(QStringLiteral("stopAndQuit"));
    QPushButton* keep = box.addButton(tr("Keep Working"), QMessageBox::RejectRole);
    box.setDefaultButton(keep);
    box.exec();
    return box.clickedButton() == stop;
}

// ---- Mesh preview and flow --------------------------------------------------------------------------

void MainWindow::startMeshPreview() {
    if (previewer_->state() == MeshPreviewer::State::Running) {
        previewer_->cancel();
        return;
    }
    if (!document_->problems().isEmpty()) {
        const auto answer =
            QMessageBox::warning(this, tr("Mesh Preview"),
                                 tr("The current state has problems:\n\n%1\n\nPreview the mesh anyway?").arg(problemText()),
                                 QMessageBox::Yes | QMessageBox::Cancel, QMessageBox::Cancel);
        if (answer != QMessageBox::Yes) return;
    }
    QString error;
    if (!previewer_->start(&error)) {
        statusBar()->showMessage(error, 8000);
        return;
    }
    if (auto* d = findChild<QDockWidget*>(QStringLiteral("meshQualityDock"))) {
        d->show();
        d->raise();
    }
}

void MainWindow::startFlowSolve(bool continueRun) {
    if (flow_->runner().running()) return;
    if (continueRun)
        flow_->continueRun();
    else
        flow_->solve();
}

void MainWindow::onMeshPreviewStateChanged() {
    using State = MeshPreviewer::State;
    switch (previewer_->state()) {
        case State::Ready:
            tree_->setGridState(counted(static_cast<long long>(previewer_->result()->grids.size()), tr("block"), tr("blocks")), true,
                                tr("The mesh preview's grid: %1").arg(previewer_->description()));
            if (!tree_->gridItem()->isDisabled() && tree_->gridItem()->checkState(0) != Qt::Checked)
                tree_->gridItem()->setCheckState(0, Qt::Checked);  // a new preview is shown
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
    applyResultVisibility();
    updateActions();
    updateDiagnostics();
}

void MainWindow::applyResultVisibility() {
    for (int p = 0; p < ModelTree::GridPartCount; ++p) meshScene_->setPartVisible(static_cast<MeshPart>(p), tree_->gridPartShown(p));
    // A grid's or a flow solution's wall lies on the geometry's surfaces: hide those while one
    // is shown.
    const bool gridWall = previewer_ && previewer_->state() == MeshPreviewer::State::Ready && tree_->gridPartShown(ModelTree::WallPart);
    const bool wall =
        gridWall || flowScene_->wallShown() || (optimization_ && optimization_->viewShown());
    const bool geometryShown = tree_->geometryItem()->checkState(0) == Qt::Checked;
    settingGeometry_ = true;
    if (wall && geometryShown) {
        tree_->geometryItem()->setCheckState(0, Qt::Unchecked);
        geometryHiddenForResults_ = true;
    } else if (!wall && geometryHiddenForResults_) {
        geometryHiddenForResults_ = false;
        if (!geometryShown) {
            tree_->geometryItem()->setCheckState(0, Qt::Checked);
        } else {  // checked again without a signal (a new document): show the surfaces ourselves
            scene_->setSurfacesVisible(true);
            scene_->setEdgesVisible(actions_->patchEdges->isChecked());
            actions_->surfaces->setChecked(true);
        }
    }
    settingGeometry_ = false;
    viewport_->requestRender();
}

// ---- FFD ----------------------------------------------------------------------------------------

void MainWindow::selectAllLatticePoints() {
    int l = selection_->lattice();
    if (l < 0 && document_->latticeCount() > 0) l = 0;
    if (l < 0) return;
    std::vector<int> all(static_cast<std::size_t>(document_->lattices()[static_cast<std::size_t>(l)].controlCount()));
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    selection_->selectPoints(l, std::move(all));
}

void MainWindow::addLattice() {
    if (!document_->hasGeometry()) return;
    QString name;
    for (int k = document_->latticeCount();; ++k) {
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
    if (!ProjectFiles::guarded([&] { document_->addLattice(dialog.lattice(), dialog.stations()); }, &error)) {
        QMessageBox::critical(this, tr("Cannot add the lattice"), error);
        return;
    }
    selection_->selectLattice(document_->latticeCount() - 1);
    actions_->lattices->setChecked(true);
    resetCamera();
    viewport_->requestRender();
}

}  // namespace aero::ui
