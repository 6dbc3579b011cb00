#pragma once
// Restarted GMRES with right preconditioning (Saad & Schultz; modified Gram-Schmidt, Givens
// rotations): solves A M^-1 u = b, x = M^-1 u, so the monitored residual is the true
// ||b - A x||. Operators are callables out = Op(in) on vectors of length n.
#include <functional>

namespace aero::flow {

using LinearMap = std::function<void(const double* in, double* out)>;

struct GmresOptions {
    int restart = 40;          // Krylov vectors per cycle
    int maxIterations = 200;   // matrix-vector products in all
    double tolerance = 1e-2;   // on ||b - A x|| / ||b||
    double hopeless = 0;       // > 0: give up after a restart cycle when the residual's fall so
                               // far, extrapolated at the same rate per iteration to
                               // maxIterations, would not bring it below this (a caller that
                               // rejects such results saves the remaining cycles)
};

struct GmresReport {
    int iterations = 0;
    double relativeResidual = 1.0;  // ||b - A x|| / ||b|| (the Arnoldi estimate)
    bool converged = false;
    bool gaveUp = false;            // stopped early: `hopeless` could not be reached
};

/// Solves A x = b; x holds the initial guess on entry. M (optional) applies the preconditioner
/// inverse. Never throws for non-convergence: see the report.
GmresReport gmres(long n, const LinearMap& A, const LinearMap& M, const double* b, double* x,
                  const GmresOptions& o);

}  // namespace aero::flow
