// The paper's inverse design (Section IV.C.2, Figure 3b) on the small grid: 4 lattice control
// points of the half-sphere perturbed (samples/inverse_design_target.json), the target's wall
// pressure recorded, and the 12 coordinates recovered from the sphere by SLSQP with adjoint
// gradients through flow, grid, mesh movement and FFD: J down by >= 12 orders and every
// coordinate to 1e-6 (the paper: 18 orders in 29 evaluations).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/Error.h"
#include "common/Format.h"
#include "ffd/ShapeConstraints.h"
#include "geometry/EnclosedVolume.h"
#include "io/CaseFile.h"
#include "io/CaseWriter.h"
#include "io/FlowFiles.h"
#include "mesh/Quality.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"
#include "study/Optimization.h"

using namespace aero;

namespace {

io::CaseFile small(const std::string& name) {
    io::CaseFile c = io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/" + name);
    c.mesh.extrusion.refine = 0.3;  // 4,320 nodes
    c.mesh.elasticity.increments = 2;
    c.outputGeometry.clear();
    c.outputWallPressure.clear();
    return c;
}

// The sample on the small grid for a run of one evaluation (SLSQP), its history in `dir`.
io::CaseFile oneEvaluation(const std::string& dir) {
    io::CaseFile c = small("sphere_to_bwb.json");
    c.optimization.optimizer = "slsqp";
    c.optimization.maxIterations = 1;
    c.optimization.maxEvaluations = 1;
    c.optimization.history = dir + "/history.csv";
    c.optimization.iterations.clear();
    return c;
}

// The same for a short SLSQP run, its history in `dir` emptied first.
io::CaseFile shortRun(const std::string& dir, int maxIterations, int maxEvaluations) {
    std::filesystem::remove_all(dir);
    io::CaseFile c = oneEvaluation(dir);
    c.optimization.maxIterations = maxIterations;
    c.optimization.maxEvaluations = maxEvaluations;
    return c;
}

// A short SLSQP run made at once (see shortRun); returns its case.
io::CaseFile runShort(const std::string& dir, int maxIterations, int maxEvaluations) {
    io::CaseFile c = shortRun(dir, maxIterations, maxEvaluations);
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    study::OptimizationOptions o;
    o.fresh = true;
    (void)study::optimizeCase(ev, o);
    return c;
}

// The second evaluation of a short SLSQP run (3 iterations, 2 evaluations) of the small sample in
// output folder `name`, the case changed by `configure` first, `onValues` called on each
// evaluation's record as it is recorded (with the evaluator, e.g. to replace its warm state).
study::OptimizationRecord secondOfTwo(
    const std::string& name, const std::function<void(io::CaseFile&)>& configure,
    const std::function<void(study::CaseEvaluator&, const study::OptimizationRecord&)>& onValues = {}) {
    io::CaseFile c = shortRun(std::string(AEROFORM_TEST_OUTPUT_DIR) + "/" + name, 3, 2);
    configure(c);
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    study::OptimizationOptions o;
    o.fresh = true;
    std::vector<study::OptimizationRecord> values;
    o.onRecord = [&](const study::OptimizationRecord& r) {
        if (r.kind != study::OptimizationRecord::Kind::Values) return;
        values.push_back(r);
        if (onValues) onValues(ev, r);
    };
    (void)study::optimizeCase(ev, o);
    EXPECT_EQ(values.size(), 2u);
    EXPECT_TRUE(!values.empty() && values[0].ok);
    return values.size() == 2 ? values[1] : study::OptimizationRecord{};
}

}  // namespace

// Without an optimizer's iterate to start from (before the first, or its state gone), a step
// starts from the closest converged design; a trial halfway between the design its step came
// from and a rejected full step starts from the former, whatever the order of the list.
TEST(Optimization, AStepStartsFromTheClosestConvergedDesign) {
    using study::WarmCandidate;
    EXPECT_EQ(study::closestWarmStart({}, {0.0, 0.0}), 0);
    const std::vector<WarmCandidate> path = {{1, {0.0, 0.0}}, {2, {1.0, 0.0}}};
    EXPECT_EQ(study::closestWarmStart(path, {0.5, 0.0}), 1);
    EXPECT_EQ(study::closestWarmStart({path[1], path[0]}, {0.5, 0.0}), 1);
    EXPECT_EQ(study::closestWarmStart(path, {0.1 + 0.2 + 0.2, 0.0}), 1);  // equal to round-off
    EXPECT_EQ(study::closestWarmStart(path, {0.25, 0.3}), 1);
    EXPECT_EQ(study::closestWarmStart(path, {0.51, 0.0}), 2);
    EXPECT_EQ(study::closestWarmStart(path, {2.0, -1.0}), 2);
    // A point of another size (a history of another problem) is never chosen.
    EXPECT_EQ(study::closestWarmStart({{3, {0.5}}, path[1]}, {0.5, 0.0}), 2);
}

