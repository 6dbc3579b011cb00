// NLopt's SLSQP (Kraft's sequential least squares QP) behind optimize::Optimizer, with a
// backtracking driver around it: SLSQP has no notion of a failed evaluation, so one stops the
// run, and SLSQP is restarted from the last good iterate inside a box (a trust region in the
// infinity norm) of half the failed step; a run that ends on its box without a failure is
// restarted from its end with the box re-centred and doubled, until the box no longer binds. A
// boxed run whose iterate sits on the box and gains less than kBoxProgress of its objective in
// one iteration is restarted so at once: SLSQP would otherwise converge on the box's face in
// many tiny steps (the 98k sphere-to-wing run: eight evaluations gaining 0.1 % in all).
// NLopt 2.7's SLSQP asks for the gradient with the first trial point of every line search (its
// shortcut for the usual case that the full step is taken) and at a later trial it accepts, not
// at the trials in between. So whether SLSQP's merit function took a first trial is known only at
// the next call: a point without a gradient is a trial of the same line search (the first one was
// rejected), a new point with a gradient starts the next line search (it was taken). Only taken
// points are iterations of the common report, and the driver restarts from the last one, never
// from a rejected trial: on the 98k multilevel path a restart from one (CL/CD -0.09 against the
// start's 7.69) sent the next steps onto another branch of the flow, and the study layer's warm
// starts come from the iterates' flows. (The driver used to judge a first trial at once, as taken
// unless it was worse in both objective and feasibility; the thirty-sixth session's Figure 4 run
// showed a trial better in feasibility by 3e-4 and worse in L/D by 0.17 that SLSQP rejected.)
#include <nlopt.hpp>
#include <algorithm>
#include <cmath>
#include <limits>

#include "optimize/Optimizer.h"
#include "optimize/Tracker.h"

