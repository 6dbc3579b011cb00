#include "FlowRun.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <limits>

#include "common/Error.h"
#include "flow/Euler.h"
#include "flow/Outputs.h"
#include "io/FlowFiles.h"

namespace aero::ui {

// ---- Fields ---------------------------------------------------------------------------------------

const char* flowFieldLabel(FlowField f) {
    switch (f) {
        case FlowField::Entropy:
            return "Entropy s \u2212 s\u221e";
        case FlowField::PressureCoefficient:
            return "Pressure coefficient Cp";
        case FlowField::Mach:
            return "Mach number";
        case FlowField::Pressure:
            return "Pressure p";
    }
    return "";
}

const char* flowFieldKey(FlowField f) {
    switch (f) {
        case FlowField::Entropy:
            return "entropy";
        case FlowField::PressureCoefficient:
            return "cp";
        case FlowField::Mach:
            return "mach";
        case FlowField::Pressure:
            return "pressure";
    }
    return "";
}

const char* flowFieldUnit(FlowField f) {
    return f == FlowField::Pressure ? "\u03c1\u221e a\u221e\u00b2" : "";
}

std::array<double, 3> fieldColour(double t) {
    // Blue, cyan, green, yellow, red, slightly softened so that contour lines stay readable.
    static constexpr double kStops[5][3] = {
        {0.16, 0.26, 0.75}, {0.15, 0.68, 0.86}, {0.36, 0.78, 0.34}, {0.97, 0.85, 0.23}, {0.84, 0.16, 0.14}};
    constexpr int kSegments = 4;
    t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
    const int seg = std::min(kSegments - 1, static_cast<int>(t * kSegments));
    const double s = t * kSegments - seg;
    std::array<double, 3> c{};
    for (int k = 0; k < 3; ++k)
        c[static_cast<std::size_t>(k)] = (1 - s) * kStops[seg][k] + s * kStops[seg + 1][k];
    return c;
}

std::array<std::vector<double>, kFlowFields> flowFields(const study::FlowResult& r) {
    const flow::FreeStream& fs = r.residualOptions.freeStream;
    std::array<std::vector<double>, kFlowFields> f;
    f[static_cast<std::size_t>(FlowField::Entropy)] = flow::entropy(r.mesh, r.q, fs);
    f[static_cast<std::size_t>(FlowField::PressureCoefficient)] = flow::pressureCoefficient(r.mesh, r.q, fs);
    f[static_cast<std::size_t>(FlowField::Mach)] = flow::machNumber(r.mesh, r.q, fs.gamma);
    std::vector<double>& p = f[static_cast<std::size_t>(FlowField::Pressure)];
    p.resize(static_cast<std::size_t>(r.mesh.nodeCount));
    for (long n = 0; n < r.mesh.nodeCount; ++n)
        p[static_cast<std::size_t>(n)] = flow::pressure(&r.q[flow::kVars * static_cast<std::size_t>(n)], fs.gamma);
    return f;
}

// ---- The work -------------------------------------------------------------------------------------

FlowRunResult runFlowSolve(const FlowRunInput& in, const FlowRunProgressFn& progress, const std::atomic<bool>* cancel) {
    const auto t0 = std::chrono::steady_clock::now();
    FlowRunResult r;
    r.wall = in.wall;
    io::CaseFile c = in.caseFile;
    c.flow.present = true;  // like `aeroform-cli flow`: a case without a flow section gets the defaults
    study::CaseEvaluator ev(c, in.baseline);  // throws for a bad case, as the CLI reports it
    if (!in.warmStateFrom.empty()) ev.setWarmStart(io::readWarmState(in.warmStateFrom));

    study::EvaluationRequest request;
    request.worstCells = 0;
    if (!in.restartFrom.empty()) {
        request.start = study::FlowStart{};
        request.start->restartFile = in.restartFrom;
    }
    const study::Evaluation e = ev.evaluate(
        ev.caseValues(), request,
        [&](const study::Progress& p) {
            if (!progress) return;
            FlowRunProgress out;
            out.stage = p.stage;
            out.message = p.message;
            out.fraction = p.fraction;
            out.coarse = p.coarse;
            out.iterationOffset = p.iterationOffset;
            if (p.iteration) {
                out.hasIteration = true;
                out.iteration = *p.iteration;
            }
            progress(out);
        },
        cancel);
    r.status = e.status;
    r.message = e.message;
    if (e.flow && !e.flow->q.empty()) {
        r.fields = flowFields(*e.flow);
        for (int f = 0; f < kFlowFields; ++f) {
            double lo = std::numeric_limits<double>::infinity(), hi = -lo;
            for (double v : r.fields[static_cast<std::size_t>(f)])
                if (std::isfinite(v)) {
                    lo = std::min(lo, v);
                    hi = std::max(hi, v);
                }
            if (!(lo <= hi)) lo = hi = 0;
            r.range[static_cast<std::size_t>(f)] = {lo, hi};
        }
        // A run that stopped early keeps its state where a restart finds it (the CLI's rule); a
        // converged one leaves no stale state to "continue" behind.
        const flow::FlowReport& rep = e.flow->report;
        if (rep.converged() && !in.restartAlways && !in.restartTo.empty()) std::remove(in.restartTo.c_str());
        if ((!rep.converged() || in.restartAlways) && !rep.history.empty() && !in.restartTo.empty()) {
            io::RestartInfo info;
            info.freeStream = e.flow->residualOptions.freeStream;
            info.iterations = (e.flow->restartContinued ? e.flow->previousIterations : 0) + rep.iterations;
            info.residual = rep.finalResidual;
            info.initialResidual = rep.initialResidual;
            info.cflBase = rep.cflBase;
            info.lumping = rep.lumping;
            try {
                io::writeRestart(in.restartTo, e.flow->mesh, e.flow->q, info);
                r.restartWritten = in.restartTo;
            } catch (const Error& err) {
                r.restartError = err.what();
            }
        }
        r.flow = e.flow;
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace aero::ui