// The design a run stopped along a constraint's boundary has found: the accepted evaluation of
// least objective that misses the tolerance by at most 1e-3 and beats the best feasible one.
TEST(Optimization, TheBestNearlyFeasibleDesignIsNamed) {
    optimize::Problem p;
    p.start = {0.5};
    p.lower = {0};
    p.upper = {1};
    p.nonlinear = {{"volume ratio", 1, std::numeric_limits<double>::infinity()}};
    auto record = [](int index, bool ok, double c, double objective, double x = 0.5) {
        study::OptimizationRecord r;
        r.index = index;
        r.ok = ok;
        r.x = {x};
        r.constraints = {c};
        r.objective = objective;
        return r;
    };
    const std::vector<study::OptimizationRecord> values = {
        record(1, true, 1.0, -1),        // feasible: the best design
        record(2, true, 0.9995, -3),     // 5e-4 short: the one
        record(3, true, 0.99999, -2),    // 1e-5 short, but not as good
        record(4, false, 1.0, -10),      // failed
        record(5, true, 0.99, -5),       // 1e-2 short: too far
        record(6, true, 1.0, -4, 1.5)};  // outside the variable's bound by 0.5
    EXPECT_EQ(study::nearlyFeasibleBest(p, values, -1, 1e-6), std::make_pair(2, 1.0 - 0.9995));
    EXPECT_EQ(study::nearlyFeasibleBest(p, values, -3.5, 1e-6).first, 0);  // none beats it
    EXPECT_EQ(study::nearlyFeasibleBest(p, values, -1, 1e-3).first, 0);    // within the tolerance: feasible
    EXPECT_EQ(study::nearlyFeasibleBest(p, {}, -1, 1e-6).first, 0);
}

TEST(Optimization, InverseDesignRecoversThePerturbedLatticePoints) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/inverse_design";
    std::filesystem::create_directories(dir);
    // The target: the perturbed design's converged wall pressure.
    const io::CaseFile target = small("inverse_design_target.json");
    study::CaseEvaluator tev(target, study::loadGeometry(target.geometry));
    const study::Evaluation te = tev.evaluate(tev.caseValues());
    ASSERT_TRUE(te.ok()) << te.message;
    const std::string pressure = dir + "/target_pressure.csv";
    io::writeWallPressureCsv(pressure, te.flow->mesh, te.flow->x, te.flow->q, te.flow->residualOptions.freeStream);

    io::CaseFile c = small("inverse_design.json");
    c.optimization.optimizer = "slsqp";
    c.optimization.targetPressure = pressure;
    c.optimization.history = dir + "/history.csv";
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    study::OptimizationOptions o;
    o.fresh = true;
    double first = -1;
    // Every warm start is from the design its step came from: of the optimizer's last two
    // iterates (the last two iterations' evaluations), the one closer to it; count those that do
    // not start from the newest accepted evaluation, and those from the previous iterate.
    std::vector<study::OptimizationRecord> accepted;
    study::WarmCandidate iterate, previous;  // evaluation 0: none yet
    int olderStarts = 0, previousStarts = 0;
    o.onRecord = [&](const study::OptimizationRecord& r) {
        if (r.kind == study::OptimizationRecord::Kind::Iteration) {
            int at = 0;
            for (const auto& a : accepted) {
                if (a.x == r.x) at = a.index;
            }
            EXPECT_GT(at, 0) << "iteration " << r.index << " is at no accepted evaluation";
            if (at != iterate.evaluation) {
                previous = iterate;
                iterate = {at, r.x};
            }
            return;
        }
        if (r.kind != study::OptimizationRecord::Kind::Values) return;
        if (r.ok && first < 0) first = r.J;
        std::vector<study::WarmCandidate> base;
        for (const study::WarmCandidate& k : {previous, iterate}) {
            if (k.evaluation > 0) base.push_back(k);
        }
        EXPECT_EQ(r.warmFrom, study::closestWarmStart(base, r.x)) << "evaluation " << r.index;
        if (previous.evaluation > 0 && r.warmFrom == previous.evaluation) ++previousStarts;
        if (!accepted.empty() && r.warmFrom != accepted.back().index) ++olderStarts;
        if (r.ok) accepted.push_back(r);
    };
    const study::OptimizationSummary s = study::optimizeCase(ev, o);
    std::printf("inverse design: %s after %d iterations, %d evaluations: J %.3e -> %.3e, optimality %.2e; %d warm "
                "starts from an accepted evaluation older than the newest, %d from the previous iterate\n",
                optimize::statusName(s.result.status), s.result.iterations, s.result.evaluations, first, s.J,
                s.result.optimality, olderStarts, previousStarts);
    EXPECT_EQ(s.result.status, optimize::Status::Converged) << s.result.message;
    EXPECT_GT(first, 1e-7);
    EXPECT_LT(s.J, 1e-12 * first);
    EXPECT_LE(s.result.evaluations, 60);
    EXPECT_EQ(s.result.failedEvaluations, 0);
    // The summary names the best design's evaluation (what `optimize --design N` and a finer
    // run's start_design take): the accepted one of least J.
    const auto bestRecord = std::min_element(accepted.begin(), accepted.end(),
                                             [](const auto& a, const auto& b) { return a.J < b.J; });
    ASSERT_NE(bestRecord, accepted.end());
    EXPECT_EQ(s.bestEvaluation, bestRecord->index);
    EXPECT_EQ(s.J, bestRecord->J);
    const std::vector<ffd::DesignVariable>& vars = ev.model()->design().variables();
    ASSERT_EQ(vars.size(), 12u);
    for (std::size_t i = 0; i < vars.size(); ++i) {
        EXPECT_NEAR(s.values[i], target.values.at(vars[i].name), 1e-6) << vars[i].name;
    }
}