namespace aero::optimize {

namespace {

constexpr int kMaxRestarts = 60;
constexpr double kBoxProgress = 1e-3;  // relative objective gain per iteration on the box's face

// The point a restart starts from: the last iteration of all runs.
struct Accepted {
    std::vector<double> x;
};

struct Run {
    Tracker& t;
    Accepted& accepted;  // the last point reported as an iteration (all runs)
    int iteration = 0;
    bool converged = false, failed = false, iterationLimit = false;
    std::vector<double> failedX{};
    // The backtracking box (null when the run has none) and the last iterate's objective.
    const std::vector<double>* boxLower = nullptr;
    const std::vector<double>* boxUpper = nullptr;
    double previous = std::numeric_limits<double>::quiet_NaN();
    // A line search's first trial, with its gradient, not yet known to be taken; the last trial
    // evaluated without a gradient.
    std::vector<double> pending{}, lastTrial{};
};

// Whether x lies on a face of the run's box that is not one of the problem's own bounds.
bool onBoxFace(const Run& r, const double* x, unsigned n) {
    if (!r.boxLower) return false;
    const Problem& p = r.t.problem();
    for (unsigned i = 0; i < n; ++i) {
        const double lo = (*r.boxLower)[i], hi = (*r.boxUpper)[i];
        const double tol = 1e-9 * std::max(1.0, hi - lo);
        if ((lo > p.lower[i] && x[i] <= lo + tol) || (hi < p.upper[i] && x[i] >= hi - tol)) return true;
    }
    return false;
}

[[noreturn]] void fail(Run& r, const double* x, unsigned n) {
    if (!r.t.stopped()) {
        r.failed = true;
        r.failedX.assign(x, x + n);
    }
    throw nlopt::forced_stop();
}

bool samePoint(const double* x, const std::vector<double>& y, unsigned n) {
    return y.size() == n && std::equal(x, x + n, y.begin());
}

// SLSQP took the pending point (its values and gradient are in the tracker's cache): it is the
// next iteration. Throws nlopt::forced_stop when the run ends there (converged, the iteration
// limit) or its box is to grow.
void take(Run& r) {
    const std::vector<double> x = std::move(r.pending);
    r.pending.clear();
    const Values* v = r.t.values(x.data());  // cached: nothing was evaluated since
    r.accepted.x = x;
    if (r.t.iterate(++r.iteration, x.data())) {
        r.converged = true;
        throw nlopt::forced_stop();
    }
    if (r.iteration >= r.t.settings().maxIterations) {
        r.iterationLimit = true;
        throw nlopt::forced_stop();
    }
    const double gain = r.previous - v->objective;
    const double scale = std::max(std::abs(r.previous), std::abs(v->objective));
    r.previous = v->objective;
    // A gain, but a small one (a worse point is a line-search trial: SLSQP goes on from it).
    if (std::isfinite(gain) && gain >= 0 && gain < kBoxProgress * scale && onBoxFace(r, x.data(), static_cast<unsigned>(x.size()))) {
        throw nlopt::forced_stop();  // the driver below grows the box
    }
}

double objective(unsigned n, const double* x, double* grad, void* data) {
    Run& r = *static_cast<Run*>(data);
    if (!r.pending.empty() && !samePoint(x, r.pending, n)) {
        if (grad) take(r);  // the next line search: the pending first trial was taken
        else r.pending.clear();  // a trial of its line search: it was rejected
    }
    const Values* v = r.t.values(x);
    if (!v) fail(r, x, n);
    if (!grad) {
        r.lastTrial.assign(x, x + n);
        return v->objective;
    }
    const Gradients* g = r.t.gradients(x);
    if (!g) fail(r, x, n);
    std::copy(g->objective.begin(), g->objective.end(), grad);
    if (samePoint(x, r.accepted.x, n)) {
        r.previous = v->objective;  // a restart's start
        return v->objective;
    }
    r.pending.assign(x, x + n);
    // The run's first point is its start. A later trial's gradient is asked for once the line
    // search has taken it; a first trial's is asked for with its values, and the next call tells.
    if (r.accepted.x.empty() || samePoint(x, r.lastTrial, n)) take(r);
    return v->objective;
}

// A constraint as c(x) <= 0: the row or nonlinear constraint k, on its lower (sign -1) or upper
// (sign +1) side, or an equality (sign 0: c(x) - lower = 0).
struct Side {
    Run* run;
    int row = -1, nonlinear = -1;
    int sign = 1;
};

double side(unsigned n, const double* x, double* grad, void* data) {
    const Side& s = *static_cast<Side*>(data);
    const Problem& p = s.run->t.problem();
    double value = 0, lo = 0, hi = 0;
    if (s.row >= 0) {
        const LinearRow& r = p.linear[s.row];
        for (std::size_t t = 0; t < r.index.size(); ++t) value += r.coefficient[t] * x[r.index[t]];
        if (grad) {
            std::fill(grad, grad + n, 0.0);
            for (std::size_t t = 0; t < r.index.size(); ++t) grad[r.index[t]] += r.coefficient[t];
        }
        lo = r.lower;
        hi = r.upper;
    } else {
        const Values* v = s.run->t.values(x);
        if (!v) fail(*s.run, x, n);
        value = v->constraints[s.nonlinear];
        if (grad) {
            const Gradients* g = s.run->t.gradients(x);
            if (!g) fail(*s.run, x, n);
            std::copy(g->constraints[s.nonlinear].begin(), g->constraints[s.nonlinear].end(), grad);
        }
        lo = p.nonlinear[s.nonlinear].lower;
        hi = p.nonlinear[s.nonlinear].upper;
    }
    if (s.sign < 0 && grad) {
        for (unsigned i = 0; i < n; ++i) grad[i] = -grad[i];
    }
    if (s.sign == 0) return value - lo;
    return s.sign > 0 ? value - hi : lo - value;
}

class SlsqpOptimizer final : public Optimizer {
public:
    std::string name() const override { return "slsqp"; }

