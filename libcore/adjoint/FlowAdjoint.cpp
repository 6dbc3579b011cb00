#include "adjoint/FlowAdjoint.h"

#include <chrono>
#include <cmath>

#include "common/Error.h"
#include "common/Format.h"
#include "flow/FlowSolver.h"
#include "flow/Gmres.h"
#include "flow/Jacobian.h"

namespace aero::adjoint {

namespace {

double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double norm(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x * x;
    return std::sqrt(s);
}

}  // namespace

void factorPseudoTimePreconditioner(const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                    const std::vector<double>& q, const flow::ResidualOptions& o, double cfl,
                                    int fill, int parts, bool transposed, flow::BlockIlu& ilu) {
    flow::ResidualOptions approx = o;
    approx.lumpedDissipation = true;
    approx.freezeCoefficients = true;
    flow::BlockSparseMatrix P = flow::jacobianPattern(fm, 1);
    flow::assembleApproximateJacobian(fm, metrics, q.data(), approx, P);
    std::vector<double> d = flow::timeStepScale(fm, metrics, q.data(), o.freeStream.gamma);
    for (double& x : d) x /= cfl;
    P.addDiagonal(d.data());
    if (transposed && !P.transposeInPlace()) throw Error("adjoint: the preconditioner's pattern is not symmetric");
    if (parts > 1) ilu.setOrdering(flow::partitionOrdering(P, flow::blockGroups(fm, parts), parts));
    if (!ilu.factor(P, fill)) throw Error(std::string(transposed ? "adjoint" : "flow linearization") + " preconditioner: " + ilu.message());
}

FlowLinearization::FlowLinearization(const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                     const std::vector<double>& q, const flow::ResidualOptions& o,
                                     const AdjointOptions& opt)
    : n_(flow::kVars * fm.nodeCount), opt_(opt) {
    const auto t0 = std::chrono::steady_clock::now();
    Jt_ = flow::jacobianPattern(fm, flow::stencilRadius(o));
    flow::assembleJacobian(fm, metrics, q.data(), o, Jt_);
    // The flow Jacobian's pattern is structurally symmetric (stencils and interface pairs are).
    if (!Jt_.transposeInPlace()) throw Error("adjoint: the flow Jacobian's pattern is not symmetric");
    // The forward solver's preconditioner at a large CFL.
    // (ILU of the exact Jacobian instead was tried on the blended wing at refine 0.5: ILU(0) does
    // not converge in 3000 iterations, ILU(1) needs 160 iterations against 162 and is slower.)
    factorPseudoTimePreconditioner(fm, metrics, q, o, opt_.cfl, opt_.iluFill, opt_.iluParts, true, ilu_);
    secondsAssembly_ = since(t0);
}

LinearSolveReport FlowLinearization::solve(bool transpose, const std::vector<double>& rhs, std::vector<double>& x) const {
    const auto t0 = std::chrono::steady_clock::now();
    LinearSolveReport rep;
    if (static_cast<long>(rhs.size()) != n_) throw Error("adjoint: right-hand side of the wrong size");
    if (static_cast<long>(x.size()) != n_) x.assign(n_, 0.0);
    // Stored transposed: the adjoint uses the fast forward products and solves, the tangent
    // (tests' duality checks) the transposed ones.
    const flow::LinearMap A = [&](const double* in, double* out) {
        if (transpose) {
            Jt_.mult(in, out);
        } else {
            Jt_.multTranspose(in, out);
        }
    };
    const flow::LinearMap M = [&](const double* in, double* out) {
        if (transpose) {
            ilu_.solve(in, out);
        } else {
            ilu_.solveTranspose(in, out);
        }
    };
    const flow::GmresReport g =
        flow::gmres(n_, A, M, rhs.data(), x.data(),
                    {opt_.gmresRestart, opt_.maxIterations, opt_.tolerance, 0.0, opt_.gmresDeflation,
                     opt_.singleBasis},
                    &krylov_);
    rep.iterations = g.iterations;
    // The true residual, not GMRES's estimate.
    std::vector<double> r(n_);
    A(x.data(), r.data());
    for (long i = 0; i < n_; ++i) r[i] = rhs[i] - r[i];
    const double b = norm(rhs);
    rep.relativeResidual = b > 0 ? norm(r) / b : 0.0;
    // GMRES's estimate reaches the tolerance; the true residual may be a little above it.
    if (rep.relativeResidual <= 10 * opt_.tolerance) {
        rep.status = LinearStatus::Converged;
    } else {
        rep.message = format("%s GMRES reached a relative residual of %.3g in %d iterations (tolerance %.3g)",
                             transpose ? "adjoint" : "tangent", rep.relativeResidual, g.iterations, opt_.tolerance);
    }
    rep.seconds = since(t0);
    return rep;
}

LinearSolveReport FlowLinearization::solveAdjoint(const std::vector<double>& rhs, std::vector<double>& psi) const {
    return solve(true, rhs, psi);
}

LinearSolveReport FlowLinearization::solveTangent(const std::vector<double>& rhs, std::vector<double>& dq) const {
    return solve(false, rhs, dq);
}

AdjointSolution solveAdjoint(const FlowLinearization& lin, Functional f, const flow::FlowMesh& fm,
                             const std::vector<double>& metrics, const std::vector<double>& x,
                             const std::vector<double>& q, const flow::FreeStream& fs, const flow::ForceReference& ref) {
    AdjointSolution a;
    a.functional = f;
    std::vector<double> rhs = stateGradient(f, fm, metrics, x, q, fs, ref);
    for (double& v : rhs) v = -v;
    a.report = lin.solveAdjoint(rhs, a.psi);
    return a;
}

double alphaDerivative(const AdjointSolution& a, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                       const std::vector<double>& q, const flow::ResidualOptions& o,
                       const flow::ForceCoefficients& forces) {
    const std::vector<double> dr = flow::alphaDerivative(fm, metrics, q.data(), o);
    double s = 0;
    for (std::size_t i = 0; i < q.size(); ++i) s += a.psi[i] * dr[i];
    return alphaPartial(a.functional, forces) + s;
}

}  // namespace aero::adjoint
