#pragma once
// What every optimizer backend shares (internal to libcore/optimize): evaluations cached by the
// exact bits of x (an optimizer asks for f, c and their gradients in separate calls at the same
// point: one flow solve and one adjoint serve them all), the evaluation limit and cancellation,
// the best point, and the major iterations reported with the common optimality measure.
#include <deque>
#include <string>
#include <utility>
#include <vector>

#include "optimize/Problem.h"

namespace aero::optimize {

class Tracker {
public:
    Tracker(const Problem& p, const Settings& s);

    /// f and c at x; null if the evaluation failed or a stop was requested (see stopped()).
    const Values* values(const double* x);
    /// df and dc at x (values first if not cached); null if either failed or on a stop.
    const Gradients* gradients(const double* x);

    /// The evaluation limit was reached or the run was cancelled (then no more evaluations).
    bool stopped() const { return stop_ != Status::Converged; }
    Status stopStatus() const { return stop_; }
    /// Why the last values() or gradients() call returned null.
    const std::string& lastFailure() const { return lastFailure_; }
    int failures() const { return failures_; }

    /// Reports major iteration k at x (its values and gradients are computed if not cached) and
    /// returns true if x satisfies the optimality and feasibility tolerances.
    bool iterate(int k, const double* x);
    int iterations() const { return iterations_; }
    /// The last point whose gradients were computed (the current iterate of every backend); empty
    /// before the first.
    const std::vector<double>& lastGradientPoint() const { return lastGradientX_; }

    /// The point of the last gradient that failed where the values had succeeded (a converged flow
    /// whose adjoint did not converge); empty when none failed since the last refuse().
    const std::vector<double>& failedGradientPoint() const { return failedGradientX_; }
    /// Makes x a failed evaluation from now on (values() returns null there, with `why`), so a
    /// backend restarted from an earlier iterate cuts a step that comes back to it.
    void refuse(const std::vector<double>& x, const std::string& why);
    /// A backend starts again from the last iterate: its iteration k is reported as the
    /// iterations so far + k, and its iteration 0 (that iterate, reported already) not again.
    void restarted() {
        iterationOffset_ = iterations_;
        restarted_ = true;
    }

    /// The result: the best point evaluated (lowest objective among the feasible ones, else the
    /// least infeasible), with the given status.
    Result result(Status status, const std::string& message) const;

    const Problem& problem() const { return p_; }
    const Settings& settings() const { return s_; }
    void log(const std::string& line) const {
        if (s_.log) s_.log(line);
    }

private:
    struct Entry {
        std::vector<double> x;
        Values v;
        bool hasGradients = false;
        Gradients g;
        int reported = 0;  // the order in which it was reported as an iteration (0: never)
    };
    Entry* find(const double* x);

    const Problem& p_;
    const Settings& s_;
    std::deque<Entry> cache_;
    Status stop_ = Status::Converged;  // Converged: not stopped
    std::string lastFailure_;
    int evaluations_ = 0, gradientCalls_ = 0, failures_ = 0, iterations_ = 0, reports_ = 0;
    std::vector<double> lastGradientX_;
    std::vector<double> failedGradientX_;
    std::vector<std::pair<std::vector<double>, std::string>> refused_;  // points made failed, and why
    int iterationOffset_ = 0;
    bool restarted_ = false;
    // The best point so far.
    std::vector<double> bestX_;
    double bestF_ = 0, bestInfeasibility_ = 0, bestOptimality_ = -1;
};

}  // namespace aero::optimize
