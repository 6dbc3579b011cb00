// The optimizers behind optimize::Optimizer on problems with known solutions: Hock-Schittkowski
// 71 (nonlinear equality and inequality, bounds), a linearly constrained quadratic, evaluations
// that fail away from the last good point (both must cut back and still converge), the
// evaluation limit and cancellation; and the common first-order optimality measure itself.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "optimize/Optimizer.h"

using namespace aero;
using namespace aero::optimize;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// HS71: min x1 x4 (x1 + x2 + x3) + x3, x1 x2 x3 x4 >= 25, sum x^2 = 40, 1 <= x <= 5.
Problem hs71() {
    Problem p;
    p.start = {1, 5, 5, 1};
    p.lower.assign(4, 1.0);
    p.upper.assign(4, 5.0);
    p.nonlinear = {{"product", 25, kInf}, {"sphere", 40, 40}};
    p.values = [](const std::vector<double>& x) {
        Values v;
        v.objective = x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2];
        v.constraints = {x[0] * x[1] * x[2] * x[3], x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + x[3] * x[3]};
        return v;
    };
    p.gradients = [](const std::vector<double>& x) {
        Gradients g;
        g.objective = {x[3] * (2 * x[0] + x[1] + x[2]), x[0] * x[3], x[0] * x[3] + 1, x[0] * (x[0] + x[1] + x[2])};
        g.constraints = {{x[1] * x[2] * x[3], x[0] * x[2] * x[3], x[0] * x[1] * x[3], x[0] * x[1] * x[2]},
                         {2 * x[0], 2 * x[1], 2 * x[2], 2 * x[3]}};
        return g;
    };
    return p;
}

// min sum (x_i - 3)^2 over [-5, 5]^2 from the origin, optionally with x + y <= 2 (then (1, 1)).
Problem quadratic(bool linear) {
    Problem p;
    p.start = {0, 0};
    p.lower = {-5, -5};
    p.upper = {5, 5};
    if (linear) p.linear.push_back({{0, 1}, {1.0, 1.0}, -kInf, 2.0, "sum"});
    p.values = [](const std::vector<double>& x) {
        Values v;
        v.objective = (x[0] - 3) * (x[0] - 3) + (x[1] - 3) * (x[1] - 3);
        return v;
    };
    p.gradients = [](const std::vector<double>& x) {
        Gradients g;
        g.objective = {2 * (x[0] - 3), 2 * (x[1] - 3)};
        return g;
    };
    return p;
}

// Makes the first `count` evaluations farther than `radius` (infinity norm) from p.start fail, as
// a fragile flow does; returns the number of failures so far.
std::shared_ptr<int> failAwayFromStart(Problem& p, int count, double radius, const std::string& why) {
    auto failures = std::make_shared<int>(0);
    auto inner = p.values;
    const std::vector<double> start = p.start;
    p.values = [=](const std::vector<double>& x) {
        double d = 0;
        for (std::size_t i = 0; i < x.size(); ++i) d = std::max(d, std::abs(x[i] - start[i]));
        if (*failures < count && d > radius) {
            ++*failures;
            Values v;
            v.ok = false;
            v.message = why;
            return v;
        }
        return inner(x);
    };
    return failures;
}

// SLSQP on p, with the first variable of every iterate it reports.
Result slsqpWithIterates(const Problem& p, std::vector<double>& iterates) {
    Settings s;
    s.onIteration = [&](const Iteration& it) { iterates.push_back(it.x[0]); };
    return makeOptimizer("slsqp")->minimize(p, s);
}

class Optimizers : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(Optimizers, SolveHockSchittkowski71) {
    const Problem p = hs71();
    Settings s;
    s.optimalityTolerance = 1e-7;
    s.feasibilityTolerance = 1e-9;
    int reported = 0;
    s.onIteration = [&](const Iteration& it) {
        EXPECT_EQ(it.x.size(), 4u);
        ++reported;
    };
    const Result r = makeOptimizer(GetParam())->minimize(p, s);
    EXPECT_EQ(r.status, Status::Converged) << r.message;
    EXPECT_NEAR(r.objective, 17.0140173, 1e-6);
    const double expected[4] = {1.0, 4.7429994, 3.8211503, 1.3794082};
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(r.x[i], expected[i], 1e-5) << i;
    EXPECT_LE(r.feasibility, 1e-9);
    EXPECT_LE(r.optimality, 1e-7);
    EXPECT_GT(reported, 2);
    EXPECT_EQ(r.failedEvaluations, 0);
    std::printf("%s: %d iterations, %d evaluations, %d gradients\n", GetParam().c_str(), r.iterations, r.evaluations,
                r.gradients);
}

