#include "adjoint/FlowModes.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>

#include "adjoint/FlowAdjoint.h"
#include "flow/BlockIlu.h"
#include "flow/FlowSolver.h"
#include "flow/Jacobian.h"

namespace aero::adjoint {

namespace {

double dot(const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
    return s;
}

}  // namespace

RitzPairs arnoldi(long n, const CheckedMap& op, const std::vector<double>& start, int steps) {
    RitzPairs out;
    std::vector<std::vector<double>> V;
    V.push_back(start);
    const double s0 = std::sqrt(dot(start, start));
    if (!(s0 > 0)) return out;
    for (double& x : V[0]) x /= s0;
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(steps + 1, steps);
    int m = 0;
    bool invariant = false;
    for (int j = 0; j < steps; ++j) {
        std::vector<double> w(static_cast<std::size_t>(n));
        if (!op(V[static_cast<std::size_t>(j)].data(), w.data())) break;
        // Classical Gram-Schmidt, twice (one pass loses orthogonality once the dominant modes
        // have converged and w is nearly in the span).
        for (int pass = 0; pass < 2; ++pass) {
            for (int i = 0; i <= j; ++i) {
                const double h = dot(V[static_cast<std::size_t>(i)], w);
                H(i, j) += h;
                const std::vector<double>& vi = V[static_cast<std::size_t>(i)];
                for (long k = 0; k < n; ++k) w[static_cast<std::size_t>(k)] -= h * vi[static_cast<std::size_t>(k)];
            }
        }
        const double beta = std::sqrt(dot(w, w));
        H(j + 1, j) = beta;
        m = j + 1;
        if (beta <= 1e-14 * H.col(j).head(j + 1).norm()) {
            invariant = true;
            break;
        }
        for (double& x : w) x /= beta;
        V.push_back(std::move(w));
    }
    out.steps = m;
    if (m == 0) return out;
    Eigen::EigenSolver<Eigen::MatrixXd> es(H.topLeftCorner(m, m));
    if (es.info() != Eigen::Success) return out;
    const Eigen::VectorXcd values = es.eigenvalues();
    const Eigen::MatrixXcd Y = es.eigenvectors();
    std::vector<int> order(static_cast<std::size_t>(m));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return std::abs(values[a]) > std::abs(values[b]); });
    const double beta = invariant ? 0.0 : H(m, m - 1);
    for (int idx : order) {
        out.values.push_back(values[idx]);
        out.residuals.push_back(std::abs(beta * Y(m - 1, idx)));
        std::vector<std::complex<double>> y(static_cast<std::size_t>(m));
        for (int i = 0; i < m; ++i) y[static_cast<std::size_t>(i)] = Y(i, idx);
        out.coefficients.push_back(std::move(y));
    }
    V.resize(static_cast<std::size_t>(m));
    out.basis = std::move(V);
    return out;
}

std::vector<std::complex<double>> RitzPairs::vector(std::size_t k) const {
    const long n = basis.empty() ? 0 : static_cast<long>(basis[0].size());
    std::vector<std::complex<double>> v(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < basis.size(); ++i) {
        const std::complex<double> y = coefficients[k][i];
        for (long j = 0; j < n; ++j) v[static_cast<std::size_t>(j)] += y * basis[i][static_cast<std::size_t>(j)];
    }
    return v;
}

ModeLocation locateMode(const std::vector<std::complex<double>>& v, long nodeCount, int count) {
    std::vector<double> nodeNorm(static_cast<std::size_t>(nodeCount));
    double total = 0;
    for (long i = 0; i < nodeCount; ++i) {
        double s = 0;
        for (int k = 0; k < flow::kVars; ++k) s += std::norm(v[static_cast<std::size_t>(flow::kVars * i + k)]);
        nodeNorm[static_cast<std::size_t>(i)] = s;
        total += s;
    }
    std::vector<long> nodes(static_cast<std::size_t>(nodeCount));
    std::iota(nodes.begin(), nodes.end(), 0L);
    const long top = std::min<long>(count, nodeCount);
    std::partial_sort(nodes.begin(), nodes.begin() + top, nodes.end(), [&](long a, long b) {
        return nodeNorm[static_cast<std::size_t>(a)] > nodeNorm[static_cast<std::size_t>(b)];
    });
    nodes.resize(static_cast<std::size_t>(top));
    ModeLocation at;
    for (long g : nodes) {
        const double share = total > 0 ? nodeNorm[static_cast<std::size_t>(g)] / total : 0.0;
        at.shares.push_back(share);
        at.regionShare += share;
    }
    at.nodes = std::move(nodes);
    return at;
}

