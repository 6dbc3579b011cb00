#pragma once
// The optimizers behind one small interface, chosen by name ("ipopt": interior point with a
// limited-memory Hessian; "slsqp": NLopt's sequential least squares QP). Adding one is one file
// and one line of the table in Optimizer.cpp. Both stop on the same first-order optimality
// measure (optimize::firstOrderOptimality), count evaluations the same way and survive failed
// evaluations: Ipopt cuts its line-search step, SLSQP is restarted by a backtracking driver from
// the last good iterate inside a box of half the failed step. A gradient that fails at a point
// Ipopt has accepted (where it cannot cut back) makes that point a failed evaluation, and Ipopt
// starts again from the last iterate.
#include <memory>
#include <string>
#include <vector>

#include "optimize/Problem.h"

namespace aero::optimize {

class Optimizer {
public:
    virtual ~Optimizer() = default;
    virtual std::string name() const = 0;
    /// Minimizes p from p.start. Never throws for a failed evaluation or a stop; the result says
    /// why it stopped. Throws std::invalid_argument for an inconsistent problem (Problem::check).
    virtual Result minimize(const Problem& p, const Settings& s) = 0;
};

/// "ipopt" or "slsqp"; throws std::invalid_argument naming the choices for anything else.
std::unique_ptr<Optimizer> makeOptimizer(const std::string& name);
const std::vector<std::string>& optimizerNames();

}  // namespace aero::optimize