TEST_P(Optimizers, KeepLinearConstraints) {
    const Result r = makeOptimizer(GetParam())->minimize(quadratic(true), Settings{});
    EXPECT_EQ(r.status, Status::Converged) << r.message;
    EXPECT_NEAR(r.x[0], 1.0, 1e-5);  // Ipopt's iterates stay inside: 1e-6 from the row at tolerance 1e-6
    EXPECT_NEAR(r.x[1], 1.0, 1e-5);
    EXPECT_NEAR(r.objective, 8.0, 1e-5);
}

// Every evaluation farther than 0.75 from the last successful one fails (as a flow that does not
// converge on a shape too far from the last): the optimizers must cut back, not stop.
TEST_P(Optimizers, SurviveFailedEvaluations) {
    Problem p = quadratic(false);
    auto last = std::make_shared<std::vector<double>>(p.start);
    auto inner = p.values;
    p.values = [inner, last](const std::vector<double>& x) {
        if (std::max(std::abs(x[0] - (*last)[0]), std::abs(x[1] - (*last)[1])) > 0.75) {
            Values v;
            v.ok = false;
            v.message = "too far from the last good point";
            return v;
        }
        *last = x;
        return inner(x);
    };
    const Result r = makeOptimizer(GetParam())->minimize(p, Settings{});
    EXPECT_EQ(r.status, Status::Converged) << r.message;
    EXPECT_NEAR(r.x[0], 3.0, 1e-5);
    EXPECT_NEAR(r.x[1], 3.0, 1e-5);
    EXPECT_GT(r.failedEvaluations, 0);
    std::printf("%s: %d evaluations, %d failed\n", GetParam().c_str(), r.evaluations, r.failedEvaluations);
}

// A gradient that fails at a point whose values succeeded (a converged flow whose adjoint does not
// converge: the 98k sphere-to-BWB run's fourth evaluation, Mach 1.9, its adjoint at 0.85 after
// 3,000 iterations). Ipopt has accepted the point and cannot cut back from it: it starts again
// from the last iterate, that point counted as failed, and its step is cut on the way back there
// (SLSQP backtracks as after any failure). Both converge; the iterations stay numbered in order.
TEST_P(Optimizers, SurviveAGradientThatFailsAtAnAcceptedPoint) {
    Problem p = quadratic(false);
    auto failedAt = std::make_shared<std::vector<double>>();
    auto inner = p.gradients;
    p.gradients = [inner, failedAt](const std::vector<double>& x) {
        if (failedAt->empty() && x[0] > 0.5) {  // the first gradient asked for away from the start
            *failedAt = x;
            Gradients g;
            g.ok = false;
            g.message = "the adjoint did not converge";
            return g;
        }
        return inner(x);
    };
    std::vector<int> numbers;
    std::string log;
    Settings s;
    s.onIteration = [&](const Iteration& it) { numbers.push_back(it.iteration); };
    s.log = [&](const std::string& line) { log += line + "\n"; };
    const Result r = makeOptimizer(GetParam())->minimize(p, s);
    EXPECT_EQ(r.status, Status::Converged) << r.message << "\n" << log;
    ASSERT_FALSE(failedAt->empty()) << "no gradient was asked for away from the start";
    EXPECT_NEAR(r.x[0], 3.0, 1e-5);
    EXPECT_NEAR(r.x[1], 3.0, 1e-5);
    EXPECT_GE(r.failedEvaluations, 1);
    for (std::size_t i = 1; i < numbers.size(); ++i) EXPECT_GT(numbers[i], numbers[i - 1]) << i;
    if (GetParam() == "ipopt") {
        EXPECT_NE(log.find("Ipopt starts again from iteration"), std::string::npos) << log;
    }
    std::printf("%s: %d evaluations, %d failed, %d iterations\n", GetParam().c_str(), r.evaluations, r.failedEvaluations,
                r.iterations);
}

