// Experiment: is there a steady solution behind a stalled flow, and which linear modes of the
// discretization stop the solver from reaching it? (Not a benchmark; prints a report.)
//   flow_modes CASE.json REFINE [RITZ=60] [NEWTON=8] [CFL=50 STEPS=30 [iterative-only]]
// 1. Solves the case's flow as the pipeline does (from the free stream) and keeps its final
//    state, converged or stalled.
// 2. Shift-invert Arnoldi on the pseudo-time dynamics there: D dq/dtau = -R(q) with D the
//    V/dtau of CFL 1 (flow::timeStepScale), linearized: dq'/dtau = -D^-1 J q'. Its eigenvalues
//    mu nearest 0 come from the Ritz values nu of (J)^-1 D (mu = -1/nu), with J factored once by
//    UMFPACK. Re(mu) > 0 is a mode that grows in pseudo-time (and J + D / CFL is singular at the
//    CFL = 1 / mu of a real one); the report locates each mode's eigenvector.
// 3. Undamped Newton steps q -= J^-1 R(q) with the same direct solver, from that state: quadratic
//    convergence means the steady solution exists and only the solver's path failed.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/UmfPackSupport>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numeric>
#include <string>

#include "adjoint/FlowModes.h"
#include "flow/FlowSolver.h"
#include "flow/Jacobian.h"
#include "flow/Residual.h"
#include "io/CaseFile.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"

using namespace aero;