// An evaluation whose flow does not converge is recorded as failed with the mode analysis's
// verdict (flow.stall_modes) in its message and as growing_mode_rate in the history's JSON lines,
// which a resume reads back.
TEST(Optimization, AFailedFlowsGrowingModeIsRecordedInTheHistory) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/failed_flow_history";
    std::filesystem::create_directories(dir);
    io::CaseFile c = oneEvaluation(dir);
    c.flow.newton.maxIterations = 3;  // not converged
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    study::OptimizationOptions o;
    o.fresh = true;
    std::vector<study::OptimizationRecord> records;
    o.onRecord = [&](const study::OptimizationRecord& r) { records.push_back(r); };
    (void)study::optimizeCase(ev, o);
    const study::OptimizationRecord* failed = nullptr;
    for (const auto& r : records) {
        if (r.kind == study::OptimizationRecord::Kind::Values && !r.ok && !failed) failed = &r;
    }
    ASSERT_TRUE(failed);
    EXPECT_EQ(failed->status, "flow-not-converged");
    ASSERT_TRUE(std::isfinite(failed->growingMode));
    EXPECT_GE(failed->growingMode, 0.0);
    EXPECT_NE(failed->message.find("grows"), std::string::npos) << failed->message;
    const std::vector<study::OptimizationRecord> file = study::readHistory(study::historyJsonlPath(c.optimization.history));
    bool found = false;
    for (const auto& r : file) {
        if (r.kind != study::OptimizationRecord::Kind::Values || r.index != failed->index) continue;
        found = true;
        EXPECT_EQ(r.growingMode, failed->growingMode);
    }
    EXPECT_TRUE(found);
}

// optimization.max_entropy: a flow that converges with more entropy error than the case allows
// is a failed evaluation with the reason (where, how much, the forces it had), and its state is
// neither kept for a resume nor left to the evaluator for the next warm start.
TEST(Optimization, AConvergedFlowBeyondTheEntropyBoundIsAFailedEvaluation) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/entropy_bound";
    std::filesystem::remove_all(dir);
    io::CaseFile c = oneEvaluation(dir);
    c.optimization.maxEntropy = 1e-6;  // the half-sphere's flow on 4,320 nodes has 0.03
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    study::OptimizationOptions o;
    o.fresh = true;
    std::vector<study::OptimizationRecord> records;
    bool flowConverged = false;
    o.onRecord = [&](const study::OptimizationRecord& r) { records.push_back(r); };
    o.onEvaluation = [&](const study::OptimizationRecord&, const study::Evaluation& e) { flowConverged = e.ok(); };
    (void)study::optimizeCase(ev, o);
    ASSERT_FALSE(records.empty());
    const study::OptimizationRecord& r = records.front();
    EXPECT_TRUE(flowConverged);  // the flow itself converged
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.status, "flow-unresolved");
    EXPECT_NE(r.message.find("optimization.max_entropy 1e-06"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("CL "), std::string::npos) << r.message;
    EXPECT_EQ(r.message.find("on the on the"), std::string::npos) << r.message;
    EXPECT_TRUE(ev.lastConvergedState().empty());  // no accepted state before it
    const std::string states = dir + "/history.states";
    int kept = 0;
    if (std::filesystem::exists(states)) {
        for (const auto& entry : std::filesystem::directory_iterator(states)) kept += entry.path().extension() == ".state";
    }
    EXPECT_EQ(kept, 0);
    // The history says so, for a resume and for the user's plot.
    const std::vector<study::OptimizationRecord> file = study::readHistory(study::historyJsonlPath(c.optimization.history));
    bool found = false;
    for (const auto& f : file) found |= f.kind == study::OptimizationRecord::Kind::Values && f.status == "flow-unresolved";
    EXPECT_TRUE(found);
    // The refused flow's forces and entropy stay in the history for the user's plots (its
    // objective does not: the optimizer saw a failure).
    EXPECT_GT(r.maxEntropy, 1e-6);
    EXPECT_GT(r.CD, 0.0);
    std::ifstream csvIn(c.optimization.history);
    std::stringstream csv;
    csv << csvIn.rdbuf();
    EXPECT_NE(csv.str().find(format("values,1,flow-unresolved,,,%.17g,%.17g,", r.CL, r.CD)), std::string::npos)
        << csv.str();
    EXPECT_NE(csv.str().find(format(",%.17g,%.17g,", r.maxMach, r.maxEntropy)), std::string::npos) << csv.str();
}

