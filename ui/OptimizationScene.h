#pragma once
// The VTK representation of an optimization's evaluations, added to one renderer:
//   shown      the evaluation on the history slider (the latest while a run is followed): its
//              flow solution's wall and symmetry plane coloured by the chosen field (entropy by
//              default, the paper's Figure 6) with the colour bar, or, when its solution is not
//              kept, its shape as a plain surface; its moved lattices;
//   compared   a second evaluation, side by side (moved above the first along +Z, its wall
//              coloured alike on the same colour range when its flow is kept; its symmetry
//              plane is not drawn) or overlaid (its shape as a translucent orange surface over
//              the first);
//   caption    which evaluations these are, in the view's top left corner.
// The scene keeps the snapshots it shows (shared, read-only). No VTK type is exposed. GUI thread
// only; the scene does not render by itself. Destroy it while the viewport's context can be made
// current (see PatchScene).
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "FlowRun.h"
#include "OptimizationRun.h"

class vtkRenderer;

namespace aero::ui {

class FlowScene;

enum class CompareMode { Off = 0, SideBySide, Overlay };

class OptimizationScene {
  public:
    explicit OptimizationScene(vtkRenderer* renderer);
    ~OptimizationScene();
    OptimizationScene(const OptimizationScene&) = delete;
    OptimizationScene& operator=(const OptimizationScene&) = delete;

    /// The evaluation shown (null: none).
    void setShown(std::shared_ptr<const EvaluationSnapshot> evaluation);
    const EvaluationSnapshot* shown() const;
    /// The evaluation compared with it (null or Off: none).
    void setCompared(std::shared_ptr<const EvaluationSnapshot> evaluation, CompareMode mode);
    const EvaluationSnapshot* compared() const;
    CompareMode compareMode() const;
    void setCaption(const std::string& text);
    std::string caption() const;

    /// Everything drawn or nothing (the document's design takes the view back).
    void setVisible(bool visible);
    bool visible() const;
    void setLatticesVisible(bool visible);
    bool latticesVisible() const;

    void setField(FlowField field);
    FlowField field() const;
    /// The shown evaluation's flow scene (colour range, parts).
    FlowScene& flow();
    /// Whether the shown evaluation's solution is drawn (else its shape, if any).
    bool flowDrawn() const;
    /// Whether anything of an evaluation is drawn.
    bool drawn() const;

    /// Where the compared evaluation is drawn relative to its data (zero unless side by side).
    std::array<double, 3> compareOffset() const;
    /// Points to keep in the camera's view: the lattices' and the corners of what is drawn.
    std::vector<double> viewPoints() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace aero::ui
