// aeroform-cli flow CASE --time-accurate STEPS --time-step DT: the case's flow run forward in
// physical time (dual time stepping, flow/TimeAccurate.h) from the free stream or a restart,
// with a line and a CSV row per time step (t, CL, CD, CM, CY, the steady residual, the inner
// iterations; CL and CD against t also plotted in an SVG beside it), and at the end what the
// flow does: settles into a steady state, oscillates periodically (period, Strouhal number) or
// neither yet. For a shape whose steady solve does not converge: is its flow unsteady?
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "cli/CliSupport.h"
#include "cli/SvgPlot.h"
#include "common/Memory.h"
#include "flow/TimeAccurate.h"
#include "io/FlowFiles.h"
#include "study/CaseEvaluator.h"

namespace aero::app {

namespace {

void say(const std::string& s) { std::fprintf(stderr, "[flow] %s\n", s.c_str()); }

std::string besideCase(const std::string& casePath, const std::string& suffix) {
    const std::filesystem::path p(casePath);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}

}  // namespace

int runTimeAccurate(const std::string& casePath, const std::string& restartArg, const flow::TimeAccurateOptions& ta,
                    const std::string& historyArg, bool json) {
    return guarded("flow", [&] {
        const auto t0 = std::chrono::steady_clock::now();
        const io::CaseFile c = io::readCase(casePath);
        geometry::PatchSet set = loadPatchSet(c.geometry);
        say("geometry " + c.geometry + ": " + std::to_string(set.size()) + " patches");
        io::CaseFile run = c;
        run.flow.present = true;
        study::CaseEvaluator ev(run, std::move(set), say);

        study::EvaluationRequest request;
        request.timeAccurate = ta;
        const std::string restartFrom = !restartArg.empty() ? restartArg : c.flow.restart;
        if (!restartFrom.empty()) {
            request.start = study::FlowStart{};
            request.start->restartFile = restartFrom;
        }
        // The state after the last step is written at the end, and during the run every
        // flow.checkpoint_seconds, to the restart file (a state to start from, not a steady run to
        // continue); the history is written row by row, so a killed run keeps both.
        const std::string restartTo = !c.outputRestart.empty() ? c.outputRestart : besideCase(casePath, ".restart");
        request.checkpointFile = restartTo;
        request.checkpointSeconds = c.flow.checkpointSeconds;
        const std::string historyPath = !historyArg.empty() ? historyArg : besideCase(casePath, ".time.csv");
        std::ofstream history(historyPath);
        if (!history) throw InputError("cannot write the time history '" + historyPath + "'");
        history << "step,time,CL,CD,CM,CY,steady_residual,inner_iterations,inner_reduction,gmres_iterations,seconds,time_step,max_mach\n";
        history << std::setprecision(10);
        auto progress = [&](const study::Progress& p) {
            if (!p.message.empty()) say(p.message);
            if (p.timeStep && p.forces) {
                const flow::TimeStepRecord& r = *p.timeStep;
                history << r.step << ',' << r.time << ',' << p.forces->CL << ',' << p.forces->CD << ',' << p.forces->CM << ','
                        << p.forces->CY << ',' << r.steadyResidual << ',' << r.innerIterations << ',' << r.innerReduction << ','
                        << r.linearIterations << ',' << r.seconds << ',' << r.timeStep << ',' << r.maxMach << '\n'
                        << std::flush;
            }
        };
        char buf[512];
        std::snprintf(buf, sizeof buf, "Mach %g, alpha %g deg, kappa2 %g, kappa4 %g", run.flow.freeStream.mach,
                      run.flow.freeStream.alphaDeg, run.flow.dissipation.kappa2, run.flow.dissipation.kappa4);
        say(buf);
        const study::Evaluation e = [&] {
            const CancelOnSignal cancel;
            return ev.evaluate(ev.caseValues(), request, progress, CancelOnSignal::flag());
        }();
        if (!e.flow) throw GeometryError("'" + casePath + "': " + e.message + " (nothing written)");
        const study::FlowResult& fr = *e.flow;
        const flow::TimeAccurateReport& rep = fr.timeAccurate;
        if (!rep.completed) say(e.message.empty() ? "stopped: " + rep.message : e.message);
        const study::FlowLocation& mm = fr.maxMach;
        std::snprintf(buf, sizeof buf,
                      "at t = %g: CL %.6f  CD %.6f  CM %.6f  CY %.6f; max Mach %.3f at block %d '%s' node (%d, %d, %d), x (%.3g, "
                      "%.3g, %.3g), %s",
                      rep.history.empty() ? 0.0 : rep.history.back().time, fr.forces.CL, fr.forces.CD, fr.forces.CM,
                      fr.forces.CY, mm.value, mm.block, mm.blockName.c_str(), mm.node[0], mm.node[1], mm.node[2], mm.x[0],
                      mm.x[1], mm.x[2], mm.boundary.c_str());
        say(buf);
        say("verdict: " + fr.timeVerdict);

        io::RestartInfo info;
        info.freeStream = fr.residualOptions.freeStream;
        if (e.mesh) study::recordGrid(info, e.mesh->control, fr.mesh, fr.x);
        io::writeRestart(restartTo, fr.mesh, fr.q, info);
        nlohmann::ordered_json outputs;
        outputs["restart"] = restartTo;
        outputs["time_history"] = historyPath;
        // CL and CD against t, beside the history.
        {
            PlotSeries cl{"CL", {}}, cd{"CD", {}};
            for (std::size_t i = 0; i < rep.history.size() && i < fr.timeForces.size(); ++i) {
                cl.points.emplace_back(rep.history[i].time, fr.timeForces[i].CL);
                cd.points.emplace_back(rep.history[i].time, fr.timeForces[i].CD);
            }
            PlotOptions po;
            po.title = "time-accurate run of " + std::filesystem::path(casePath).filename().string() + " (time step " +
                       nlohmann::json(ta.timeStep).dump() + ")";
            po.xLabel = "t (grid lengths / free-stream speed of sound)";
            po.yLabel = "force coefficient";
            const std::string plotPath = (std::filesystem::path(historyPath).replace_extension(".svg")).string();
            writeSvgPlot(plotPath, {cl, cd}, po);
            outputs["time_plot"] = plotPath;
        }
        if (!c.outputFlowVtk.empty()) {
            io::writeFlowVtm(c.outputFlowVtk, fr.mesh, fr.x, fr.q, fr.residualOptions.freeStream);
            outputs["flow_vtk"] = c.outputFlowVtk;
        }
        for (const auto& [key, file] : outputs.items()) say("wrote " + file.get<std::string>());

        std::vector<double> times, lift;
        for (std::size_t i = 0; i < rep.history.size() && i < fr.timeForces.size(); ++i) {
            times.push_back(rep.history[i].time);
            lift.push_back(fr.timeForces[i].CL);
        }
        const flow::SignalSummary s = flow::summarizeSignal(times, lift, 0.5);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double peak = peakMemoryMb();
        if (json) {
            nlohmann::ordered_json j;
            j["case"] = casePath;
            j["time_accurate"] = true;
            j["completed"] = rep.completed;
            j["message"] = rep.completed ? "" : (e.message.empty() ? rep.message : e.message);
            j["breakdown"] = rep.breakdownNode >= 0;
            j["verdict"] = fr.timeVerdict;
            j["time_step"] = ta.timeStep;
            j["steps"] = rep.history.size();
            j["time"] = rep.history.empty() ? 0.0 : rep.history.back().time;
            j["steady_residual"] = rep.history.empty() ? 0.0 : rep.history.back().steadyResidual;
            j["linear_iterations"] = rep.linearIterations;
            j["halved_steps"] = rep.halvedSteps;
            j["CL"] = fr.forces.CL;
            j["CD"] = fr.forces.CD;
            j["CM"] = fr.forces.CM;
            j["CY"] = fr.forces.CY;
            j["max_mach"] = fr.maxMach.value;
            j["max_mach_at"] = {{"block", fr.maxMach.block}, {"node", fr.maxMach.node}, {"x", fr.maxMach.x},
                                {"boundary", fr.maxMach.boundary}};
            j["lift_second_half"] = {{"mean", s.mean},     {"min", s.minimum},       {"max", s.maximum},
                                     {"cycles", s.cycles}, {"period", s.period},     {"period_spread", s.periodSpread},
                                     {"amplitude_ratio", s.amplitudeRatio}, {"drift", s.drift}};
            j["grid_nodes"] = fr.mesh.nodeCount;
            j["restarted_from"] = restartFrom;
            j["seconds_flow"] = e.secondsFlow;
            j["seconds"] = seconds;
            j["peak_memory_mb"] = peak;
            j["outputs"] = outputs;
            std::printf("%s\n", j.dump(2).c_str());
        }
        std::snprintf(buf, sizeof buf, "done in %.1f s (%zu time steps, %d GMRES iterations), peak memory %.0f MB", seconds,
                      rep.history.size(), rep.linearIterations, peak);
        say(buf);
        if (rep.cancelled) say("continue with: aeroform-cli flow " + casePath + " --restart " + restartTo + " --time-accurate ...");
        return rep.completed ? kOk : kFailed;
    });
}

}  // namespace aero::app
