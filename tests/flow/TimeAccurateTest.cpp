// Time-accurate solutions by dual time stepping (flow/TimeAccurate.h): second order in time, an
// entropy wave carried at the free-stream speed, a disturbance that leaves the domain settling
// into the steady free stream, and the verdict on force histories.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "FlowFixtures.h"
#include "common/Error.h"
#include "flow/TimeAccurate.h"

namespace aero::flow {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The free stream (Mach 0.5 along x) with a density bump centred at (x0, 0.5, 0.5): the same
// velocity and pressure everywhere, so the exact solution is the bump carried along x at the
// free-stream speed (an entropy wave).
std::vector<double> entropyWave(const testing::FlowCase& c, const FreeStream& fs, double x0) {
    std::vector<double> q(kVars * static_cast<std::size_t>(c.fm.nodeCount));
    const auto u = fs.velocity();
    for (long n = 0; n < c.fm.nodeCount; ++n) {
        const double* x = &c.x[3 * n];
        const double r2 = (x[0] - x0) * (x[0] - x0) + (x[1] - 0.5) * (x[1] - 0.5) + (x[2] - 0.5) * (x[2] - 0.5);
        const double rho = 1.0 + 0.2 * std::exp(-r2 / 0.03);
        double* a = &q[kVars * n];
        a[0] = rho;
        for (int d = 0; d < 3; ++d) a[1 + d] = rho * u[d];
        a[4] = fs.pressure() / (fs.gamma - 1.0) + 0.5 * rho * fs.mach * fs.mach;
    }
    return q;
}

// The density bump's centre along x: the x of its excess mass (rho - 1), weighted by the volume
// 1/J of each node.
double bumpCentre(const testing::FlowCase& c, const std::vector<double>& q) {
    double mass = 0, moment = 0;
    for (long n = 0; n < c.fm.nodeCount; ++n) {
        const double m = (q[kVars * n] - 1.0) * c.metrics[kMetricWidth * n + 9];
        mass += m;
        moment += m * c.x[3 * n];
    }
    return moment / mass;
}

std::vector<double> advance(const testing::FlowCase& c, const ResidualOptions& o, double dt, double until,
                            TimeAccurateReport* report = nullptr) {
    std::vector<double> q = entropyWave(c, o.freeStream, 0.6);
    TimeAccurateOptions t;
    t.timeStep = dt;
    t.steps = static_cast<int>(std::lround(until / dt));
    t.innerTolerance = 1e-9;
    t.maxInner = 30;
    NewtonOptions n;
    n.linearTolerance = 1e-3;
    const TimeAccurateReport r = solveTimeAccurate(c.fm, c.metrics, o, q, n, t);
    EXPECT_TRUE(r.completed) << r.message;
    if (report) *report = r;
    return q;
}

double distance(const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
    return std::sqrt(s / static_cast<double>(a.size()));
}

TEST(TimeAccurate, AnEntropyWaveTravelsAtTheFreeStreamSpeedAndTheErrorIsSecondOrderInTime) {
    const auto box = testing::wavyBox(12, mesh::BoundaryKind::Symmetry);
    ResidualOptions o;
    o.freeStream.mach = 0.5;
    const double until = 0.8;  // the bump, centred at 0.6, ends at 1.0: far from both farfields
    TimeAccurateReport fine;
    const std::vector<double> reference = advance(box, o, until / 128, until, &fine);
    // The bump's centre moved by the free-stream speed times the time (the dissipation spreads
    // it, symmetrically to first order).
    const double moved = bumpCentre(box, reference) - bumpCentre(box, entropyWave(box, o.freeStream, 0.6));
    std::printf("bump moved %.4f (exact %.4f) in %zu steps, %d GMRES iterations\n", moved, 0.5 * until,
                fine.history.size(), fine.linearIterations);
    EXPECT_NEAR(moved, 0.5 * until, 0.01);
    // The temporal error against the 128-step answer falls by about 4 per halving of dt (BDF2;
    // the backward-Euler first step is O(dt^2) locally and keeps the order).
    std::vector<double> errors;
    for (int steps : {8, 16, 32}) {
        errors.push_back(distance(advance(box, o, until / steps, until), reference));
        std::printf("%2d steps: error %.3e\n", steps, errors.back());
    }
    for (std::size_t k = 0; k + 1 < errors.size(); ++k) {
        const double order = std::log2(errors[k] / errors[k + 1]);
        EXPECT_GT(order, 1.7) << "halving " << k;
        EXPECT_LT(order, 2.4) << "halving " << k;
    }
}

TEST(TimeAccurate, AStepWhoseInnerIterationsFailIsHalvedAndTheStepsGrowBack) {
    // One Newton iteration per step, which must reduce the unsteady residual 1000 times: too
    // nonlinear a step for that at dt 0.4 (the bump crosses two cells per step), enough at a
    // fraction of it. The run halves the steps that fail, grows the next ones back, ends exactly
    // at t = 0.8, and is closer to the fine reference than the two full steps are
    // (variable-step BDF2).
    const auto box = testing::wavyBox(12, mesh::BoundaryKind::Symmetry);
    ResidualOptions o;
    o.freeStream.mach = 0.5;
    const std::vector<double> reference = advance(box, o, 0.8 / 128, 0.8);
    std::vector<double> q = entropyWave(box, o.freeStream, 0.6);
    TimeAccurateOptions t;
    t.timeStep = 0.4;
    t.steps = 2;
    NewtonOptions n;
    n.linearTolerance = 1e-6;
    std::vector<double> full = q;
    const TimeAccurateReport two = solveTimeAccurate(box.fm, box.metrics, o, full, n, t);
    ASSERT_TRUE(two.completed && two.halvedSteps == 0) << two.message;
    t.maxInner = 1;
    t.innerTolerance = 1e-3;
    const TimeAccurateReport r = solveTimeAccurate(box.fm, box.metrics, o, q, n, t);
    ASSERT_TRUE(r.completed) << r.message;
    std::printf("%zu steps, %d halved:", r.history.size(), r.halvedSteps);
    for (const auto& rec : r.history) std::printf(" %g", rec.timeStep);
    std::printf("; error %.3e (two full steps: %.3e)\n", distance(q, reference), distance(full, reference));
    EXPECT_GT(r.halvedSteps, 0);
    EXPECT_GT(r.history.size(), 2u);
    EXPECT_NEAR(r.history.back().time, 0.8, 1e-12);
    double smallest = t.timeStep;
    for (std::size_t k = 0; k < r.history.size(); ++k) {
        smallest = std::min(smallest, r.history[k].timeStep);
        if (k > 0) {
            EXPECT_LE(r.history[k].timeStep, 2.0 * r.history[k - 1].timeStep * (1 + 1e-12));  // grows by 2 at most
        }
    }
    EXPECT_LT(smallest, t.timeStep);
    EXPECT_LT(distance(q, reference), 0.5 * distance(full, reference));
    // With no halving left to try (the smallest step allowed is the step itself) the run stops
    // and says why.
    std::vector<double> q2 = entropyWave(box, o.freeStream, 0.6);
    t.innerTolerance = 1e-12;
    n.relativeTolerance = 1e-14;
    n.linearTolerance = 0.5;  // one such Newton iteration cannot reduce the residual 1e12 times
    const TimeAccurateReport failed = solveTimeAccurate(box.fm, box.metrics, o, q2, n, t);
    EXPECT_FALSE(failed.completed);
    EXPECT_NE(failed.message.find("also with the time step halved to"), std::string::npos) << failed.message;
}

TEST(TimeAccurate, ADisturbanceCarriedOutOfTheDomainSettlesIntoTheSteadyFreeStream) {
    const auto box = testing::wavyBox(10, mesh::BoundaryKind::Symmetry);
    ResidualOptions o;
    o.freeStream.mach = 0.5;
    std::vector<double> q = entropyWave(box, o.freeStream, 0.6);
    TimeAccurateOptions t;
    t.timeStep = 0.5;
    t.steps = 40;
    NewtonOptions n;
    n.referenceResidual = 1.0;
    std::vector<double> lift;
    const TimeAccurateReport r = solveTimeAccurate(box.fm, box.metrics, o, q, n, t, [&](const TimeStepRecord& rec, const std::vector<double>&) {
        lift.push_back(rec.steadyResidual);  // (no wall: any signal will do for the verdict)
    });
    ASSERT_TRUE(r.completed) << r.message;
    ASSERT_EQ(r.history.size(), 40u);
    std::printf("steady residual: step 1 %.3e, 10 %.3e, 40 %.3e\n", r.history[0].steadyResidual, r.history[9].steadyResidual,
                r.history.back().steadyResidual);
    EXPECT_LT(r.history.back().steadyResidual, 1e-3 * r.history[0].steadyResidual);
    EXPECT_LT(r.history.back().rate, 1e-3 * r.history[0].rate);
    EXPECT_NEAR(r.history.back().time, 20.0, 1e-12);
    const std::string verdict = describeUnsteadiness(r, lift, 10.0 * r.history.back().steadyResidual, 1.0, 0.5);
    EXPECT_EQ(verdict.rfind("the flow settled into a steady state", 0), 0u) << verdict;
    const std::string later = describeUnsteadiness(r, lift, 1e-20, 1.0, 0.5);
    EXPECT_EQ(later.rfind("the flow is settling", 0), 0u) << later;
}

TEST(TimeAccurate, TheVerdictTellsAPeriodicFromADecayingFromAnUnsettledLift) {
    TimeAccurateReport r;
    std::vector<double> periodic, decaying, drifting, irregular;
    for (int k = 1; k <= 200; ++k) {
        TimeStepRecord rec;
        rec.step = k;
        rec.time = 0.25 * k;
        rec.steadyResidual = 1e-3;  // not falling: no steady state is being approached
        r.history.push_back(rec);
        periodic.push_back(0.3 + 0.1 * std::sin(2 * kPi * rec.time / 5.0));
        decaying.push_back(0.3 + 0.1 * std::exp(-rec.time / 6.0) * std::sin(2 * kPi * rec.time / 5.0));
        drifting.push_back(0.3 + 0.002 * rec.time);
        irregular.push_back(0.3 + 0.1 * std::sin(2 * kPi * rec.time / 5.0) + 0.09 * std::sin(2 * kPi * rec.time / 2.3));
    }
    std::vector<double> t;
    for (const auto& rec : r.history) t.push_back(rec.time);
    const SignalSummary s = summarizeSignal(t, periodic, 0.5);
    EXPECT_NEAR(s.mean, 0.3, 2e-3);
    EXPECT_NEAR(s.maximum - s.minimum, 0.2, 2e-3);
    EXPECT_NEAR(s.period, 5.0, 0.05);
    EXPECT_GE(s.cycles, 4);
    EXPECT_LT(s.periodSpread, 0.05);
    EXPECT_NEAR(s.amplitudeRatio, 1.0, 0.02);
    // Period 5 at Mach 0.5 on a reference length 1: Strouhal 1 / (5 x 0.5) = 0.4.
    const std::string p = describeUnsteadiness(r, periodic, 1e-10, 1.0, 0.5);
    EXPECT_EQ(p.rfind("the flow is unsteady and periodic", 0), 0u) << p;
    EXPECT_NE(p.find("period 5"), std::string::npos) << p;
    EXPECT_NE(p.find("Strouhal number 0.4"), std::string::npos) << p;
    const std::string d = describeUnsteadiness(r, decaying, 1e-10, 1.0, 0.5);
    EXPECT_EQ(d.rfind("the flow oscillates with a decaying amplitude", 0), 0u) << d;
    const std::string u = describeUnsteadiness(r, drifting, 1e-10, 1.0, 0.5);
    EXPECT_EQ(u.rfind("the flow has not settled", 0), 0u) << u;
    EXPECT_NEAR(summarizeSignal(t, drifting, 0.5).drift, 1.0, 1e-9);
    const std::string i = describeUnsteadiness(r, irregular, 1e-10, 1.0, 0.5);
    EXPECT_EQ(i.rfind("the flow is unsteady after", 0), 0u) << i;
    EXPECT_NE(i.find("not periodically"), std::string::npos) << i;
}

TEST(TimeAccurate, StopsWhereTheLocalMachNumberPassesItsBoundAndSaysWhere) {
    // A flow breaking down (pressure collapsing at a crease) shows as a local Mach number far
    // above any a steady flow at Mach 0.5 has; the bound here is set below the free stream's
    // own, so the first step passes it.
    const auto box = testing::wavyBox(6, mesh::BoundaryKind::Symmetry);
    ResidualOptions o;
    o.freeStream.mach = 0.5;
    std::vector<double> q = entropyWave(box, o.freeStream, 0.6);
    TimeAccurateOptions t;
    t.timeStep = 0.1;
    t.steps = 5;
    t.maxMach = 0.45;
    const TimeAccurateReport r = solveTimeAccurate(box.fm, box.metrics, o, q, {}, t);
    EXPECT_FALSE(r.completed);
    ASSERT_EQ(r.history.size(), 1u);
    EXPECT_GT(r.history[0].maxMach, 0.45);
    EXPECT_EQ(r.breakdownNode, r.history[0].maxMachNode);
    EXPECT_GE(r.breakdownNode, 0);
    EXPECT_NE(r.message.find("the local Mach number reached"), std::string::npos) << r.message;
}

TEST(TimeAccurate, RejectsATimeStepThatIsNotPositive) {
    const auto box = testing::wavyBox(6, mesh::BoundaryKind::Symmetry);
    ResidualOptions o;
    std::vector<double> q;
    TimeAccurateOptions t;
    t.timeStep = 0;
    EXPECT_THROW(solveTimeAccurate(box.fm, box.metrics, o, q, {}, t), InputError);
}

}  // namespace
}  // namespace aero::flow
