// aeroform-cli flow CASE: the function evaluation of the optimization, headless. Runs the case's
// geometry -> first FFD level (if any) -> grid (generated, moved, regenerated) -> Euler solution,
// with a progress line per nonlinear iteration, then reports forces and writes the solution
// (VTK multiblock with Cp, Mach and entropy), the residual history (CSV) and a restart file.
// Ctrl+C (SIGINT) or SIGTERM stops the solver between iterations; the state reached is kept in
// the restart file so `--restart` continues where it stopped.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "adjoint/FlowAdjoint.h"
#include "cli/CliSupport.h"
#include "common/Memory.h"
#include "flow/FlowMesh.h"
#include "flow/FlowSolver.h"
#include "flow/Metrics.h"
#include "flow/Outputs.h"
#include "io/FlowFiles.h"
#include "io/Options.h"
#include "mesh/Quality.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"

namespace aero::app {

namespace {

const char* kFlowHelp =
    "usage: aeroform-cli flow CASE.json [--restart FILE] [--adjoint LIST] [--json]\n"
    "\n"
    "Solves the Euler equations around the case's geometry: the first FFD level deforms it (if the\n"
    "case has lattices), the grid is generated and moved (case key \"mesh\"), then the flow is\n"
    "solved by pseudo-transient continuation and Newton-Krylov (case key \"flow\": mach, alpha,\n"
    "reference_area, reference_length, reference_point, kappa2, kappa4, tolerance, max_iterations,\n"
    "cfl0, ...; docs/case-file.md). A progress line is printed per nonlinear iteration.\n"
    "Outputs (case key \"output\"): flow_vtk (.vtm: density, velocity, pressure, Cp, Mach, entropy;\n"
    "wall faces with Cp), residual_csv, restart. Ctrl+C stops between iterations and keeps the\n"
    "state in the restart file (output.restart, or CASE.restart next to the case); during the\n"
    "solve that file is also rewritten every flow.checkpoint_seconds (60), so a killed run loses\n"
    "at most that much work. --restart FILE (or flow.restart) continues from it; a restart of the\n"
    "same case at another mesh.refine (another sampling of the same analytic grid) is\n"
    "interpolated onto this grid as the start, so a refined grid starts from the coarse solution.\n"
    "Exit 1 if the solver does not converge (the reason is printed; outputs are still written).\n"
    "The reason of a stall names the fastest mode that grows in pseudo time at the final state,\n"
    "where it is and what to do (flow.stall_modes, on by default: about 30 GMRES solves), or that\n"
    "none grows; a solve stopped by max_iterations while its residual still falls says so instead.\n"
    "A solve from the free stream that stalls, diverges or turns non-physical is solved again by\n"
    "continuation in the dissipation: kappa2 and kappa4 times 4, 2, 1.41, then the case's own, each\n"
    "from the state before; 8 and 16 times from the free stream first if 4 times does not\n"
    "converge; a step that misses is retried halfway (1.19 between 1.41 and 1; down to a ratio of\n"
    "2^(1/16), at most 16 stages); the answer is always the case's own problem's.\n"
    "\n"
    "  --restart FILE  start from this restart file (the same grid, or another mesh.refine of it)\n"
    "                  instead of the free stream\n"
    "  --adjoint LIST  after a converged solve, the discrete adjoint of each functional of LIST\n"
    "                  (comma-separated: CL, CD, CM, CY) and its derivative with respect to the\n"
    "                  angle of attack, per degree (exit 1 if an adjoint does not converge)\n"
    "  --json          print one JSON summary on stdout (converged, status, orders_reduced,\n"
    "                  newton_iterations, linear_iterations, CL, CD, CM, grid_nodes, seconds\n"
    "                  (the command), seconds_flow (the flow stage: metrics, grid sequencing's\n"
    "                  pre-solves in seconds_sequencing, every solve), seconds_solve (the last\n"
    "                  solve), peak_memory_mb, stall_modes for a solve that did not converge,\n"
    "                  dissipation_continuation: the first attempt and every stage of a\n"
    "                  continuation, each with status, iterations and relative_residual\n"
    "                  (its final residual over its start's), ...)\n"
    "  --time-accurate STEPS  instead of a steady solve, run the flow forward in physical time\n"
    "                  (dual time stepping, BDF2) for STEPS time steps from the free stream or the\n"
    "                  restart, a line and a row of CASE.time.csv per step (t, CL, CD, CM, CY, the\n"
    "                  steady residual, inner iterations; CL and CD against t in CASE.time.svg);\n"
    "                  at the end the verdict: the flow settles\n"
    "                  into a steady state, oscillates periodically (period, amplitude, Strouhal\n"
    "                  number) or neither yet. For a shape whose steady solve does not converge.\n"
    "                  The state is written to the restart file (output.restart or CASE.restart)\n"
    "  --time-step DT  the physical time step (grid lengths over the free-stream speed of sound:\n"
    "                  the free stream crosses a unit length in 1/Mach of these; default 0.25); a\n"
    "                  step whose inner iterations do not converge is taken again with half the\n"
    "                  size (down to DT/64), and the steps after it grow back; the run ends at\n"
    "                  t = STEPS x DT\n"
    "  --inner-iterations N  Newton iterations per time step at most (default 20)\n"
    "  --inner-tolerance X   each time step solved to X of its first iterate's residual (1e-3)\n"
    "  --history FILE  the time history's CSV (default CASE.time.csv)\n"
    "  --help          this text\n";

double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void say(const std::string& s) { std::fprintf(stderr, "[flow] %s\n", s.c_str()); }

std::string defaultRestartPath(const std::string& casePath) {
    std::filesystem::path p(casePath);
    return (p.parent_path() / (p.stem().string() + ".restart")).string();
}


// A coordinate for a message: round-off around zero (a node on a symmetry plane) printed as 0.
double tidy(double x) { return std::abs(x) < 1e-12 ? 0.0 : x; }

}  // namespace

int runFlow(const std::string& casePath, const std::string& restartArg, bool json, const std::vector<std::string>& adjoints) {
    return guarded("flow", [&] {
        const auto t0 = std::chrono::steady_clock::now();
        const io::CaseFile c = io::readCase(casePath);
        if (!c.flow.present) say("the case has no \"flow\" section: Mach 0.5, alpha 0 and the default solver options");
        geometry::PatchSet set = loadPatchSet(c.geometry);
        say("geometry " + c.geometry + ": " + std::to_string(set.size()) + " patches");
        io::CaseFile run = c;
        run.flow.present = true;  // the flow command solves the flow even without a flow section
        study::CaseEvaluator ev(run, std::move(set), say);

        study::EvaluationRequest request;
        const std::string restartFrom = !restartArg.empty() ? restartArg : c.flow.restart;
        if (!restartFrom.empty()) {
            request.start = study::FlowStart{};
            request.start->restartFile = restartFrom;
        }
        // Checkpoints: the restart file is rewritten (atomically) during the solve, so kill -9 or a
        // power cut costs at most flow.checkpoint_seconds of work. Without output.restart the file
        // next to the case only serves as that protection: removed again if the run converges and
        // this run created it.
        const std::string checkpointPath = !c.outputRestart.empty() ? c.outputRestart : defaultRestartPath(casePath);
        const bool checkpointExisted = std::filesystem::exists(checkpointPath);
        request.checkpointFile = checkpointPath;
        request.checkpointSeconds = c.flow.checkpointSeconds;
        char buf[512];
        int first = 0;  // iterations of the run a restart continues
        auto progress = [&](const study::Progress& p) {
            if (!p.iteration) {
                if (!p.message.empty()) say(p.message);
                return;
            }
            const flow::FlowIteration& it = *p.iteration;
            first = p.iterationOffset;
            const char* tag = p.coarse ? " (coarse)" : "";
            if (!it.rejected.empty()) {
                std::snprintf(buf, sizeof buf, "iter %4d%s  rejected at CFL %.2e (%s), retrying  %7.1f s", first + it.iteration,
                              tag, it.cfl, it.rejected.c_str(), it.seconds);
                say(buf);
                return;
            }
            std::snprintf(buf, sizeof buf, "iter %4d%s  residual %.3e  (rel %.2e)  CFL %.2e  GMRES %3d (%.1e)%s  step %.2f  %7.1f s",
                          first + it.iteration, tag, it.residual, it.relativeResidual, it.cfl, it.linearIterations,
                          it.linearResidual, it.exact ? " exact" : "", it.stepScale, it.seconds);
            say(buf);
        };
        std::snprintf(buf, sizeof buf, "Mach %g, alpha %g deg, %s scheme, kappa2 %g, kappa4 %g; tolerance %.1e, at most %d iterations",
                      run.flow.freeStream.mach, run.flow.freeStream.alphaDeg,
                      run.flow.scheme == flow::InviscidScheme::Central ? "central" : "entropy-conservative",
                      run.flow.dissipation.kappa2, run.flow.dissipation.kappa4, run.flow.newton.relativeTolerance,
                      run.flow.newton.maxIterations);
        say(buf);

        const study::Evaluation e = [&] {
            const CancelOnSignal cancel;
            return ev.evaluate(ev.caseValues(), request, progress, CancelOnSignal::flag());
        }();
        if (!e.flow) {
            // The shape or the mesh failed: nothing was solved.
            throw GeometryError("'" + casePath + "': " + e.message + " (nothing written)");
        }
        const study::FlowResult& fr = *e.flow;
        first = fr.restartContinued ? fr.previousIterations : 0;  // (also when no iteration was needed)
        const flow::FlowReport& rep = fr.report;
        const flow::FlowMesh& fm = fr.mesh;
        if (rep.history.empty() && !fr.report.message.empty() && e.status == study::EvaluationStatus::InvalidMesh) {
            throw GeometryError("'" + casePath + "': " + e.message);
        }
        const std::string status = flow::flowStatusName(rep.status);
        say(rep.message.rfind(status, 0) == 0 ? rep.message : status + ": " + rep.message);
        if (!e.ok() && e.status != study::EvaluationStatus::Cancelled) say("why: " + e.message);
        if (rep.lumping > fr.residualOptions.dissipation.lumping) {
            std::snprintf(buf, sizeof buf, "note: GMRES failed on the preconditioner's lumped system; its lumping factor was raised from %g to %g",
                          fr.residualOptions.dissipation.lumping, rep.lumping);
            say(buf);
        }
        if (rep.approximateFrom > 0) {
            say("note: from iteration " + std::to_string(first + rep.approximateFrom) +
                " approximate-Newton steps took over: the Newton steps did not recover from a failed linear solve within " +
                std::to_string(run.flow.newton.recoveryIterations) + " iterations (flow.exact_recovery_iterations)");
        }
        if (rep.switchedAt > 0) {
            std::snprintf(buf, sizeof buf,
                          "note: iterations %d-%d solved with the pressure switch smoothed to %g (flow.switch_continuation), "
                          "the case's own switch (%g) from iteration %d",
                          first + 1, first + rep.switchedAt - 1, run.flow.newton.switchContinuation,
                          fr.residualOptions.dissipation.switchSmoothing, first + rep.switchedAt);
            say(buf);
        }
        const flow::ForceCoefficients& f = fr.forces;
        std::snprintf(buf, sizeof buf, "CL %.6f  CD %.6f  CM %.6f  CY %.6f  max |s - s_inf| %.3e  max Mach %.3f", f.CL, f.CD,
                      f.CM, f.CY, std::abs(fr.maxEntropy.value), fr.maxMach.value);
        say(buf);
        std::snprintf(buf, sizeof buf, "max Mach at block %d '%s' node (%d, %d, %d), x (%.3g, %.3g, %.3g), %s",
                      fr.maxMach.block, fr.maxMach.blockName.c_str(), fr.maxMach.node[0], fr.maxMach.node[1],
                      fr.maxMach.node[2], tidy(fr.maxMach.x[0]), tidy(fr.maxMach.x[1]), tidy(fr.maxMach.x[2]),
                      fr.maxMach.boundary.c_str());
        say(buf);

        // Outputs, also when the solver failed (the user needs to see it). The state is never lost:
        // without output.restart a cancelled or failed run keeps it next to the case.
        nlohmann::ordered_json outputs = nlohmann::ordered_json::object();
        std::string restartTo = c.outputRestart;
        if (restartTo.empty() && (!rep.converged() || (fr.checkpoints > 0 && checkpointExisted))) {
            restartTo = defaultRestartPath(casePath);  // (a file that existed: left with the final state)
        } else if (restartTo.empty() && fr.checkpoints > 0) {
            std::error_code ec;
            std::filesystem::remove(checkpointPath, ec);  // only a checkpoint of this converged run
        }
        if (!restartTo.empty()) {
            io::RestartInfo info;
            info.freeStream = fr.residualOptions.freeStream;
            info.iterations = first + rep.iterations;
            info.residual = rep.finalResidual;
            info.initialResidual = rep.initialResidual;
            info.cflBase = rep.cflBase;
            info.lumping = rep.lumping;
            if (e.mesh) study::recordGrid(info, e.mesh->control, fm, fr.x);  // (another mesh.refine can start from it)
            io::writeRestart(restartTo, fm, fr.q, info);
            outputs["restart"] = restartTo;
        }
        if (!c.outputResidualCsv.empty()) {
            io::writeResidualCsv(c.outputResidualCsv, rep.history, first);
            outputs["residual_csv"] = c.outputResidualCsv;
        }
        if (!c.outputFlowVtk.empty()) {
            io::writeFlowVtm(c.outputFlowVtk, fm, fr.x, fr.q, fr.residualOptions.freeStream);
            outputs["flow_vtk"] = c.outputFlowVtk;
        }
        if (!c.outputWallPressure.empty()) {
            io::writeWallPressureCsv(c.outputWallPressure, fm, fr.x, fr.q, fr.residualOptions.freeStream);
            outputs["wall_pressure"] = c.outputWallPressure;
        }
        for (const auto& [key, file] : outputs.items()) say("wrote " + file.get<std::string>());

        // Adjoints of the converged state (libcore/adjoint): one linearization, one solve each.
        nlohmann::ordered_json adjointJson = nlohmann::ordered_json::array();
        bool adjointsOk = true;
        double secondsLinearization = 0;
        if (!adjoints.empty() && rep.converged()) {
            std::vector<adjoint::Functional> functionals;
            for (const std::string& name : adjoints) functionals.push_back(adjoint::functionalByName(name));
            say("adjoint: assembling the exact Jacobian and the preconditioner");
            const adjoint::FlowLinearization lin(fm, fr.metrics, fr.q, fr.residualOptions);
            secondsLinearization = lin.secondsAssembly();
            std::snprintf(buf, sizeof buf, "adjoint: linearization assembled in %.1f s", secondsLinearization);
            say(buf);
            for (adjoint::Functional fn : functionals) {
                const adjoint::AdjointSolution a = adjoint::solveAdjoint(lin, fn, fm, fr.metrics, fr.x, fr.q,
                                                                         fr.residualOptions.freeStream, run.flow.reference);
                const double dAlpha = adjoint::alphaDerivative(a, fm, fr.metrics, fr.q, fr.residualOptions, f);
                std::snprintf(buf, sizeof buf, "adjoint of %s: %s, %d GMRES iterations, relative residual %.2e, %.1f s; d%s/dalpha %.6g per degree",
                              adjoint::functionalName(fn), a.report.converged() ? "converged" : "NOT converged", a.report.iterations,
                              a.report.relativeResidual, a.report.seconds, adjoint::functionalName(fn), dAlpha);
                say(buf);
                if (!a.report.converged()) say("  why: " + a.report.message);
                adjointsOk = adjointsOk && a.report.converged();
                adjointJson.push_back({{"functional", adjoint::functionalName(fn)},
                                       {"converged", a.report.converged()},
                                       {"gmres_iterations", a.report.iterations},
                                       {"relative_residual", a.report.relativeResidual},
                                       {"seconds", a.report.seconds},
                                       {"value", adjoint::functionalValue(fn, f)},
                                       {"d_dalpha_per_degree", dAlpha}});
            }
        } else if (!adjoints.empty()) {
            say("adjoint: skipped, the flow did not converge");
            adjointsOk = false;
        }
        const double orders = rep.finalResidual > 0 ? std::log10(rep.initialResidual / rep.finalResidual) : 16.0;
        const double peak = peakMemoryMb();
        double sequencingSeconds = 0;  // grid sequencing's pre-solves on coarser samplings
        for (const auto& level : fr.sequencing) sequencingSeconds += level.report.seconds;
        if (json) {
            auto where = [](const study::FlowLocation& l) {
                nlohmann::ordered_json w;
                w["value"] = l.value;
                w["block"] = l.block;
                w["block_name"] = l.blockName;
                w["node"] = l.node;
                w["x"] = l.x;
                w["boundary"] = l.boundary;
                return w;
            };
            nlohmann::ordered_json j;
            j["case"] = casePath;
            j["converged"] = rep.converged();
            j["status"] = flow::flowStatusName(rep.status);
            j["message"] = e.ok() ? rep.message : e.message;
            j["orders_reduced"] = orders;
            j["newton_iterations"] = rep.iterations;
            j["total_iterations"] = first + rep.iterations;
            j["linear_iterations"] = rep.linearIterations;
            j["lumping"] = rep.lumping;
            j["approximate_from"] = rep.approximateFrom > 0 ? first + rep.approximateFrom : 0;
            j["switched_at"] = rep.switchedAt > 0 ? first + rep.switchedAt : 0;
            j["initial_residual"] = rep.initialResidual;
            j["final_residual"] = rep.finalResidual;
            j["CL"] = f.CL;
            j["CD"] = f.CD;
            j["CM"] = f.CM;
            j["CY"] = f.CY;
            j["force"] = f.force;
            j["moment"] = f.moment;
            j["max_entropy"] = std::abs(fr.maxEntropy.value);
            j["max_mach"] = fr.maxMach.value;
            j["max_mach_at"] = where(fr.maxMach);
            j["max_entropy_at"] = where(fr.maxEntropy);
            j["largest_residual_at"] = where(fr.largestResidual);
            if (fr.interpolatedRestart > 0) j["restart_interpolated_from_nodes"] = fr.interpolatedRestart;
            if (!fr.sequencing.empty()) {
                // The grid-sequencing pre-solves on coarser samplings of the grid, coarsest first.
                nlohmann::ordered_json sj;
                for (const auto& level : fr.sequencing) {
                    sj["levels"].push_back({{"nodes", level.nodes},
                                            {"status", flow::flowStatusName(level.report.status)},
                                            {"iterations", level.report.iterations},
                                            {"linear_iterations", level.report.linearIterations},
                                            {"relative_residual", level.report.relativeResidual()}});
                }
                sj["started_from_them"] = fr.sequenced || fr.sequencedRetry();
                if (fr.sequencedRetry()) {
                    sj["failed_attempt"] = {{"status", flow::flowStatusName(fr.sequencedReport.status)},
                                            {"iterations", fr.sequencedReport.iterations},
                                            {"relative_residual", fr.sequencedReport.relativeResidual()}};
                }
                j["grid_sequencing"] = sj;
            }
            if (fr.dissipationRetry()) {
                // The first attempt stopped; the answer comes from a continuation in the dissipation.
                nlohmann::ordered_json dj;
                dj["first_attempt"] = {{"status", flow::flowStatusName(fr.failedReport.status)},
                                       {"iterations", fr.failedReport.iterations},
                                       {"relative_residual", fr.failedReport.relativeResidual()}};
                for (const auto& st : fr.dissipationStages) {
                    dj["stages"].push_back({{"factor", st.factor},
                                            {"status", flow::flowStatusName(st.report.status)},
                                            {"iterations", st.report.iterations},
                                            {"relative_residual", st.report.relativeResidual()}});
                }
                j["dissipation_continuation"] = dj;
            }
            if (fr.modesChecked) {
                // Why a solve did not converge: the growing modes at its final state.
                nlohmann::ordered_json mj;
                mj["arnoldi_steps"] = fr.modes.steps;
                mj["linear_iterations"] = fr.modes.linearIterations;
                mj["seconds"] = fr.modes.seconds;
                mj["converged_modes"] = fr.modes.modes.size();
                if (!fr.modes.failure.empty()) mj["failure"] = fr.modes.failure;
                const adjoint::FlowMode* g = fr.modes.growing();
                mj["growing"] = g != nullptr;
                if (g) {
                    mj["rate"] = g->rate.real();
                    mj["frequency"] = std::abs(g->rate.imag());
                    mj["at"] = where(fr.modeAt);
                    mj["mach_at"] = fr.modeAt.value;
                } else if (!fr.modes.modes.empty()) {
                    mj["slowest_decay"] = -fr.modes.modes.front().rate.real();
                }
                j["stall_modes"] = mj;
            }
            j["mach"] = fr.residualOptions.freeStream.mach;
            j["alpha"] = fr.residualOptions.freeStream.alphaDeg;
            j["blocks"] = fm.blocks.size();
            j["grid_nodes"] = fm.nodeCount;
            j["largest_spacing_jump"] = e.mesh->spacingJump.ratio;
            j["sharpest_wall_bend"] = wallBendJson(e.mesh->wallBend);
            j["deformed"] = e.mesh->moved;
            j["restarted_from"] = restartFrom;
            j["seconds_solve"] = rep.seconds;
            j["seconds_sequencing"] = sequencingSeconds;
            j["seconds_flow"] = e.secondsFlow;
            j["seconds"] = since(t0);
            j["peak_memory_mb"] = peak;
            j["outputs"] = outputs;
            if (!adjoints.empty()) {
                j["adjoint"] = adjointJson;
                j["seconds_adjoint_linearization"] = secondsLinearization;
            }
            std::printf("%s\n", j.dump(2).c_str());
        }
        // The flow stage is what a solver comparison times: the grid's metrics, the pre-solves of
        // grid sequencing and every solve of the case's grid (the last one is "solver").
        if (fr.sequencing.empty()) {
            std::snprintf(buf, sizeof buf, "done in %.1f s (flow %.1f s, of it the solver %.1f s), peak memory %.0f MB", since(t0),
                          e.secondsFlow, rep.seconds, peak);
        } else {
            std::snprintf(buf, sizeof buf,
                          "done in %.1f s (flow %.1f s, of it grid sequencing %.1f s and the solver %.1f s), peak memory %.0f MB",
                          since(t0), e.secondsFlow, sequencingSeconds, rep.seconds, peak);
        }
        say(buf);
        if (rep.status == flow::FlowStatus::Cancelled ||
            (rep.status == flow::FlowStatus::TimeLimit && fr.dissipationStages.empty())) {
            say("continue with: aeroform-cli flow " + casePath + " --restart " + restartTo);
        } else if (!rep.converged() && !restartTo.empty() &&
                   (rep.status == flow::FlowStatus::Stalled || fr.dissipationRetry())) {
            // A stall the continuation did not cure: whether this shape's flow is unsteady is
            // what a time-accurate run from the state reached tells (flow/TimeAccurate.h).
            say("whether this flow is unsteady: aeroform-cli flow " + casePath + " --restart " + restartTo +
                " --time-accurate 400 --time-step 0.5");
        }
        return rep.converged() && adjointsOk ? kOk : kFailed;
    });
}

int cmdFlow(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::printf("%s", kFlowHelp);
        // The case keys, from the option table the parser uses (io/Options.h).
        std::printf("\nCase keys of \"flow\" (default, range; docs/case-file.md has the descriptions):\n");
        const io::FlowCase defaults;
        for (const auto& o : io::flowOptions()) {
            std::printf("  %-24s %-22s %s\n", o.spec.key.c_str(), io::formatOptionValue(o.get(defaults)).c_str(),
                        o.spec.rangeWithUnit().c_str());
        }
        std::printf("  %-24s %-22s %s\n", "restart", "none", "a restart file");
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json"},
               {"--restart", "--adjoint", "--time-accurate", "--time-step", "--inner-iterations", "--inner-tolerance", "--history"},
               pos, val, err)) {
        return usageError("flow", err, kFlowHelp);
    }
    if (pos.size() != 1) return usageError("flow", "expected exactly one CASE file", kFlowHelp);
    const bool timeAccurate = val.count("--time-accurate") > 0;
    for (const char* option : {"--time-step", "--inner-iterations", "--inner-tolerance", "--history"}) {
        if (val.count(option) && !timeAccurate) return usageError("flow", std::string(option) + " needs --time-accurate", kFlowHelp);
    }
    if (timeAccurate) {
        if (val.count("--adjoint")) return usageError("flow", "--adjoint needs a steady solve, not --time-accurate", kFlowHelp);
        flow::TimeAccurateOptions ta;
        // A positive number, the whole argument (a count: also whole).
        auto number = [&](const char* option, double& out, bool count) {
            const std::string& text = val[option];
            std::size_t used = 0;
            double x = 0;
            try {
                x = std::stod(text, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != text.size() || !(x > 0) || !std::isfinite(x) || (count && (x != std::floor(x) || x > 1e7))) {
                err = std::string(option) + ": '" + text + "' is not a positive " + (count ? "whole number" : "number");
                return false;
            }
            out = x;
            return true;
        };
        double steps = 0, inner = ta.maxInner;
        if (!number("--time-accurate", steps, true)) return usageError("flow", err, kFlowHelp);
        ta.steps = static_cast<int>(steps);
        if (val.count("--time-step") && !number("--time-step", ta.timeStep, false)) return usageError("flow", err, kFlowHelp);
        if (val.count("--inner-iterations") && !number("--inner-iterations", inner, true)) return usageError("flow", err, kFlowHelp);
        ta.maxInner = static_cast<int>(inner);
        if (val.count("--inner-tolerance") && !number("--inner-tolerance", ta.innerTolerance, false)) {
            return usageError("flow", err, kFlowHelp);
        }
        return runTimeAccurate(pos[0], val.count("--restart") ? val["--restart"] : "", ta,
                               val.count("--history") ? val["--history"] : "", val.count("--json") > 0);
    }
    std::vector<std::string> adjoints;
    if (val.count("--adjoint")) {
        for (const std::string& item : splitList(val["--adjoint"])) {
            try {
                (void)adjoint::functionalByName(item);
            } catch (const CaseError& e) {
                return usageError("flow", std::string("--adjoint: ") + e.what(), kFlowHelp);
            }
            adjoints.push_back(item);
        }
        if (adjoints.empty()) return usageError("flow", "--adjoint needs at least one functional (CL, CD, CM, CY)", kFlowHelp);
    }
    return runFlow(pos[0], val.count("--restart") ? val["--restart"] : "", val.count("--json") > 0, adjoints);
}

}  // namespace aero::app
