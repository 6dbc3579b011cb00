// Newton-Krylov solution of the Euler equations: convergence, the reported status, and the
// physics of subsonic flow past the half-sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>

#include "FlowFixtures.h"
#include "flow/FlowSolver.h"
#include "flow/Outputs.h"

namespace aero::flow {
namespace {

// Residual options at this free stream (the rest default).
ResidualOptions freeStreamAt(double mach, double alphaDeg) {
    ResidualOptions o;
    o.freeStream.mach = mach;
    o.freeStream.alphaDeg = alphaDeg;
    return o;
}

FlowReport solve(const testing::FlowCase& c, const ResidualOptions& o, std::vector<double>& q,
                 const NewtonOptions& n = {}) {
    return solveFlow(c.fm, c.metrics, o, q, n, [](const FlowIteration& it) {
        if (it.iteration % 10 == 0) {
            std::printf("  it %3d  |R|/|R0| %.3e  CFL %.2e  GMRES %3d (%.2e)  %.2f s\n", it.iteration,
                        it.relativeResidual, it.cfl, it.linearIterations, it.linearResidual, it.seconds);
        }
    });
}

// Settings under which exact steps fail and hand over to approximate ones on the coarse
// half-sphere at Mach 0.75 (GMRES cut to 15 iterations per step).
NewtonOptions failingExactSteps() {
    NewtonOptions n;
    n.gmresRestart = 15;
    n.gmresMaxIterations = 15;
    n.gmresDeflation = 0;
    n.cflGrowth = 2.5;
    n.maxIterations = 50;
    n.recoveryIterations = 10;
    n.switchContinuation = 0;  // the kinked switch throughout: the smoothed one avoids the failures
    n.backoffMiss = 1.0;       // and the CFL backed off after every miss: with GMRES cut to 15
                               // iterations most steps miss, and without the back-off the run
                               // takes a path (which one depends on the thread count's
                               // rounding) where the exact steps recover from each failure
    return n;
}

TEST(FlowSolver, DisturbedFlowInACurvedBoxReturnsToTheFreeStream) {
    // Farfield all round (symmetry planes at y = 0, 1): the only steady state is the free
    // stream, which the discretization preserves exactly on this curved grid.
    const auto box = testing::wavyBox(10, mesh::BoundaryKind::Symmetry);
    ResidualOptions o;
    o.freeStream.mach = 0.5;
    std::vector<double> q = testing::smoothState(box, 0.5, 0.2);
    const FlowReport rep = solve(box, o, q);
    std::printf("%s\n", rep.message.c_str());
    ASSERT_TRUE(rep.converged()) << rep.message;
    EXPECT_LE(rep.finalResidual, 1e-10 * rep.initialResidual);
    EXPECT_EQ(rep.iterations, static_cast<int>(rep.history.size()));
    const auto qinf = o.freeStream.state();
    double worst = 0;
    for (long n = 0; n < box.fm.nodeCount; ++n) {
        for (int v = 0; v < kVars; ++v) worst = std::max(worst, std::abs(q[kVars * n + v] - qinf[v]));
    }
    EXPECT_LT(worst, 1e-9);
}

TEST(FlowSolver, HalfSphereAtMachHalfConvergesTenOrdersWithoutLift) {
    // A small half-sphere grid (20 blocks of 9 x 9 x 7 nodes, farfield at 5 radii).
    const auto& c = testing::halfSphere(0.5, 0.05, 5.0);
    ResidualOptions o;
    o.freeStream.mach = 0.5;
    std::vector<double> q;
    const FlowReport rep = solve(c, o, q);
    std::printf("%s (%d GMRES iterations, %.1f s)\n", rep.message.c_str(), rep.linearIterations, rep.seconds);
    ASSERT_TRUE(rep.converged()) << rep.message;
    EXPECT_LE(rep.finalResidual, 1e-10 * rep.initialResidual);
    // The last iterations are inexact Newton's (GMRES forcing term 0.05): the residual falls by
    // more than a factor 10 per iteration.
    ASSERT_GE(rep.history.size(), 3u);
    const auto& h = rep.history;
    EXPECT_LT(h.back().residual, 1e-2 * h[h.size() - 3].residual);

    ForceReference ref;
    ref.area = 3.14159265358979323846 / 2;  // the half-sphere's frontal area
    const ForceCoefficients f = integrateForces(c.fm, c.metrics, c.x, q, o.freeStream, ref);
    const auto s = entropy(c.fm, q, o.freeStream);
    const auto mach = machNumber(c.fm, q, o.freeStream.gamma);
    double smax = 0;
    for (double v : s) smax = std::max(smax, std::abs(v));
    const double mmax = *std::max_element(mach.begin(), mach.end());
    std::printf("CL %.3e  CD %.4f  CM %.3e  CY %.3e  max |s - s_inf| %.3e  max Mach %.3f\n", f.CL, f.CD, f.CM, f.CY, smax, mmax);
    // Up-down symmetry of the body and of the flow at alpha 0: no lift, no pitching moment.
    EXPECT_LT(std::abs(f.CL), 1e-3);
    EXPECT_LT(std::abs(f.CM), 1e-3);
    // d'Alembert: the drag is numerical error only; on this coarse grid it is small but not zero.
    EXPECT_GT(f.CD, -0.05);
    EXPECT_LT(f.CD, 0.2);
    // Subsonic flow accelerates around the sphere (potential flow: 1.5 U at the equator).
    EXPECT_GT(mmax, 0.6);
    EXPECT_LT(mmax, 1.0);
    // The largest entropy error sits at the rear stagnation point, a corner of wall, symmetry
    // plane and block interface: 0.050 here, 0.0082 on the 75k-node grid of the same level
    // (docs/validation.md). It was 0.045 before the wall junctions got a shared normal, which
    // removed an O(1) truncation error at every other wall junction (ResidualTest).
    EXPECT_LT(smax, 0.06);
}

TEST(FlowSolver, TheLastNewtonStepSolvesOnlyAsFarAsTheToleranceNeeds) {
    // With the forcing term 0.05 throughout, the last Newton step takes the residual past the
    // tolerance by up to a factor 20 and pays GMRES iterations for it, or leaves it short by a
    // small factor that takes one more step (an assembly, a factorization and its GMRES
    // iterations). NewtonOptions::finalForcing solves the last step only to half the factor left
    // (at most finalForcing), and solves a step further when that makes it the last one (to half
    // the factor left, when that is within 8 times the forcing term and the step before followed
    // its own; a factor of 8 to 10 left is not loosened: 0.05 is about half of it already). At two
    // tolerances, which end this grid's path in each way: the same path up to the first step so
    // adjusted, that step the last one, and still converged.
    const auto& c = testing::halfSphere(0.5, 0.05, 5.0);
    const ResidualOptions o = freeStreamAt(0.5, 0.0);
    bool loosened = false, tightened = false;
    // (The path without them: 1.1e-8 after step 14, 5.4e-10 after 15, 2.7e-11 after 16.)
    for (const double tolerance : {1e-10, 1.25e-9}) {
        SCOPED_TRACE(tolerance);
        NewtonOptions always, adjusted;
        always.finalForcing = 0;
        always.relativeTolerance = adjusted.relativeTolerance = tolerance;
        std::vector<double> qAlways, qFinal;
        const FlowReport a = solve(c, o, qAlways, always);
        const FlowReport f = solve(c, o, qFinal, adjusted);
        ASSERT_TRUE(a.converged()) << a.message;
        ASSERT_TRUE(f.converged()) << f.message;
        EXPECT_LE(f.finalResidual, tolerance * f.initialResidual);
        for (const FlowIteration& h : a.history) EXPECT_DOUBLE_EQ(h.linearTarget, 0.05) << "iteration " << h.iteration;
        const std::size_t last = f.history.size() - 1;
        std::size_t first = 0;  // the first step whose GMRES tolerance was adjusted
        while (first < f.history.size() && f.history[first].linearTarget == 0.05) ++first;
        ASSERT_EQ(first, last) << "only the last step is adjusted";
        ASSERT_LE(f.history.size(), a.history.size());
        for (std::size_t i = 0; i < last; ++i) {
            EXPECT_EQ(a.history[i].residual, f.history[i].residual) << "iteration " << i + 1;
            EXPECT_EQ(a.history[i].linearIterations, f.history[i].linearIterations) << "iteration " << i + 1;
        }
        // Half the factor that was left, loosened to at most finalForcing or tightened to at
        // least an eighth of the forcing term.
        const double left = tolerance * f.initialResidual / f.history[last - 1].residual;  // (after each step)
        const double target = f.history[last].linearTarget;
        EXPECT_DOUBLE_EQ(target, left > 0.05 ? std::min(0.25, 0.5 * left) : 0.5 * left);
        EXPECT_GE(left, 0.05 / 8);
        EXPECT_LE(f.history[last].linearResidual, target);
        // Tightened: one step less. Loosened from 0.05 to at most 0.065 here: at most as many
        // GMRES iterations (one GMRES iteration reduces more than that).
        if (target < 0.05) {
            EXPECT_LT(f.linearIterations, a.linearIterations);
            EXPECT_EQ(f.history.size() + 1, a.history.size());
        } else {
            EXPECT_LE(f.linearIterations, a.linearIterations);
        }
        loosened = loosened || target > 0.05;
        tightened = tightened || target < 0.05;
        std::printf("tolerance %.3g: %zu steps against %zu; the last: %d GMRES iterations to %.4f (a factor %.2f "
                    "left); %d GMRES in all against %d\n",
                    tolerance, f.history.size(), a.history.size(), f.history[last].linearIterations, target, 1 / left,
                    f.linearIterations, a.linearIterations);
    }
    EXPECT_TRUE(loosened);
    EXPECT_TRUE(tightened);
}

TEST(FlowSolver, HandsACrawlingApproximatePhaseToNewton) {
    // Exact steps only through the crawl test (exactBelow 0): the disturbed box first runs on
    // approximate-Jacobian steps only, then with a contraction threshold above their observed
    // rate, which must hand the iteration to Newton for good (no exact step fails here).
    const auto box = testing::wavyBox(8, mesh::BoundaryKind::Wall);
    ResidualOptions o;
    o.freeStream.mach = 0.5;
    NewtonOptions n;
    n.exactBelow = 0;
    n.exactCfl = 10;
    n.slowWindow = 0;  // no crawl test
    std::vector<double> q = testing::smoothState(box, 0.5, 0.2);
    const FlowReport plain = solve(box, o, q, n);
    ASSERT_TRUE(plain.converged()) << plain.message;
    for (const FlowIteration& it : plain.history) EXPECT_FALSE(it.exact) << "iteration " << it.iteration;
    // The approximate phase's contraction per step once the CFL is past exactCfl.
    double slowest = 0;
    for (std::size_t i = 1; i < plain.history.size(); ++i) {
        if (plain.history[i].cfl >= n.exactCfl) {
            slowest = std::max(slowest, plain.history[i].residual / plain.history[i - 1].residual);
        }
    }
    std::printf("approximate steps only: %d iterations, slowest contraction %.3f\n", plain.iterations, slowest);
    ASSERT_GT(slowest, 0.05);

    n.slowWindow = 3;
    n.slowContraction = 0.5 * slowest;
    q = testing::smoothState(box, 0.5, 0.2);
    const FlowReport newton = solve(box, o, q, n);
    ASSERT_TRUE(newton.converged()) << newton.message;
    const auto& h = newton.history;
    const auto first = std::find_if(h.begin(), h.end(), [](const FlowIteration& it) { return it.exact; });
    ASSERT_NE(first, h.end()) << "no exact step";
    // Not before the window of full approximate steps at CFL >= exactCfl, and for good after.
    const long before = first - h.begin();
    EXPECT_GE(before, n.slowWindow + 1);
    for (auto it = first; it != h.end(); ++it) EXPECT_TRUE(it->exact) << "iteration " << it->iteration;
    std::printf("with the crawl test: %d iterations, the first exact one %d\n", newton.iterations, first->iteration);
    EXPECT_LE(newton.iterations, plain.iterations);
}

TEST(FlowSolver, ExactStepsThatDoNotRecoverFromAFailureHandOverToApproximateOnes) {
    // A failed exact step falls back to one approximate step; the exact steps that follow get
    // recoveryIterations to reach a new best residual, and when they do not, approximate steps
    // take over until the crawl test hands them back to Newton (on the 903k half-sphere the exact
    // steps after a failure wandered at CFL 70-300 and stalled; the approximate ones converged
    // it; docs/validation.md). Provoked here on the coarse half-sphere at Mach 0.75 with GMRES
    // cut to 15 iterations per step, so that exact steps fail and the residual wanders; the
    // test checks the rule, not convergence (this case does not converge either way).
    const testing::FlowCase& c = testing::halfSphere(0.3);
    const ResidualOptions o = freeStreamAt(0.75, 1.2);
    NewtonOptions n = failingExactSteps();
    std::vector<double> q;
    const FlowReport rep = solve(c, o, q, n);
    std::printf("%s; approximate steps from iteration %d\n", rep.message.c_str(), rep.approximateFrom);
    ASSERT_GT(rep.approximateFrom, 0) << "the exact steps always recovered: the test does not test the hand-over";
    const auto& h = rep.history;
    const std::size_t from = static_cast<std::size_t>(rep.approximateFrom - 1);  // history index
    ASSERT_LT(from, h.size());
    // Before the hand-over: the failure (an approximate step right after an exact one), then
    // recoveryIterations iterations with no new best residual (other failures may come in them).
    ASSERT_GT(from, static_cast<std::size_t>(n.recoveryIterations + 1));
    const std::size_t fail = from - static_cast<std::size_t>(n.recoveryIterations + 1);
    EXPECT_TRUE(h[fail - 1].exact && !h[fail].exact) << "no failed exact step at iteration " << h[fail].iteration;
    double bestBefore = h[0].residual;
    for (std::size_t i = 0; i < fail; ++i) bestBefore = std::min(bestBefore, h[i].residual);
    for (std::size_t i = fail + 1; i < from; ++i) {
        EXPECT_GE(h[i].residual, 0.99 * bestBefore) << "iteration " << h[i].iteration << ": a new best, no hand-over due";
    }
    // After it: approximate steps only (the crawl test needs full steps at CFL >= 1e6 to hand
    // back to Newton, which this run does not reach).
    for (std::size_t i = from; i < h.size(); ++i) EXPECT_FALSE(h[i].exact) << "iteration " << h[i].iteration;

    // With recoveryIterations 0 the same run never hands over: exact steps follow every failure.
    n.recoveryIterations = 0;
    q.clear();
    const FlowReport never = solve(c, o, q, n);
    EXPECT_EQ(never.approximateFrom, 0);
    int exactAfterFailure = 0;
    for (std::size_t i = 2; i < never.history.size(); ++i) {
        if (never.history[i - 2].exact && !never.history[i - 1].exact && never.history[i].exact) ++exactAfterFailure;
    }
    EXPECT_GT(exactAfterFailure, 0);
}

TEST(FlowSolver, LowMemoryStepsFreeTheMatrixAndTheBasisAndRebuildThem) {
    // NewtonOptions::lowMemoryNodes 0 frees the approximate Jacobian after each exact step's
    // factorization (keeps it rounded to float for an approximate step's products) and the Krylov
    // basis before each assembly; a failed exact step assembles the matrix again for its
    // approximate retry; and it stores the ILU factors in bfloat16 and the basis in float,
    // whatever the options say. Same run as above (exact steps that fail, then approximate ones),
    // against a run with those two storages chosen and the memory kept: the exact steps up to the
    // first approximate one must be the same to the bit, the failed step's retry the same to
    // float rounding.
    const testing::FlowCase& c = testing::halfSphere(0.3);
    const ResidualOptions o = freeStreamAt(0.75, 1.2);
    NewtonOptions n = failingExactSteps();
    n.maxIterations = 30;
    n.exactBelow = 2;  // exact steps from the start, so the first approximate one is a retry
    n.iluPrecision = IluPrecision::Bfloat16;
    n.gmresSingleBasis = true;
    std::vector<double> q;
    const FlowReport plain = solve(c, o, q, n);
    n.lowMemoryNodes = 0;
    n.iluPrecision = IluPrecision::Double;  // overridden by the low-memory mode
    n.gmresSingleBasis = false;
    std::vector<double> lean;
    const FlowReport low = solve(c, o, lean, n);
    ASSERT_GE(low.history.size(), 2u);
    const auto& h = plain.history;
    std::size_t retry = 0;
    while (retry < h.size() && h[retry].exact) ++retry;
    std::printf("%d iterations; the first approximate step (a failed exact step's retry): %zu\n", plain.iterations, retry + 1);
    ASSERT_GT(retry, 0u) << "no exact step";
    ASSERT_LT(retry, h.size()) << "no failed exact step: the rebuild is not tested";
    ASSERT_GT(low.history.size(), retry);
    for (std::size_t i = 0; i < retry; ++i) {
        EXPECT_EQ(low.history[i].residual, h[i].residual) << "iteration " << i + 1;
        EXPECT_EQ(low.history[i].linearIterations, h[i].linearIterations) << "iteration " << i + 1;
    }
    EXPECT_FALSE(low.history[retry].exact);
    EXPECT_NEAR(low.history[retry].residual, h[retry].residual, 1e-4 * h[retry].residual);
    std::printf("iteration %zu: residual %.6e, low memory %.6e\n", retry + 1, h[retry].residual, low.history[retry].residual);

    // A converging case with approximate steps down to 1e-2: the same solution (the residual is
    // the same; only the path differs).
    const ResidualOptions half = freeStreamAt(0.5, 1.2);
    std::vector<double> q0, q1;
    NewtonOptions late;
    late.exactBelow = 1e-2;
    late.iluPrecision = IluPrecision::Bfloat16;
    late.gmresSingleBasis = true;
    const FlowReport a = solve(c, half, q0, late);
    late.lowMemoryNodes = 0;
    const FlowReport b = solve(c, half, q1, late);
    ASSERT_FALSE(a.history.front().exact);
    ASSERT_TRUE(a.converged()) << a.message;
    ASSERT_TRUE(b.converged()) << b.message;
    double worst = 0;
    for (std::size_t i = 0; i < q0.size(); ++i) worst = std::max(worst, std::abs(q0[i] - q1[i]));
    std::printf("Mach 0.5: %d and %d iterations, states differ by %.3e at most\n", a.iterations, b.iterations, worst);
    EXPECT_LT(worst, 1e-8);
    EXPECT_LE(std::abs(a.iterations - b.iterations), 2);
}

TEST(FlowSolver, BfloatPreconditionerFactorsReachTheSameSolution) {
    // flow.ilu_precision bfloat16: the ILU factors stored with 8 significant bits (half the memory
    // of float). Only the preconditioner changes, so the converged state is the same and the
    // Newton and GMRES iterations stay close to the float factors' (the same counts on the
    // samples: docs/performance.md).
    const testing::FlowCase& c = testing::halfSphere(0.3);
    const ResidualOptions o = freeStreamAt(0.5, 1.2);
    NewtonOptions n;
    std::vector<double> q0, q1;
    const FlowReport single = solve(c, o, q0, n);
    n.iluPrecision = IluPrecision::Bfloat16;
    const FlowReport half = solve(c, o, q1, n);
    ASSERT_TRUE(single.converged()) << single.message;
    ASSERT_TRUE(half.converged()) << half.message;
    double worst = 0;
    for (std::size_t i = 0; i < q0.size(); ++i) worst = std::max(worst, std::abs(q0[i] - q1[i]));
    std::printf("float factors: %d iterations, %d GMRES; bfloat16: %d, %d; states differ by %.3e\n", single.iterations,
                single.linearIterations, half.iterations, half.linearIterations, worst);
    EXPECT_LT(worst, 1e-8);
    EXPECT_LE(std::abs(single.iterations - half.iterations), 2);
    EXPECT_LE(half.linearIterations, single.linearIterations + single.linearIterations / 5);
}

TEST(FlowSolver, ANearerPreconditionerForTheLastNewtonStepsChangesThePathNotTheAnswer) {
    // NewtonOptions::exactLumping (flow.exact_lumping, off by default): from CFL exactLumpingCfl
    // on, the exact steps' preconditioner is assembled with less lumping (nearer the exact
    // Jacobian). Only the preconditioner of those steps changes: every step before the first
    // such one is the same, some GMRES count after it differs, and the converged state is the
    // same.
    const testing::FlowCase& c = testing::halfSphere(0.3);
    const ResidualOptions o = freeStreamAt(0.5, 1.2);
    const double nearerLumping = 2.5;  // the factor measured in docs/performance.md
    NewtonOptions n;
    n.exactLumping = 0;
    std::vector<double> q0, q1;
    const FlowReport plain = solve(c, o, q1, n);
    ASSERT_TRUE(plain.converged()) << plain.message;
    // From the CFL of the third step from the end, so that the option acts on the last steps of
    // this path (the default, 1e6, is for grids whose paths go further).
    ASSERT_GE(plain.history.size(), 3u);
    n.exactLumpingCfl = plain.history[plain.history.size() - 3].cfl;
    n.exactLumping = nearerLumping;
    ASSERT_LT(n.exactLumping, o.dissipation.lumping);
    const FlowReport nearer = solve(c, o, q0, n);
    ASSERT_TRUE(nearer.converged()) << nearer.message;
    double worst = 0;
    for (std::size_t i = 0; i < q0.size(); ++i) worst = std::max(worst, std::abs(q0[i] - q1[i]));
    std::printf("lumping %g from CFL %g: %d iterations, %d GMRES; lumping %g throughout: %d, %d; states differ by %.3e\n",
                nearerLumping, n.exactLumpingCfl, nearer.iterations, nearer.linearIterations,
                o.dissipation.lumping, plain.iterations, plain.linearIterations, worst);
    EXPECT_LT(worst, 1e-8);
    std::size_t first = 0;  // the first step the option acts on
    while (first < plain.history.size() &&
           !(plain.history[first].exact && plain.history[first].cfl >= n.exactLumpingCfl)) {
        ++first;
    }
    ASSERT_LT(first, plain.history.size()) << "no exact step reached CFL " << n.exactLumpingCfl;
    ASSERT_GT(nearer.history.size(), first);
    for (std::size_t k = 0; k < first; ++k) {
        EXPECT_EQ(nearer.history[k].linearIterations, plain.history[k].linearIterations) << "step " << k + 1;
        EXPECT_EQ(nearer.history[k].residual, plain.history[k].residual) << "step " << k + 1;
    }
    bool differs = nearer.history.size() != plain.history.size();
    for (std::size_t k = first; k < std::min(nearer.history.size(), plain.history.size()); ++k) {
        differs = differs || nearer.history[k].linearIterations != plain.history[k].linearIterations;
    }
    EXPECT_TRUE(differs) << "the option did not change any step from " << first + 1 << " on";
}

TEST(FlowSolver, LocalCflKeepsOneStiffNodeFromHoldingTheWholeStep) {
    // A smooth disturbance plus one node at a hundredth of its pressure: the steps that fill it
    // change it by far more than the 30 % limit. With one global step scale the whole field
    // creeps at that node's pace; with per-node CFL factors only that node's time step is cut.
    // Both must reach the same (exact) steady state, the free stream.
    const auto box = testing::wavyBox(10, mesh::BoundaryKind::Symmetry);
    ResidualOptions o;
    o.freeStream.mach = 0.5;
    const std::vector<double> start = [&] {
        std::vector<double> q = testing::smoothState(box, 0.5, 0.05);
        double* spike = &q[kVars * (box.fm.nodeCount / 2)];
        const double kinetic = 0.5 * (spike[1] * spike[1] + spike[2] * spike[2] + spike[3] * spike[3]) / spike[0];
        const double p = 0.4 * (spike[4] - kinetic);
        spike[4] = kinetic + 0.01 * p / 0.4;  // a near-vacuum node: p / 100
        return q;
    }();
    const auto qinf = o.freeStream.state();
    struct Run {
        int iterations = 0;
        double lowestCfl = 0;
    };
    auto run = [&](bool local) {
        std::vector<double> q = start;
        NewtonOptions n;
        n.localCfl = local;
        const FlowReport rep = solve(box, o, q, n);
        EXPECT_TRUE(rep.converged()) << (local ? "local: " : "global: ") << rep.message;
        double worst = 0;
        for (long i = 0; i < box.fm.nodeCount; ++i) {
            for (int v = 0; v < kVars; ++v) worst = std::max(worst, std::abs(q[kVars * i + v] - qinf[v]));
        }
        EXPECT_LT(worst, 1e-9);
        Run r{rep.iterations, std::numeric_limits<double>::infinity()};
        for (const FlowIteration& it : rep.history) r.lowestCfl = std::min(r.lowestCfl, it.cfl);
        std::printf("%s CFL: %d iterations, lowest CFL %.3g\n", local ? "local" : "global", r.iterations, r.lowestCfl);
        return r;
    };
    const Run global = run(false), local = run(true);
    EXPECT_LT(global.lowestCfl, 0.5);            // the case does hold a global CFL down
    EXPECT_GT(local.lowestCfl, 10.0 * global.lowestCfl);
    EXPECT_LT(local.iterations, global.iterations);
}

TEST(FlowSolver, ReportsAStallWhenNeitherTheResidualNorTheCflMoves) {
    // Steps cut to a millionth of a relative change: the CFL base never grows and the residual
    // hardly moves, so the solver must stop after stallIterations and say so.
    const auto box = testing::wavyBox(5, mesh::BoundaryKind::Wall);
    ResidualOptions o;
    std::vector<double> q = testing::smoothState(box, 0.5, 0.2);
    NewtonOptions n;
    n.maxRelativeChange = 1e-6;
    n.stallIterations = 6;
    n.switchContinuation = 0;  // the stall rule alone first
    const std::vector<double> start = q;
    const FlowReport rep = solve(box, o, q, n);
    EXPECT_EQ(rep.status, FlowStatus::Stalled) << rep.message;
    EXPECT_EQ(rep.iterations, n.stallIterations + 1);  // the first step sets the CFL high
    EXPECT_NE(rep.message.find("no progress in 6 iterations"), std::string::npos) << rep.message;
    for (const FlowIteration& it : rep.history) EXPECT_LT(it.stepScale, 1.0);
    // With the switch continuation a stall of the smoothed problem hands over to the case's own
    // switch with a fresh window, and the stall of that one is reported.
    n.switchContinuation = 0.01;
    q = start;
    const FlowReport twice = solve(box, o, q, n);
    EXPECT_EQ(twice.status, FlowStatus::Stalled) << twice.message;
    EXPECT_EQ(twice.switchedAt, n.stallIterations + 2);
    EXPECT_EQ(twice.iterations, 2 * n.stallIterations + 1);
    EXPECT_NE(twice.message.find("no progress in 6 iterations"), std::string::npos) << twice.message;
    // A new highest CFL at or above stallCflCeiling is no progress: with the ceiling below the
    // first step's CFL that step no longer opens the window, so the stall comes one step sooner.
    n.switchContinuation = 0;
    n.stallCflCeiling = 0.5 * n.cfl0;
    q = start;
    const FlowReport capped = solve(box, o, q, n);
    EXPECT_EQ(capped.status, FlowStatus::Stalled) << capped.message;
    EXPECT_EQ(capped.iterations, n.stallIterations);
    EXPECT_GE(capped.history.front().cfl, n.stallCflCeiling);
}

TEST(CflLaw, ARejectedAttemptCutsTheCflActuallyUsedEvenNearConvergence) {
    // The 98k random 2 design's last steps: accepted at CFL 1.05e5 at a relative residual of
    // 1.48e-9, then the attempt at 4 times that rejected. Every retry has to come at a tenth of
    // the CFL before it (the base alone times (R0/R) = 6.7e8 gave back 4.19e5 nine times).
    NewtonOptions o;
    const double R0 = 1.0, R = 1.48e-9;
    CflLaw law(o, o.cfl0);
    FlowIteration rec;
    rec.cfl = 1.05e5;
    rec.stepScale = 1.0;
    rec.linearResidual = 0.5 * o.linearTolerance;
    law.accepted(rec);
    double cfl = law.next(R, R0);
    EXPECT_DOUBLE_EQ(cfl, o.cflMaxIncrease * rec.cfl);  // capped by the last accepted step's
    for (int retry = 0; retry < 10; ++retry) {
        law.rejected(cfl, R, R0);
        const double cut = law.next(R, R0);
        EXPECT_NEAR(cut, std::max(1e-3 * o.cfl0, 0.1 * cfl), 1e-9 * cfl) << "retry " << retry;
        cfl = cut;
    }
    EXPECT_DOUBLE_EQ(cfl, 1e-3 * o.cfl0);  // 4.19e5 / 1e9 < the floor, which bounds the CFL itself
    // Far from convergence (R = R0) the same cut: a tenth of the CFL used.
    CflLaw early(o, o.cfl0);
    early.rejected(o.cfl0, R0, R0);
    EXPECT_DOUBLE_EQ(early.next(R0, R0), 0.1 * o.cfl0);
    // After the cut, full steps grow the CFL again from there.
    rec.cfl = cfl;
    law.accepted(rec);
    EXPECT_NEAR(law.next(R, R0), o.cflGrowth * cfl, 1e-12 * cfl);
}

TEST(CflLaw, BacksOffOnlyWhenGmresMissesItsToleranceByMoreThanTheDriftOfItsEstimate) {
    // Deflated GMRES stops on its estimate; the true residual it reports can end a few percent
    // above the tolerance (0.051-0.07 against 0.05 on the coarse optimum's 98k flow). Such a step
    // is as good as one that met it: the CFL grows. A real miss (the system too hard at this
    // CFL) halves the base, and so does any miss when backoffMiss is 1.
    NewtonOptions o;
    FlowIteration rec;
    rec.cfl = 1e4;
    rec.stepScale = 1.0;
    auto baseAfter = [&](double linearResidual, double linearTarget, const NewtonOptions& opt) {
        CflLaw law(opt, 100.0);
        rec.linearResidual = linearResidual;
        rec.linearTarget = linearTarget;
        law.accepted(rec);
        return law.base();
    };
    EXPECT_DOUBLE_EQ(baseAfter(0.04, 0.0, o), 100.0 * o.cflGrowth);
    EXPECT_DOUBLE_EQ(baseAfter(0.07, 0.0, o), 100.0 * o.cflGrowth);   // drift
    EXPECT_DOUBLE_EQ(baseAfter(0.2, 0.0, o), 100.0 * o.cflBackoff);  // a real miss
    // Against a looser target (the last step's) the same: 0.4 misses 0.25 by less than 2.
    EXPECT_DOUBLE_EQ(baseAfter(0.4, 0.25, o), 100.0 * o.cflGrowth);
    EXPECT_DOUBLE_EQ(baseAfter(0.6, 0.25, o), 100.0 * o.cflBackoff);
    NewtonOptions strict = o;
    strict.backoffMiss = 1.0;
    EXPECT_DOUBLE_EQ(baseAfter(0.051, 0.0, strict), 100.0 * o.cflBackoff);
}

TEST(FlowSolver, ATolerancePastTheRoundOffLevelEndsConvergedThere) {
    // No double-precision state meets a relative tolerance of 1e-30: the residual settles at its
    // round-off level, and after kRoundOffWindow (5) steps without a new best there the solve
    // ends converged and says why, instead of stalling (which would start the evaluator's retries
    // and mode search) after stallIterations.
    const auto box = testing::wavyBox(6, mesh::BoundaryKind::Wall);
    ResidualOptions o;
    std::vector<double> q = testing::smoothState(box, 0.5, 0.2);
    NewtonOptions n;
    n.relativeTolerance = 1e-30;
    n.absoluteTolerance = 0;
    n.stallIterations = 50;
    const FlowReport rep = solve(box, o, q, n);
    ASSERT_EQ(rep.status, FlowStatus::Converged) << rep.message;
    EXPECT_NE(rep.message.find("round-off level"), std::string::npos) << rep.message;
    EXPECT_LT(rep.relativeResidual(), 1e-11);
    const int h = static_cast<int>(rep.history.size());
    ASSERT_GT(h, 6);
    // It ended well before the stall test would have.
    int firstBelow = -1;
    for (int i = 0; i < h && firstBelow < 0; ++i) {
        if (rep.history[i].residual <= 1e-10 * rep.initialResidual) firstBelow = i;
    }
    ASSERT_GE(firstBelow, 0);
    EXPECT_LT(h - firstBelow, n.stallIterations) << rep.message;
}

TEST(FlowSolver, ReportsANonPhysicalStartInsteadOfIterating) {
    const auto box = testing::wavyBox(5, mesh::BoundaryKind::Wall);
    ResidualOptions o;
    std::vector<double> q = freeStreamState(box.fm, o.freeStream);
    q[kVars * 7] = -1.0;  // negative density at node 7
    const FlowReport rep = solve(box, o, q);
    EXPECT_EQ(rep.status, FlowStatus::NotANumber);
    EXPECT_NE(rep.message.find("density"), std::string::npos) << rep.message;
    q[kVars * 7] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(solve(box, o, q).status, FlowStatus::NotANumber);
}

TEST(FlowSolver, StopsOnCancelAndOnTheIterationLimitWithTheReason) {
    const auto box = testing::wavyBox(6, mesh::BoundaryKind::Wall);
    ResidualOptions o;
    std::vector<double> q = testing::smoothState(box, 0.5, 0.2);
    std::atomic<bool> cancel{true};
    const FlowReport cancelled = solveFlow(box.fm, box.metrics, o, q, {}, {}, &cancel);
    EXPECT_EQ(cancelled.status, FlowStatus::Cancelled);
    EXPECT_EQ(cancelled.iterations, 0);

    NewtonOptions n;
    n.maxIterations = 2;
    const FlowReport limited = solve(box, o, q, n);
    EXPECT_EQ(limited.status, FlowStatus::MaxIterations);
    EXPECT_FALSE(limited.converged());
    EXPECT_NE(limited.message.find("not converged"), std::string::npos) << limited.message;
    EXPECT_LT(limited.finalResidual, limited.initialResidual);
    EXPECT_STREQ(flowStatusName(limited.status), "max-iterations");

    // A time limit already spent stops the solve before its first iteration, with the residual.
    NewtonOptions timed;
    timed.maxSeconds = 1e-9;
    std::vector<double> qt = testing::smoothState(box, 0.5, 0.2);
    const std::vector<double> before = qt;
    const FlowReport late = solve(box, o, qt, timed);
    EXPECT_EQ(late.status, FlowStatus::TimeLimit);
    EXPECT_EQ(late.iterations, 0);
    EXPECT_FALSE(late.converged());
    EXPECT_EQ(qt, before);
    EXPECT_GT(late.finalResidual, 0.0);
    EXPECT_NE(late.message.find("time limit after 0 iterations"), std::string::npos) << late.message;
    EXPECT_STREQ(flowStatusName(late.status), "time-limit");
    // A generous one changes nothing.
    timed.maxSeconds = 1e6;
    timed.maxIterations = 2;
    const FlowReport generous = solve(box, o, qt, timed);
    EXPECT_EQ(generous.status, FlowStatus::MaxIterations);
    EXPECT_EQ(generous.finalResidual, limited.finalResidual);
}

TEST(FlowSolver, SwitchContinuationSolvesTheSmoothedProblemFirstAndConvergesTheCasesOwn) {
    // Far from the solution the pressure switch is smoothed (NewtonOptions::switchContinuation),
    // then the case's own (kinked) switch takes over from that state. The answer must be the
    // case's own steady state: the same as a run without the continuation, to the tolerance.
    const testing::FlowCase& c = testing::halfSphere(0.3);
    const ResidualOptions o = freeStreamAt(0.6, 1.2);
    NewtonOptions n;
    ASSERT_GT(n.switchContinuation, o.dissipation.switchSmoothing);  // on by default
    std::vector<double> q;
    const FlowReport rep = solve(c, o, q, n);
    ASSERT_TRUE(rep.converged()) << rep.message;
    ASSERT_GT(rep.switchedAt, 1) << "no continuation";
    // The smoothed phase ran until its residual was below switchContinuationUntil.
    const FlowIteration* last = nullptr;
    for (const FlowIteration& h : rep.history) {
        if (h.iteration < rep.switchedAt) last = &h;
    }
    ASSERT_NE(last, nullptr);
    EXPECT_LE(last->relativeResidual, n.switchContinuationUntil);
    EXPECT_GT(last->relativeResidual, n.relativeTolerance);
    // The final state solves the case's own residual.
    std::vector<double> r(q.size());
    residual(c.fm, c.metrics.data(), q.data(), o, r.data());
    double rr = 0;
    for (double v : r) rr += v * v;
    EXPECT_LE(std::sqrt(rr), 1.0001 * n.relativeTolerance * rep.initialResidual);
    // ... and is the state a run without the continuation converges to.
    NewtonOptions off = n;
    off.switchContinuation = 0;
    std::vector<double> plainQ;
    const FlowReport plain = solve(c, o, plainQ, off);
    ASSERT_TRUE(plain.converged()) << plain.message;
    EXPECT_EQ(plain.switchedAt, 0);
    double worst = 0;
    for (std::size_t i = 0; i < q.size(); ++i) worst = std::max(worst, std::abs(q[i] - plainQ[i]));
    EXPECT_LT(worst, 1e-8);
    std::printf("continuation: %d iterations (switch at %d), without: %d\n", rep.iterations, rep.switchedAt,
                plain.iterations);
    // A run stopped during the smoothed phase reports the case's own residual at its state.
    NewtonOptions shortRun = n;
    shortRun.maxIterations = 3;
    std::vector<double> early;
    const FlowReport stopped = solve(c, o, early, shortRun);
    ASSERT_EQ(stopped.status, FlowStatus::MaxIterations);
    ASSERT_EQ(stopped.switchedAt, 0);
    residual(c.fm, c.metrics.data(), early.data(), o, r.data());
    rr = 0;
    for (double v : r) rr += v * v;
    EXPECT_NEAR(stopped.finalResidual, std::sqrt(rr), 1e-12 * std::sqrt(rr));
    // A case whose own switch is already at least as smooth needs no continuation.
    ResidualOptions smooth = o;
    smooth.dissipation.switchSmoothing = n.switchContinuation;
    std::vector<double> smoothQ;
    const FlowReport same = solve(c, smooth, smoothQ, n);
    EXPECT_TRUE(same.converged()) << same.message;
    EXPECT_EQ(same.switchedAt, 0);
}

}  // namespace
}  // namespace aero::flow