    Result minimize(const Problem& p, const Settings& s) override {
        p.check();
        Tracker t(p, s);
        const unsigned n = static_cast<unsigned>(p.size());
        std::vector<double> lo = p.lower, hi = p.upper, x = p.start;
        double radius = std::numeric_limits<double>::infinity();  // the box's half-width
        auto box = [&](const std::vector<double>& centre) {
            for (unsigned i = 0; i < n; ++i) {
                lo[i] = std::max(p.lower[i], centre[i] - radius);
                hi[i] = std::min(p.upper[i], centre[i] + radius);
            }
            x = centre;
        };
        int iterations = 0;
        Accepted accepted;
        for (int restart = 0;; ++restart) {
            Run run{t, accepted};
            run.iteration = iterations;
            if (lo != p.lower || hi != p.upper) {
                run.boxLower = &lo;
                run.boxUpper = &hi;
            }
            nlopt::opt opt(nlopt::LD_SLSQP, n);
            opt.set_lower_bounds(lo);
            opt.set_upper_bounds(hi);
            opt.set_min_objective(objective, &run);
            std::vector<Side> sides;
            auto addSides = [&](int row, int nonlinear, double l, double u) {
                if (l == u) {
                    sides.push_back({&run, row, nonlinear, 0});
                    return;
                }
                if (std::isfinite(l)) sides.push_back({&run, row, nonlinear, -1});
                if (std::isfinite(u)) sides.push_back({&run, row, nonlinear, 1});
            };
            for (std::size_t r = 0; r < p.linear.size(); ++r) addSides(static_cast<int>(r), -1, p.linear[r].lower, p.linear[r].upper);
            for (std::size_t k = 0; k < p.nonlinear.size(); ++k) {
                addSides(-1, static_cast<int>(k), p.nonlinear[k].lower, p.nonlinear[k].upper);
            }
            for (Side& sd : sides) {
                if (sd.sign == 0) opt.add_equality_constraint(side, &sd, s.feasibilityTolerance * 0.1);
                else opt.add_inequality_constraint(side, &sd, s.feasibilityTolerance * 0.1);
            }
            opt.set_ftol_rel(1e-14);
            opt.set_xtol_rel(1e-14);
            std::string why;
            nlopt::result r = nlopt::FAILURE;
            double f = 0;
            try {
                r = opt.optimize(x, f);
            } catch (const nlopt::forced_stop&) {
                r = nlopt::FORCED_STOP;
            } catch (const nlopt::roundoff_limited&) {
                why = "SLSQP is limited by round-off";
            } catch (const std::exception& e) {
                why = std::string("SLSQP failed: ") + e.what();
            }
            if (!run.pending.empty() && r != nlopt::FORCED_STOP) {
                // NLopt ended right after a line search took its first trial (its own tests run
                // on a taken point only).
                try {
                    take(run);
                } catch (const nlopt::forced_stop&) {
                }
            }
            iterations = run.iteration;
            if (run.converged) return t.result(Status::Converged, "optimality and feasibility within their tolerances");
            if (t.stopped()) {
                return t.result(t.stopStatus(), t.stopStatus() == Status::Cancelled ? "cancelled" : "the evaluation limit was reached");
            }
            if (run.iterationLimit) return t.result(Status::IterationLimit, "the iteration limit was reached");
            if (restart >= kMaxRestarts) {
                return t.result(Status::Stalled, "SLSQP restarted " + std::to_string(kMaxRestarts) + " times without converging" +
                                                     (t.lastFailure().empty() ? std::string() : " (last failure: " + t.lastFailure() + ")"));
            }
            const std::vector<double> good = accepted.x.empty() ? p.start : accepted.x;
            if (run.failed) {
                // Backtrack: a box of half the failed step around the last good iterate.
                double step = 0;
                for (unsigned i = 0; i < n; ++i) step = std::max(step, std::abs(run.failedX[i] - good[i]));
                radius = std::min(radius, 0.5 * step);
                if (!(radius > 1e-12)) {
                    return t.result(Status::Stalled, "evaluations fail arbitrarily close to the last good point: " + t.lastFailure());
                }
                t.log("SLSQP: evaluation failed (" + t.lastFailure() + "); restarting from the last good iterate, steps "
                      "limited to " + std::to_string(radius));
                box(good);
                continue;
            }
            if (lo != p.lower || hi != p.upper) {
                // The run ended without a failure while its box binds (or crept along its face):
                // go on from its end with a larger box (lifted once it covers the bounds).
                const std::vector<double> end = accepted.x.empty() ? x : accepted.x;
                radius *= 2;
                box(end);
                continue;
            }
            if (why.empty()) {
                why = r == nlopt::FTOL_REACHED || r == nlopt::XTOL_REACHED ? "SLSQP made no more progress"
                                                                            : "SLSQP stopped (NLopt result " + std::to_string(static_cast<int>(r)) + ")";
            }
            return t.result(Status::Stalled, why + " before the optimality tolerance was reached");
        }
    }
};

}  // namespace

std::unique_ptr<Optimizer> makeSlsqp() { return std::make_unique<SlsqpOptimizer>(); }

}  // namespace aero::optimize
