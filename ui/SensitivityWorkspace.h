#pragma once
// The sensitivities in the main window: Flow > Compute Sensitivities (SensitivityRunner) and the
// places its result is shown, kept in step with the document: dJ/dv next to the design
// variables' sliders (DesignVariablePanel), dJ/dB as arrows at the lattice points (View > Gradient
// Arrows), dJ/dA . n on the wall (View > Surface Sensitivity), the first-order prediction of J for
// the design as shown (the panel and the status bar's label); and View > Sensitivity, the arrows
// dS/dv of the current design variable on the surfaces. The choice of objective comes from the
// panel; the runner's messages go out through `message`.
//
// GUI thread only; no VTK here (the scenes keep it to itself). The window owns the runner, the
// panel, the label and the scenes, and renders.
#include <QObject>
#include <QString>

class QLabel;

namespace aero::ui {

struct ActionSet;
class DesignVariablePanel;
class Document;
class FlowRunner;
class LatticeScene;
class ModelTree;
class OptimizationWorkspace;
class OverlayScene;
class PatchScene;
class SensitivityRunner;
class SurfaceFieldScene;
class VtkViewport;

class SensitivityWorkspace : public QObject {
    Q_OBJECT

  public:
    /// Where the sensitivities are drawn; all owned by the window and alive as long as this.
    struct Views {
        VtkViewport* viewport = nullptr;
        PatchScene* patches = nullptr;           // the geometry as drawn (bounds, visible patches)
        LatticeScene* lattices = nullptr;        // which lattices are shown
        OverlayScene* shapeArrows = nullptr;     // dS/dv (View > Sensitivity)
        OverlayScene* gradientArrows = nullptr;  // dJ/dB at the lattice points
        SurfaceFieldScene* surfaceField = nullptr;  // dJ/dA . n on the wall
        DesignVariablePanel* variables = nullptr;
        ModelTree* tree = nullptr;
        QLabel* prediction = nullptr;  // the status bar's prediction
    };

    /// Connects the actions (compute, cancel, confirm, the view toggles), the panel, the runner
    /// and the document, and shows the runner's current state.
    SensitivityWorkspace(Document* document, SensitivityRunner* runner, FlowRunner* flow,
                         OptimizationWorkspace* optimization, const ActionSet& actions,
                         const Views& views, QObject* parent = nullptr);

    /// View > Sensitivity: the arrows dS/dv of the panel's current variable on the visible
    /// patches (none when the view is off or no variable is chosen), with the panel's note.
    void updateShapeArrows();

  signals:
    /// A message for the status bar.
    void message(const QString& text, int timeoutMs);

  private:
    void compute();
    void confirm();
    /// The objective choices: the case's objective when it has one, then the force coefficients.
    void fillObjectives();
    void chooseObjective(int index);
    /// The runner's result (or state) in the panel, then the arrows, the field and the prediction.
    void updateGradient();
    void updateGradientArrows();
    void updateSurfaceSensitivity();
    void updatePrediction();

    Document* document_;
    SensitivityRunner* runner_;
    FlowRunner* flow_;
    OptimizationWorkspace* optimization_;
    const ActionSet& actions_;
    Views views_;
};

}  // namespace aero::ui