// optimization.max_entropy_rise: the first evaluation is accepted whatever its entropy (there is
// nothing to jump from); a later one whose entropy error is more than the factor times that of the
// design its flow started from is refused with the reason, and a resumed run compares with the
// replayed record's entropy, not with nothing.
TEST(Optimization, AnEntropyJumpFromTheLastAcceptedDesignIsAFailedEvaluation) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/entropy_rise";
    io::CaseFile c = shortRun(dir, 3, 2);
    c.optimization.maxEntropyRise = 1e-3;  // any next design's flow is a "jump" from the first's
    auto run = [&](bool resume, std::vector<study::OptimizationRecord>& values) {
        study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
        study::OptimizationOptions o;
        o.fresh = !resume;
        o.resume = resume;
        o.onRecord = [&](const study::OptimizationRecord& r) {
            if (r.kind == study::OptimizationRecord::Kind::Values) values.push_back(r);
        };
        return study::optimizeCase(ev, o);
    };
    std::vector<study::OptimizationRecord> first;
    (void)run(false, first);
    ASSERT_EQ(first.size(), 2u);
    EXPECT_TRUE(first[0].ok) << first[0].message;
    EXPECT_GT(first[0].maxEntropy, 0.0);
    EXPECT_FALSE(first[1].ok);
    EXPECT_EQ(first[1].status, "flow-unresolved");
    EXPECT_NE(first[1].message.find("of evaluation 1, the design this flow started from; optimization.max_entropy_rise 0.001"),
              std::string::npos)
        << first[1].message;
    EXPECT_NE(first[1].message.find("a jump to another steady state"), std::string::npos) << first[1].message;

    // Resumed with one more evaluation: 1 and 2 are replayed, the third is compared with the first.
    c.optimization.maxEvaluations = 3;
    std::vector<study::OptimizationRecord> resumed;
    const study::OptimizationSummary s = run(true, resumed);
    ASSERT_EQ(resumed.size(), 3u);
    EXPECT_EQ(s.coldFlowIterations, first[0].flowIterations);  // the replayed cold start's, not 0
    EXPECT_TRUE(resumed[0].replayed);
    EXPECT_TRUE(resumed[1].replayed);
    EXPECT_FALSE(resumed[2].replayed);
    EXPECT_EQ(resumed[2].status, "flow-unresolved") << resumed[2].message;
    EXPECT_NE(resumed[2].message.find("of evaluation 1,"), std::string::npos) << resumed[2].message;
}

// optimization.warm_start_fallback: the second evaluation's warm start is made to fail at once
// (a state of zero density in place of the first evaluation's, in its file); "none" makes that a
// failed evaluation with the reason, "free_stream" solves it again from the free stream and
// converges.
TEST(Optimization, AStalledWarmStartFallsBackAsTheCaseSays) {
    auto secondEvaluation = [](const std::string& fallback) {
        const std::string name = "warm_fallback_" + fallback;
        const std::string state = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/" + name + "/history.states/1.state";
        return secondOfTwo(name, [&](io::CaseFile& c) { c.optimization.warmStartFallback = fallback; },
                           [&](study::CaseEvaluator& ev, const study::OptimizationRecord& r) {
                               if (r.ok && r.index == 1) {
                                   ASSERT_EQ(io::readWarmState(state).size(), ev.lastConvergedState().size());
                                   io::writeWarmState(state, std::vector<double>(ev.lastConvergedState().size(), 0.0));
                               }
                           });
    };
    const study::OptimizationRecord none = secondEvaluation("none");
    EXPECT_FALSE(none.ok);
    EXPECT_NE(none.message.find("non-positive density"), std::string::npos) << none.message;
    EXPECT_NE(none.message.find("(a warm start from evaluation 1; optimization.warm_start_fallback none: not solved "
                                "again, the step is cut)"),
              std::string::npos)
        << none.message;
    EXPECT_EQ(none.flowIterations, 0);
    const study::OptimizationRecord cold = secondEvaluation("free_stream");
    EXPECT_TRUE(cold.ok) << cold.message;
    EXPECT_GT(cold.flowIterations, 5);
}

