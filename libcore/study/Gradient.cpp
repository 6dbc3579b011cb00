#include "study/Gradient.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "adjoint/GridSensitivity.h"
#include "common/Error.h"
#include "common/Format.h"
#include "ffd/FfdModel.h"
#include "mesh/MultiBlock.h"
#include "mesh/Quality.h"

namespace aero::study {

namespace {

double since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

constexpr const char* kRatio = "CL/CD";
constexpr const char* kPressure = "pressure";

}  // namespace

void checkGradientFunctional(const std::string& name) {
    if (name == kRatio || name == kPressure || name == kWallMach) return;
    try {
        (void)adjoint::functionalByName(name);
    } catch (const CaseError&) {
        throw CaseError("unknown functional '" + name + "' (expected CL, CD, CM, CY, CL/CD, pressure or wall_mach)");
    }
}

const FunctionalGradient* GradientResult::find(const std::string& name) const {
    for (const FunctionalGradient& f : functionals) {
        if (f.name == name) return &f;
    }
    return nullptr;
}

GradientResult computeGradient(CaseEvaluator& ev, const Evaluation& e, const GradientOptions& o, const Log& log) {
    GradientResult res;
    if (!e.ok() || !e.mesh || !e.flow) {
        res.message = "the design was not evaluated through the flow stage" + (e.message.empty() ? "" : ": " + e.message);
        return res;
    }
    // The base functionals the requested ones need.
    std::vector<adjoint::Functional> bases;
    adjoint::Functional pressure;
    auto byName = [&](const std::string& name) {
        if (name == kWallMach) {
            if (!(o.wallMachRho > 0)) throw CaseError("the functional 'wall_mach' needs its rho (GradientOptions::wallMachRho)");
            return adjoint::Functional::wallMachSum(o.wallMachRho, o.wallMachReference);
        }
        if (name != kPressure) return adjoint::functionalByName(name);
        if (!pressure.targetPressure) {
            if (o.targetPressure.empty()) throw CaseError("the functional 'pressure' needs a target pressure");
            pressure = adjoint::Functional::pressureMismatch(o.targetPressure);
        }
        return pressure;
    };
    auto need = [&](const adjoint::Functional& f) {
        for (adjoint::Functional b : bases) {
            if (b == f) return;
        }
        bases.push_back(f);
    };
    const FlowResult& f = *e.flow;
    // CL/CD through its linearization at this state, (1/CD) CL - (CL/CD^2) CD: one adjoint
    // instead of one for CL and one for CD.
    const double CL = f.forces.CL, CD = f.forces.CD;
    const adjoint::Functional ratio = adjoint::Functional::forceCombination(1.0 / CD, -CL / (CD * CD));
    // With CL and CD requested too, CL/CD's gradient is their quotient rule's combination (the
    // adjoint systems are linear in the right-hand side, so its own adjoint would be this same
    // combination of theirs): one adjoint fewer.
    const bool ratioFromParts =
        std::find(o.functionals.begin(), o.functionals.end(), "CL") != o.functionals.end() &&
        std::find(o.functionals.begin(), o.functionals.end(), "CD") != o.functionals.end();
    for (const std::string& name : o.functionals) {
        checkGradientFunctional(name);
        if (name == kRatio && ratioFromParts) continue;
        need(name == kRatio ? ratio : byName(name));
    }
    const MeshResult& m = *e.mesh;
    const io::CaseFile& c = ev.caseFile();
    const flow::FreeStream& fs = f.residualOptions.freeStream;

    // The linearization (the Jacobian and its ILU, most of the gradient's memory) lives only
    // while the adjoints are solved: the grid sensitivities after them need memory of their own.
    std::vector<adjoint::AdjointSolution> adj;
    auto nameOf = [&](const adjoint::Functional& b) -> std::string {
        return b == ratio ? kRatio : adjoint::functionalName(b);
    };
    auto t = std::chrono::steady_clock::now();
    {
        const adjoint::FlowLinearization lin(f.mesh, f.metrics, f.q, f.residualOptions, o.adjoint);
        res.secondsLinearization = since(t);
        if (log) log(format("assembled the exact flow Jacobian and its preconditioner: %.1f s", res.secondsLinearization));

        t = std::chrono::steady_clock::now();
        for (adjoint::Functional b : bases) {
            adj.push_back(adjoint::solveAdjoint(lin, b, f.mesh, f.metrics, f.x, f.q, fs, c.flow.reference));
            res.adjoints.push_back(adj.back().report);
            if (log) {
                log("flow adjoint of " + nameOf(b) +
                    format(": %d GMRES iterations, relative residual %.2e, %.1f s", adj.back().report.iterations,
                        adj.back().report.relativeResidual, adj.back().report.seconds));
            }
            if (!adj.back().report.converged()) {
                res.message = "the flow adjoint of " + nameOf(b) + " did not converge: " + adj.back().report.message;
                return res;
            }
        }
        res.secondsAdjoint = since(t);
    }

    t = std::chrono::steady_clock::now();
    std::vector<std::vector<double>> psis;
    for (const auto& a : adj) psis.push_back(a.psi);
    const std::vector<std::vector<double>> gx =
        adjoint::coordinateGradients(bases, psis, f.mesh, f.x, f.metrics, f.q, f.residualOptions, c.flow.reference);
    res.secondsGrid = since(t);
    if (log) log(format("grid sensitivities (psi^T dR/dx + dJ/dx): %.1f s", res.secondsGrid));

    // The forward move's increments (a shape whose wall is the baseline's was not moved: the
    // move's linearization is then m solves on the baseline grid with zero displacement).
    t = std::chrono::steady_clock::now();
    mesh::MoveHistory still;
    const mesh::MoveHistory* history = &m.history;
    if (!m.moved) {
        const int increments = c.mesh.elasticity.increments;
        still.before.assign(increments, m.control.control);
        still.displacement.assign(increments, std::vector<double>(m.control.control.size(), 0.0));
        history = &still;
    }
    res.historyBytes = history->bytes();
    // The grid-validity and wall-bend functions go through the same transpose and mesh adjoint, last.
    std::vector<std::vector<double>> gxAll = gx;
    // A per-block gradient (each grid's xyz layout) in the global node order.
    auto appendGlobal = [&](const std::vector<std::vector<double>>& perBlock) {
        std::vector<double> g(f.x.size(), 0.0);
        for (std::size_t b = 0; b < perBlock.size(); ++b) {
            std::copy(perBlock[b].begin(), perBlock[b].end(), g.begin() + 3 * f.mesh.blocks[b].offset);
        }
        gxAll.push_back(std::move(g));
    };
    double cornerRatio = 0;
    if (o.cornerRatioRho > 0) {
        std::vector<std::vector<double>> perBlock;
        cornerRatio = mesh::cornerRatioSmoothMin(m.grids, ev.baselineGrids(), o.cornerRatioRho, &perBlock);
        if (perBlock.empty()) {
            res.message = "the grid has a folded cell: no gradient of its corner ratio";
            return res;
        }
        appendGlobal(perBlock);
    }
    double wallBend = 0;
    if (o.wallBendRho > 0) {
        std::vector<std::vector<double>> perBlock;
        wallBend = mesh::wallBendSmoothMax(m.grids, mesh::wallFaces(m.control), o.wallBendRho, &perBlock);
        appendGlobal(perBlock);
    }
    std::vector<std::vector<double>> gb(gxAll.size(), std::vector<double>(m.control.control.size(), 0.0));
    for (std::size_t p = 0; p < gxAll.size(); ++p) {
        for (std::size_t b = 0; b < f.mesh.blocks.size(); ++b) {
            mesh::regenerateTranspose(m.control, static_cast<int>(b), &gxAll[p][3 * f.mesh.blocks[b].offset], gb[p]);
        }
    }
    const std::vector<std::vector<double>> gA =
        mesh::moveControlGridAdjoints(m.control, *history, c.mesh.elasticity, gb, &res.meshAdjoint, &ev.moveWorkspace());
    if (!res.meshAdjoint.converged) {
        res.message = "the mesh adjoint did not converge: " + res.meshAdjoint.message;
        return res;
    }
    res.secondsMesh = since(t);
    if (log) {
        log(format("mesh adjoint: %.0f increments in reverse, %.1f s (%.1f MB of stored increments",
                   static_cast<double>(history->before.size()), res.secondsMesh, res.historyBytes / 1e6) +
            (res.meshAdjoint.reusedIncrements > 0
                 ? format("; the move's %d stiffness matrices and factors reused, %.1f MB)", res.meshAdjoint.reusedIncrements,
                          res.meshAdjoint.keptBytes / 1e6)
                 : std::string(")")));
    }

    t = std::chrono::steady_clock::now();
    Eigen::SparseMatrix<double> dAdv;
    if (ev.model()) dAdv = ev.model()->dUniqueDv();
    // dA/dB of each lattice: A_p = sum_a W(p, a) B_a for the points p it embeds (the same W for
    // every coordinate), so dJ/dB_a = sum_p W(p, a) g_A(p).
    std::vector<Eigen::SparseMatrix<double, Eigen::RowMajor>> dAdB;
    if (o.geometrySensitivities && ev.model()) {
        const ffd::FfdModel& model = *ev.model();
        for (std::size_t l = 0; l < model.lattices().size(); ++l)
            dAdB.push_back(ffd::sensitivity(model.lattices()[l].lattice, model.embeddings()[l]));
    }
    auto latticeGradients = [&](const std::vector<double>& g) {
        std::vector<std::vector<double>> out(dAdB.size());
        for (std::size_t l = 0; l < dAdB.size(); ++l) {
            const std::vector<int>& points = ev.model()->embeddings()[l].points;
            out[l].assign(3 * static_cast<std::size_t>(dAdB[l].cols()), 0.0);
            for (Eigen::Index p = 0; p < dAdB[l].outerSize(); ++p) {
                const double* gp = &g[3 * static_cast<std::size_t>(points[static_cast<std::size_t>(p)])];
                for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(dAdB[l], p); it; ++it) {
                    for (int d = 0; d < 3; ++d) out[l][3 * static_cast<std::size_t>(it.col()) + d] += it.value() * gp[d];
                }
            }
        }
        return out;
    };
    std::vector<FunctionalGradient> base(bases.size());
    for (std::size_t p = 0; p < bases.size(); ++p) {
        base[p].name = nameOf(bases[p]);
        base[p].value = bases[p] == ratio     ? CL / CD
                        : bases[p].isForce() ? adjoint::functionalValue(bases[p], f.forces)
                                             : adjoint::functionalValue(bases[p], f.mesh, f.metrics, f.x, f.q, fs, c.flow.reference);
        if (ev.model()) {
            const Eigen::Map<const Eigen::VectorXd> g(gA[p].data(), static_cast<Eigen::Index>(gA[p].size()));
            const Eigen::VectorXd dv = dAdv.transpose() * g;
            base[p].dv.assign(dv.data(), dv.data() + dv.size());
        }
        base[p].dalpha = adjoint::alphaDerivative(adj[p], f.mesh, f.metrics, f.q, f.residualOptions, f.forces);
        if (o.geometrySensitivities) {
            base[p].dUnique = gA[p];
            base[p].dLattice = latticeGradients(gA[p]);
        }
    }
    auto baseOf = [&](adjoint::Functional b) -> const FunctionalGradient& {
        for (std::size_t p = 0; p < bases.size(); ++p) {
            if (bases[p] == b) return base[p];
        }
        throw Error("gradient: missing base functional");
    };
    // (1/CD) dCL - (CL/CD^2) dCD, for every part of the gradient.
    auto quotient = [&](const FunctionalGradient& L, const FunctionalGradient& D) {
        const double a = 1.0 / D.value, b = -L.value / (D.value * D.value);
        auto mix = [&](const std::vector<double>& x, const std::vector<double>& y) {
            std::vector<double> out(x.size());
            for (std::size_t i = 0; i < x.size(); ++i) out[i] = a * x[i] + b * y[i];
            return out;
        };
        FunctionalGradient r;
        r.name = kRatio;
        r.value = L.value / D.value;
        r.dv = mix(L.dv, D.dv);
        r.dalpha = a * L.dalpha + b * D.dalpha;
        r.dUnique = mix(L.dUnique, D.dUnique);
        for (std::size_t l = 0; l < L.dLattice.size(); ++l) r.dLattice.push_back(mix(L.dLattice[l], D.dLattice[l]));
        return r;
    };
    for (const std::string& name : o.functionals) {
        if (name == kRatio && ratioFromParts) {
            res.functionals.push_back(quotient(baseOf(adjoint::Functional::CL), baseOf(adjoint::Functional::CD)));
        } else if (name == kWallMach) {
            // The smooth maximum instead of the sum: its chain rule on every part of the gradient.
            const adjoint::Functional sum = byName(name);
            FunctionalGradient r = baseOf(sum);
            double dS = 0;
            r.value = adjoint::wallMachSmoothMax(sum, r.value, &dS);
            for (double& x : r.dv) x *= dS;
            r.dalpha *= dS;
            for (double& x : r.dUnique) x *= dS;
            for (auto& l : r.dLattice) {
                for (double& x : l) x *= dS;
            }
            res.functionals.push_back(std::move(r));
        } else {
            res.functionals.push_back(baseOf(name == kRatio ? ratio : byName(name)));
        }
    }
    // The geometric functions after the flow's: gA[bases.size()], then on.
    std::size_t next = bases.size();
    auto geometric = [&](const char* name, double value) {
        const std::vector<double>& ga = gA[next++];
        FunctionalGradient r;
        r.name = name;
        r.value = value;
        if (ev.model()) {
            const Eigen::Map<const Eigen::VectorXd> g(ga.data(), static_cast<Eigen::Index>(ga.size()));
            const Eigen::VectorXd dv = dAdv.transpose() * g;
            r.dv.assign(dv.data(), dv.data() + dv.size());
        }
        if (o.geometrySensitivities) {
            r.dUnique = ga;
            r.dLattice = latticeGradients(ga);
        }
        res.functionals.push_back(r);
    };
    if (o.cornerRatioRho > 0) geometric(kCornerRatio, cornerRatio);
    if (o.wallBendRho > 0) geometric(kWallBend, wallBend);
    res.secondsChain = since(t);
    res.ok = true;
    return res;
}

}  // namespace aero::study
