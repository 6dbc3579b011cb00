// aeroform-cli optimize CASE: the case's "optimization" section (study/Optimization.h): progress
// per evaluation and per major iteration on stderr, the history appended as it happens, the best
// shape as exact IGES, a JSON summary on stdout with --json. Ctrl+C (SIGINT) or SIGTERM stops at
// the next flow iteration; --resume continues the history (what it holds is replayed, not solved
// again) and reaches the iterates an uninterrupted run reaches.
#include <atomic>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include <filesystem>

#include "cli/CliSupport.h"
#include "cli/SvgPlot.h"
#include "common/Format.h"
#include "common/Memory.h"
#include "io/CaseWriter.h"
#include "io/FlowFiles.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"
#include "study/Optimization.h"

namespace aero::app {

namespace {

const char* kHelp =
    "usage: aeroform-cli optimize CASE.json [--resume | --fresh] [--json] [--quiet]\n"
    "       aeroform-cli optimize CASE.json --design N OUT.json\n"
    "\n"
    "Runs the case's \"optimization\" section: the objective (a flow functional) over the design\n"
    "variables (and alpha) with the case's constraints, by Ipopt or SLSQP with exact adjoint\n"
    "gradients. Every evaluation is appended to the history as it happens (optimization.history:\n"
    "CSV, with the exact JSON-lines record beside it); each major iteration's shape is written to\n"
    "optimization.iterations when given, the best shape as IGES beside the history.\n"
    "\n"
    "  --resume  continue the history: the evaluations it holds are replayed to the optimizer, not\n"
    "            solved again, so a run killed at any moment goes on where it stopped\n"
    "  --fresh   start over, replacing an existing history (without either, an existing history is\n"
    "            an error: nothing is overwritten)\n"
    "  --json    a summary as JSON on stdout at the end\n"
    "  --quiet   no flow iterations on stderr (evaluations and iterations are still shown)\n"
    "  --design N OUT.json\n"
    "            write evaluation N of the history as a case of its own (its design values and\n"
    "            angle of attack, no outputs, no optimization section) and stop: aeroform-cli flow\n"
    "            OUT.json solves it again, e.g. to see why a failed step's flow did not converge\n"
    "            (flow.stall_modes) or to look at the flow of an iterate; another case's\n"
    "            optimization.start_design starts its run from it (e.g. a coarser grid's best design).\n"
    "            When the run kept that evaluation's flow (its newest accepted evaluations and\n"
    "            last iterates), it is written beside OUT.json as OUT.restart: aeroform-cli flow\n"
    "            OUT.json --restart OUT.restart starts from it, also at another mesh.refine\n"
    "  --help    this text\n"
    "Ctrl+C stops at the next flow iteration (the history is kept: --resume continues it).\n"
    "Exit 0 when the optimizer converged or reached its iteration or evaluation limit, 1 when it\n"
    "failed, stalled, found no feasible design or was stopped, 2 usage error.\n";

void say(const std::string& s) { std::fprintf(stderr, "[optimize] %s\n", s.c_str()); }

// The convergence history as the paper's Figures 3b and 4 show it, from the history's records:
// J against evaluation (log scale for the pressure mismatch), and optimality and feasibility
// (log) at each major iteration. Returns the files written.
std::vector<std::string> writeConvergencePlots(const study::OptimizationSummary& s, const std::string& objective) {
    const std::vector<study::OptimizationRecord> records = study::readHistory(s.historyJsonl);
    PlotSeries J{objective, {}}, optimality{"optimality", {}}, feasibility{"feasibility", {}};
    for (const study::OptimizationRecord& r : records) {
        if (r.kind == study::OptimizationRecord::Kind::Values && r.ok) J.points.emplace_back(r.index, r.J);
        if (r.kind == study::OptimizationRecord::Kind::Iteration) {
            optimality.points.emplace_back(r.evaluations, r.optimality);
            feasibility.points.emplace_back(r.evaluations, r.feasibility);
        }
    }
    const std::filesystem::path stem = std::filesystem::path(s.historyCsv).replace_extension();
    const std::string objectivePlot = stem.string() + "_objective.svg", optimalityPlot = stem.string() + "_optimality.svg";
    PlotOptions o;
    o.title = "Objective " + objective + " of every converged evaluation";
    o.xLabel = "evaluation";
    o.yLabel = objective;
    o.logY = objective == "pressure";
    writeSvgPlot(objectivePlot, {J}, o);
    o.title = "First-order optimality and feasibility at the major iterations";
    o.yLabel = "optimality, largest constraint violation";
    o.logY = true;
    writeSvgPlot(optimalityPlot, {optimality, feasibility}, o);
    return {objectivePlot, optimalityPlot};
}

// `optimize CASE --design N OUT`: evaluation N of the history as a case of its own.
int writeEvaluationCase(const std::string& casePath, int evaluation, const std::string& out) {
    return guarded("optimize", [&] {
        const io::CaseFile c = io::readCase(casePath);
        const geometry::PatchSet patches = loadPatchSet(c.geometry);
        const study::CaseEvaluator ev(c, patches);
        const io::CaseFile one = study::evaluationCase(ev, evaluation);
        if (std::filesystem::exists(out) && std::filesystem::equivalent(out, casePath)) {
            throw InputError("'" + out + "' is the case itself: not overwritten");
        }
        io::writeCase(one, out);
        say(format("wrote evaluation %d as '%s' (its description says what the optimizer saw); solve it with: "
                   "aeroform-cli flow %s",
                   evaluation, out.c_str(), out.c_str()));
        // The flow the run kept for this evaluation (a warm-start state: the values alone) as a
        // restart with its grid's layout, parameters and corners, so the optimizer's own solution
        // starts the case again or a finer mesh.refine of it (the paper refined its optimum).
        const std::vector<double> kept = io::readWarmState(study::warmStatePath(c.optimization.history, evaluation));
        if (kept.empty()) return kOk;
        study::CaseEvaluator oneEv(one, patches);
        study::EvaluationRequest meshOnly;
        meshOnly.flow = false;
        const study::Evaluation m = oneEv.evaluate(oneEv.caseValues(), meshOnly);
        if (!m.ok() || !m.mesh) return kOk;
        const flow::FlowMesh fm = flow::makeFlowMesh(m.mesh->control, m.mesh->grids);
        if (kept.size() != static_cast<std::size_t>(flow::kVars * fm.nodeCount)) return kOk;  // another grid's
        io::RestartInfo info;
        info.freeStream = one.flow.freeStream;
        study::recordGrid(info, m.mesh->control, fm, flow::gatherCoordinates(fm, m.mesh->grids));
        const std::string restart = std::filesystem::path(out).replace_extension(".restart").string();
        io::writeRestart(restart, fm, kept, info);
        say(format("wrote its flow, kept by the run, as '%s': aeroform-cli flow %s --restart %s starts from it (also at "
                   "another mesh.refine)",
                   restart.c_str(), out.c_str(), restart.c_str()));
        return kOk;
    });
}

}  // namespace

int cmdOptimize(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::printf("%s", kHelp);
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--resume", "--fresh", "--json", "--quiet"}, {"--design"}, pos, val, err)) return usageError("optimize", err, kHelp);
    if (val.count("--design")) {
        if (pos.size() != 2) return usageError("optimize", "--design N needs the case file and the output file", kHelp);
        if (hasFlag(args, "--resume") || hasFlag(args, "--fresh")) {
            return usageError("optimize", "--design writes a case and runs nothing: no --resume or --fresh", kHelp);
        }
        char* end = nullptr;
        const long n = std::strtol(val["--design"].c_str(), &end, 10);
        if (end == val["--design"].c_str() || *end != '\0' || n < 1 || n > 100000000) {
            return usageError("optimize", "--design: '" + val["--design"] + "' is not an evaluation number (1, 2, ...)", kHelp);
        }
        return writeEvaluationCase(pos[0], static_cast<int>(n), pos[1]);
    }
    if (pos.size() != 1) return usageError("optimize", "expected exactly one case file", kHelp);
    if (hasFlag(args, "--resume") && hasFlag(args, "--fresh")) return usageError("optimize", "--resume and --fresh exclude each other", kHelp);
    return runOptimize(pos[0], hasFlag(args, "--resume"), hasFlag(args, "--fresh"), hasFlag(args, "--json"),
                       hasFlag(args, "--quiet"));
}

int runOptimize(const std::string& casePath, bool resume, bool fresh, bool json, bool quiet) {
    return guarded("optimize", [&] {
        const io::CaseFile c = io::readCase(casePath);
        if (!c.optimization.present) throw CaseError("'" + casePath + "': the case has no \"optimization\" section");
        study::CaseEvaluator ev(c, loadPatchSet(c.geometry), say);
        study::OptimizationOptions o;
        o.resume = resume;
        o.fresh = fresh;
        o.cancel = CancelOnSignal::flag();
        o.log = say;
        o.progress = [quiet](const study::Progress& p) {
            if (quiet || !p.iteration) return;
            const flow::FlowIteration& it = *p.iteration;
            if (it.rejected.empty() && it.iteration % 10 == 0) {
                say(format("  flow iteration %.0f%s: relative residual %.2e, %.1f s", static_cast<double>(it.iteration),
                           p.coarse ? " (coarse)" : "", it.relativeResidual, it.seconds));
            }
        };
        o.onRecord = [&](const study::OptimizationRecord& r) {
            const char* tag = r.replayed ? " [replayed]" : "";
            if (r.kind == study::OptimizationRecord::Kind::Values) {
                if (r.ok) {
                    std::string grid = r.cornerRatio != 0 ? format(", smallest cell corner %.3g of its baseline", std::exp(r.cornerRatio)) : "";
                    if (r.wallBend > 0) grid += format(", wall bend %.1f deg", r.wallBend);
                    say(format("evaluation %.0f: %s %.8g, CL %.6f, CD %.6f, volume %.6f, half-span %.4f, aspect ratio %.3f, "
                               "alpha %.4g%s, max Mach %.3f, %.0f flow iterations%s, %.1f s%s",
                               static_cast<double>(r.index), c.optimization.objective.c_str(), r.J, r.CL, r.CD, r.volume,
                               r.planform.halfSpan, r.planform.aspectRatio, r.alphaDeg, grid.c_str(), r.maxMach,
                               static_cast<double>(r.flowIterations),
                               r.warmFrom ? " (warm)" : "", r.seconds, tag));
                } else {
                    say(format("evaluation %.0f failed (%s): %s%s", static_cast<double>(r.index), r.status.c_str(),
                               r.message.c_str(), tag));
                }
            } else if (r.kind == study::OptimizationRecord::Kind::Gradient) {
                say(format("gradient %.0f: %s%.0f adjoint GMRES iterations, %.1f s%s", static_cast<double>(r.index),
                           r.ok ? "" : ("failed: " + r.message + "; ").c_str(), static_cast<double>(r.adjointIterations),
                           r.seconds, tag));
            }
        };
        const study::OptimizationSummary s = [&] {
            const CancelOnSignal cancel;
            return study::optimizeCase(ev, o);
        }();
        const optimize::Result& r = s.result;
        say(format("%s after %.0f iterations, %.0f evaluations (%.0f failed), %.0f gradients: %s", optimize::statusName(r.status),
                   static_cast<double>(r.iterations), static_cast<double>(r.evaluations),
                   static_cast<double>(r.failedEvaluations), static_cast<double>(r.gradients), r.message.c_str()));
        say(format("best: %s%s %.8g, CL %.6f, CD %.6f, volume %.6f (start %.6f), optimality %.2e, feasibility %.2e",
                   s.bestEvaluation > 0 ? format("evaluation %d, ", s.bestEvaluation).c_str() : "",
                   c.optimization.objective.c_str(), s.J, s.forces.CL, s.forces.CD, s.volume, s.startVolume, r.optimality,
                   r.feasibility));
        if (s.bestEvaluation > 0) {
            say(format("as a case of its own (e.g. optimization.start_design of a finer grid's run): aeroform-cli optimize %s "
                       "--design %d OUT.json",
                       casePath.c_str(), s.bestEvaluation));
        }
        if (s.nearlyFeasibleEvaluation > 0) {
            say(format("best within 1e-3 of feasibility: evaluation %d, %s %.8g (infeasibility %.2e); as a case: "
                       "aeroform-cli optimize %s --design %d OUT.json",
                       s.nearlyFeasibleEvaluation, c.optimization.objective.c_str(), s.nearlyFeasibleJ,
                       s.nearlyFeasibleInfeasibility, casePath.c_str(), s.nearlyFeasibleEvaluation));
        }
        say(format("best planform: half-span %.4f, projected area %.4f, aspect ratio %.3f (start %.4f, %.4f, %.3f)",
                   s.planform.halfSpan, s.planform.projectedArea, s.planform.aspectRatio, s.startPlanform.halfSpan,
                   s.startPlanform.projectedArea, s.startPlanform.aspectRatio));
        if (s.replayedEvaluations > 0) {
            say(format("replayed from the history: %.0f evaluations, %.0f gradients", static_cast<double>(s.replayedEvaluations),
                       static_cast<double>(s.replayedGradients)));
        }
        if (s.warmStarts > 0) {
            say(format("warm starts: %.0f evaluations, %.1f flow iterations on average", static_cast<double>(s.warmStarts),
                       s.meanWarmFlowIterations) +
                (s.coldFlowIterations > 0 ? format(" (the cold start took %d)", s.coldFlowIterations) : std::string()));
        }
        say("history: " + s.historyCsv + ", " + s.iterationsCsv + " (exact records: " + s.historyJsonl + ")");
        say("best shape: " + s.finalGeometry + (c.outputGeometry.empty() ? "" : " and " + c.outputGeometry));
        const std::vector<std::string> plots = writeConvergencePlots(s, c.optimization.objective);
        say("convergence plots: " + plots[0] + ", " + plots[1]);
        say(format("%.1f s, peak memory %.0f MB", s.seconds, peakMemoryMb()));
        if (r.status == optimize::Status::Cancelled) say("stopped; continue with: aeroform-cli optimize " + casePath + " --resume");
        if (json) {
            nlohmann::ordered_json j;
            j["case"] = casePath;
            j["status"] = optimize::statusName(r.status);
            j["message"] = r.message;
            j["objective"] = c.optimization.objective;
            j["best_evaluation"] = s.bestEvaluation;
            if (s.nearlyFeasibleEvaluation > 0) {
                j["nearly_feasible_evaluation"] = s.nearlyFeasibleEvaluation;
                j["nearly_feasible_J"] = s.nearlyFeasibleJ;
                j["nearly_feasible_infeasibility"] = s.nearlyFeasibleInfeasibility;
            }
            j["J"] = s.J;
            j["CL"] = s.forces.CL;
            j["CD"] = s.forces.CD;
            j["CM"] = s.forces.CM;
            j["volume"] = s.volume;
            j["start_volume"] = s.startVolume;
            j["half_span"] = s.planform.halfSpan;
            j["projected_area"] = s.planform.projectedArea;
            j["aspect_ratio"] = s.planform.aspectRatio;
            j["start_half_span"] = s.startPlanform.halfSpan;
            j["start_projected_area"] = s.startPlanform.projectedArea;
            j["start_aspect_ratio"] = s.startPlanform.aspectRatio;
            j["alpha_deg"] = s.alphaDeg;
            j["optimality"] = std::isfinite(r.optimality) ? nlohmann::ordered_json(r.optimality) : nlohmann::ordered_json(nullptr);
            j["feasibility"] = r.feasibility;
            j["iterations"] = r.iterations;
            j["evaluations"] = r.evaluations;
            j["failed_evaluations"] = r.failedEvaluations;
            j["gradients"] = r.gradients;
            j["replayed_evaluations"] = s.replayedEvaluations;
            j["replayed_gradients"] = s.replayedGradients;
            j["cold_flow_iterations"] = s.coldFlowIterations;
            j["mean_warm_flow_iterations"] = s.meanWarmFlowIterations;
            j["seconds"] = s.seconds;
            j["history"] = s.historyCsv;
            j["best_geometry"] = s.finalGeometry;
            nlohmann::ordered_json x = nlohmann::ordered_json::object();
            for (std::size_t i = 0; i < s.names.size(); ++i) x[s.names[i]] = i < s.values.size() ? s.values[i] : s.alphaDeg;
            j["design"] = x;
            nlohmann::ordered_json raw = nlohmann::ordered_json::array();
            for (double u : r.x) raw.push_back(u);
            j["x"] = raw;  // the optimizer's scaled variables, exact
            std::printf("%s\n", j.dump(2).c_str());
        }
        const bool good = r.status == optimize::Status::Converged || r.status == optimize::Status::IterationLimit ||
                          r.status == optimize::Status::EvaluationLimit;
        return good ? kOk : kFailed;
    });
}

}  // namespace aero::app
