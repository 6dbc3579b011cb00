#include "study/DesignSweep.h"

#include <algorithm>

#include <Eigen/Dense>

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

RandomDesigns::RandomDesigns(const CaseEvaluator& ev, std::uint64_t seed, double spread, bool feasible)
    : ev_(&ev), rng_(seed), spread_(spread), feasible_(feasible) {
    if (!(spread >= 0)) throw CaseError("random designs: the spread must be >= 0");
    if (!feasible_) return;
    for (auto& c : ev.linearConstraints()) (c.lower == c.upper ? equalities_ : inequalities_).push_back(std::move(c));
}

std::vector<double> RandomDesigns::draw() {
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

bool RandomDesigns::satisfies(const std::vector<double>& v) const {
    const auto& vars = ev_->model()->design().variables();
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (v[i] < vars[i].lower - 1e-12 || v[i] > vars[i].upper + 1e-12) return false;
    }
    for (const auto& c : inequalities_) {
        double s = 0;
        for (std::size_t i = 0; i < v.size(); ++i) s += c.row[i] * v[i];
        if (s < c.lower || s > c.upper) return false;
    }
    return true;
}

std::vector<double> RandomDesigns::next() {
    if (!feasible_ || !ev_->model()) return draw();
    const int n = static_cast<int>(ev_->caseValues().size());
    const int m = static_cast<int>(equalities_.size());
    Eigen::MatrixXd A(m, n);
    Eigen::VectorXd b(m);
    for (int r = 0; r < m; ++r) {
        A.row(r) = Eigen::Map<const Eigen::RowVectorXd>(equalities_[r].row.data(), n);
        b[r] = equalities_[r].lower;
    }
    const Eigen::MatrixXd AAt = A * A.transpose();
    const Eigen::LDLT<Eigen::MatrixXd> solver(AAt);
    for (long t = 0; t < 1000000; ++t) {
        std::vector<double> v = draw();
        if (m > 0) {
            // Nearest point of the affine set A v = b: v - A^T (A A^T)^-1 (A v - b).
            Eigen::Map<Eigen::VectorXd> x(v.data(), n);
            x -= A.transpose() * solver.solve(A * x - b);
        }
        if (satisfies(v)) return v;
        ++linearRejections_;
    }
    throw CaseError("random designs: no draw in 10^6 satisfied the case's linear constraints (constraints.station_gap, "
                    "constraints.station_second_difference, constraints.symmetry) at spread " + std::to_string(spread_) + "; lower the spread");
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
