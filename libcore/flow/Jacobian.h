#pragma once
// The flow Jacobian dR/dq as a 5x5-block sparse matrix, and exact Jacobian-vector products.
//
// Exact assembly is by forward mode with a colouring of the stencil: R at a node depends on the
// nodes within 2 along each grid line of its block (13-point star: central fluxes, the fourth
// difference, the pressure switch) and, through interface SATs, on its coincident partners. The
// block-local part is differentiated with all nodes of one colour perturbed at once (a linear
// colouring (i + a j + b k) mod P whose equal colours never share a row: 13 colours for the
// 13-point star, 7 for the 7-point one), one residual in dual numbers per colour (StateDual: the
// node's 5 state values as 5 directions; it replaced 5 complex residuals per colour); the
// interface SATs, pointwise in (q_A, q_B), are differentiated pair by pair by complex step.
#include <complex>
#include <vector>

#include "flow/BlockSparse.h"
#include "flow/FlowMesh.h"
#include "flow/Residual.h"

namespace aero::flow {

/// Linear colouring c(i, j, k) = (i + a j + b k) mod count such that two nodes of one colour never
/// appear in the same star stencil of `radius` (distance-2 colouring of the star graph).
struct StencilColouring {
    int count = 1, a = 0, b = 0;
    int colour(int i, int j, int k) const { return (i + a * j + b * k) % count; }
};
StencilColouring stencilColouring(int radius);

/// The stencil radius of R for options o: 1 for the lumped residual with frozen coefficients, 2
/// otherwise.
int stencilRadius(const ResidualOptions& o);

/// Pattern (zero values) coupling every node to the nodes within `radius` along its grid lines
/// and to its interface partners; block rows/columns in the global node order.
BlockSparseMatrix jacobianPattern(const FlowMesh& fm, int radius);

/// J = dR/dq at q, exact to round-off (forward mode with colouring). J must have a pattern with
/// at least stencilRadius(o) (from jacobianPattern); its values are overwritten.
void assembleJacobian(const FlowMesh& fm, const std::vector<double>& metrics, const double* q,
                      const ResidualOptions& o, BlockSparseMatrix& J);

/// The preconditioner's approximate Jacobian, assembled directly: the exact Jacobian of the
/// residual with lumped second-difference dissipation and frozen coefficients (o's lumping
/// factor; o.lumpedDissipation / freezeCoefficients are ignored and taken as true). Pattern of
/// radius 1. Inviscid blocks are D_ij dF_n/dq(q_j); SAT blocks by pointwise complex step.
void assembleApproximateJacobian(const FlowMesh& fm, const std::vector<double>& metrics,
                                 const double* q, const ResidualOptions& o, BlockSparseMatrix& J);

/// How JacobianProduct forms dR/dq v.
enum class ProductMode {
    ComplexStep,  // Im R(q + i h v) / h: exact to round-off; one complex residual (about 3.5 real
                  // ones with the entropy-conservative flux's logarithms)
    Difference,   // (R(q + h v) - R(q)) / h, h = sqrt(eps) sqrt(1 + ||q||) / ||v||: one real
                  // residual, relative error about 1e-7 (far below a Newton step's GMRES tolerance)
};

/// Matrix-free products with dR/dq: out = dR/dq v, one residual each.
class JacobianProduct {
public:
    /// `metrics` must outlive the object in Difference mode (it is referenced, not copied).
    JacobianProduct(const FlowMesh& fm, const std::vector<double>& metrics, const ResidualOptions& o,
                    ProductMode mode = ProductMode::ComplexStep);
    /// The state q; in Difference mode also R(q) (computed here when r is null).
    void setState(const double* q, const double* r = nullptr);
    /// Other residual options (the switch continuation's hand-over); setState again before mult.
    void setResidualOptions(const ResidualOptions& o) { o_ = o; }
    void mult(const double* v, double* out) const;
    long size() const { return kVars * fm_->nodeCount; }
    ProductMode mode() const { return mode_; }

private:
    const FlowMesh* fm_;
    ResidualOptions o_;
    ProductMode mode_;
    const std::vector<double>* realMetrics_;
    std::vector<std::complex<double>> metrics_;  // ComplexStep only
    std::vector<double> q_, r_;                  // r_: R(q), Difference only
    double qNorm_ = 0;
    mutable std::vector<std::complex<double>> qc_, rc_;
    mutable std::vector<double> qp_, rp_;
};

/// out = (dR/dx) v at (q, x): v and x hold 3 values per node (grid coordinates, global node
/// order), out 5 per node. Complex step through the metrics (exact).
void coordinateProduct(const FlowMesh& fm, const std::vector<double>& x, const double* q,
                       const double* v, const ResidualOptions& o, double* out);

}  // namespace aero::flow
