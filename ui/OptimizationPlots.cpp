#include "OptimizationPlots.h"

#include <QDir>
#include <QGridLayout>
#include <QRegularExpression>
#include <QSaveFile>
#include <cmath>
#include <cstring>
#include <limits>

#include "PlotWidget.h"
#include "ResidualPlot.h"

namespace aero::ui {

namespace {

using Kind = study::OptimizationRecord::Kind;

const QColor kEvaluation(120, 126, 140);
const QColor kIterate(34, 88, 176);
const QColor kFeasibility(214, 118, 24);
const QColor kBound(60, 140, 60);
const QColor kFailedBand(250, 222, 222);
const QColor kShownBand(214, 228, 250);
const QColor kComparedBand(236, 226, 250);
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

PlotWidget* makePlot(QWidget* parent, const char* name, const QString& title, const QString& yLabel,
                     const QString& yUnit = {}) {
    auto* p = new PlotWidget(parent);
    p->setObjectName(QString::fromLatin1(name));
    p->setTitle(title);
    p->xAxis().label = QObject::tr("Evaluation");
    p->xAxis().minimumSpan = 4;
    p->yAxis().label = yLabel;
    p->yAxis().unit = yUnit;
    p->setPlaceholder(QObject::tr("No data yet"));
    return p;
}

PlotSeries line(const QString& name, QColor colour, MarkerShape marker = MarkerShape::Circle,
                double width = 1.5) {
    PlotSeries s;
    s.name = name;
    s.colour = colour;
    s.lineWidth = width;
    s.marker = marker;
    s.markerSize = 5;
    return s;
}

PlotSeries dashed(const QString& name, QColor colour) {
    PlotSeries s;
    s.name = name;
    s.colour = colour;
    s.lineWidth = 1.2;
    s.lineStyle = Qt::DashLine;
    return s;
}

// A horizontal line across the evaluations plotted so far.
std::vector<QPointF> level(double y, int evaluations) {
    return {{1.0, y}, {std::max(2.0, static_cast<double>(evaluations)), y}};
}

// The objective's axis label: short, as the plots are small (the title says it in words).
QString objectiveLabel(const std::string& name) {
    if (name == "pressure") return QObject::tr("Mismatch J");
    return QString::fromStdString(name);
}

// The objective plot's title: "Maximize lift-to-drag ratio".
QString objectiveTitle(const std::string& name, bool maximize) {
    QString what = QString::fromStdString(name);
    if (name == "CL/CD") what = QObject::tr("lift-to-drag ratio");
    if (name == "CL") what = QObject::tr("lift");
    if (name == "CD") what = QObject::tr("drag");
    if (name == "CM") what = QObject::tr("pitching moment");
    if (name == "CY") what = QObject::tr("side force");
    if (name == "pressure") what = QObject::tr("pressure mismatch");
    return (maximize ? QObject::tr("Maximize %1") : QObject::tr("Minimize %1")).arg(what);
}

// The objective plot's short title: "Max. CL/CD".
QString objectiveShortTitle(const std::string& name, bool maximize) {
    const QString what =
        name == "pressure" ? QObject::tr("mismatch") : QString::fromStdString(name);
    return (maximize ? QObject::tr("Max. %1") : QObject::tr("Min. %1")).arg(what);
}

QString csvNumber(double v) {
    return std::isfinite(v) ? QString::number(v, 'g', 17) : QString();
}

QString csvText(QString s) {
    if (!s.contains(QLatin1Char(',')) && !s.contains(QLatin1Char('"')) &&
        !s.contains(QLatin1Char('\n')))
        return s;
    s.replace(QLatin1Char('"'), QStringLiteral("\"\""));
    s.replace(QLatin1Char('\n'), QLatin1Char(' '));
    return QLatin1Char('"') + s + QLatin1Char('"');
}

}  // namespace

QString plotFileName(const QString& title) {
    QString s = title.toLower();
    s.replace(QRegularExpression(QStringLiteral("[^a-z0-9]+")), QStringLiteral("_"));
    while (s.endsWith(QLatin1Char('_'))) s.chop(1);
    while (s.startsWith(QLatin1Char('_'))) s.remove(0, 1);
    return s.isEmpty() ? QStringLiteral("plot") : s;
}

OptimizationPlots::OptimizationPlots(QWidget* parent) : QWidget(parent) {
    setObjectName(QStringLiteral("optimizationPlots"));
    auto* grid = new QGridLayout(this);
    grid->setContentsMargins(2, 2, 2, 2);
    grid->setSpacing(4);
    objective_ = makePlot(this, "objectivePlot", tr("Objective"), objectiveLabel("CL/CD"));
    optimality_ = makePlot(this, "optimalityPlot", tr("Optimality"), tr("Opt. / violation"));
    optimality_->yAxis().log = true;
    optimality_->setPlaceholder(tr("No data yet"));
    lift_ = makePlot(this, "liftPlot", tr("Lift coefficient"), tr("CL"));
    drag_ = makePlot(this, "dragPlot", tr("Drag coefficient"), tr("CD"));
    ratio_ = makePlot(this, "liftToDragPlot", tr("Lift-to-drag ratio"), tr("L/D"));
    volume_ = makePlot(this, "volumePlot", tr("Enclosed volume"), tr("Volume"), tr("length\u00b3"));
    mach_ = makePlot(this, "machPlot", tr("Largest Mach"), tr("Max. local Mach"));
    residual_ = new ResidualPlot(this);
    residual_->setObjectName(QStringLiteral("optimizationResidualPlot"));
    residual_->setTitle(tr("Flow residual of the current evaluation"));
    residual_->setPlaceholder(tr("No solve yet"));
    const std::vector<PlotWidget*> all = plots();
    for (std::size_t i = 0; i < all.size(); ++i) {
        all[i]->setMinimumSize(140, 140);  // four across below the view, beside the side docks
        grid->addWidget(all[i], static_cast<int>(i / 4), static_cast<int>(i % 4));
    }
    for (int c = 0; c < 4; ++c) grid->setColumnStretch(c, 1);
    for (PlotWidget* p : {objective_, lift_, drag_, ratio_, volume_, mach_})
        p->setCsvWriter([this] { return evaluationsCsv(); });
    optimality_->setCsvWriter([this] { return iterationsCsv(); });
    rebuild();
}

std::vector<PlotWidget*> OptimizationPlots::plots() const {
    return {objective_, optimality_, lift_, drag_, ratio_, volume_, mach_, residual_};
}

void OptimizationPlots::setProblem(const io::CaseFile& c) {
    const io::OptimizationCase& oc = c.optimization;
    objectiveName_ = oc.objective;
    maximize_ = oc.maximize;
    logObjective_ = oc.objective == "pressure";
    minVolume_ = c.minVolume;
    liftConstraint_ = oc.liftConstraint;
    targetCL_ = oc.targetCL;
    optimalityTolerance_ = oc.optimalityTolerance;
    feasibilityTolerance_ = oc.feasibilityTolerance;
    objective_->yAxis().label = objectiveLabel(objectiveName_);
    objective_->yAxis().unit =
        logObjective_ ? tr("(\u03c1\u221e a\u221e\u00b2)\u00b2 length\u00b2") : QString();
    objective_->yAxis().log = logObjective_;
    objective_->setTitle(objectiveShortTitle(objectiveName_, maximize_));
    objective_->setToolTip(objectiveTitle(objectiveName_, maximize_));
    rebuild();
}

void OptimizationPlots::setHistory(const OptimizationHistory& h) {
    evaluations_.clear();
    for (const auto& e : h.evaluations()) evaluations_.push_back(e.record);
    iterations_ = h.iterations();
    iterateEvaluation_.assign(iterations_.size(), 0);
    for (std::size_t i = 0; i < iterations_.size(); ++i) {
        const std::vector<double>& x = iterations_[i].x;
        const int last =
            std::min<int>(iterations_[i].evaluations, static_cast<int>(evaluations_.size()));
        for (int k = last; k >= 1; --k) {
            const std::vector<double>& y = evaluations_[static_cast<std::size_t>(k - 1)].x;
            if (y.size() == x.size() &&
                std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0) {
                iterateEvaluation_[i] = k;
                break;
            }
        }
        if (iterateEvaluation_[i] == 0) iterateEvaluation_[i] = std::max(1, last);
    }
    rebuild();
}

void OptimizationPlots::setShown(int evaluation, int compared) {
    shown_ = evaluation;
    compared_ = compared;
    updateBands();
}

void OptimizationPlots::rebuild() {
    const int n = static_cast<int>(evaluations_.size());
    auto value = [](const study::OptimizationRecord& r, double v) { return r.ok ? v : kNaN; };

    // Objective: every converged evaluation, and the iterates joined.
    objective_->clearSeries();
    PlotSeries all = line(tr("evaluation"), kEvaluation, MarkerShape::Circle, 0);
    all.markerSize = 4.5;
    for (const auto& r : evaluations_)
        if (r.ok && std::isfinite(r.J)) all.points.emplace_back(r.index, r.J);
    objective_->addSeries(all);
    PlotSeries iterates = line(tr("major iterate"), kIterate);
    for (std::size_t i = 0; i < iterations_.size(); ++i) {
        const int k = iterateEvaluation_[i];
        if (k >= 1 && k <= n && evaluations_[static_cast<std::size_t>(k - 1)].ok)
            iterates.points.emplace_back(k, evaluations_[static_cast<std::size_t>(k - 1)].J);
    }
    iterates.legend = !iterates.points.empty();
    objective_->addSeries(iterates);

    // Optimality and feasibility at the iterations (log: a zero violation is not drawn).
    optimality_->clearSeries();
    PlotSeries opt = line(tr("optimality"), kIterate);
    PlotSeries feas = line(tr("feasibility (> 0)"), kFeasibility, MarkerShape::Square);
    for (std::size_t i = 0; i < iterations_.size(); ++i) {
        const double x = iterateEvaluation_[i];
        opt.points.emplace_back(x,
                                iterations_[i].optimality > 0 ? iterations_[i].optimality : kNaN);
        feas.points.emplace_back(
            x, iterations_[i].feasibility > 0 ? iterations_[i].feasibility : kNaN);
    }
    optimality_->addSeries(opt);
    optimality_->addSeries(feas);
    if (!iterations_.empty()) {
        PlotSeries t = dashed(tr("optimality tolerance"), kIterate.lighter(140));
        t.points = level(optimalityTolerance_, n);
        optimality_->addSeries(t);
        if (feasibilityTolerance_ != optimalityTolerance_) {
            PlotSeries f = dashed(tr("feasibility tolerance"), kFeasibility.lighter(130));
            f.points = level(feasibilityTolerance_, n);
            optimality_->addSeries(f);
        }
    }

    // Forces.
    auto forces = [&](PlotWidget* p, const QString& name, QColor colour, auto get) {
        p->clearSeries();
        PlotSeries s = line(name, colour);
        s.legend = false;
        for (const auto& r : evaluations_) s.points.emplace_back(r.index, value(r, get(r)));
        p->addSeries(s);
    };
    forces(lift_, tr("CL"), QColor(34, 120, 90),
           [](const study::OptimizationRecord& r) { return r.CL; });
    if (liftConstraint_ && n > 0) {
        PlotSeries t = dashed(tr("target CL"), kBound);
        t.points = level(targetCL_, n);
        lift_->addSeries(t);
    }
    forces(drag_, tr("CD"), QColor(176, 60, 40),
           [](const study::OptimizationRecord& r) { return r.CD; });
    forces(ratio_, tr("L/D"), kIterate,
           [](const study::OptimizationRecord& r) { return r.CD != 0 ? r.CL / r.CD : kNaN; });

    // Volume against its bound (every evaluation has one: it is known before the flow).
    volume_->clearSeries();
    PlotSeries v = line(tr("volume"), QColor(110, 70, 160));
    for (const auto& r : evaluations_)
        v.points.emplace_back(r.index, std::isfinite(r.volume) ? r.volume : kNaN);
    volume_->addSeries(v);
    if (minVolume_ && n > 0) {
        const double bound = std::isnan(*minVolume_) ? evaluations_.front().volume : *minVolume_;
        PlotSeries b =
            dashed(std::isnan(*minVolume_) ? tr("bound: the start's volume") : tr("bound"), kBound);
        b.points = level(bound, n);
        volume_->addSeries(b);
    } else {
        volume_->series(0).legend = false;
    }

    // The largest Mach number (the physics check).
    mach_->clearSeries();
    PlotSeries m = line(tr("max. Mach"), QColor(40, 40, 48));
    m.legend = false;
    for (const auto& r : evaluations_)
        m.points.emplace_back(r.index, r.ok && r.maxMach > 0 ? r.maxMach : kNaN);
    mach_->addSeries(m);
    if (n > 0) {
        PlotSeries sonic = dashed(tr("Mach 1"), QColor(190, 30, 40));
        sonic.points = level(1.0, n);
        mach_->addSeries(sonic);
    }
    updateBands();
}

void OptimizationPlots::updateBands() {
    std::vector<PlotBand> bands;
    for (const auto& r : evaluations_) {
        if (r.ok) continue;
        PlotBand b;
        b.x0 = r.index - 0.45;
        b.x1 = r.index + 0.45;
        b.colour = kFailedBand;
        b.label = tr("failed");
        bands.push_back(b);
    }
    auto mark = [&](int k, QColor colour) {
        if (k < 1 || k > static_cast<int>(evaluations_.size())) return;
        PlotBand b;
        b.x0 = k - 0.3;
        b.x1 = k + 0.3;
        b.colour = colour;
        bands.push_back(b);
    };
    mark(compared_, kComparedBand);
    mark(shown_, kShownBand);
    for (PlotWidget* p : {objective_, optimality_, lift_, drag_, ratio_, volume_, mach_}) {
        p->setBands(bands);
        p->changed();
    }
}

int OptimizationPlots::objectivePoints() const {
    return static_cast<int>(objective_->allSeries().front().points.size());
}

int OptimizationPlots::volumePoints() const {
    int k = 0;
    for (const QPointF& p : volume_->allSeries().front().points) k += std::isfinite(p.y()) ? 1 : 0;
    return k;
}

int OptimizationPlots::iterationPoints() const {
    return static_cast<int>(optimality_->allSeries().front().points.size());
}

QString OptimizationPlots::evaluationsCsv() const {
    QString out = QStringLiteral(
        "evaluation,status,objective,J,CL,CD,L/"
        "D,volume,half_span,projected_area,aspect_ratio,max_mach,alpha_deg,flow_iterations,message\n");
    for (const auto& r : evaluations_) {
        const bool flow = study::hasConvergedFlow(r);  // a refused converged flow keeps its forces
        const double ld = flow && r.CD != 0 ? r.CL / r.CD : kNaN;
        const geometry::Planform& f = r.planform;
        const bool planform = f.projectedArea > 0;
        out +=
            QStringLiteral("%1,%2,%3,%4,%5,%6,%7,%8,%9,%10,%11,%12,%13,%14,%15\n")
                .arg(r.index)
                .arg(csvText(QString::fromStdString(r.status)))
                .arg(csvNumber(r.ok ? r.objective : kNaN), csvNumber(r.ok ? r.J : kNaN),
                     csvNumber(flow ? r.CL : kNaN), csvNumber(flow ? r.CD : kNaN), csvNumber(ld),
                     csvNumber(r.volume), csvNumber(planform ? f.halfSpan : kNaN),
                     csvNumber(planform ? f.projectedArea : kNaN), csvNumber(planform ? f.aspectRatio : kNaN))
                .arg(csvNumber(flow ? r.maxMach : kNaN), csvNumber(r.alphaDeg))
                .arg(r.flowIterations)
                .arg(csvText(QString::fromStdString(r.message)));
    }
    return out;
}

QString OptimizationPlots::iterationsCsv() const {
    QString out = QStringLiteral(
        "iteration,evaluation,evaluations,gradients,objective,optimality,feasibility\n");
    for (std::size_t i = 0; i < iterations_.size(); ++i) {
        const auto& r = iterations_[i];
        out += QStringLiteral("%1,%2,%3,%4,%5,%6,%7\n")
                   .arg(r.index)
                   .arg(iterateEvaluation_[i])
                   .arg(r.evaluations)
                   .arg(r.gradients)
                   .arg(csvNumber(r.objective), csvNumber(r.optimality), csvNumber(r.feasibility));
    }
    return out;
}

bool OptimizationPlots::exportAll(const QString& folder, QString* error) const {
    QDir dir(folder);
    if (!dir.exists() && !QDir().mkpath(folder)) {
        if (error) *error = tr("Cannot create the folder '%1'.").arg(folder);
        return false;
    }
    for (PlotWidget* p : plots()) {
        if (p->width() < 100 || p->height() < 80)
            p->resize(p->sizeHint());  // never shown yet (a hidden dock)
        const QString base = dir.filePath(plotFileName(p->title()));
        if (!p->exportPng(base + QStringLiteral(".png")) ||
            !p->exportSvg(base + QStringLiteral(".svg")) ||
            !p->exportCsv(base + QStringLiteral(".csv"))) {
            if (error) *error = tr("Cannot write '%1'.").arg(base);
            return false;
        }
    }
    return true;
}

}  // namespace aero::ui
