#pragma once
// The live residual history of a flow solve: the relative residual ||R|| / ||R0|| against the
// nonlinear iteration on a log scale, one point per iteration as the reports arrive, the steps
// solved with the exact Jacobian (Newton) as filled circles and those with the approximate,
// lumped Jacobian as hollow squares on a shaded band ("approximate"), rejected attempts as
// crosses, a grid-sequencing pre-solve as its own grey line, and the case's tolerance as a
// dashed line. Its CSV export is the CLI's residual CSV with the phase and rejections added.
// GUI thread only; no VTK.
#include <vector>

#include "FlowRun.h"
#include "PlotWidget.h"

namespace aero::ui {

class ResidualPlot : public PlotWidget {
    Q_OBJECT

  public:
    explicit ResidualPlot(QWidget* parent = nullptr);

    /// Empties the plot for a new run with this relative tolerance.
    void begin(double tolerance);
    /// Adds one report (reports without an iteration are ignored).
    void add(const FlowRunProgress& p);
    /// Accepted iterations plotted (the case's grid, not the coarse pre-solve).
    int points() const { return accepted_; }
    int rejectedPoints() const { return rejected_; }
    /// Iterations plotted as solved with the exact Jacobian / the approximate one.
    int exactPoints() const;
    int approximatePoints() const;

  private:
    QString csv() const;
    void updateBands();

    std::vector<FlowRunProgress> reports_;
    double tolerance_ = 1e-10;
    int accepted_ = 0, rejected_ = 0;
    int line_ = -1, exact_ = -1, approximate_ = -1, rejectedSeries_ = -1, coarse_ = -1, toleranceSeries_ = -1;
};

}  // namespace aero::ui