ModeReport pseudoTimeModes(const flow::FlowMesh& fm, const std::vector<double>& metrics, const std::vector<double>& q,
                           const flow::ResidualOptions& o, const ModeOptions& opt, double converged) {
    const auto t0 = std::chrono::steady_clock::now();
    ModeReport rep;
    const long n = flow::kVars * fm.nodeCount;
    flow::BlockSparseMatrix J = flow::jacobianPattern(fm, flow::stencilRadius(o));
    flow::assembleJacobian(fm, metrics, q.data(), o, J);
    flow::BlockIlu ilu;
    factorPseudoTimePreconditioner(fm, metrics, q, o, opt.cfl, 1, 2, false, ilu);
    const std::vector<double> scale = flow::timeStepScale(fm, metrics, q.data(), o.freeStream.gamma);
    std::vector<double> dc(static_cast<std::size_t>(n));  // D / c per unknown
    for (long i = 0; i < fm.nodeCount; ++i) {
        for (int v = 0; v < flow::kVars; ++v) dc[static_cast<std::size_t>(flow::kVars * i + v)] = scale[i] / opt.cfl;
    }
    const flow::LinearMap A = [&](const double* in, double* out) {
        J.mult(in, out);
        for (long i = 0; i < n; ++i) out[i] += dc[static_cast<std::size_t>(i)] * in[i];
    };
    const flow::LinearMap M = [&](const double* in, double* out) { ilu.solve(in, out); };
    flow::GmresWorkspace krylov;
    std::vector<double> rhs(static_cast<std::size_t>(n));
    const CheckedMap step = [&](const double* in, double* out) {
        if (opt.cancel && opt.cancel->load()) {
            rep.failure = "cancelled";
            return false;
        }
        for (long i = 0; i < n; ++i) rhs[static_cast<std::size_t>(i)] = dc[static_cast<std::size_t>(i)] * in[i];
        std::fill(out, out + n, 0.0);
        const flow::GmresReport g = flow::gmres(
            n, A, M, rhs.data(), out, {opt.gmresRestart, opt.maxIterations, opt.tolerance, 0.0, opt.gmresDeflation},
            &krylov);
        rep.linearIterations += g.iterations;
        if (g.relativeResidual > 10 * opt.tolerance) {
            rep.failure = "GMRES reached only " + std::to_string(g.relativeResidual) + " in " +
                          std::to_string(g.iterations) + " iterations at CFL " + std::to_string(opt.cfl);
            return false;
        }
        return true;
    };
    std::mt19937_64 rng(20261204);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::vector<double> start(static_cast<std::size_t>(n));
    for (double& x : start) x = uniform(rng);
    const RitzPairs ritz = arnoldi(n, step, start, opt.steps);
    rep.steps = ritz.steps;
    std::vector<double> re(static_cast<std::size_t>(n)), im(static_cast<std::size_t>(n));
    std::vector<double> jre(static_cast<std::size_t>(n)), jim(static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < ritz.values.size(); ++k) {
        const std::complex<double> nu = ritz.values[k];
        if (std::abs(nu) == 0 || ritz.residuals[k] > converged * std::abs(nu)) continue;
        FlowMode mode;
        mode.rate = (1.0 - 1.0 / nu) / opt.cfl;
        mode.residual = ritz.residuals[k] / std::abs(nu);
        mode.vector = ritz.vector(k);
        const std::vector<std::complex<double>>& vec = mode.vector;
        for (long i = 0; i < n; ++i) {
            re[static_cast<std::size_t>(i)] = vec[static_cast<std::size_t>(i)].real();
            im[static_cast<std::size_t>(i)] = vec[static_cast<std::size_t>(i)].imag();
        }
        J.mult(re.data(), jre.data());
        J.mult(im.data(), jim.data());
        double defect = 0, jv = 0, dv = 0;
        for (long i = 0; i < n; ++i) {
            const auto u = static_cast<std::size_t>(i);
            const std::complex<double> Jv(jre[u], jim[u]);
            const std::complex<double> muDv = mode.rate * (scale[static_cast<std::size_t>(i / flow::kVars)] * vec[u]);
            defect += std::norm(Jv + muDv);
            jv += std::norm(Jv);
            dv += std::norm(muDv);
        }
        mode.defect = std::sqrt(defect) / (std::sqrt(jv) + std::sqrt(dv));
        const ModeLocation at = locateMode(vec, fm.nodeCount);
        mode.node = at.nodes.front();
        mode.share = at.shares.front();
        mode.regionShare = at.regionShare;
        rep.modes.push_back(std::move(mode));
    }
    std::stable_sort(rep.modes.begin(), rep.modes.end(),
                     [](const FlowMode& a, const FlowMode& b) { return a.rate.real() > b.rate.real(); });
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return rep;
}

}  // namespace aero::adjoint
