#include "study/DesignSweep.h"

#include <algorithm>

#include "common/Error.h"

namespace aero::study {

std::vector<double> scaledDesign(const CaseEvaluator& ev, double fraction) {
    std::vector<double> v = ev.caseValues();
    if (!ev.model()) return v;
    const auto& vars = ev.model()->design().variables();
    for (std::size_t i = 0; i < v.size(); ++i) {
        const double b = vars[i].baseline;
        v[i] = std::clamp(b + fraction * (v[i] - b), vars[i].lower, vars[i].upper);
    }
    return v;
}

RandomDesigns::RandomDesigns(const CaseEvaluator& ev, std::uint64_t seed, double spread)
    : ev_(&ev), rng_(seed), spread_(spread) {
    if (!(spread >= 0)) throw CaseError("random designs: the spread must be >= 0");
}

std::vector<double> RandomDesigns::next() {
    std::vector<double> v = ev_->caseValues();
    if (!ev_->model()) return v;
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    const auto& vars = ev_->model()->design().variables();
    for (std::size_t i = 0; i < v.size(); ++i) {
        const auto& d = vars[i];
        v[i] = std::clamp(d.baseline + spread_ * (d.upper - d.lower) * U(rng_), d.lower, d.upper);
    }
    return v;
}

ValidDraw drawValidDesign(CaseEvaluator& ev, RandomDesigns& designs, int maxDraws, const std::atomic<bool>* cancel) {
    ValidDraw out;
    EvaluationRequest shapeAndMesh;
    shapeAndMesh.flow = false;
    for (int d = 0; d < maxDraws; ++d) {
        if (cancel && cancel->load()) break;
        std::vector<double> v = designs.next();
        const Evaluation e = ev.evaluate(v, shapeAndMesh, {}, cancel);
        if (e.ok()) {
            out.values = std::move(v);
            out.accepted = true;
            return out;
        }
        if (e.status == EvaluationStatus::Cancelled) break;
        ++out.rejected;
        (e.status == EvaluationStatus::InvalidShape ? out.rejectedShape : out.rejectedMesh) += 1;
        out.lastReason = e.message;
    }
    return out;
}

}  // namespace aero::study
