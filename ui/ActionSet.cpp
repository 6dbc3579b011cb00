#include "ActionSet.h"

#include <QAction>
#include <QApplication>
#include <QKeySequence>
#include <QStyle>
#include <QUndoStack>

#include "Resources.h"

namespace aero::ui {

QIcon appIcon(const QString& name, int fallback) {
    initResources();
    QIcon icon(QStringLiteral(":/icons/%1.svg").arg(name));
    // Without the SVG icon engine (the libqt6svg6 runtime package) the icon draws nothing.
    if (icon.pixmap(16, 16).isNull())
        return fallback >= 0 ? QApplication::style()->standardIcon(static_cast<QStyle::StandardPixmap>(fallback)) : QIcon();
    return icon;
}

ActionSet::ActionSet(QObject* owner, QUndoStack* stack) {
    auto make = [owner](const QString& text, const char* name, const QString& tip = {}) {
        auto* a = new QAction(text, owner);
        a->setObjectName(QString::fromLatin1(name));
        if (!tip.isEmpty()) {
            a->setToolTip(tip);
            a->setStatusTip(tip);
        }
        return a;
    };
    auto checkable = [&](const QString& text, const char* name, bool on, const QString& tip = {}) {
        QAction* a = make(text, name, tip);
        a->setCheckable(true);
        a->setChecked(on);
        return a;
    };

    // File.
    open = make(QObject::tr("&Open..."), "actionOpen", QObject::tr("Open a project (.json case), an IGES or STEP file or a patch set"));
    open->setIcon(appIcon(QStringLiteral("open"), QStyle::SP_DialogOpenButton));
    open->setShortcut(QKeySequence::Open);
    openSample = make(QObject::tr("Half-Sphere with the Paper's &FFD Lattice"), "actionOpenSample");
    openSampleGeometry = make(QObject::tr("Half-Sphere &Geometry Only"), "actionOpenSampleGeometry");
    save = make(QObject::tr("&Save"), "actionSave", QObject::tr("Save the project (a case file)"));
    save->setIcon(appIcon(QStringLiteral("save"), QStyle::SP_DialogSaveButton));
    save->setShortcut(QKeySequence::Save);
    saveAs = make(QObject::tr("Save &As..."), "actionSaveAs");
    saveAs->setShortcut(QKeySequence::SaveAs);
    exportGeometry = make(QObject::tr("Deformed &Geometry (IGES, STEP, JSON)..."), "actionExportGeometry");
    exportVtk = make(QObject::tr("Geometry for &ParaView (VTK)..."), "actionExportVtk");
    exportGrid = make(QObject::tr("G&rid (VTK, Plot3D)..."), "actionExportGrid",
                      QObject::tr("The previewed grid: VTK multiblock with the quality fields, or Plot3D"));
    exportFlow = make(QObject::tr("&Flow Solution (VTK)..."), "actionExportFlow",
                      QObject::tr("The flow solution for ParaView: density, velocity, pressure, Cp, Mach, entropy; the wall's Cp"));
    screenshot = make(QObject::tr("Screens&hot (PNG)..."), "actionSaveScreenshot");
    screenshot->setShortcut(QKeySequence(QObject::tr("Ctrl+Alt+S")));
    quit = make(QObject::tr("&Quit"), "actionQuit");
    quit->setShortcut(QKeySequence::Quit);
    quit->setMenuRole(QAction::QuitRole);

    // Edit.
    undo = stack->createUndoAction(owner, QObject::tr("&Undo"));
    undo->setObjectName(QStringLiteral("actionUndo"));
    undo->setShortcut(QKeySequence::Undo);
    undo->setIcon(appIcon(QStringLiteral("undo"), QStyle::SP_ArrowBack));
    redo = stack->createRedoAction(owner, QObject::tr("&Redo"));
    redo->setObjectName(QStringLiteral("actionRedo"));
    redo->setShortcut(QKeySequence::Redo);
    redo->setIcon(appIcon(QStringLiteral("redo"), QStyle::SP_ArrowForward));
    undoTool = make(QObject::tr("Undo"), "toolUndo");
    undoTool->setIcon(undo->icon());
    redoTool = make(QObject::tr("Redo"), "toolRedo");
    redoTool->setIcon(redo->icon());
    selectAllPoints = make(QObject::tr("Select All Lattice Points"), "actionSelectAllPoints");
    selectAllPoints->setShortcut(QKeySequence(QObject::tr("Ctrl+Shift+A")));
    resetPoints = make(QObject::tr("Reset Selected Lattice Points"), "actionResetPoints");
    resetPoints->setShortcut(QKeySequence(Qt::Key_Delete));
    resetPoints->setShortcutContext(Qt::WidgetWithChildrenShortcut);
    resetVariables = make(QObject::tr("Reset Design Variables"), "actionResetVariables");

    // View.
    surfaces = checkable(QObject::tr("&Surfaces"), "actionSurfaces", true);
    patchEdges = checkable(QObject::tr("Patch &Edges"), "actionPatchEdges", true);
    controlNets = checkable(QObject::tr("&Control Nets"), "actionControlNets", false);
    lattices = checkable(QObject::tr("FFD &Lattices"), "actionLattices", true);
    lattices->setShortcut(QKeySequence(QObject::tr("Ctrl+L")));
    lattices->setIcon(appIcon(QStringLiteral("lattices")));
    sensitivity = checkable(QObject::tr("Sensitivity &Arrows"), "actionSensitivity", false,
                            QObject::tr("Arrows dS/dv of the selected design variable"));
    sensitivity->setIcon(appIcon(QStringLiteral("sensitivity")));
    gradientArrows = checkable(QObject::tr("&Gradient Arrows dJ/dB"), "actionGradientArrows", true,
                               QObject::tr("Arrows at the lattice points in the direction that improves the objective "
                                           "(dJ/dB, signed by the objective's sense; the longest drawn at a tenth of "
                                           "the model), after Flow \u25b8 Compute Sensitivities"));
    surfaceSensitivity =
        checkable(QObject::tr("Surface Sensitivity dJ/dA\u00b7n"), "actionSurfaceSensitivity", false,
                  QObject::tr("Colours the wall by the objective's gradient with respect to the geometry's control "
                              "points (dJ/dA, after Flow \u25b8 Compute Sensitivities), interpolated on the surface "
                              "with the patches' own basis and projected on the outward normal: red where pushing the "
                              "wall out increases J, blue where it decreases J. Each control point's share of the "
                              "wall, not a derivative per unit area"));
    orientationAxes = checkable(QObject::tr("Orientation A&xes"), "actionOrientationAxes", true);
    resetCamera = make(QObject::tr("&Reset Camera"), "actionResetCamera");
    resetCamera->setShortcut(QKeySequence(QObject::tr("Ctrl+R")));
    resetCamera->setIcon(appIcon(QStringLiteral("camera-reset")));
    viewFront = make(QObject::tr("&Front (from upstream)"), "actionViewFront");
    viewFront->setShortcut(QKeySequence(QStringLiteral("Ctrl+1")));
    viewSide = make(QObject::tr("S&ide (from +Y)"), "actionViewSide");
    viewSide->setShortcut(QKeySequence(QStringLiteral("Ctrl+2")));
    viewTop = make(QObject::tr("&Top (planform)"), "actionViewTop");
    viewTop->setShortcut(QKeySequence(QStringLiteral("Ctrl+3")));

    // FFD.
    addLattice = make(QObject::tr("&Add Lattice..."), "actionAddLattice",
                      QObject::tr("Place an FFD lattice around the geometry or the selected patches"));
    addLattice->setShortcut(QKeySequence(QObject::tr("Ctrl+Shift+L")));
    addLattice->setIcon(appIcon(QStringLiteral("lattice-add")));
    removeLattice = make(QObject::tr("&Remove Selected Lattice"), "actionRemoveLattice");

    // Mesh.
    meshPreview = make(QObject::tr("&Preview"), "actionMeshPreview",
                       QObject::tr("Generate the volume grid at the case's level, move it to the deformed geometry and "
                                   "check its cells"));
    meshPreview->setShortcut(QKeySequence(QObject::tr("Ctrl+M")));
    meshPreview->setIconText(QObject::tr("Mesh Preview"));
    meshPreview->setIcon(appIcon(QStringLiteral("mesh-preview")));
    meshCancel = make(QObject::tr("&Cancel Preview"), "actionMeshCancel");
    meshClear = make(QObject::tr("C&lear Preview"), "actionMeshClear");

    // Flow.
    flowSolve = make(QObject::tr("&Solve"), "actionFlowSolve",
                     QObject::tr("Solve the Euler flow around the shape as shown (grid, mesh movement, Newton-Krylov) "
                                 "in the background, with the residual plotted live"));
    flowSolve->setShortcut(QKeySequence(Qt::Key_F5));
    flowSolve->setIconText(QObject::tr("Solve Flow"));
    flowSolve->setIcon(appIcon(QStringLiteral("flow-solve"), QStyle::SP_MediaPlay));
    flowStop = make(QObject::tr("S&top"), "actionFlowStop",
                    QObject::tr("Stop the flow solve between iterations; the state reached is kept"));
    flowStop->setShortcut(QKeySequence(Qt::SHIFT | Qt::Key_F5));
    flowStop->setIconText(QObject::tr("Stop"));
    flowStop->setIcon(appIcon(QStringLiteral("flow-stop"), QStyle::SP_MediaStop));
    flowContinue = make(QObject::tr("&Continue Stopped Run"), "actionFlowContinue",
                        QObject::tr("Continue the run that was stopped, from its restart file"));
    flowContinue->setIcon(appIcon(QStringLiteral("flow-continue"), QStyle::SP_MediaSeekForward));

    computeSensitivities = make(QObject::tr("Compute &Sensitivities"), "actionComputeSensitivities",
                                QObject::tr("Solve the flow of the design as shown and its adjoint, in the background: "
                                            "the objective's dJ/dv next to every slider, dJ/dB as arrows at the lattice "
                                            "points and a first-order prediction of J while you drag. The objective is "
                                            "the case's optimization objective, else CL/CD"));
    computeSensitivities->setShortcut(QKeySequence(Qt::Key_F6));
    cancelSensitivities = make(QObject::tr("Cancel Sensitivities"), "actionCancelSensitivities",
                               QObject::tr("Stop the sensitivity computation"));
    confirmPrediction = make(QObject::tr("Confirm &Prediction with a Flow Solve"), "actionConfirmPrediction",
                             QObject::tr("Solve the flow of the design as shown and compare the actual change of the "
                                         "objective with the first-order prediction"));

    // Optimize.
    optimizeStart = make(
        QObject::tr("&Start"), "actionOptimizeStart",
        QObject::tr(
            "Run the case's optimization in the background: each evaluation a flow solve, each "
            "gradient an adjoint, the history written as it runs and plotted live"));
    optimizeStart->setShortcut(QKeySequence(Qt::Key_F7));
    optimizeStart->setIconText(QObject::tr("Optimize"));
    optimizeStart->setIcon(appIcon(QStringLiteral("optimize"), QStyle::SP_MediaPlay));
    optimizePause =
        make(QObject::tr("&Pause"), "actionOptimizePause",
             QObject::tr(
                 "Pause after the evaluation (or gradient) being computed; Resume continues it"));
    optimizePause->setIconText(QObject::tr("Pause"));
    optimizePause->setIcon(appIcon(QStringLiteral("optimize-pause"), QStyle::SP_MediaPause));
    optimizeStop = make(
        QObject::tr("S&top"), "actionOptimizeStop",
        QObject::tr(
            "Stop within the current flow iteration (the interrupted evaluation is solved again "
            "on Resume)"));
    optimizeStop->setShortcut(QKeySequence(Qt::SHIFT | Qt::Key_F7));
    optimizeStop->setIcon(appIcon(QStringLiteral("flow-stop"), QStyle::SP_MediaStop));
    optimizeResume =
        make(QObject::tr("&Resume"), "actionOptimizeResume",
             QObject::tr(
                 "Continue the optimization's history (also one a closed or crashed session left): "
                 "what it holds is replayed, not solved again"));
    optimizeResume->setIconText(QObject::tr("Resume"));
    optimizeResume->setIcon(
        appIcon(QStringLiteral("optimize-resume"), QStyle::SP_MediaSeekForward));
    optimizeExportShape =
        make(QObject::tr("Export Evaluation's &Shape (IGES)..."), "actionOptimizeExportShape",
             QObject::tr("The shape of the evaluation shown (the history slider) as exact IGES"));
    optimizeExportHistory =
        make(QObject::tr("Export &History..."), "actionOptimizeExportHistory",
             QObject::tr("The optimization history: every evaluation and gradient (CSV), the major "
                         "iterations (CSV) and the exact records (JSON lines)"));

    // Help.
    mouseAndKeys = make(QObject::tr("&Mouse and Keys"), "actionMouseAndKeys");
    about = make(QObject::tr("&About Aeroform"), "actionAbout");
}

}  // namespace aero::ui