// A step whose warm start has not converged within optimization.warm_start_iterations fails as a
// stalled one does (here with no fallback: the step is cut), with the budget named; within the
// default budget the same step converges.
TEST(Optimization, AWarmStartBeyondItsBudgetIsAFailedStep) {
    auto secondEvaluation = [](int budget) {
        return secondOfTwo("warm_budget_" + std::to_string(budget), [&](io::CaseFile& c) {
            c.optimization.warmStartFallback = "none";
            c.optimization.warmStartIterations = budget;
        });
    };
    const study::OptimizationRecord cut = secondEvaluation(2);
    EXPECT_FALSE(cut.ok);
    EXPECT_EQ(cut.status, "flow-not-converged");
    EXPECT_EQ(cut.flowIterations, 2);
    EXPECT_NE(cut.message.find("the warm start's budget of 2 iterations (optimization.warm_start_iterations) is spent"),
              std::string::npos)
        << cut.message;
    EXPECT_EQ(cut.message.find("more flow.max_iterations"), std::string::npos) << cut.message;
    const study::OptimizationRecord within = secondEvaluation(io::OptimizationCase{}.warmStartIterations);
    EXPECT_TRUE(within.ok) << within.message;
    EXPECT_GT(within.flowIterations, 2);
    EXPECT_LE(within.flowIterations, io::OptimizationCase{}.warmStartIterations);
}

// A resumed run that leaves its recorded path (here: gradient 2's recorded objective row changed,
// as another build's round-off would, so SLSQP asks for another third point) goes on from
// evaluation 2; the flow states of evaluations 1 and 2 are gone (removed here, as a build that
// kept only the newest two left them), so the next flow starts from the newest state left, a
// nearby converged flow, not from the free stream.
TEST(Optimization, LeavingTheRecordedPathWarmStartsFromTheNewestStateLeft) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/left_path";
    io::CaseFile c = runShort(dir, 10, 5);
    const std::string jsonl = study::historyJsonlPath(c.optimization.history);
    std::vector<std::string> lines;
    {
        std::ifstream in(jsonl);
        for (std::string line; std::getline(in, line);) lines.push_back(line);
    }
    bool changed = false;
    for (std::string& line : lines) {
        nlohmann::json j = nlohmann::json::parse(line);
        if (j.value("kind", "") != "gradient" || j.value("gradient", 0) != 2) continue;
        ASSERT_TRUE(j.value("ok", false)) << line;
        for (auto& g : j["d_objective"]) g = g.get<double>() * 1.01;
        line = j.dump();
        changed = true;
    }
    ASSERT_TRUE(changed);
    {
        std::ofstream out(jsonl, std::ios::trunc);
        for (const std::string& line : lines) out << line << "\n";
    }
    ASSERT_TRUE(std::filesystem::remove(dir + "/history.states/1.state"));
    ASSERT_TRUE(std::filesystem::remove(dir + "/history.states/2.state"));
    int newest = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir + "/history.states"))
        newest = std::max(newest, std::atoi(entry.path().stem().string().c_str()));
    ASSERT_GT(newest, 2);
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    study::OptimizationOptions o;
    o.resume = true;
    std::string log;
    o.log = [&](const std::string& line) { log += line + "\n"; };
    std::vector<bool> warm;
    o.onEvaluation = [&](const study::OptimizationRecord&, const study::Evaluation& e) {
        warm.push_back(e.flow && e.flow->warmStarted);
    };
    (void)study::optimizeCase(ev, o);
    EXPECT_NE(log.find("the optimizer left the recorded path (another evaluation point)"), std::string::npos) << log;
    EXPECT_NE(log.find("evaluation 2's flow state was not kept: the next flow starts from that of the discarded "
                       "evaluation " + std::to_string(newest)),
              std::string::npos)
        << log;
    ASSERT_FALSE(warm.empty());
    EXPECT_TRUE(warm[0]);
    // The history holds the path as it now is: evaluations, gradients and iterations numbered
    // once each, in order (none of the discarded records left between them).
    int values = 0, gradients = 0, iterations = -1;
    for (const auto& r : study::readHistory(jsonl)) {
        if (r.kind == study::OptimizationRecord::Kind::Values) {
            EXPECT_EQ(r.index, ++values);
        } else if (r.kind == study::OptimizationRecord::Kind::Gradient) {
            EXPECT_EQ(r.index, ++gradients);
        } else if (r.kind == study::OptimizationRecord::Kind::Iteration) {
            if (iterations >= 0) {
                EXPECT_EQ(r.index, iterations + 1);
            }
            iterations = r.index;
        }
    }
    EXPECT_EQ(values, 5);
}

