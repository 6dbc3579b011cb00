#pragma once
// Time-accurate Euler solutions by dual time stepping. The semi-discrete equations
//   (1/J) dq/dt + R(q) = 0                                         (Residual.h)
// are discretized in time by the second-order backward difference (BDF2; the first step, which
// has no earlier level, by backward Euler), so that every physical time step solves
//   R*(q) = R(q) + (1/J) (a0 q - a1 q^n + a2 q^(n-1)) / dt = 0,
//   BDF2: a0 = 3/2, a1 = 2, a2 = 1/2;    backward Euler: a0 = a1 = 1, a2 = 0,
// for q^(n+1) by inexact Newton-Krylov iterations ("inner" iterations): the steady solver's step
// system (FlowSolver.h, StepSystem) with a0 / (J dt) added to its diagonal, which makes its exact
// system matrix the exact Jacobian of R*, and its preconditioner the approximate Jacobian plus
// that diagonal. An optional pseudo-time term (pseudoCfl) damps the inner iterations of large time
// steps.
//
// What it is for: a shape whose steady solve does not converge may have no steady flow at all
// (vortex shedding behind a blunt or creased edge). Run forward in physical time, such a flow
// oscillates; one that has a steady state settles into it (and a steady solve from there
// converges). summarizeSignal turns the lift's history into that verdict.
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "flow/FlowMesh.h"
#include "flow/FlowSolver.h"
#include "flow/Residual.h"

namespace aero::flow {

struct TimeAccurateOptions {
    double timeStep = 0.25;        // physical dt, in grid lengths over the free-stream speed of
                                   // sound (Euler.h): the free stream crosses a unit length in
                                   // 1 / Mach of these
    int steps = 100;               // physical time steps: the run ends at t = steps timeStep (a
                                   // step whose inner iterations do not converge is taken again
                                   // with half the size, down to timeStep / 64, and the steps
                                   // after it grow back by 2 each: variable-step BDF2)
    int maxInner = 20;             // Newton iterations per time step at most
    double innerTolerance = 1e-3;  // a step is solved when ||R*|| is this factor below its value
                                   // at the step's first iterate (or below the steady tolerance:
                                   // NewtonOptions::relativeTolerance times the reference residual)
    double pseudoCfl = 0;          // > 0: the inner iterations add the pseudo-time term of the
                                   // steady solver's local time steps at this CFL (grown 10 times
                                   // per accepted iteration); 0: none (Newton on R*)
    double maxSeconds = 0;         // > 0: stop before a time step once this much wall time passed
    double maxMach = 10;           // the run stops when the local Mach number exceeds this
                                   // anywhere: pressure or density has collapsed to nearly zero
                                   // (a flow that breaks down at a crease the grid does not
                                   // resolve), not an expansion a steady flow at Mach 0.5 has
    bool lagPreconditioner = false; // true: the inner iterations after a step's first keep its
                                   // preconditioner (only the exact products follow the state).
                                   // Measured on the small half-sphere's impulsive start (20 steps
                                   // of 0.5): 365 GMRES iterations and 4.7 s against 169 and 4.1 s
                                   // with a fresh factorization every iteration, so off by default
                                   // (bench/FlowBench.cpp, docs/performance.md)
};

struct TimeStepRecord {
    int step = 0;
    double time = 0;                // t at the end of the step
    double timeStep = 0;            // its size (below TimeAccurateOptions::timeStep after a halving)
    int innerIterations = 0;        // Newton iterations (accepted)
    int linearIterations = 0;       // GMRES iterations of the step
    double innerReduction = 0;      // ||R*|| at the end over its value at the step's first iterate
    double steadyResidual = 0;      // ||R(q^(n+1))|| over the reference residual: how far the
                                    // state is from a steady one (falls towards the steady
                                    // tolerance when the flow settles)
    double rate = 0;                // rms over all values of (q^(n+1) - q^n) / dt
    double maxMach = 0;             // the largest local Mach number after the step ...
    long maxMachNode = -1;          // ... and where (global node)
    double seconds = 0;             // since the start
};

struct TimeAccurateReport {
    bool completed = false;         // every time step was taken
    bool cancelled = false;
    std::string message;            // the reason, when not completed
    std::vector<TimeStepRecord> history;
    int linearIterations = 0;
    int halvedSteps = 0;            // time steps taken again with half the size
    long breakdownNode = -1;        // >= 0: the run stopped because the local Mach number passed
                                    // TimeAccurateOptions::maxMach at this node (the last record's)
    double referenceResidual = 0;   // what TimeStepRecord::steadyResidual refers to
    double seconds = 0;
};

/// Advances q (5 per node; the free stream if empty) by t.steps physical time steps of t.timeStep.
/// `n` supplies the linear solver's settings (GMRES, preconditioner, products, maxRelativeChange)
/// and, in referenceResidual, the residual the steady residual is reported against (0: ||R(q)||
/// at the start). onStep is called after every step with its record and the new state; cancel is
/// checked between inner iterations. On return q holds the last completed step's state.
using TimeStepFn = std::function<void(const TimeStepRecord&, const std::vector<double>& q)>;
TimeAccurateReport solveTimeAccurate(const FlowMesh& fm, const std::vector<double>& metrics, const ResidualOptions& o,
                                     std::vector<double>& q, const NewtonOptions& n, const TimeAccurateOptions& t,
                                     const TimeStepFn& onStep = {}, const std::atomic<bool>* cancel = nullptr);

/// What a sampled signal y(t) (a force coefficient's history) does over its later part: from
/// `from` on (a fraction of the samples, e.g. 0.5: the second half), its mean, range and the
/// periods between successive upward crossings of its mean.
struct SignalSummary {
    double mean = 0, minimum = 0, maximum = 0;
    int cycles = 0;                 // complete periods between upward mean crossings
    double period = 0;              // their mean length (0: fewer than one cycle)
    double periodSpread = 0;        // (longest - shortest) / mean period
    double amplitudeRatio = 0;      // the range over the last cycle over that of the first one
                                    // (< 1: decaying, about 1: sustained; 0: fewer than 2 cycles)
    double drift = 0;               // |y(end) - y(start of the window)| over the window's range
                                    // (near 1: monotone, the signal still moving one way)
};
SignalSummary summarizeSignal(const std::vector<double>& t, const std::vector<double>& y, double from = 0.5);

/// The verdict on a time-accurate run for a human: whether the flow settles (its steady residual
/// falls to `steadyTolerance`, or the lift stops moving), oscillates periodically (period,
/// amplitude, Strouhal number on `referenceLength` at free-stream Mach `mach`) or neither yet.
std::string describeUnsteadiness(const TimeAccurateReport& r, const std::vector<double>& lift, double steadyTolerance,
                                 double referenceLength, double mach);

}  // namespace aero::flow
