#include "flow/TimeAccurate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common/Error.h"
#include "flow/ChunkedSum.h"
#include "flow/Metrics.h"
#include "flow/Outputs.h"

namespace aero::flow {

namespace {

double norm2(const std::vector<double>& v) {
    return std::sqrt(chunkedDot(static_cast<long>(v.size()), v.data(), v.data()));
}

std::string format3(const char* fmt, double a, double b = 0, double c = 0) {
    char buf[512];
    std::snprintf(buf, sizeof buf, fmt, a, b, c);
    return buf;
}

// A pseudo-time CFL cut after a rejected inner iteration: from Newton's (no pseudo-time term) to
// kFirstCut, then by 10 each time.
constexpr double kFirstCut = 100.0;

// A time step whose inner iterations do not converge is halved, down to this fraction of the
// requested one.
constexpr double kSmallestStep = 64.0;

// The verdict: a flow whose steady residual fell by more than this factor over the second half of
// the run is settling (the 4k blended-wing sample from the free stream, dt 2: 4.4 times from t = 60
// to 120, its lift within 4e-4 of the steady answer) ...
constexpr double kSettling = 3.0;
// ... and a lift that oscillates by less than this (peak to peak) is no unsteadiness a user needs
// to know of (that run's lift crosses its mean twice in the second half by 4e-4).
constexpr double kNegligibleLift = 1e-3;
// The part of the run the lift's oscillation is judged by starts after this fraction of its time
// (the start-up transient: from the free stream or from a steady solver's stalled state).
constexpr double kTransient = 0.25;

}  // namespace

TimeAccurateReport solveTimeAccurate(const FlowMesh& fm, const std::vector<double>& metrics, const ResidualOptions& o,
                                     std::vector<double>& q, const NewtonOptions& n, const TimeAccurateOptions& t,
                                     const TimeStepFn& onStep, const std::atomic<bool>* cancel) {
    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    const long N = fm.nodeCount, nv = kVars * N;
    const double gamma = o.freeStream.gamma;
    if (!(t.timeStep > 0) || t.steps < 1 || t.maxInner < 1) {
        throw InputError(format3("time-accurate solve: the time step (%g) must be positive and the steps (%g) and inner "
                                 "iterations (%g) at least 1",
                                 t.timeStep, t.steps, t.maxInner));
    }
    if (q.empty()) q = freeStreamState(fm, o.freeStream);
    if (static_cast<long>(q.size()) != nv || static_cast<long>(metrics.size()) != kMetricWidth * N) {
        throw Error("time-accurate solve: state or metrics do not match the mesh");
    }
    TimeAccurateReport rep;
    auto finish = [&](const std::string& why) {
        rep.message = why;
        rep.seconds = elapsed();
        return rep;
    };
    if (!isPhysical(fm, q.data(), gamma)) return finish("the initial state has non-positive density or pressure");

    std::vector<double> r(nv), rs(nv), dq(nv), qNew(nv), rNew(nv), rsNew(nv), change;
    residual(fm, metrics.data(), q.data(), o, r.data());
    rep.referenceResidual = n.referenceResidual > 0 ? n.referenceResidual : norm2(r);
    if (!(rep.referenceResidual > 0)) rep.referenceResidual = 1.0;  // a uniform flow on a closed grid
    std::vector<double> jinv(N), timeTerm(N);
    for (long i = 0; i < N; ++i) jinv[i] = metrics[kMetricWidth * i + 9];
    std::vector<double> qn = q, qm;  // q^n and q^(n-1) (empty before the second step)
    // The step's BDF coefficients: dq/dt ~ (a0 q - a1 q^n + a2 q^(n-1)) / h. With steps of
    // different sizes (ratio w = h / h_prev), the variable-step BDF2: a0 = (1 + 2w) / (1 + w),
    // a1 = 1 + w, a2 = w^2 / (1 + w) (3/2, 2, 1/2 for w = 1; zero-stable for w < 1 + sqrt 2).
    double a0 = 1, a1 = 1, a2 = 0, h = t.timeStep;
    // R*(state) from R(state) = steady; its norm.
    auto unsteady = [&](const std::vector<double>& state, const std::vector<double>& steady, std::vector<double>& out) {
        const bool two = !qm.empty();
#pragma omp parallel for schedule(static)
        for (long i = 0; i < nv; ++i) {
            const double older = two ? a2 * qm[i] : 0.0;
            out[i] = steady[i] + jinv[i / kVars] * (a0 * state[i] - a1 * qn[i] + older) / h;
        }
        return norm2(out);
    };
    const NewtonOptions inner = n;  // (the step system keeps a reference)
    StepSystem system(fm, metrics, o, inner);
    system.setTimeTerm(&timeTerm);
    const double endTime = t.steps * t.timeStep;
    double time = 0, previous = 0;  // previous: the last step's size (0: none yet)
    double next = t.timeStep;       // the next step's size
    bool cancelled = false;
    // One time step of size h from q^n (q holds q^n on entry): true when its inner iterations
    // converged (q then holds q^(n+1)); false with the reason in `failure`.
    auto takeStep = [&](TimeStepRecord& rec, std::string& failure) -> bool {
        const bool bdf2 = !qm.empty();
        const double w = bdf2 ? h / previous : 0.0;
        a0 = bdf2 ? (1 + 2 * w) / (1 + w) : 1.0;
        a1 = bdf2 ? 1 + w : 1.0;
        a2 = bdf2 ? w * w / (1 + w) : 0.0;
        for (long i = 0; i < N; ++i) timeTerm[i] = a0 * jinv[i] / h;
        // The first iterate: q^n, or the state extrapolated linearly in time when that is physical
        // and closer to the answer (second order where the flow is smooth in time; after an
        // impulsive start it overshoots).
        residual(fm, metrics.data(), q.data(), o, r.data());
        double Rs = unsteady(q, r, rs);
        if (bdf2) {
            for (long i = 0; i < nv; ++i) qNew[i] = qn[i] + w * (qn[i] - qm[i]);
            if (isPhysical(fm, qNew.data(), gamma)) {
                residual(fm, metrics.data(), qNew.data(), o, rNew.data());
                const double extrapolated = unsteady(qNew, rNew, rsNew);
                if (extrapolated < Rs) {
                    q.swap(qNew);
                    r.swap(rNew);
                    rs.swap(rsNew);
                    Rs = extrapolated;
                }
            }
        }
        const double Rs0 = Rs;
        const double target = std::max({t.innerTolerance * Rs0, n.relativeTolerance * rep.referenceResidual, n.absoluteTolerance});
        double cfl = t.pseudoCfl > 0 ? t.pseudoCfl : n.cflMax;
        int rejections = 0;
        bool lagged = false;  // the next iteration keeps the preconditioner
        std::string why;
        // The exact Jacobian of R* as the system matrix; when GMRES cannot solve that with the
        // approximate Jacobian's ILU, the approximate Jacobian itself (an approximate Newton
        // step), then more lumping in it (kept for the run), as the steady solver does.
        auto linear = [&] {
            const GmresReport g = system.solve(rs.data(), dq.data(), n.linearTolerance);
            rec.linearIterations += g.iterations;
            rep.linearIterations += g.iterations;
            if (g.relativeResidual <= n.linearFailure) return true;
            why = format3("GMRES reduced the linear residual only to %.3e", g.relativeResidual);
            return false;
        };
        while (Rs > target) {
            // Newton's iterations either get there in a few or not at all: an attempt that has not
            // gained half the orders it needs in half its iterations is given up (and the step
            // halved) instead of spending the other half (the 98k random design 5 spent 270 s on
            // one such attempt of a step of 0.5 before its halves converged in 5 s).
            const bool hopeless = 2 * rec.innerIterations >= t.maxInner && Rs > std::sqrt(target * Rs0);
            if (rec.innerIterations >= t.maxInner || hopeless) {
                failure = format3("the inner iterations reduced the unsteady residual only to %.3e of its start in %g iterations",
                                  Rs / Rs0, rec.innerIterations);
                return false;
            }
            if (cancel && cancel->load()) {
                cancelled = true;
                return false;
            }
            // With lagPreconditioner, after the step's first iteration the preconditioner is kept
            // and only the products follow the state; assembled and factored again when GMRES
            // cannot solve with it.
            why.clear();
            bool ok = false;
            if (lagged) {
                system.setState(q.data(), r.data());
                ok = linear();
                why.clear();
            }
            if (!ok) {
                system.assemble(q.data(), r.data(), cfl, true);
                ok = system.factor(why) && linear();
            }
            if (!ok && why.rfind("GMRES", 0) == 0) {
                system.useApproximate();
                ok = linear();
            }
            while (!ok && system.lumping() < n.maxLumping) {
                system.setLumping(std::min(n.maxLumping, 2.0 * system.lumping()));
                system.assemble(q.data(), r.data(), cfl, false);
                ok = system.factor(why) && linear();
            }
            double Rnew = 0;
            if (ok) {
                relativeChanges(N, q.data(), dq.data(), gamma, change);
                const double worst = *std::max_element(change.begin(), change.end());
                double alpha = worst > n.maxRelativeChange ? n.maxRelativeChange / worst : 1.0;
                bool physical = false;
                for (int tries = 0; tries < 10 && !physical; ++tries) {
                    for (long i = 0; i < nv; ++i) qNew[i] = q[i] + alpha * dq[i];
                    physical = isPhysical(fm, qNew.data(), gamma);
                    if (!physical) alpha *= 0.5;
                }
                ok = physical;
                if (!ok) why = "the update makes density or pressure negative";
            }
            if (ok) {
                residual(fm, metrics.data(), qNew.data(), o, rNew.data());
                Rnew = unsteady(qNew, rNew, rsNew);
                ok = std::isfinite(Rnew) && Rnew < 10.0 * Rs;
                if (!ok) why = format3("the unsteady residual would grow %.3g times", Rnew / Rs);
            }
            if (!ok) {
                if (++rejections > n.maxRejections) {
                    failure = format3("%g inner iterations in a row were rejected", rejections) + " (the last: " + why + ")";
                    return false;
                }
                cfl = std::min(0.1 * cfl, kFirstCut);
                lagged = false;  // (the diagonal changes with the CFL)
                continue;
            }
            q.swap(qNew);
            r.swap(rNew);
            rs.swap(rsNew);
            Rs = Rnew;
            rejections = 0;
            ++rec.innerIterations;
            const double grown = std::min(n.cflMax, 10.0 * cfl);
            lagged = t.lagPreconditioner && system.exact() && grown == cfl;
            cfl = grown;
        }
        rec.innerReduction = Rs0 > 0 ? Rs / Rs0 : 0.0;
        return true;
    };
    for (int step = 1; time < endTime * (1 - 1e-12); ++step) {
        if (cancel && cancel->load()) {
            rep.cancelled = true;
            return finish("cancelled after " + std::to_string(step - 1) + " time steps");
        }
        if (t.maxSeconds > 0 && elapsed() >= t.maxSeconds) {
            return finish(format3("stopped by the time limit after %g time steps (t = %g, %.4g s)", step - 1, time, elapsed()));
        }
        // A step whose inner iterations fail is taken again from q^n with half the size, down to
        // timeStep / kSmallestStep; the steps after it grow back by 2 each up to timeStep.
        h = std::min(next, endTime - time);
        TimeStepRecord rec;
        rec.step = step;
        std::string failure;
        while (!takeStep(rec, failure)) {
            q = qn;
            if (cancelled) {
                rep.cancelled = true;
                return finish("cancelled during time step " + std::to_string(step));
            }
            if (h <= t.timeStep / kSmallestStep * (1 + 1e-12)) {
                return finish(format3("time step %g (t = %g to %g): ", step, time, time + h) + failure +
                              format3(", also with the time step halved to %g: a smaller --time-step", h));
            }
            h *= 0.5;
            ++rep.halvedSteps;
            rec = TimeStepRecord{};
            rec.step = step;
        }
        time += h;
        double rate = 0;
        for (long i = 0; i < nv; ++i) rate += (q[i] - qn[i]) * (q[i] - qn[i]);
        rec.rate = std::sqrt(rate / static_cast<double>(nv)) / h;
        rec.time = time;
        rec.timeStep = h;
        rec.steadyResidual = norm2(r) / rep.referenceResidual;
        const std::vector<double> mach = machNumber(fm, q, gamma);
        const auto fastest = std::max_element(mach.begin(), mach.end());
        rec.maxMach = *fastest;
        rec.maxMachNode = fastest - mach.begin();
        rec.seconds = elapsed();
        qm.swap(qn);
        qn = q;
        previous = h;
        next = std::min(t.timeStep, 2.0 * h);
        rep.history.push_back(rec);
        if (onStep) onStep(rec, q);
        if (rec.maxMach > t.maxMach) {
            rep.breakdownNode = rec.maxMachNode;
            return finish(format3("at t = %g the local Mach number reached %.3g (pressure or density nearly zero): the flow "
                                  "breaks down there",
                                  time, rec.maxMach));
        }
    }
    rep.completed = true;
    rep.seconds = elapsed();
    return rep;
}

SignalSummary summarizeSignal(const std::vector<double>& t, const std::vector<double>& y, double from) {
    SignalSummary s;
    const std::size_t size = std::min(t.size(), y.size());
    if (size == 0) return s;
    // The window: from the first sample at or after t0 + from (t_end - t0) (the steps may differ).
    const double t0 = t[0] + std::clamp(from, 0.0, 1.0) * (t[size - 1] - t[0]);
    std::size_t w0 = 0;
    while (w0 + 1 < size && t[w0] < t0) ++w0;
    double sum = 0;
    s.minimum = s.maximum = y[w0];
    for (std::size_t i = w0; i < size; ++i) {
        sum += y[i];
        s.minimum = std::min(s.minimum, y[i]);
        s.maximum = std::max(s.maximum, y[i]);
    }
    s.mean = sum / static_cast<double>(size - w0);
    const double range = s.maximum - s.minimum;
    s.drift = range > 0 ? std::abs(y[size - 1] - y[w0]) / range : 0.0;
    // Upward crossings of the mean, each at its interpolated time; the samples between two of
    // them are one cycle.
    std::vector<double> when;
    std::vector<std::size_t> at;
    for (std::size_t i = w0 + 1; i < size; ++i) {
        if (y[i - 1] < s.mean && y[i] >= s.mean) {
            const double f = (s.mean - y[i - 1]) / (y[i] - y[i - 1]);
            when.push_back(t[i - 1] + f * (t[i] - t[i - 1]));
            at.push_back(i);
        }
    }
    if (when.size() < 2) return s;
    s.cycles = static_cast<int>(when.size()) - 1;
    double shortest = when[1] - when[0], longest = shortest;
    for (std::size_t k = 1; k + 1 < when.size(); ++k) {
        shortest = std::min(shortest, when[k + 1] - when[k]);
        longest = std::max(longest, when[k + 1] - when[k]);
    }
    s.period = (when.back() - when.front()) / s.cycles;
    s.periodSpread = (longest - shortest) / s.period;
    if (s.cycles >= 2) {
        auto cycleRange = [&](std::size_t a, std::size_t b) {
            const auto [lo, hi] = std::minmax_element(y.begin() + static_cast<long>(a), y.begin() + static_cast<long>(b));
            return *hi - *lo;
        };
        const double first = cycleRange(at[0], at[1]);
        s.amplitudeRatio = first > 0 ? cycleRange(at[at.size() - 2], at.back()) / first : 0.0;
    }
    return s;
}

std::string describeUnsteadiness(const TimeAccurateReport& r, const std::vector<double>& lift, double steadyTolerance,
                                 double referenceLength, double mach) {
    if (r.history.empty()) return "no time step was taken";
    const TimeStepRecord& last = r.history.back();
    const std::size_t size = r.history.size();
    std::vector<double> t(size);
    for (std::size_t i = 0; i < size; ++i) t[i] = r.history[i].time;
    // The lift's oscillation is judged after the first quarter of the run (its start-up transient).
    const SignalSummary s = summarizeSignal(t, lift, kTransient);
    const double earlier = r.history[size / 2].steadyResidual;
    const std::string lasting = format3(" after t = %g (%g time steps)", last.time, static_cast<double>(size));
    if (last.steadyResidual <= steadyTolerance) {
        return "the flow settled into a steady state" + lasting +
               format3(": its steady residual is %.3e of the free stream's; the steady solver converges from this state",
                       last.steadyResidual);
    }
    if (earlier > kSettling * last.steadyResidual) {
        return "the flow is settling" + lasting +
               format3(": its steady residual fell from %.3e to %.3e over the second half (CL %.4f); a longer run, or a "
                       "steady solve from this state, should converge",
                       earlier, last.steadyResidual, lift.empty() ? 0.0 : lift.back());
    }
    const std::string range =
        format3("over the last three quarters of the run CL oscillates between %.4f and %.4f (mean %.4f)", s.minimum,
                s.maximum, s.mean);
    const std::string stays = format3("; its steady residual stays at %.3e: the flow does not settle into a steady state "
                                      "(a steady solution at this dissipation, if there is one, is unstable)",
                                      last.steadyResidual);
    if (s.cycles >= 3 && s.periodSpread < 0.2 && s.amplitudeRatio > 0.5 && s.maximum - s.minimum > kNegligibleLift) {
        const double strouhal = s.period > 0 && mach > 0 ? referenceLength / (s.period * mach) : 0.0;
        return "the flow is unsteady and periodic" + lasting + ": " + range +
               format3(" with period %.4g (Strouhal number %.3g on the reference length), the last cycle's amplitude %.2f "
                       "times the first's",
                       s.period, strouhal, s.amplitudeRatio) +
               format3(" over %g cycles", s.cycles) + stays;
    }
    if (s.cycles >= 2 && s.amplitudeRatio > 0 && s.amplitudeRatio <= 0.5) {
        return "the flow oscillates with a decaying amplitude" + lasting + ": " + range +
               format3(", the last cycle's amplitude %.2f times the first's (period %.4g): it may settle; run longer",
                       s.amplitudeRatio, s.period);
    }
    if (s.cycles >= 1 && s.maximum - s.minimum > kNegligibleLift) {
        return "the flow is unsteady" + lasting + ": " + range +
               (s.cycles == 1 ? format3(", not periodically: one cycle, of length %.4g", s.period)
                              : format3(", not periodically: %g cycles of mean length %.4g, their lengths differing by %.2f of "
                                        "it",
                                        s.cycles, s.period, s.periodSpread)) +
               stays;
    }
    return "the flow has not settled" + lasting + ": over the last three quarters of the run " +
           format3("CL ranges over %.4f to %.4f (%g full cycles about its mean)", s.minimum, s.maximum, s.cycles) +
           format3(" and its steady residual is %.3e; run longer", last.steadyResidual);
}

}  // namespace aero::flow