// A history whose iterations another build numbered otherwise (here: iteration 2 at a point next
// to the real one's, and one more iteration after the last, as the driver that took SLSQP's
// rejected first trials for iterations wrote): the evaluations replay, and the history ends with
// the iterations as this build reports them, each once, in order, at the points reported (those
// after the first that differs too, though the file held them), none of the stale ones left.
TEST(Optimization, AResumeRewritesIterationsNumberedOtherwise) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/renumbered";
    io::CaseFile c = runShort(dir, 10, 4);
    const std::string jsonl = study::historyJsonlPath(c.optimization.history);
    std::vector<std::string> lines;
    int iterationsBefore = 0;
    nlohmann::json last;
    {
        std::ifstream in(jsonl);
        for (std::string line; std::getline(in, line);) {
            nlohmann::json j = nlohmann::json::parse(line);
            if (j.value("kind", "") == "iteration") {
                ++iterationsBefore;
                last = j;
                if (j["iteration"] == 2) {
                    j["x"][0] = j["x"][0].get<double>() + 1e-3;
                    line = j.dump();
                }
            }
            lines.push_back(line);
        }
    }
    ASSERT_GE(iterationsBefore, 3);  // one replayed after the one that differs
    last["iteration"] = last["iteration"].get<int>() + 1;
    last["x"][1] = last["x"][1].get<double>() + 1e-3;
    lines.push_back(last.dump());
    {
        std::ofstream out(jsonl, std::ios::trunc);
        for (const std::string& line : lines) out << line << "\n";
    }
    c.optimization.maxEvaluations = 6;
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    study::OptimizationOptions o;
    o.resume = true;
    std::vector<study::OptimizationRecord> reported;
    o.onRecord = [&](const study::OptimizationRecord& r) {
        if (r.kind == study::OptimizationRecord::Kind::Iteration) reported.push_back(r);
    };
    const study::OptimizationSummary s = study::optimizeCase(ev, o);
    EXPECT_EQ(s.replayedEvaluations, 4);
    std::vector<study::OptimizationRecord> written;
    for (const auto& r : study::readHistory(jsonl)) {
        if (r.kind == study::OptimizationRecord::Kind::Iteration) written.push_back(r);
    }
    ASSERT_EQ(written.size(), reported.size());
    for (std::size_t k = 0; k < written.size(); ++k) {
        EXPECT_EQ(written[k].index, reported[k].index) << k;
        EXPECT_EQ(written[k].x, reported[k].x) << "iteration " << written[k].index;
        if (k > 0) {
            EXPECT_EQ(written[k].index, written[k - 1].index + 1);
        }
    }
    // The iterations CSV too: one row per iteration, in order.
    std::ifstream csv(s.iterationsCsv);
    std::string header, line;
    std::getline(csv, header);
    int rows = 0;
    while (std::getline(csv, line)) {
        ++rows;
        EXPECT_EQ(std::atoi(line.c_str()), written[rows - 1].index) << line;
    }
    EXPECT_EQ(rows, static_cast<int>(written.size()));
}

// The FFD model's own constraints (thickness at stations, the lattice Jacobian bound) reach the
// optimizer after the flow ones, with their values at the start and gradient rows in the
// optimizer's scaled variables (checked against differences of the model's functions).
TEST(Optimization, AMinimumVolumeOnPatchesFacingInwardIsRefusedWithTheReason) {
    // CAD files orient patches either way. The half-sphere with every patch's u direction
    // reversed (its normals into the body) has the enclosed volume -2 pi / 3; the constraint is
    // the volume's ratio to the start's, so a bound given as a number would be met by every such
    // shape: the run stops before its first evaluation and says why.
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/inward_volume";
    std::filesystem::remove_all(dir);
    io::CaseFile c = small("sphere_to_bwb.json");
    ASSERT_TRUE(c.minVolume.has_value());
    c.optimization.history = dir + "/history.csv";
    c.optimization.iterations.clear();
    geometry::PatchSet set = study::loadGeometry(c.geometry);
    const double outward = geometry::enclosedVolume(set);
    for (geometry::Patch& p : set.patches) {
        std::vector<double> points(p.points.size());
        for (int j = 0; j < p.countV; ++j)
            for (int i = 0; i < p.countU; ++i)
                for (int k = 0; k < 3; ++k)
                    points[3 * (i + p.countU * j) + k] = p.points[3 * (p.countU - 1 - i + p.countU * j) + k];
        p.points = points;
        std::vector<double> knots(p.knotsU.rbegin(), p.knotsU.rend());
        for (double& u : knots) u = p.knotsU.front() + p.knotsU.back() - u;
        p.knotsU = knots;
        ASSERT_TRUE(p.weights.empty());
    }
    EXPECT_NEAR(geometry::enclosedVolume(set), -outward, 1e-12);
    study::CaseEvaluator ev(c, set);
    study::OptimizationOptions o;
    o.fresh = true;
    int records = 0;
    o.onRecord = [&](const study::OptimizationRecord&) { ++records; };
    try {
        (void)study::optimizeCase(ev, o);
        ADD_FAILURE() << "the run started";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("constraints.min_volume"), std::string::npos) << m;
        EXPECT_NE(m.find("-2.0944"), std::string::npos) << m;
        EXPECT_NE(m.find("normals point into the body"), std::string::npos) << m;
    }
    EXPECT_EQ(records, 0);
}