// Early failures shrink SLSQP's backtracking box to a small one around the start, far from the
// optimum of a non-quadratic objective; the box must then grow again as the iterates reach its
// face, not after SLSQP has converged on each face in many tiny steps.
TEST_P(Optimizers, GrowBackAfterEarlyFailures) {
    // min -x0 + 50 (x1 - sin x0)^2 on [-10, 10]^2: along a curved valley to x0 = 10.
    Problem p;
    p.start = {0, 0};
    p.lower = {-10, -10};
    p.upper = {10, 10};
    p.values = [](const std::vector<double>& x) {
        Values v;
        v.objective = -x[0] + 50 * std::pow(x[1] - std::sin(x[0]), 2);
        return v;
    };
    p.gradients = [](const std::vector<double>& x) {
        const double d = x[1] - std::sin(x[0]);
        Gradients g;
        g.objective = {-1 - 100 * d * std::cos(x[0]), 100 * d};
        return g;
    };
    (void)failAwayFromStart(p, 5, 0.02, "too far while the flow is fragile");
    const Result r = makeOptimizer(GetParam())->minimize(p, Settings{});
    EXPECT_EQ(r.status, Status::Converged) << r.message;
    std::printf("%s: %d evaluations, %d failed, x %.6f %.6f\n", GetParam().c_str(), r.evaluations, r.failedEvaluations, r.x[0], r.x[1]);
    EXPECT_NEAR(r.x[0], 10.0, 1e-6);
    EXPECT_EQ(r.failedEvaluations, 5);
    // SLSQP creeping along each box's face took 154 evaluations and stopped short (x0 7.97).
    EXPECT_LE(r.evaluations, 120);
}

// Seven failed trials in a row do not push the start out of the evaluation cache: the restart
// from it (SLSQP's driver) or the step cut back to it (Ipopt) does not evaluate it again (on the
// 98k grid: a flow and an adjoint, 30 s).
TEST_P(Optimizers, EvaluateTheStartOnceThroughARunOfFailures) {
    Problem p = quadratic(false);
    auto calls = std::make_shared<int>(0);
    auto atStart = std::make_shared<int>(0);
    const std::shared_ptr<int> failures = failAwayFromStart(p, 7, 1e-3, "failed");
    auto inner = p.values;
    p.values = [inner, calls, atStart, start = p.start](const std::vector<double>& x) {
        ++*calls;
        if (x == start) ++*atStart;
        return inner(x);
    };
    const Result r = makeOptimizer(GetParam())->minimize(p, Settings{});
    EXPECT_EQ(r.status, Status::Converged) << r.message;
    EXPECT_EQ(*failures, 7);
    EXPECT_EQ(*atStart, 1) << *calls << " evaluations";
}

TEST_P(Optimizers, StopAtTheEvaluationLimitAndOnCancel) {
    Settings s;
    s.maxEvaluations = 3;
    Result r = makeOptimizer(GetParam())->minimize(hs71(), s);
    EXPECT_EQ(r.status, Status::EvaluationLimit) << r.message;
    EXPECT_EQ(r.evaluations, 3);
    std::atomic<bool> cancel{false};
    Settings c;
    c.cancel = &cancel;
    c.onIteration = [&](const Iteration& it) {
        if (it.iteration >= 2) cancel = true;
    };
    r = makeOptimizer(GetParam())->minimize(hs71(), c);
    EXPECT_EQ(r.status, Status::Cancelled) << r.message;
    EXPECT_LT(r.iterations, 6);
}

