#include "optimize/Tracker.h"

#include <cmath>
#include <cstring>

namespace aero::optimize {

namespace {

constexpr std::size_t kCachedPoints = 6;
// Of them, the last ones reported as iterations stay whatever comes after: the iterates a
// backtracking driver restarts from after a run of failed trials (SLSQP on the 98k multilevel
// path solved its start again, flow and adjoint, after six failed steps had pushed it out).
constexpr int kPinnedIterates = 2;

}  // namespace

Tracker::Tracker(const Problem& p, const Settings& s) : p_(p), s_(s) {}

Tracker::Entry* Tracker::find(const double* x) {
    const std::size_t n = p_.start.size();
    for (Entry& e : cache_) {
        if (std::memcmp(e.x.data(), x, n * sizeof(double)) == 0) return &e;
    }
    return nullptr;
}

const Values* Tracker::values(const double* x) {
    for (const auto& [point, why] : refused_) {
        if (std::memcmp(point.data(), x, point.size() * sizeof(double)) == 0) {
            lastFailure_ = why;
            return nullptr;
        }
    }
    if (Entry* e = find(x)) {
        if (!e->v.ok) {
            lastFailure_ = e->v.message;
            return nullptr;
        }
        return &e->v;
    }
    if (s_.cancel && s_.cancel->load()) stop_ = Status::Cancelled;
    if (evaluations_ >= s_.maxEvaluations) stop_ = Status::EvaluationLimit;
    if (stopped()) {
        lastFailure_ = stop_ == Status::Cancelled ? "cancelled" : "the evaluation limit was reached";
        return nullptr;
    }
    Entry e;
    e.x.assign(x, x + p_.start.size());
    ++evaluations_;
    e.v = p_.values(e.x);
    if (!e.v.ok && s_.cancel && s_.cancel->load()) {
        // Cut short by a cancel: not an evaluation of the run (the caller records none, and a
        // resumed run makes it again), so neither counted nor a failure that cuts the step.
        --evaluations_;
        stop_ = Status::Cancelled;
        lastFailure_ = "cancelled";
        return nullptr;
    }
    if (e.v.ok && e.v.constraints.size() != p_.nonlinear.size()) {
        e.v.ok = false;
        e.v.message = "the evaluation returned " + std::to_string(e.v.constraints.size()) + " constraint values, expected " +
                      std::to_string(p_.nonlinear.size());
    }
    if (e.v.ok && !std::isfinite(e.v.objective)) {
        e.v.ok = false;
        e.v.message = "the objective is not finite";
    }
    if (!e.v.ok) {
        ++failures_;
        lastFailure_ = e.v.message;  // the caller's values function reports it
    } else {
        const double infeasible = feasibility(p_, e.x, e.v.constraints);
        const double tol = s_.feasibilityTolerance;
        const bool feasible = infeasible <= tol, bestFeasible = !bestX_.empty() && bestInfeasibility_ <= tol;
        if (bestX_.empty() || (feasible && (!bestFeasible || e.v.objective < bestF_)) ||
            (!feasible && !bestFeasible && infeasible < bestInfeasibility_)) {
            bestX_ = e.x;
            bestF_ = e.v.objective;
            bestInfeasibility_ = infeasible;
            bestOptimality_ = -1;
        }
    }
    cache_.push_front(std::move(e));
    if (cache_.size() > kCachedPoints) {
        // The oldest entry that is not one of the pinned iterates.
        std::size_t victim = cache_.size();
        for (std::size_t k = 0; k < cache_.size(); ++k) {
            const bool pinned = cache_[k].reported > 0 && cache_[k].reported > reports_ - kPinnedIterates;
            if (!pinned) victim = k;
        }
        if (victim < cache_.size()) cache_.erase(cache_.begin() + static_cast<std::ptrdiff_t>(victim));
    }
    Entry& front = cache_.front();
    return front.v.ok ? &front.v : nullptr;
}

const Gradients* Tracker::gradients(const double* x) {
    if (!values(x)) return nullptr;
    Entry* e = find(x);
    if (!e->hasGradients) {
        if (s_.cancel && s_.cancel->load()) {
            stop_ = Status::Cancelled;
            lastFailure_ = "cancelled";
            return nullptr;
        }
        ++gradientCalls_;
        e->g = p_.gradients(e->x);
        e->hasGradients = true;
        const std::size_t n = p_.start.size();
        if (e->g.ok && (e->g.objective.size() != n || e->g.constraints.size() != p_.nonlinear.size())) {
            e->g.ok = false;
            e->g.message = "the gradient has the wrong size";
        }
        for (const auto& row : e->g.constraints) {
            if (e->g.ok && row.size() != n) {
                e->g.ok = false;
                e->g.message = "a constraint gradient has the wrong size";
            }
        }
        if (!e->g.ok) {
            ++failures_;
            failedGradientX_ = e->x;
        }
    }
    if (!e->g.ok) {
        lastFailure_ = e->g.message;
        return nullptr;
    }
    lastGradientX_ = e->x;
    return &e->g;
}

void Tracker::refuse(const std::vector<double>& x, const std::string& why) {
    refused_.emplace_back(x, why);
    if (failedGradientX_ == x) failedGradientX_.clear();
}

bool Tracker::iterate(int k, const double* x) {
    const Gradients* g = gradients(x);
    if (!g) return false;
    Entry* e = find(x);
    const double infeasibility = feasibility(p_, e->x, e->v.constraints);
    const double optimality = firstOrderOptimality(p_, e->x, e->v, *g, std::max(s_.feasibilityTolerance, 1e-9));
    const bool done = optimality <= s_.optimalityTolerance && infeasibility <= s_.feasibilityTolerance;
    // A restarted backend's iteration 0 is the iterate it starts from, reported already.
    if (restarted_ && k == 0) return done;
    k += iterationOffset_;
    e->reported = ++reports_;
    Iteration it;
    it.iteration = k;
    it.evaluations = evaluations_;
    it.gradients = gradientCalls_;
    it.objective = e->v.objective;
    it.x = e->x;
    it.feasibility = infeasibility;
    it.optimality = optimality;
    iterations_ = k;
    if (e->x == bestX_) bestOptimality_ = it.optimality;
    if (s_.onIteration) s_.onIteration(it);
    return done;
}

Result Tracker::result(Status status, const std::string& message) const {
    Result r;
    r.status = status;
    r.message = message;
    r.x = bestX_.empty() ? p_.start : bestX_;
    r.objective = bestF_;
    r.feasibility = bestInfeasibility_;
    r.optimality = bestOptimality_ < 0 ? std::nan("") : bestOptimality_;  // NaN: not at an iterate
    r.iterations = iterations_;
    r.evaluations = evaluations_;
    r.gradients = gradientCalls_;
    r.failedEvaluations = failures_;
    return r;
}

}  // namespace aero::optimize
