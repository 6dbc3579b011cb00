#pragma once
// A smooth constrained minimization as the optimizers see it (libcore/optimize, between adjoint
// and study; it knows nothing of flows or lattices):
//   minimize f(x)  subject to  lower <= x <= upper,
//                              lo_j <= a_j . x <= up_j      (linear rows, exact, no evaluation),
//                              lo_k <= c_k(x) <= up_k       (nonlinear, evaluated with f),
// equality where the two bounds are equal. f and c come from one call (`values`, e.g. a flow
// solve) and their gradients from another (`gradients`, e.g. the adjoint), which is only asked
// at a point whose values succeeded. An evaluation may fail (a flow that does not converge, a
// folded lattice): the optimizers cut the step back instead of stopping.
#include <atomic>
#include <functional>
#include <string>
#include <vector>

namespace aero::optimize {

/// A sparse linear row: sum of coefficient[i] * x[index[i]], kept within [lower, upper].
struct LinearRow {
    std::vector<int> index;
    std::vector<double> coefficient;
    double lower = 0, upper = 0;
    std::string name;  // for reports ("symmetry 3", "station gap body S1-S2")
    double value(const std::vector<double>& x) const;
};

/// A nonlinear constraint's name and bounds (use +-infinity for a one-sided constraint).
struct ConstraintSpec {
    std::string name;
    double lower = 0, upper = 0;
};

/// f and c at a point, or why they could not be computed.
struct Values {
    bool ok = true;
    std::string message;            // the reason when not ok
    double objective = 0;
    std::vector<double> constraints;  // one per ConstraintSpec
};

/// df/dx and dc_k/dx at a point whose values succeeded.
struct Gradients {
    bool ok = true;
    std::string message;
    std::vector<double> objective;                 // n
    std::vector<std::vector<double>> constraints;  // one row of n per ConstraintSpec
};

struct Problem {
    std::vector<double> start, lower, upper;  // n each
    std::vector<LinearRow> linear;
    std::vector<ConstraintSpec> nonlinear;
    std::function<Values(const std::vector<double>& x)> values;
    std::function<Gradients(const std::vector<double>& x)> gradients;
    int size() const { return static_cast<int>(start.size()); }
    /// Throws std::invalid_argument for inconsistent sizes, a start outside the bounds, a row
    /// index out of range or crossed bounds (naming the variable or row).
    void check() const;
};

/// One major iteration as reported to the caller.
struct Iteration {
    int iteration = 0;       // 0 = the start
    int evaluations = 0;     // values calls so far (failed ones included)
    int gradients = 0;       // gradient calls so far
    double objective = 0;
    double optimality = 0;   // firstOrderOptimality at the iterate
    double feasibility = 0;  // largest violation of a bound, row or constraint
    std::vector<double> x;
};

struct Settings {
    double optimalityTolerance = 1e-6;  // stop when firstOrderOptimality is below this ...
    double feasibilityTolerance = 1e-6; // ... at a point no constraint violates by more than this
    int maxIterations = 100;
    int maxEvaluations = 200;           // values calls, failed ones included
    const std::atomic<bool>* cancel = nullptr;  // checked before every evaluation
    std::function<void(const Iteration&)> onIteration;  // after every major iteration
    std::function<void(const std::string&)> log;        // lines for a human (may be empty)
};

enum class Status {
    Converged,        // optimality and feasibility within their tolerances
    IterationLimit,
    EvaluationLimit,
    Cancelled,
    Stalled,          // the optimizer could not make progress (reason in the message)
    Infeasible,       // the optimizer found no feasible point
    Failed,           // the start could not be evaluated, or the optimizer failed
};
const char* statusName(Status s);

struct Result {
    Status status = Status::Failed;
    std::string message;
    std::vector<double> x;       // the best feasible point found (the start if none)
    double objective = 0;
    double optimality = 0, feasibility = 0;
    int iterations = 0, evaluations = 0, gradients = 0, failedEvaluations = 0;
};

/// The largest violation at x of a bound, a linear row or a nonlinear constraint (c from Values).
double feasibility(const Problem& p, const std::vector<double>& x, const std::vector<double>& c);

/// First-order optimality at x (the same measure for every optimizer): the infinity norm of the
/// Lagrangian's gradient df - sum mu_j da_j over the active bounds, rows and constraints, with
/// multipliers that fit df best in least squares and have the sign that makes the point a
/// minimum (mu >= 0 at a lower bound, <= 0 at an upper one, free for an equality). A constraint
/// within `activeTolerance` of a bound (or violating it) counts as active.
double firstOrderOptimality(const Problem& p, const std::vector<double>& x, const Values& v, const Gradients& g,
                            double activeTolerance);

}  // namespace aero::optimize