// A cancel that arrives during an evaluation cuts it short (the flow stops and its values say
// so): the run stops there as cancelled. That evaluation is neither counted nor a failure, so the
// optimizer does not cut its step and log a restart on its way out.
TEST_P(Optimizers, AnEvaluationCutShortByACancelIsNoFailure) {
    std::atomic<bool> cancel{false};
    Problem p = hs71();
    int made = 0;
    const auto inner = p.values;
    p.values = [&](const std::vector<double>& x) {
        if (++made < 4) return inner(x);
        cancel = true;  // the cancel arrives while the fourth evaluation runs
        Values v;
        v.ok = false;
        v.message = "cancelled";
        return v;
    };
    Settings s;
    s.cancel = &cancel;
    std::vector<std::string> lines;
    s.log = [&](const std::string& line) { lines.push_back(line); };
    const Result r = makeOptimizer(GetParam())->minimize(p, s);
    EXPECT_EQ(r.status, Status::Cancelled) << r.message;
    EXPECT_EQ(made, 4);
    EXPECT_EQ(r.evaluations, 3);
    EXPECT_EQ(r.failedEvaluations, 0);
    for (const std::string& line : lines) EXPECT_EQ(line.find("restart"), std::string::npos) << line;
}

TEST_P(Optimizers, ReportAStartThatCannotBeEvaluated) {
    Problem p = quadratic(false);
    p.values = [](const std::vector<double>&) {
        Values v;
        v.ok = false;
        v.message = "the flow did not converge";
        return v;
    };
    const Result r = makeOptimizer(GetParam())->minimize(p, Settings{});
    EXPECT_NE(r.status, Status::Converged);
    EXPECT_GE(r.failedEvaluations, 1);
    EXPECT_NE(r.message.find("the flow did not converge"), std::string::npos) << r.message;
}

INSTANTIATE_TEST_SUITE_P(Both, Optimizers, ::testing::Values("ipopt", "slsqp"));

// SLSQP's first step from a steep start overshoots to a worse point, a line-search trial it
// rejects but whose gradient NLopt asks for; the next trial fails. The rejected trial is not
// reported as an iteration, and the driver restarts from the last iteration, the start (it used
// to restart from the rejected trial and walk on through points far worse than the start).
TEST(Slsqp, RestartsFromThePointBeforeARejectedTrial) {
    Problem p;
    p.start = {1};
    p.lower = {-30};
    p.upper = {30};
    auto points = std::make_shared<std::vector<double>>();
    p.values = [points](const std::vector<double>& x) {
        points->push_back(x[0]);
        Values v;
        if (x[0] >= -5 && x[0] < -0.5) {
            v.ok = false;
            v.message = "a failure band";
            return v;
        }
        v.objective = 10 * x[0] * x[0];
        return v;
    };
    p.gradients = [](const std::vector<double>& x) {
        Gradients g;
        g.objective = {20 * x[0]};
        return g;
    };
    std::vector<double> iterates;
    const Result r = slsqpWithIterates(p, iterates);
    std::string path;
    for (double x : *points) path += " " + std::to_string(x);
    EXPECT_EQ(r.status, Status::Converged) << r.message << ";" << path;
    EXPECT_NEAR(r.x[0], 0.0, 1e-6) << path;
    // The path: the start, the rejected full step (-19), the failed trial, then inside a box of
    // half that failure around the start.
    ASSERT_GE(points->size(), 4u) << path;
    EXPECT_EQ((*points)[1], -19.0) << path;
    EXPECT_TRUE((*points)[2] >= -5 && (*points)[2] < -0.5) << path;
    const double radius = 0.5 * (1 - (*points)[2]);
    for (std::size_t k = 3; k < points->size(); ++k) EXPECT_LE(std::abs((*points)[k] - 1), radius * (1 + 1e-12)) << path;
    EXPECT_EQ(r.failedEvaluations, 1) << path;
    // The rejected trial is no iteration: the iterates only improve.
    ASSERT_FALSE(iterates.empty());
    EXPECT_EQ(iterates.front(), 1.0);
    for (std::size_t k = 1; k < iterates.size(); ++k) EXPECT_LE(std::abs(iterates[k]), std::abs(iterates[k - 1])) << path;
}