// optimization.start_design: a run on a finer grid starts from a coarser run's design (a case of
// its own, as `aeroform-cli optimize --design` writes it). The optimizer's first point is that
// design, bit for bit; the problem stays the case's own: the volume constraint's reference is the
// case's own design (the sphere), not the start. A start that does not fit is refused before any
// evaluation, naming the key and the variable.
TEST(Optimization, ARunStartsFromAnotherCasesDesignWithTheCasesOwnProblem) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/start_design";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    io::CaseFile c = oneEvaluation(dir);
    ASSERT_TRUE(c.minVolume.has_value());
    const geometry::PatchSet sphere = study::loadGeometry(c.geometry);
    const study::CaseEvaluator probe(c, sphere);
    const ffd::FfdModel& model = *probe.model();
    const std::vector<ffd::DesignVariable>& vars = model.design().variables();
    std::vector<double> v = probe.caseValues();
    int moved = 0;
    for (std::size_t i = 0; i < vars.size(); ++i) {
        const std::string& name = vars[i].name;
        if (name.size() > 3 && name.compare(name.size() - 3, 3, ".sz") == 0) {
            v[i] = 1.1;  // every section 10 % taller: a body whose volume is not the sphere's
            ++moved;
        }
    }
    ASSERT_GT(moved, 10);
    const std::string startPath = dir + "/start.json";
    io::writeCase(probe.designCase(v, std::nullopt, "a start design"), startPath);
    c.optimization.startDesign = startPath;

    study::CaseEvaluator ev(c, sphere);
    study::OptimizationOptions o;
    o.fresh = true;
    std::vector<study::OptimizationRecord> values;
    o.onRecord = [&](const study::OptimizationRecord& r) {
        if (r.kind == study::OptimizationRecord::Kind::Values) values.push_back(r);
    };
    const study::OptimizationSummary s = study::optimizeCase(ev, o);
    ASSERT_GE(values.size(), 1u);
    ASSERT_EQ(values[0].x.size(), v.size());
    for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(values[0].x[i], v[i]) << vars[i].name;
    const double sphereVolume = model.volume(probe.caseValues()), startVolume = model.volume(v);
    EXPECT_GT(startVolume, 1.05 * sphereVolume);
    EXPECT_EQ(s.startVolume, sphereVolume);
    ASSERT_TRUE(values[0].ok) << values[0].message;
    ASSERT_GE(values[0].constraints.size(), 1u);
    EXPECT_NEAR(values[0].constraints[0], startVolume / sphereVolume, 1e-9);

    auto refused = [&](const std::string& body, const std::vector<std::string>& words) {
        std::ofstream(startPath) << body;
        study::CaseEvaluator e(c, sphere);
        int records = 0;
        study::OptimizationOptions q;
        q.fresh = true;
        q.onRecord = [&](const study::OptimizationRecord&) { ++records; };
        try {
            (void)study::optimizeCase(e, q);
            ADD_FAILURE() << "the run started from " << body;
        } catch (const CaseError& x) {
            const std::string m = x.what();
            EXPECT_NE(m.find("optimization.start_design"), std::string::npos) << m;
            for (const std::string& w : words) EXPECT_NE(m.find(w), std::string::npos) << m;
        }
        EXPECT_EQ(records, 0);
    };
    const std::string head = R"({"format": "aeroform.case", "version": 1, "geometry": "g.igs", "values": {")";
    refused(head + vars[0].name + "\": " + format("%.17g", vars[0].upper + 1) + "}}", {vars[0].name, "outside the bounds"});
    refused(head + "no_such_variable\": 0.1}}", {"no_such_variable", "no design variable of that name"});
    std::filesystem::remove(startPath);
    refused("", {"start.json"});
}