namespace {

double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, SuiteSparse_long>;  // umfpack_dl: 64-bit workspace

SparseMatrix toEigen(const flow::BlockSparseMatrix& J) {
    std::vector<Eigen::Triplet<double, SuiteSparse_long>> t;
    t.reserve(static_cast<std::size_t>(J.blockCount()) * flow::kBlockSize);
    for (long r = 0; r < J.rows; ++r) {
        for (long b = J.rowStart[r]; b < J.rowStart[r + 1]; ++b) {
            const double* a = J.block(b);
            for (int v = 0; v < flow::kBlock; ++v) {
                for (int w = 0; w < flow::kBlock; ++w) {
                    const double x = a[flow::kBlock * v + w];
                    if (x != 0) {
                        t.emplace_back(flow::kBlock * r + v,
                                       flow::kBlock * J.cols[b] + w, x);
                    }
                }
            }
        }
    }
    const SuiteSparse_long n = flow::kBlock * J.rows;
    SparseMatrix A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    return A;
}

double machAt(const double* q, double gamma) {
    const double u2 = (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) / (q[0] * q[0]);
    const double p = (gamma - 1) * (q[4] - 0.5 * q[0] * u2);
    return std::sqrt(u2 / (gamma * p / q[0]));
}

std::string where(const flow::FlowMesh& fm, const std::vector<double>& x, long g) {
    for (const flow::FlowBlock& blk : fm.blocks) {
        if (g < blk.offset || g >= blk.offset + blk.nodeCount()) continue;
        const auto idx = flow::nodeIndex(blk.dims, g - blk.offset);
        std::string faces;
        for (int f = 0; f < 6; ++f) {
            if (!flow::onFace(blk.dims, g - blk.offset, f)) continue;
            faces += std::string(faces.empty() ? "" : "/") + mesh::boundaryName(blk.faces[f].kind);
        }
        char s[256];
        std::snprintf(s, sizeof s, "block %-9s (%2d,%2d,%2d) x (%6.3f, %6.3f, %6.3f) %s", blk.name.c_str(), idx[0],
                      idx[1], idx[2], x[3 * g], x[3 * g + 1], x[3 * g + 2], faces.empty() ? "interior" : faces.c_str());
        return s;
    }
    return "?";
}

double norm(const std::vector<double>& v) { return std::sqrt(std::inner_product(v.begin(), v.end(), v.begin(), 0.0)); }

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: flow_modes CASE.json REFINE [RITZ=60] [NEWTON=8] [CFL STEPS [iterative-only]]\n");
        return 2;
    }
    io::CaseFile c = io::readCase(argv[1]);
    c.mesh.extrusion.refine = std::stod(argv[2]);
    const int m = argc > 3 ? std::stoi(argv[3]) : 60;
    const int newtonSteps = argc > 4 ? std::stoi(argv[4]) : 8;
    c.outputFlowVtk.clear();
    c.outputResidualCsv.clear();
    c.outputRestart.clear();
    study::CaseEvaluator ev(c, study::loadGeometry(c.geometry));
    auto t0 = std::chrono::steady_clock::now();
    study::Evaluation e = ev.evaluate(ev.caseValues());
    if (!e.flow || e.flow->q.empty()) {
        std::printf("no flow state: %s\n", e.message.c_str());
        return 1;
    }
    const study::FlowResult& f = *e.flow;
    std::printf("flow: %s; %d iterations, relative residual %.3e, %.1f s\n", e.ok() ? "converged" : e.message.c_str(),
                f.report.iterations, f.report.finalResidual / f.report.initialResidual, since(t0));
    const flow::FlowMesh& fm = f.mesh;
    const long n = flow::kVars * fm.nodeCount;
    const flow::ResidualOptions& o = f.residualOptions;
    std::vector<double> q = f.q;
    std::vector<double> r(n);

    auto factorAt = [&](const std::vector<double>& state, Eigen::UmfPackLU<SparseMatrix>& lu, SparseMatrix& A) {
        const auto t1 = std::chrono::steady_clock::now();
        flow::BlockSparseMatrix J = flow::jacobianPattern(fm, flow::stencilRadius(o));
        flow::assembleJacobian(fm, f.metrics, state.data(), o, J);
        A = toEigen(J);
        lu.compute(A);
        std::printf("  exact Jacobian %ld x %ld, %ld nonzeros, UMFPACK %s, %.1f s\n", static_cast<long>(A.rows()),
                    static_cast<long>(A.cols()), static_cast<long>(A.nonZeros()),
                    lu.info() == Eigen::Success ? "factored" : "FAILED", since(t1));
        return lu.info() == Eigen::Success;
    };

    // 2a. The pipeline's iterative estimate (adjoint::pseudoTimeModes), to compare.
    {
        adjoint::ModeOptions mo;
        if (argc > 5) mo.cfl = std::stod(argv[5]);
        if (argc > 6) mo.steps = std::stoi(argv[6]);
        const adjoint::ModeReport mr = adjoint::pseudoTimeModes(fm, f.metrics, q, o, mo);
        std::printf("iterative (CFL %g, %d Arnoldi steps, %d GMRES, %.1f s%s%s): %zu converged modes\n", mo.cfl, mr.steps,
                    mr.linearIterations, mr.seconds, mr.failure.empty() ? "" : ", ", mr.failure.c_str(),
                    mr.modes.size());
        for (const adjoint::FlowMode& md : mr.modes) {
            std::printf("  mu %+.4e %+.4ei (residual %.1e, defect %.1e), node share %.1f%%, 20 nodes %.0f%%: %s\n", md.rate.real(),
                        md.rate.imag(), md.residual, md.defect, 100 * md.share, 100 * md.regionShare,
                        where(fm, f.x, md.node).c_str());
        }
        std::fflush(stdout);
        if (argc > 7) return 0;
    }

    // 2b. Modes of the pseudo-time dynamics at the final state, by a direct factorization.
    {
        Eigen::UmfPackLU<SparseMatrix> lu;
        SparseMatrix A;
        if (!factorAt(q, lu, A)) return 1;
        const std::vector<double> scale = flow::timeStepScale(fm, f.metrics, q.data(), o.freeStream.gamma);
        Eigen::VectorXd d(n);
        for (long i = 0; i < fm.nodeCount; ++i) {
            for (int v = 0; v < flow::kVars; ++v) d[flow::kVars * i + v] = scale[i];
        }
        const auto t1 = std::chrono::steady_clock::now();
        const adjoint::CheckedMap shiftInvert = [&](const double* in, double* out) {
            Eigen::VectorXd rhs(n);
            for (long i = 0; i < n; ++i) rhs[i] = d[i] * in[i];
            Eigen::Map<Eigen::VectorXd>(out, n) = lu.solve(rhs);
            return true;
        };
        std::vector<double> start(static_cast<std::size_t>(n));
        for (long i = 0; i < n; ++i) start[static_cast<std::size_t>(i)] = 1 + 0.1 * std::sin(0.37 * static_cast<double>(i));
        const adjoint::RitzPairs ritz = adjoint::arnoldi(n, shiftInvert, start, m);
        std::printf("Arnoldi, %d steps, %.1f s: eigenvalues mu of -D^-1 J nearest 0 (Re mu > 0 grows in pseudo-time)\n",
                    ritz.steps, since(t1));
        const std::size_t show = std::min<std::size_t>(ritz.values.size(), 24);
        for (std::size_t k = 0; k < show; ++k) {
            const std::complex<double> nu = ritz.values[k];
            const std::complex<double> mu = -1.0 / nu;
            std::printf("  mu %+.4e %+.4ei  (Ritz residual %.1e)%s\n", mu.real(), mu.imag(), ritz.residuals[k] / std::abs(nu),
                        mu.real() > 0 ? "  GROWS" : "");
            if (k < 6 || mu.real() > 0) {
                // The eigenvector: where it lives (the 5 nodes of largest |v| and the share of the
                // vector's squared norm in the largest 20).
                const std::vector<std::complex<double>> vec = ritz.vector(k);
                const adjoint::ModeLocation at = adjoint::locateMode(vec, fm.nodeCount);
                std::printf("    largest 20 nodes hold %.0f%% of |v|^2; the largest:\n", 100 * at.regionShare);
                for (std::size_t s = 0; s < std::min<std::size_t>(5, at.nodes.size()); ++s) {
                    const long g = at.nodes[s];
                    std::printf("      %5.1f%%  %s, Mach %.2f; |v| rho %.2f, momentum %.2f %.2f %.2f, energy %.2f\n",
                                100 * at.shares[s], where(fm, f.x, g).c_str(), machAt(&q[flow::kVars * g], o.freeStream.gamma),
                                std::abs(vec[5 * g]), std::abs(vec[5 * g + 1]), std::abs(vec[5 * g + 2]),
                                std::abs(vec[5 * g + 3]), std::abs(vec[5 * g + 4]));
                }
            }
        }
    }

    // 3. Undamped Newton with direct solves.
    flow::residual(fm, f.metrics.data(), q.data(), o, r.data());
    const double r0 = f.report.initialResidual;
    std::printf("Newton with direct solves from the final state (relative to the first iteration's residual):\n");
    std::printf("  step 0: relative residual %.3e\n", norm(r) / r0);
    for (int it = 1; it <= newtonSteps; ++it) {
        Eigen::UmfPackLU<SparseMatrix> lu;
        SparseMatrix A;
        if (!factorAt(q, lu, A)) break;
        const Eigen::VectorXd rhs = Eigen::Map<Eigen::VectorXd>(r.data(), n);
        const Eigen::VectorXd dq = lu.solve(rhs);
        for (long i = 0; i < n; ++i) q[i] -= dq[i];
        long bad = -1;
        if (!flow::isPhysical(fm, q.data(), o.freeStream.gamma, &bad)) {
            std::printf("  step %d: non-physical state at %s\n", it, where(fm, f.x, bad).c_str());
            break;
        }
        flow::residual(fm, f.metrics.data(), q.data(), o, r.data());
        std::printf("  step %d: |dq| %.3e, relative residual %.3e\n", it, dq.norm(), norm(r) / r0);
        if (norm(r) / r0 < 1e-13) break;
    }
    return 0;
}
