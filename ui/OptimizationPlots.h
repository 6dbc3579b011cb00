#pragma once
// The live plots of an optimization (the paper's Figure 4), against the evaluation number:
//   Objective      the objective J of every converged evaluation (log scale for the pressure
//                  mismatch of an inverse design), the optimizer's major iterates joined by a line;
//   Optimality     first-order optimality and feasibility at the major iterations (log), with
//                  their tolerances dashed;
//   CL, CD, L/D    the forces of every converged evaluation (CL with its target when it is
//                  constrained);
//   Volume         the enclosed volume of every evaluation against its bound (dashed);
//   Max. Mach      the largest local Mach number of every evaluation (the path's physics check),
//                  with Mach 1 dashed;
//   Residual       the current flow solve's residual history (ResidualPlot).
// Failed evaluations are red bands labelled "failed" (the panel says why); the evaluation shown in
// the 3D view is a blue band. Every plot has hover values and exports PNG, SVG and CSV (its
// context menu); the evaluation plots' CSV is the whole table of evaluations, the optimality
// plot's that of the iterations. GUI thread only; no VTK.
#include <QWidget>
#include <vector>

#include "OptimizationHistory.h"
#include "io/CaseFile.h"

namespace aero::ui {

class PlotWidget;
class ResidualPlot;

class OptimizationPlots : public QWidget {
    Q_OBJECT

  public:
    explicit OptimizationPlots(QWidget* parent = nullptr);

    /// What the axes and bounds come from: the objective, its scale, the bounds and tolerances.
    void setProblem(const io::CaseFile& c);
    /// Redraws every evaluation plot from the history.
    void setHistory(const OptimizationHistory& h);
    /// The evaluation shown in the 3D view (0: none) and the one compared with it (0: none).
    void setShown(int evaluation, int compared = 0);

    PlotWidget* objectivePlot() const { return objective_; }
    PlotWidget* optimalityPlot() const { return optimality_; }
    PlotWidget* liftPlot() const { return lift_; }
    PlotWidget* dragPlot() const { return drag_; }
    PlotWidget* liftToDragPlot() const { return ratio_; }
    PlotWidget* volumePlot() const { return volume_; }
    PlotWidget* machPlot() const { return mach_; }
    ResidualPlot* residualPlot() const { return residual_; }
    /// Every plot, in the grid's order.
    std::vector<PlotWidget*> plots() const;

    /// Points plotted: converged evaluations on the objective, every evaluation on the volume,
    /// major iterations on the optimality.
    int objectivePoints() const;
    int volumePoints() const;
    int iterationPoints() const;

    /// Writes every plot as <name>.png, .svg and .csv into `folder`; false with *error.
    bool exportAll(const QString& folder, QString* error = nullptr) const;
    /// The table behind the evaluation plots (one row per evaluation) and the optimality plot.
    QString evaluationsCsv() const;
    QString iterationsCsv() const;

  private:
    void rebuild();
    void updateBands();

    PlotWidget* objective_ = nullptr;
    PlotWidget* optimality_ = nullptr;
    PlotWidget* lift_ = nullptr;
    PlotWidget* drag_ = nullptr;
    PlotWidget* ratio_ = nullptr;
    PlotWidget* volume_ = nullptr;
    PlotWidget* mach_ = nullptr;
    ResidualPlot* residual_ = nullptr;

    // The problem.
    std::string objectiveName_ = "CL/CD";
    bool maximize_ = true;
    bool logObjective_ = false;
    std::optional<double> minVolume_;  // NaN: the start's
    bool liftConstraint_ = false;
    double targetCL_ = 0;
    double optimalityTolerance_ = 1e-6, feasibilityTolerance_ = 1e-6;
    // The data, copied from the history (small: numbers per evaluation).
    std::vector<study::OptimizationRecord> evaluations_, iterations_;
    std::vector<int> iterateEvaluation_;  // per iteration: the evaluation at its x (0: unknown)
    int shown_ = 0, compared_ = 0;
};

/// A plot's file name from its title ("Lift coefficient" -> "lift_coefficient").
QString plotFileName(const QString& title);

}  // namespace aero::ui