// A first trial that is better in feasibility but much worse in objective: SLSQP's merit function
// rejects it and its line search goes on between the start and it. It is no iteration (the
// driver judged it one, as feasibility had improved: the thirty-sixth session's Figure 4 run), and
// neither is any trial the line search passes over; every iterate is a point SLSQP took.
TEST(Slsqp, AFirstTrialTheLineSearchRejectsIsNoIterationThoughMoreFeasible) {
    Problem p;
    p.start = {1};  // infeasible by 1e-3
    p.lower = {-30};
    p.upper = {30};
    p.nonlinear = {{"x", -kInf, 0.999}};
    auto points = std::make_shared<std::vector<std::pair<double, bool>>>();  // x, with a gradient
    p.values = [points](const std::vector<double>& x) {
        points->push_back({x[0], false});
        Values v;
        v.objective = 10 * x[0] * x[0];
        v.constraints = {x[0]};
        return v;
    };
    p.gradients = [points](const std::vector<double>& x) {
        for (auto& [at, withGradient] : *points) {
            if (at == x[0]) withGradient = true;
        }
        Gradients g;
        g.objective = {20 * x[0]};
        g.constraints = {{1.0}};
        return g;
    };
    std::vector<double> iterates;
    const Result r = slsqpWithIterates(p, iterates);
    std::string path;
    for (const auto& [x, withGradient] : *points) path += " " + std::to_string(x) + (withGradient ? "g" : "");
    std::string taken;
    for (double x : iterates) taken += " " + std::to_string(x);
    EXPECT_EQ(r.status, Status::Converged) << r.message << ";" << path;
    EXPECT_NEAR(r.x[0], 0.0, 1e-6) << path;
    // The path: the start, the full step of the first QP (-19: feasible, f 3,610 against 10),
    // then a trial between them without a gradient.
    ASSERT_GE(points->size(), 3u) << path;
    EXPECT_EQ((*points)[1].first, -19.0) << path;
    EXPECT_TRUE((*points)[1].second) << path;
    EXPECT_FALSE((*points)[2].second) << path;
    EXPECT_GT((*points)[2].first, -19.0) << path;
    EXPECT_LT((*points)[2].first, 1.0) << path;
    ASSERT_FALSE(iterates.empty());
    EXPECT_EQ(iterates.front(), 1.0);
    // Each iterate is better than the last in objective or in feasibility, and -19 is none of them.
    for (double x : iterates) EXPECT_NE(x, -19.0) << "iterates:" << taken << "; path:" << path;
    for (std::size_t k = 1; k < iterates.size(); ++k) {
        EXPECT_TRUE(std::abs(iterates[k]) <= std::abs(iterates[k - 1]) || iterates[k - 1] > 0.999)
            << "iterates:" << taken << "; path:" << path;
    }
}

TEST(Optimizer, UnknownNameListsTheChoices) {
    try {
        (void)makeOptimizer("snopt");
        ADD_FAILURE();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("ipopt, slsqp"), std::string::npos) << e.what();
    }
}

// The measure is zero at a constrained minimum (multipliers of the right sign), and not zero where
// the only fitting multiplier has the wrong sign (the bound is active but the minimum is inside).
TEST(FirstOrderOptimality, SeesTheSignOfTheMultipliers) {
    const Problem p = quadratic(true);
    auto at = [&](double x, double y) {
        const std::vector<double> v{x, y};
        return firstOrderOptimality(p, v, p.values(v), p.gradients(v), 1e-9);
    };
    EXPECT_NEAR(at(1, 1), 0.0, 1e-14);   // on x + y = 2 (upper side): df = (-4, -4) = -mu (1, 1), mu = 4
    EXPECT_NEAR(at(3, 3) , 0.0, 1e-14);  // infeasible for the row, but the gradient vanishes
    EXPECT_NEAR(at(0.5, 0.5), 5.0, 1e-12);  // inside: |df|_inf
    Problem q = quadratic(false);
    q.lower = {3.5, -5};  // x >= 3.5: at x = 3.5 the bound pushes the right way
    const std::vector<double> v{3.5, 3.0};
    EXPECT_NEAR(firstOrderOptimality(q, v, q.values(v), q.gradients(v), 1e-9), 0.0, 1e-14);
    q.lower = {-5, -5};
    q.upper = {3.5, 5};  // x <= 3.5 active at 3.5, but df_x = 1 > 0 wants x smaller: not a minimum
    EXPECT_NEAR(firstOrderOptimality(q, v, q.values(v), q.gradients(v), 1e-9), 1.0, 1e-14);
}
