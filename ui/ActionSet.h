#pragma once
// Every command of the main window as a typed QAction, made in one place with its text,
// shortcut, icon (resources/icons), tooltip and object name (for settings and tests): code
// refers to `actions.meshPreview`, never looks an action up by its name. The actions are not
// connected here (MainWindow connects them to what they do) and not placed (Menus.h puts them
// into the menu bar and the tool bar). GUI thread only.
#include <QIcon>
#include <QString>

class QAction;
class QObject;
class QUndoStack;

namespace aero::ui {

struct ActionSet {
    // File.
    QAction* open = nullptr;
    QAction* openSample = nullptr;          // the half-sphere with the paper's FFD lattice
    QAction* openSampleGeometry = nullptr;  // the half-sphere geometry alone
    QAction* save = nullptr;
    QAction* saveAs = nullptr;
    QAction* exportGeometry = nullptr;
    QAction* exportVtk = nullptr;
    QAction* exportGrid = nullptr;
    QAction* exportFlow = nullptr;
    QAction* screenshot = nullptr;
    QAction* quit = nullptr;
    // Edit (undo/redo: the undo stack's, whose text names the command; the tool bar's pair
    // keeps short labels).
    QAction* undo = nullptr;
    QAction* redo = nullptr;
    QAction* undoTool = nullptr;
    QAction* redoTool = nullptr;
    QAction* selectAllPoints = nullptr;
    QAction* resetPoints = nullptr;
    QAction* resetVariables = nullptr;
    // View (checkable ones first).
    QAction* surfaces = nullptr;
    QAction* patchEdges = nullptr;
    QAction* controlNets = nullptr;
    QAction* lattices = nullptr;
    QAction* sensitivity = nullptr;
    QAction* gradientArrows = nullptr;     // dJ/dB at the lattice points (after a gradient)
    QAction* surfaceSensitivity = nullptr; // dJ/dA . n as a colour map on the wall (after a gradient)
    QAction* orientationAxes = nullptr;
    QAction* resetCamera = nullptr;
    QAction* viewFront = nullptr;
    QAction* viewSide = nullptr;
    QAction* viewTop = nullptr;
    // FFD.
    QAction* addLattice = nullptr;
    QAction* removeLattice = nullptr;
    // Mesh.
    QAction* meshPreview = nullptr;
    QAction* meshCancel = nullptr;
    QAction* meshClear = nullptr;
    // Flow.
    QAction* flowSolve = nullptr;
    QAction* flowStop = nullptr;
    QAction* flowContinue = nullptr;
    QAction* computeSensitivities = nullptr;  // the objective's adjoint gradient of the design
    QAction* cancelSensitivities = nullptr;
    QAction* confirmPrediction = nullptr;     // a flow solve of the design as shown
    // Optimize.
    QAction* optimizeStart = nullptr;          // a new run (Start Over when a history exists: asks)
    QAction* optimizePause = nullptr;          // after the evaluation being computed
    QAction* optimizeStop = nullptr;           // within a flow iteration
    QAction* optimizeResume = nullptr;         // continue the history
    QAction* optimizeExportShape = nullptr;    // the shown evaluation's shape as IGES
    QAction* optimizeExportHistory = nullptr;  // the history files
    // Help.
    QAction* mouseAndKeys = nullptr;
    QAction* about = nullptr;

    /// Creates every action, owned by `owner`; undo/redo come from `stack`.
    ActionSet(QObject* owner, QUndoStack* stack);
};

/// An icon of resources/icons (e.g. "flow-solve"); when SVG icons cannot be drawn (no Qt SVG
/// icon engine installed) the style's `fallback` icon.
QIcon appIcon(const QString& name, int fallback = -1);

}  // namespace aero::ui
