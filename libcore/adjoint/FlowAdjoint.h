#pragma once
// The flow's linearization at a converged state, for the discrete adjoint (the paper's Eq. 10):
//   (dR/dq)^T psi = -(dJ/dq)^T
// solved by GMRES on the assembled exact Jacobian's transpose, right-preconditioned by the
// transpose of the forward solver's preconditioner (block ILU of the approximate Jacobian plus a
// pseudo-time diagonal), with no copy of the forward solver: the same GMRES on (J^T, P^T). Both
// are stored transposed (J^T assembled then transposed in place; the ILU of P^T, which is the
// transpose of P's ILU: with a unit block-diagonal L the incomplete factorization on a symmetric
// pattern is unique, so ILU(P^T) = U^T L^T rescaled), so the adjoint's products and triangular
// solves run in the fast row-oriented order (3-4x faster than gathering transposed blocks). The
// same object solves tangent (forward) systems dR/dq dq = b, which the tests use for the duality
// check  dJ/dq . dq = psi^T b. Built once per state; several right-hand sides reuse it.
#include <string>
#include <vector>

#include "adjoint/Functionals.h"
#include "flow/BlockIlu.h"
#include "flow/BlockSparse.h"
#include "flow/FlowMesh.h"
#include "flow/Gmres.h"
#include "flow/Residual.h"

namespace aero::adjoint {

struct AdjointOptions {
    double tolerance = 1e-10;   // GMRES relative residual ||b - A x|| / ||b||
    int gmresRestart = 60;
    int gmresDeflation = 20;    // harmonic Ritz vectors kept over a restart (GMRES-DR: 326 instead
                                // of 820 products for the 98k blended wing's CL adjoint)
    bool singleBasis = false;   // the Krylov basis in float (flow::GmresOptions::singleBasis): not
                                // for the adjoint's 1e-10 with deflated restarts (98k blended
                                // wing: 504 products against 329, the carried Arnoldi relations
                                // hold only to float round-off)
    int maxIterations = 3000;   // matrix products in all
    double cfl = 1e6;           // of the preconditioner's pseudo-time diagonal (the adjoint itself
                                // is steady: only the preconditioner sees it)
    int iluFill = 1;
    int iluParts = 2;           // ILU ordering in this many groups of blocks (as the flow solve)
};

enum class LinearStatus { Converged, NotConverged };

struct LinearSolveReport {
    LinearStatus status = LinearStatus::NotConverged;
    int iterations = 0;
    double relativeResidual = 1;  // true residual ||b - A x|| / ||b|| after the solve
    double seconds = 0;
    std::string message;          // the reason when not converged
    bool converged() const { return status == LinearStatus::Converged; }
};

/// The flow solver's preconditioner at a CFL: ILU(fill) of the approximate (lumped dissipation,
/// frozen coefficients) Jacobian plus V/dt (flow::timeStepScale / cfl), in `parts` groups of
/// blocks; of its transpose when `transposed`. Throws flow::Error on a singular pivot.
void factorPseudoTimePreconditioner(const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                    const std::vector<double>& q, const flow::ResidualOptions& o, double cfl,
                                    int fill, int parts, bool transposed, flow::BlockIlu& ilu);

class FlowLinearization {
public:
    /// Assembles dR/dq at q (exact, coloured complex step) and factors the preconditioner.
    /// Throws flow::Error naming the row when the preconditioner has a singular pivot.
    FlowLinearization(const flow::FlowMesh& fm, const std::vector<double>& metrics, const std::vector<double>& q,
                      const flow::ResidualOptions& o, const AdjointOptions& opt = {});

    /// (dR/dq)^T psi = rhs; psi holds the initial guess (zero if empty).
    LinearSolveReport solveAdjoint(const std::vector<double>& rhs, std::vector<double>& psi) const;
    /// (dR/dq) dq = rhs.
    LinearSolveReport solveTangent(const std::vector<double>& rhs, std::vector<double>& dq) const;

    double secondsAssembly() const { return secondsAssembly_; }

private:
    LinearSolveReport solve(bool transpose, const std::vector<double>& rhs, std::vector<double>& x) const;

    long n_;
    AdjointOptions opt_;
    flow::BlockSparseMatrix Jt_;  // (dR/dq)^T
    flow::BlockIlu ilu_;          // of P^T, P the preconditioner's matrix
    mutable flow::GmresWorkspace krylov_;  // one solve at a time per linearization
    double secondsAssembly_ = 0;
};

/// The adjoint of functional f at a converged state: psi with (dR/dq)^T psi = -(dJ/dq)^T.
struct AdjointSolution {
    Functional functional = Functional::CL;
    std::vector<double> psi;
    LinearSolveReport report;
};
AdjointSolution solveAdjoint(const FlowLinearization& lin, Functional f, const flow::FlowMesh& fm,
                             const std::vector<double>& metrics, const std::vector<double>& x,
                             const std::vector<double>& q, const flow::FreeStream& fs, const flow::ForceReference& ref);

/// dJ/dalpha (per degree) through the flow: dJ/dalpha|_q + psi^T dR/dalpha|_q, the residual's
/// derivative exact (flow::alphaDerivative: complex step in the farfield's free-stream state).
double alphaDerivative(const AdjointSolution& a, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                       const std::vector<double>& q, const flow::ResidualOptions& o,
                       const flow::ForceCoefficients& forces);

}  // namespace aero::adjoint
