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
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/CliSupport.h"
#include "common/Memory.h"
#include "flow/FlowMesh.h"
#include "flow/FlowSolver.h"
#include "flow/Metrics.h"
#include "flow/Outputs.h"
#include "io/FlowFiles.h"
#include "mesh/Quality.h"
#include "study/CaseGrid.h"

namespace aero::app {

namespace {

const char* kFlowHelp =
    "usage: aeroform-cli flow CASE.json [--restart FILE] [--json]\n"
    "\n"
    "Solves the Euler equations around the case's geometry: the first FFD level deforms it (if the\n"
    "case has lattices), the grid is generated and moved (case key \"mesh\"), then the flow is\n"
    "solved by pseudo-transient continuation and Newton-Krylov (case key \"flow\": mach, alpha,\n"
    "reference_area, reference_length, reference_point, kappa2, kappa4, tolerance, max_iterations,\n"
    "cfl0, ...; docs/case-file.md). A progress line is printed per nonlinear iteration.\n"
    "Outputs (case key \"output\"): flow_vtk (.vtm: density, velocity, pressure, Cp, Mach, entropy;\n"
    "wall faces with Cp), residual_csv, restart. Ctrl+C stops between iterations and keeps the\n"
    "state in the restart file (output.restart, or CASE.restart next to the case); --restart FILE\n"
    "(or flow.restart) continues from it. Exit 1 if the solver does not converge (the reason is\n"
    "printed; outputs are still written).\n"
    "\n"
    "  --restart FILE  start from this restart file (same grid) instead of the free stream\n"
    "  --json          print one JSON summary on stdout (converged, status, orders_reduced,\n"
    "                  newton_iterations, linear_iterations, CL, CD, CM, seconds, grid_nodes,\n"
    "                  peak_memory_mb, ...)\n"
    "  --help          this text\n";

std::atomic<bool> gCancel{false};
extern "C" void onSignal(int) { gCancel.store(true); }

double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void say(const std::string& s) { std::fprintf(stderr, "[flow] %s\n", s.c_str()); }

std::string defaultRestartPath(const std::string& casePath) {
    std::filesystem::path p(casePath);
    return (p.parent_path() / (p.stem().string() + ".restart")).string();
}

// Largest ratio of neighbouring grid spacings accepted without a warning: the medium and paper
// half-sphere levels (4.7 and 3.0, their last radial cell) converge; the coarse level with wall
// spacing 1e-3 (18.5) stalls.
constexpr double kSpacingJumpWarning = 8.0;

// A coordinate for a message: round-off around zero (a node on a symmetry plane) printed as 0.
double tidy(double x) { return std::abs(x) < 1e-12 ? 0.0 : x; }

}  // namespace

int runFlow(const std::string& casePath, const std::string& restartArg, bool json) {
    return guarded("flow", [&] {
        const auto t0 = std::chrono::steady_clock::now();
        const io::CaseFile c = io::readCase(casePath);
        if (!c.flow.present) say("the case has no \"flow\" section: Mach 0.5, alpha 0 and the default solver options");
        const geometry::PatchSet set = loadPatchSet(c.geometry);
        say("geometry " + c.geometry + ": " + std::to_string(set.size()) + " patches");
        const study::CaseShape shape = study::deformCase(c, set, say);
        const study::CaseGrid cg = study::buildCaseGrid(c, set, shape, say);

        std::vector<mesh::CellQuality> quality;
        for (const auto& g : cg.grids) quality.push_back(mesh::cellQuality(g));
        mesh::requirePositiveJacobians(cg.grids, quality);  // throws naming block and cell
        // Central differences lose their accuracy across a sudden change of spacing, and a flow
        // solve on such a grid tends to stall there (docs/validation.md): say so before it starts.
        const mesh::SpacingJump jump = mesh::largestSpacingJump(cg.grids);
        const bool steepJump = jump.ratio > kSpacingJumpWarning;
        if (steepJump) {
            char w[512];
            std::snprintf(w, sizeof w,
                          "warning: the grid spacing jumps by a factor %.1f along %c at block %d '%s' node (%d, %d, %d) "
                          "(x %.3g, %.3g, %.3g); central differences are poor there and the flow may stall "
                          "(a finer level, a higher mesh.refine or a larger grid_wall_spacing reduces it)",
                          jump.ratio, "ijk"[jump.direction], jump.block, jump.blockName.c_str(), jump.node[0], jump.node[1],
                          jump.node[2], tidy(jump.x[0]), tidy(jump.x[1]), tidy(jump.x[2]));
            say(w);
        }

        auto t = std::chrono::steady_clock::now();
        const flow::FlowMesh fm = flow::makeFlowMesh(cg.mesh, cg.grids);
        const std::vector<double> x = flow::gatherCoordinates(fm, cg.grids);
        const std::vector<double> metrics = flow::computeMetrics(fm, x);
        char buf[512];
        std::snprintf(buf, sizeof buf, "flow grid: %zu blocks, %ld nodes, %zu interface patches, metrics in %.3f s",
                      fm.blocks.size(), fm.nodeCount, fm.interfaces.size(), since(t));
        say(buf);

        flow::ResidualOptions ro;
        ro.freeStream = c.flow.freeStream;
        ro.dissipation = c.flow.dissipation;
        ro.scheme = c.flow.scheme;
        flow::NewtonOptions no = c.flow.newton;
        if (const char* e = std::getenv("AERO_CFLINC")) no.cflMaxIncrease = std::atof(e);  // EXPERIMENT
        if (const char* e = std::getenv("AERO_GMRES")) no.gmresMaxIterations = std::atoi(e);  // EXPERIMENT
        if (const char* e = std::getenv("AERO_FILL")) no.iluFill = std::atoi(e);  // EXPERIMENT
        if (const char* e = std::getenv("AERO_LUMP")) ro.dissipation.lumping = std::atof(e);  // EXPERIMENT

        // Start: a restart file (command line first, then the case) or the free stream.
        std::vector<double> q;
        io::RestartInfo previous;
        const std::string restartFrom = !restartArg.empty() ? restartArg : c.flow.restart;
        if (!restartFrom.empty()) {
            q = io::readRestart(restartFrom, fm, &previous);
            const flow::FreeStream& fs = previous.freeStream;
            std::snprintf(buf, sizeof buf, "restart from %s: %d iterations done, residual %.3e (Mach %g, alpha %g)",
                          restartFrom.c_str(), previous.iterations, previous.residual, fs.mach, fs.alphaDeg);
            say(buf);
            const bool sameConditions = fs.mach == ro.freeStream.mach && fs.alphaDeg == ro.freeStream.alphaDeg &&
                                        fs.gamma == ro.freeStream.gamma;
            if (sameConditions && previous.initialResidual > 0) {
                // Continue the same run: orders, tolerances and the CFL law refer to its first residual.
                no.referenceResidual = previous.initialResidual;
                if (previous.cflBase > 0) no.cfl0 = previous.cflBase;
                ro.dissipation.lumping = std::max(ro.dissipation.lumping, previous.lumping);
            } else {
                say("the restart's free stream differs from the case's: it is only the initial guess");
                previous.iterations = 0;
            }
        } else {
            say("starting from the free stream");
        }
        std::snprintf(buf, sizeof buf, "Mach %g, alpha %g deg, kappa2 %g, kappa4 %g; tolerance %.1e, at most %d iterations",
                      ro.freeStream.mach, ro.freeStream.alphaDeg, ro.dissipation.kappa2, ro.dissipation.kappa4,
                      no.relativeTolerance, no.maxIterations);
        say(buf);

        gCancel.store(false);
        auto oldInt = std::signal(SIGINT, onSignal);
        auto oldTerm = std::signal(SIGTERM, onSignal);
        const int first = previous.iterations;
        const flow::FlowReport rep = flow::solveFlow(fm, metrics, ro, q, no, [&](const flow::FlowIteration& it) {
            if (!it.rejected.empty()) {
                std::snprintf(buf, sizeof buf, "iter %4d  rejected at CFL %.2e (%s), retrying  %7.1f s",
                              first + it.iteration, it.cfl, it.rejected.c_str(), it.seconds);
                say(buf);
                return;
            }
            std::snprintf(buf, sizeof buf, "iter %4d  residual %.3e  (rel %.2e)  CFL %.2e  GMRES %3d (%.1e)%s  step %.2f  %7.1f s",
                          first + it.iteration, it.residual, it.relativeResidual, it.cfl, it.linearIterations,
                          it.linearResidual, it.exact ? " exact" : "", it.stepScale, it.seconds);
            say(buf);
        }, &gCancel);
        std::signal(SIGINT, oldInt);
        std::signal(SIGTERM, oldTerm);
        const std::string status = flow::flowStatusName(rep.status);
        say(rep.message.rfind(status, 0) == 0 ? rep.message : status + ": " + rep.message);
        if (rep.lumping > ro.dissipation.lumping) {
            std::snprintf(buf, sizeof buf, "note: GMRES failed on the preconditioner's lumped system; its lumping factor was raised from %g to %g",
                          ro.dissipation.lumping, rep.lumping);
            say(buf);
        }

        const bool failed = rep.status == flow::FlowStatus::Stalled || rep.status == flow::FlowStatus::Diverged ||
                            rep.status == flow::FlowStatus::NotANumber;
        if (failed && steepJump) {
            std::snprintf(buf, sizeof buf, "hint: the grid's spacing jump (factor %.1f, warned about above) is the likely cause",
                          jump.ratio);
            say(buf);
        } else if (failed && ro.dissipation.kappa4 < 0.05) {
            std::snprintf(buf, sizeof buf,
                          "hint: kappa4 %g is below the default 0.05, with which the half-sphere grids converge; "
                          "less dissipation is known to stall at the rear stagnation point (docs/validation.md, known problem 1)",
                          ro.dissipation.kappa4);
            say(buf);
        }
        const flow::ForceCoefficients f = flow::integrateForces(fm, metrics, x, q, ro.freeStream, c.flow.reference);
        const std::vector<double> s = flow::entropy(fm, q, ro.freeStream);
        const std::vector<double> mach = flow::machNumber(fm, q, ro.freeStream.gamma);
        double maxEntropy = 0, maxMach = 0;
        for (long i = 0; i < fm.nodeCount; ++i) {
            maxEntropy = std::max(maxEntropy, std::abs(s[i]));
            maxMach = std::max(maxMach, mach[i]);
        }
        std::snprintf(buf, sizeof buf, "CL %.6f  CD %.6f  CM %.6f  CY %.6f  max |s - s_inf| %.3e  max Mach %.3f", f.CL, f.CD,
                      f.CM, f.CY, maxEntropy, maxMach);
        say(buf);

        // Outputs, also when the solver failed (the user needs to see it). The state is never lost:
        // without output.restart a cancelled or failed run keeps it next to the case.
        nlohmann::ordered_json outputs = nlohmann::ordered_json::object();
        std::string restartTo = c.outputRestart;
        if (restartTo.empty() && !rep.converged()) restartTo = defaultRestartPath(casePath);
        if (!restartTo.empty()) {
            io::RestartInfo info;
            info.freeStream = ro.freeStream;
            info.iterations = first + rep.iterations;
            info.residual = rep.finalResidual;
            info.initialResidual = rep.initialResidual;
            info.cflBase = rep.cflBase;
            info.lumping = rep.lumping;
            io::writeRestart(restartTo, fm, q, info);
            outputs["restart"] = restartTo;
        }
        if (!c.outputResidualCsv.empty()) {
            io::writeResidualCsv(c.outputResidualCsv, rep.history, first);
            outputs["residual_csv"] = c.outputResidualCsv;
        }
        if (!c.outputFlowVtk.empty()) {
            io::writeFlowVtm(c.outputFlowVtk, fm, x, q, ro.freeStream);
            outputs["flow_vtk"] = c.outputFlowVtk;
        }
        for (const auto& [key, file] : outputs.items()) say("wrote " + file.get<std::string>());

        const double orders = rep.finalResidual > 0 ? std::log10(rep.initialResidual / rep.finalResidual) : 16.0;
        const double peak = peakMemoryMb();
        if (json) {
            nlohmann::ordered_json j;
            j["case"] = casePath;
            j["converged"] = rep.converged();
            j["status"] = flow::flowStatusName(rep.status);
            j["message"] = rep.message;
            j["orders_reduced"] = orders;
            j["newton_iterations"] = rep.iterations;
            j["total_iterations"] = first + rep.iterations;
            j["linear_iterations"] = rep.linearIterations;
            j["lumping"] = rep.lumping;
            j["initial_residual"] = rep.initialResidual;
            j["final_residual"] = rep.finalResidual;
            j["CL"] = f.CL;
            j["CD"] = f.CD;
            j["CM"] = f.CM;
            j["CY"] = f.CY;
            j["force"] = f.force;
            j["moment"] = f.moment;
            j["max_entropy"] = maxEntropy;
            j["max_mach"] = maxMach;
            j["mach"] = ro.freeStream.mach;
            j["alpha"] = ro.freeStream.alphaDeg;
            j["blocks"] = fm.blocks.size();
            j["grid_nodes"] = fm.nodeCount;
            j["largest_spacing_jump"] = jump.ratio;
            j["deformed"] = cg.moved;
            j["restarted_from"] = restartFrom;
            j["seconds_solve"] = rep.seconds;
            j["seconds"] = since(t0);
            j["peak_memory_mb"] = peak;
            j["outputs"] = outputs;
            std::printf("%s\n", j.dump(2).c_str());
        }
        std::snprintf(buf, sizeof buf, "done in %.1f s (solver %.1f s), peak memory %.0f MB", since(t0), rep.seconds, peak);
        say(buf);
        if (rep.status == flow::FlowStatus::Cancelled) {
            say("continue with: aeroform-cli flow " + casePath + " --restart " + restartTo);
        }
        return rep.converged() ? kOk : kFailed;
    });
}

int cmdFlow(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::printf("%s", kFlowHelp);
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json"}, {"--restart"}, pos, val, err)) return usageError("flow", err, kFlowHelp);
    if (pos.size() != 1) return usageError("flow", "expected exactly one CASE file", kFlowHelp);
    return runFlow(pos[0], val.count("--restart") ? val["--restart"] : "", val.count("--json") > 0);
}

}  // namespace aero::app
