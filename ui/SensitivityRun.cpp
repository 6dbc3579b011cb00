#include "SensitivityRun.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "adjoint/Functionals.h"
#include "common/Error.h"
#include "common/Format.h"
#include "nurbs/Surface.h"
#include "study/Gradient.h"

namespace aero::ui {

Objective caseObjective(const io::CaseFile& c) {
    Objective o;
    if (c.optimization.present) {
        o.name = c.optimization.objective;
        o.maximize = c.optimization.maximize;
    }
    return o;
}

std::optional<double> objectiveValue(const std::string& name, const flow::ForceCoefficients& forces) {
    if (name == "CL/CD") return forces.CD != 0 ? std::optional<double>(forces.CL / forces.CD) : std::nullopt;
    if (name == "pressure") return std::nullopt;
    try {
        const adjoint::Functional f = adjoint::functionalByName(name);
        if (!f.isForce()) return std::nullopt;
        return adjoint::functionalValue(f, forces);
    } catch (const Error&) {
        return std::nullopt;
    }
}

SensitivityResult runSensitivities(const SensitivityInput& in, const SensitivityStatusFn& status,
                                   const std::atomic<bool>* cancel) {
    using Clock = std::chrono::steady_clock;
    SensitivityResult r;
    r.objective = in.objective;
    auto say = [&](double fraction, const std::string& line) {
        if (status) status(fraction, line);
    };
    if (in.objective.name == "pressure") {
        r.message = "the inverse design's pressure objective needs its target pressure; the sensitivities "
                    "here are of CL, CD, CM, CY or CL/CD";
        return r;
    }
    io::CaseFile c = in.caseFile;
    c.flow.present = true;
    study::CaseEvaluator ev(c, in.baseline);  // throws for a bad case
    ev.moveWorkspace().setKeepIncrements(true);  // the mesh adjoint reuses the move's K and factors
    if (!ev.model()) {
        r.message = "the project has no lattice: there is nothing to differentiate with respect to";
        return r;
    }

    study::EvaluationRequest request;
    request.worstCells = 0;
    if (!in.warmState.empty()) {
        request.start = study::FlowStart{};
        request.start->state = in.warmState;
    }
    const double tolerance = c.flow.newton.relativeTolerance;
    auto t = Clock::now();
    const study::Evaluation e = ev.evaluate(
        ev.caseValues(), request,
        [&](const study::Progress& p) {
            if (p.iteration) {
                const flow::FlowIteration& it = *p.iteration;
                if (!it.rejected.empty() || p.coarse) return;
                const double fraction = it.relativeResidual > 0 && tolerance > 0 && tolerance < 1
                                            ? std::clamp(std::log10(it.relativeResidual) / std::log10(tolerance), 0.0, 1.0)
                                            : -1;
                say(0.8 * fraction, format("Sensitivities: flow iteration %d, residual %.2e of the start",
                                           p.iterationOffset + it.iteration, it.relativeResidual));
            } else if (!p.message.empty()) {
                say(-1, "Sensitivities: " + p.message);
            }
        },
        cancel);
    r.secondsFlow = std::chrono::duration<double>(Clock::now() - t).count();
    r.values = e.values;
    r.lattices = e.lattices;
    if (e.flow) {
        r.forces = e.flow->forces;
        r.flowIterations = e.flow->report.iterations;
    }
    if (!e.ok()) {
        r.message = e.status == study::EvaluationStatus::FlowNotConverged
                        ? "the flow did not converge (" + e.message + "): a gradient needs a converged flow"
                        : std::string(study::evaluationStatusName(e.status)) + (e.message.empty() ? "" : ": " + e.message);
        return r;
    }
    if (cancel && cancel->load()) {
        r.message = "cancelled";
        return r;
    }
    say(0.85, "Sensitivities: adjoint of " + in.objective.name + " (flow, grid, mesh movement, lattices)");
    t = Clock::now();
    study::GradientOptions o;
    o.functionals = {in.objective.name};
    o.geometrySensitivities = true;
    const study::GradientResult g =
        study::computeGradient(ev, e, o, [&](const std::string& line) { say(-1, "Sensitivities: " + line); });
    r.secondsGradient = std::chrono::duration<double>(Clock::now() - t).count();
    if (!g.ok) {
        r.message = g.message;
        return r;
    }
    const study::FunctionalGradient& f = g.functionals.front();
    r.J = f.value;
    r.dv = f.dv;
    r.dLattice = f.dLattice;
    r.dUnique = f.dUnique;
    r.ok = true;
    return r;
}

std::optional<double> predictedChange(const SensitivityResult& r, const std::vector<ffd::Lattice>& now) {
    if (!r.ok || now.size() != r.lattices.size() || now.size() != r.dLattice.size()) return std::nullopt;
    double dJ = 0;
    for (std::size_t l = 0; l < now.size(); ++l) {
        const std::vector<double>& b = now[l].points;
        const std::vector<double>& b0 = r.lattices[l].points;
        const std::vector<double>& g = r.dLattice[l];
        if (b.size() != b0.size() || b.size() != g.size()) return std::nullopt;
        for (std::size_t k = 0; k < b.size(); ++k) dJ += g[k] * (b[k] - b0[k]);
    }
    return dJ;
}

// ---- The surface sensitivity --------------------------------------------------------------------

std::vector<double> normalSensitivity(const geometry::Patch& gradientNet, const std::vector<double>& uv,
                                      const std::vector<double>& normals) {
    const std::size_t n = uv.size() / 2;
    std::vector<double> g(3 * n), out(n);
    if (n == 0 || normals.size() != 3 * n) return std::vector<double>(n, 0.0);
    // The surface is linear in its control points (weights fixed): evaluating the net of dJ/dA
    // interpolates them with the patch's basis.
    nurbs::evaluate(gradientNet, uv, g.data());
    for (std::size_t k = 0; k < n; ++k)
        out[k] = g[3 * k] * normals[3 * k] + g[3 * k + 1] * normals[3 * k + 1] + g[3 * k + 2] * normals[3 * k + 2];
    return out;
}

std::vector<double> outwardNormals(const std::vector<double>& points, const std::vector<int>& triangles,
                                   const std::array<double, 3>& centre) {
    std::vector<double> nrm(points.size(), 0.0);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const double* a = &points[3 * static_cast<std::size_t>(triangles[t])];
        const double* b = &points[3 * static_cast<std::size_t>(triangles[t + 1])];
        const double* c = &points[3 * static_cast<std::size_t>(triangles[t + 2])];
        const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k) nrm[3 * static_cast<std::size_t>(triangles[t + static_cast<std::size_t>(v)]) + k] += cross[k];
    }
    double outward = 0;
    for (std::size_t p = 0; p + 2 < nrm.size(); p += 3) {
        const double len = std::sqrt(nrm[p] * nrm[p] + nrm[p + 1] * nrm[p + 1] + nrm[p + 2] * nrm[p + 2]);
        if (len > 0)
            for (int k = 0; k < 3; ++k) nrm[p + k] /= len;
        for (int k = 0; k < 3; ++k) outward += nrm[p + k] * (points[p + k] - centre[static_cast<std::size_t>(k)]);
    }
    if (outward < 0)
        for (double& x : nrm) x = -x;
    return nrm;
}

}  // namespace aero::ui