TEST(Optimization, ThicknessLatticeJacobianWallBendAndWallMachConstraintsReachTheOptimizer) {
    const std::string dir = std::string(AEROFORM_TEST_OUTPUT_DIR) + "/shape_constraints";
    std::filesystem::create_directories(dir);
    io::CaseFile c = small("sphere_to_bwb.json");
    c.optimization.optimizer = "slsqp";
    c.optimization.maxIterations = 1;
    c.optimization.maxEvaluations = 2;
    c.optimization.rangeScaling = true;
    c.optimization.history = dir + "/history.csv";
    c.optimization.iterations.clear();
    c.thickness.stations = {0.0, 0.5};
    c.thickness.chordFractions = {0.25, 0.75};
    c.thickness.minRatio = 0.5;
    c.minLatticeJacobian = 0.2;
    c.optimization.maxWallBend = 30;
    c.optimization.maxWallMach = 1.2;
    // The best shape into a folder that does not exist yet: made at the start, not found missing
    // at the end of the run.
    std::filesystem::remove_all(dir + "/shapes");
    c.outputGeometry = dir + "/shapes/best.igs";
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    study::OptimizationOptions o;
    o.fresh = true;
    std::vector<study::OptimizationRecord> records;
    o.onRecord = [&](const study::OptimizationRecord& r) { records.push_back(r); };
    (void)study::optimizeCase(ev, o);
    EXPECT_TRUE(std::filesystem::exists(dir + "/shapes/best.igs"));
    const study::OptimizationRecord* values = nullptr;
    const study::OptimizationRecord* gradient = nullptr;
    for (const auto& r : records) {
        if (r.kind == study::OptimizationRecord::Kind::Values && r.ok && !values) values = &r;
        if (r.kind == study::OptimizationRecord::Kind::Gradient && r.ok && !gradient) gradient = &r;
    }
    // The constraint names as the history's header records them.
    const std::vector<study::OptimizationRecord> file = study::readHistory(study::historyJsonlPath(c.optimization.history));
    ASSERT_FALSE(file.empty());
    const std::vector<std::string>& names = file.front().constraintNames;
    ASSERT_EQ(names.size(), 4u + 4u + 1u);  // volume, grid, wall bend, wall Mach, 4 thickness points, lattice
    EXPECT_EQ(names[2], "wall bend (degrees, smooth max)");
    EXPECT_EQ(names[3], "wall Mach (smooth max)");
    EXPECT_EQ(names[4], "thickness y=0 x/c=0.25 / baseline");
    EXPECT_EQ(names[8], "lattice det J / baseline (smooth min)");
    ASSERT_TRUE(values && gradient);
    ASSERT_EQ(values->constraints.size(), names.size());
    // The start is the sphere: its wall bend is the baseline grid's (KS bound and sharpest).
    const std::vector<std::array<bool, 6>> walls = mesh::wallFaces(ev.baselineMesh());
    EXPECT_NEAR(values->constraints[2], mesh::wallBendSmoothMax(ev.baselineGrids(), walls, 1000), 1e-12);
    EXPECT_NEAR(values->wallBend, mesh::sharpestWallBend(ev.baselineGrids(), walls).degrees, 1e-12);
    EXPECT_GT(values->constraints[2], values->wallBend);
    EXPECT_LT(values->constraints[2], 30.0);
    // The sphere's wall Mach number: its smooth maximum is above the largest, which is about 0.84
    // on the optimization grid (docs/validation.md), and below the bound.
    EXPECT_GE(values->constraints[3], values->maxMach - 0.05);
    EXPECT_GT(values->constraints[3], 0.7);
    EXPECT_LT(values->constraints[3], 1.2);
    for (int k = 4; k < 8; ++k) EXPECT_NEAR(values->constraints[k], 1.0, 1e-12) << names[k];
    const ffd::FfdModel& model = *ev.model();
    const ffd::LatticeJacobianBound bound(model);
    EXPECT_NEAR(values->constraints[8], 1.0 - std::log(static_cast<double>(bound.sampleCount())) / bound.rho(), 1e-12);
    // Gradient rows in the optimizer's variables (each divided by its range): central differences.
    const ffd::ThicknessConstraints thick(model, {c.thickness.stations, c.thickness.chordFractions, {}});
    const auto& vars = model.design().variables();
    ASSERT_EQ(gradient->dConstraints.size(), names.size());
    const std::vector<double> v0 = model.design().baselineValues();
    for (std::size_t i = 0; i < vars.size(); i += 7) {
        const double range = vars[i].upper - vars[i].lower, h = 1e-6;
        std::vector<double> up = v0, down = v0;
        up[i] += h * range;
        down[i] -= h * range;
        for (int k = 0; k < 4; ++k) {
            const double fd = (thick.ratios(up)[k] - thick.ratios(down)[k]) / (2 * h);
            EXPECT_NEAR(gradient->dConstraints[4 + k][i], fd, 1e-6 * (1 + std::abs(fd))) << names[4 + k] << ", " << vars[i].name;
        }
        const double fd = (bound.value(up) - bound.value(down)) / (2 * h);
        EXPECT_NEAR(gradient->dConstraints[8][i], fd, 1e-5 * (1 + std::abs(fd))) << vars[i].name;
    }
    // The wall Mach row: the flow adjoint's (checked against differences in tests/adjoint/GradientTest).
    double machRow = 0;
    for (double x : gradient->dConstraints[3]) machRow = std::max(machRow, std::abs(x));
    EXPECT_GT(machRow, 1e-3);
}
