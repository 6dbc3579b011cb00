#include "optimize/Problem.h"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

namespace aero::optimize {

double LinearRow::value(const std::vector<double>& x) const {
    double s = 0;
    for (std::size_t i = 0; i < index.size(); ++i) s += coefficient[i] * x[index[i]];
    return s;
}

void Problem::check() const {
    const std::size_t n = start.size();
    if (n == 0) throw std::invalid_argument("the problem has no variables");
    if (lower.size() != n || upper.size() != n) throw std::invalid_argument("bounds and start differ in size");
    for (std::size_t i = 0; i < n; ++i) {
        if (!(lower[i] <= upper[i])) throw std::invalid_argument("variable " + std::to_string(i) + ": lower bound above upper");
        if (!(start[i] >= lower[i] && start[i] <= upper[i])) {
            throw std::invalid_argument("variable " + std::to_string(i) + ": start outside its bounds");
        }
    }
    for (const LinearRow& r : linear) {
        if (r.index.size() != r.coefficient.size()) throw std::invalid_argument("row '" + r.name + "': sizes differ");
        for (int i : r.index) {
            if (i < 0 || static_cast<std::size_t>(i) >= n) throw std::invalid_argument("row '" + r.name + "': index out of range");
        }
        if (!(r.lower <= r.upper)) throw std::invalid_argument("row '" + r.name + "': lower bound above upper");
    }
    for (const ConstraintSpec& c : nonlinear) {
        if (!(c.lower <= c.upper)) throw std::invalid_argument("constraint '" + c.name + "': lower bound above upper");
    }
    if (!values) throw std::invalid_argument("the problem has no values function");
    if (!gradients) throw std::invalid_argument("the problem has no gradients function");
}

const char* statusName(Status s) {
    switch (s) {
        case Status::Converged: return "converged";
        case Status::IterationLimit: return "iteration limit";
        case Status::EvaluationLimit: return "evaluation limit";
        case Status::Cancelled: return "cancelled";
        case Status::Stalled: return "stalled";
        case Status::Infeasible: return "infeasible";
        case Status::Failed: return "failed";
    }
    return "?";
}

namespace {

double violation(double v, double lo, double hi) {
    if (v < lo) return lo - v;
    if (v > hi) return v - hi;
    return 0;
}

}  // namespace

double feasibility(const Problem& p, const std::vector<double>& x, const std::vector<double>& c) {
    double worst = 0;
    for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, violation(x[i], p.lower[i], p.upper[i]));
    for (const LinearRow& r : p.linear) worst = std::max(worst, violation(r.value(x), r.lower, r.upper));
    for (std::size_t k = 0; k < p.nonlinear.size() && k < c.size(); ++k) {
        worst = std::max(worst, violation(c[k], p.nonlinear[k].lower, p.nonlinear[k].upper));
    }
    return worst;
}

double firstOrderOptimality(const Problem& p, const std::vector<double>& x, const Values& v, const Gradients& g,
                            double activeTolerance) {
    const int n = p.size();
    // Active columns a_j with their sign s_j: the Lagrangian's gradient is df - sum mu_j s_j a_j
    // with mu_j >= 0 (free for an equality, marked by s_j = 0).
    std::vector<Eigen::VectorXd> columns;
    std::vector<int> sign;
    auto add = [&](double value, double lo, double hi, const auto& fill) {
        const bool atLower = value <= lo + activeTolerance * (1 + std::abs(lo));
        const bool atUpper = value >= hi - activeTolerance * (1 + std::abs(hi));
        if (!atLower && !atUpper) return;
        Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
        fill(a);
        columns.push_back(a);
        sign.push_back(atLower && atUpper ? 0 : (atLower ? 1 : -1));
    };
    for (int i = 0; i < n; ++i) add(x[i], p.lower[i], p.upper[i], [&](Eigen::VectorXd& a) { a[i] = 1; });
    for (const LinearRow& r : p.linear) {
        add(r.value(x), r.lower, r.upper, [&](Eigen::VectorXd& a) {
            for (std::size_t t = 0; t < r.index.size(); ++t) a[r.index[t]] += r.coefficient[t];
        });
    }
    for (std::size_t k = 0; k < p.nonlinear.size(); ++k) {
        add(v.constraints[k], p.nonlinear[k].lower, p.nonlinear[k].upper, [&](Eigen::VectorXd& a) {
            for (int i = 0; i < n; ++i) a[i] = g.constraints[k][i];
        });
    }
    const Eigen::Map<const Eigen::VectorXd> df(g.objective.data(), n);
    // Least squares over the active set; a multiplier of the wrong sign leaves the set (the most
    // negative first) until all have the sign of a minimum.
    std::vector<int> set(columns.size());
    for (std::size_t j = 0; j < set.size(); ++j) set[j] = static_cast<int>(j);
    Eigen::VectorXd r = df;
    while (!set.empty()) {
        Eigen::MatrixXd C(n, static_cast<Eigen::Index>(set.size()));
        for (std::size_t j = 0; j < set.size(); ++j) {
            const int s = sign[set[j]] == 0 ? 1 : sign[set[j]];
            C.col(static_cast<Eigen::Index>(j)) = s * columns[set[j]];
        }
        const Eigen::VectorXd mu = C.colPivHouseholderQr().solve(df);
        int worst = -1;
        double most = 0;
        for (std::size_t j = 0; j < set.size(); ++j) {
            if (sign[set[j]] != 0 && mu[static_cast<Eigen::Index>(j)] < most) {
                most = mu[static_cast<Eigen::Index>(j)];
                worst = static_cast<int>(j);
            }
        }
        if (worst < 0) {
            r = df - C * mu;
            break;
        }
        set.erase(set.begin() + worst);
    }
    return set.empty() ? df.lpNorm<Eigen::Infinity>() : r.lpNorm<Eigen::Infinity>();
}

}  // namespace aero::optimize
