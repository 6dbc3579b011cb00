#include "MeshPreview.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common/Error.h"
#include "common/Format.h"
#include "io/VtkXml.h"
#include "mesh/Extrusion.h"
#include "mesh/Plot3d.h"
#include "study/CaseEvaluator.h"

namespace aero::ui {

// ---- Quality metrics ----------------------------------------------------------------------------

const char* metricLabel(QualityMetric m) {
    switch (m) {
        case QualityMetric::ScaledJacobian:
            return "Scaled Jacobian";
        case QualityMetric::MinJacobian:
            return "Min. Jacobian";
        case QualityMetric::Orthogonality:
            return "Orthogonality";
        case QualityMetric::AspectRatio:
            return "Aspect ratio";
        case QualityMetric::Skewness:
            return "Skewness";
    }
    return "";
}

const char* metricField(QualityMetric m) {
    switch (m) {
        case QualityMetric::ScaledJacobian:
            return "scaled_jacobian";
        case QualityMetric::MinJacobian:
            return "min_jacobian";
        case QualityMetric::Orthogonality:
            return "orthogonality";
        case QualityMetric::AspectRatio:
            return "aspect_ratio";
        case QualityMetric::Skewness:
            return "skewness";
    }
    return "";
}

bool higherIsBetter(QualityMetric m) {
    return m == QualityMetric::ScaledJacobian || m == QualityMetric::MinJacobian ||
           m == QualityMetric::Orthogonality;
}

const std::vector<double>& metricValues(const mesh::CellQuality& q, QualityMetric m) {
    switch (m) {
        case QualityMetric::MinJacobian:
            return q.minJacobian;
        case QualityMetric::Orthogonality:
            return q.orthogonality;
        case QualityMetric::AspectRatio:
            return q.aspectRatio;
        case QualityMetric::Skewness:
            return q.skewness;
        case QualityMetric::ScaledJacobian:
            break;
    }
    return q.scaledJacobian;
}

const mesh::MetricSummary& metricSummary(const mesh::QualitySummary& s, QualityMetric m) {
    switch (m) {
        case QualityMetric::MinJacobian:
            return s.minJacobian;
        case QualityMetric::Orthogonality:
            return s.orthogonality;
        case QualityMetric::AspectRatio:
            return s.aspectRatio;
        case QualityMetric::Skewness:
            return s.skewness;
        case QualityMetric::ScaledJacobian:
            break;
    }
    return s.scaledJacobian;
}

std::array<double, 3> qualityColour(double t) {
    // Stops from bad (0) to good (1), interpolated in RGB.
    static constexpr double kStops[4][3] = {
        {0.78, 0.06, 0.10}, {0.96, 0.52, 0.18}, {0.98, 0.90, 0.58}, {0.74, 0.81, 0.92}};
    constexpr int kSegments = 3;
    t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
    const int seg = std::min(kSegments - 1, static_cast<int>(t * kSegments));
    const double s = t * kSegments - seg;
    std::array<double, 3> c{};
    for (int k = 0; k < 3; ++k)
        c[static_cast<std::size_t>(k)] = (1 - s) * kStops[seg][k] + s * kStops[seg + 1][k];
    return c;
}

std::array<double, 2> colourRange(const mesh::QualitySummary& summary, QualityMetric m) {
    const mesh::MetricSummary& s = metricSummary(summary, m);
    double lo = std::isfinite(s.min) ? s.min : s.lo;
    double hi = std::isfinite(s.max) ? s.max : s.hi;
    if (!(hi > lo)) {
        const double pad = std::max(1e-12, 1e-6 * std::abs(lo));
        lo -= pad;
        hi += pad;
    }
    return {lo, hi};
}

bool useLogScale(QualityMetric m, double lo, double hi) {
    if (!(lo > 0) || !std::isfinite(hi)) return false;
    if (m == QualityMetric::AspectRatio) return hi > 10 * lo;
    return m == QualityMetric::MinJacobian && hi > 100 * lo;
}

double qualityPosition(QualityMetric m, double value, double lo, double hi, bool logScale) {
    if (!std::isfinite(value)) return higherIsBetter(m) && value > 0 ? 1.0 : 0.0;
    double t = 0.5;
    if (logScale && value > 0) {
        t = (std::log10(value) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
    } else if (hi > lo) {
        t = (value - lo) / (hi - lo);
    }
    t = std::clamp(t, 0.0, 1.0);
    return higherIsBetter(m) ? t : 1.0 - t;
}

std::vector<long> rangeHistogram(const std::vector<mesh::CellQuality>& q, QualityMetric m,
                                 double lo, double hi, bool logScale, int bins) {
    std::vector<long> counts(static_cast<std::size_t>(std::max(1, bins)), 0);
    const bool useLog = logScale && lo > 0 && hi > lo;
    const double a = useLog ? std::log10(lo) : lo, b = useLog ? std::log10(hi) : hi;
    const double scale = b > a ? static_cast<double>(counts.size()) / (b - a) : 0.0;
    const long last = static_cast<long>(counts.size()) - 1;
    for (const mesh::CellQuality& block : q)
        for (double v : metricValues(block, m)) {
            if (!std::isfinite(v)) continue;
            const double x = useLog ? (v > 0 ? std::log10(v) : a) : v;
            const long bin = std::clamp(static_cast<long>(std::floor((x - a) * scale)), 0L, last);
            ++counts[static_cast<std::size_t>(bin)];
        }
    return counts;
}

// ---- The work ---------------------------------------------------------------------------------


MeshPreviewResult runMeshPreview(const MeshPreviewInput& in, const MeshPreviewProgress& progress,
                                 const std::atomic<bool>* cancel) {
    const auto t0 = std::chrono::steady_clock::now();
    MeshPreviewResult r;
    r.level = in.caseFile.mesh.level;
    r.wall = in.wall;
    if (progress) progress(0.0, format("Generating the %s grid blocks...", r.level.c_str()));
    // The one pipeline: a bad case (points outside every lattice, ...) throws, and the job
    // reports it as the CLI would.
    study::CaseEvaluator ev(in.caseFile, in.baseline);
    study::EvaluationRequest request;
    request.flow = false;
    request.worstCells = in.worstCells;
    double last = 0;
    const study::Evaluation e = ev.evaluate(ev.caseValues(), request, [&](const study::Progress& p) {
        if (!progress || p.message.empty()) return;
        if (p.fraction >= 0) last = p.fraction;
        std::string text = p.message;
        if (!text.empty()) text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
        progress(last, text + "...");
    }, cancel);
    if (e.status == study::EvaluationStatus::InvalidShape) throw GeometryError(e.message);
    if (e.status == study::EvaluationStatus::Cancelled || !e.mesh || e.mesh->grids.empty()) {
        r.status = MeshPreviewStatus::Cancelled;
        return r;
    }
    study::MeshResult& m = *e.mesh;
    r.mesh = std::move(m.control);
    r.grids = std::move(m.grids);
    r.quality = std::move(m.cellQuality);
    r.summary = std::move(m.quality);
    r.wallBend = m.wallBend;
    r.moved = m.moved;
    r.move = std::move(m.move);
    if (r.moved && r.move.status != mesh::SolveStatus::Converged) {
        // The grid is the last increment's, shown with the reason.
        r.status = MeshPreviewStatus::NotConverged;
        r.message = "the control grid's elasticity move did not converge: " + r.move.message;
    }
    // A folded grid is a result too: the window marks the cells and names the problem.
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (progress) progress(1.0, {});
    return r;
}

void writeGrid(const MeshPreviewResult& r, const std::string& path) {
    const std::size_t dot = path.find_last_of('.');
    std::string ext = dot == std::string::npos ? std::string() : path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == "vtm") {
        std::vector<io::StructuredBlock> grid;
        for (std::size_t b = 0; b < r.grids.size(); ++b) {
            io::StructuredBlock sb{r.grids[b].name, r.grids[b].dims, r.grids[b].xyz, {}, {}};
            for (int m = 0; m < kQualityMetrics; ++m) {
                const auto metric = static_cast<QualityMetric>(m);
                sb.cellData.push_back({metricField(metric), 1, metricValues(r.quality[b], metric)});
            }
            grid.push_back(std::move(sb));
        }
        std::vector<io::StructuredBlock> control;
        for (std::size_t b = 0; b < r.mesh.blocks.size(); ++b) {
            const nurbs::Volume<double> v = mesh::blockVolume(r.mesh, static_cast<int>(b));
            control.push_back({r.mesh.blocks[b].name, v.count, v.points, {}, {}});
        }
        io::writeVtm(path, {{"grid", std::move(grid)}, {"control_grid", std::move(control)}});
    } else if (ext == "xyz" || ext == "p3d" || ext == "fmt") {
        mesh::writePlot3d(path, r.grids, ext == "xyz");
    } else {
        throw InputError("'" + path + "': unknown grid format (use .vtm, .xyz or .p3d)");
    }
}

}  // namespace aero::ui
