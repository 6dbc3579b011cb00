#include "ResidualPlot.h"

#include <cmath>

namespace aero::ui {

namespace {

const QColor kExact(34, 88, 176);
const QColor kApproximate(214, 118, 24);
const QColor kRejected(190, 30, 40);
const QColor kCoarse(140, 144, 152);

}  // namespace

ResidualPlot::ResidualPlot(QWidget* parent) : PlotWidget(parent) {
    setObjectName(QStringLiteral("residualPlot"));
    setTitle(tr("Residual history"));
    xAxis().label = tr("Nonlinear iteration");
    xAxis().minimumSpan = 10;
    yAxis().label = tr("Relative residual \u2016R\u2016/\u2016R\u2080\u2016");
    yAxis().log = true;
    setPlaceholder(tr("Flow > Solve plots the residual here, one point per iteration"));
    setCsvWriter([this] { return csv(); });
    begin(1e-10);
}

void ResidualPlot::begin(double tolerance) {
    reports_.clear();
    tolerance_ = tolerance;
    accepted_ = rejected_ = 0;
    clearSeries();
    PlotSeries coarse;
    coarse.name = tr("coarse grid (sequencing)");
    coarse.colour = kCoarse;
    coarse.lineWidth = 1.2;
    coarse.marker = MarkerShape::Circle;
    coarse.markerSize = 3.5;
    coarse_ = addSeries(coarse);
    PlotSeries line;
    line.name = tr("residual");
    line.colour = QColor(90, 100, 120);
    line.lineWidth = 1.3;
    line.legend = false;
    line_ = addSeries(line);
    PlotSeries exact;
    exact.name = tr("exact Jacobian (Newton)");
    exact.colour = kExact;
    exact.lineWidth = 0;
    exact.marker = MarkerShape::Circle;
    exact.markerSize = 5.5;
    exact_ = addSeries(exact);
    PlotSeries approximate;
    approximate.name = tr("approximate Jacobian");
    approximate.colour = kApproximate;
    approximate.lineWidth = 0;
    approximate.marker = MarkerShape::Square;
    approximate.markerSize = 5.5;
    approximate_ = addSeries(approximate);
    PlotSeries rejected;
    rejected.name = tr("rejected step");
    rejected.colour = kRejected;
    rejected.lineWidth = 0;
    rejected.marker = MarkerShape::Cross;
    rejected.markerSize = 7;
    rejectedSeries_ = addSeries(rejected);
    PlotSeries tol;
    tol.name = tr("tolerance");
    tol.colour = QColor(60, 140, 60);
    tol.lineWidth = 1.2;
    tol.lineStyle = Qt::DashLine;
    toleranceSeries_ = addSeries(tol);
    // Series without points stay out of the legend until they get some.
    for (int s : {coarse_, approximate_, rejectedSeries_, toleranceSeries_}) series(s).legend = false;
    changed();
}

void ResidualPlot::add(const FlowRunProgress& p) {
    if (!p.hasIteration) return;
    reports_.push_back(p);
    const flow::FlowIteration& it = p.iteration;
    const double y = it.relativeResidual > 0 ? it.relativeResidual : std::nan("");
    if (p.coarse) {
        if (it.rejected.empty()) {
            series(coarse_).points.push_back({double(p.iterationOffset + it.iteration), y});
            series(coarse_).legend = true;
        }
        changed();
        return;
    }
    const double x = p.iterationOffset + it.iteration;
    if (!it.rejected.empty()) {
        ++rejected_;
        series(rejectedSeries_).points.push_back({x, y});
        series(rejectedSeries_).legend = true;
    } else {
        ++accepted_;
        series(line_).points.push_back({x, y});
        const int s = it.exact ? exact_ : approximate_;
        series(s).points.push_back({x, y});
        series(s).legend = true;
        // The tolerance across the iterations so far.
        const double first = series(line_).points.front().x();
        series(toleranceSeries_).points = {{std::min(first, 1.0), tolerance_}, {std::max(x, first + 1), tolerance_}};
        series(toleranceSeries_).legend = true;
    }
    updateBands();
    changed();
}

int ResidualPlot::exactPoints() const {
    return static_cast<int>(allSeries()[static_cast<std::size_t>(exact_)].points.size());
}

int ResidualPlot::approximatePoints() const {
    return static_cast<int>(allSeries()[static_cast<std::size_t>(approximate_)].points.size());
}

void ResidualPlot::updateBands() {
    // One band per run of consecutive approximate steps (the start-up phase), half an iteration
    // wide on each side.
    std::vector<PlotBand> bands;
    for (const FlowRunProgress& p : reports_) {
        if (p.coarse || !p.iteration.rejected.empty() || p.iteration.exact) continue;
        const double x = p.iterationOffset + p.iteration.iteration;
        if (!bands.empty() && x - bands.back().x1 <= 0.51) {
            bands.back().x1 = x + 0.5;
        } else {
            PlotBand b;
            b.x0 = x - 0.5;
            b.x1 = x + 0.5;
            b.colour = QColor(252, 236, 214);
            b.label = tr("approximate");
            bands.push_back(b);
        }
    }
    setBands(std::move(bands));
}

QString ResidualPlot::csv() const {
    QString out = QStringLiteral(
        "iteration,residual,relative_residual,cfl,linear_iterations,linear_residual,step_scale,seconds,jacobian,rejected,"
        "grid\n");
    for (const FlowRunProgress& p : reports_) {
        const flow::FlowIteration& it = p.iteration;
        QString why = QString::fromStdString(it.rejected);
        why.replace(QLatin1Char('"'), QStringLiteral("\"\""));
        out += QStringLiteral("%1,%2,%3,%4,%5,%6,%7,%8,%9,\"%10\",%11\n")
                   .arg(p.iterationOffset + it.iteration)
                   .arg(it.residual, 0, 'g', 10)
                   .arg(it.relativeResidual, 0, 'g', 10)
                   .arg(it.cfl, 0, 'g', 6)
                   .arg(it.linearIterations)
                   .arg(it.linearResidual, 0, 'g', 6)
                   .arg(it.stepScale, 0, 'g', 6)
                   .arg(it.seconds, 0, 'f', 3)
                   .arg(it.exact ? QStringLiteral("exact") : QStringLiteral("approximate"))
                   .arg(why)
                   .arg(p.coarse ? QStringLiteral("coarse") : QStringLiteral("case"));
    }
    return out;
}

}  // namespace aero::ui
