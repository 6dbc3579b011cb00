#pragma once
// Linear-elasticity movement of the control grid b (Eq. 6-7 of the paper): each control cell of
// each block is a trilinear hexahedral finite element; K(b^(i-1)) u = f is solved in m
// increments A^(i) = A0 + i/m (A^(m) - A0) with preconditioned conjugate gradients.
// Boundary conditions come from the block faces: wall nodes follow the geometry control points,
// farfield nodes are fixed, symmetry-plane nodes (Y = 0) slide in the plane (u_y = 0).
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mesh/MultiBlock.h"

namespace aero::mesh {

struct ElasticityOptions {
    double poisson = -0.2;  // the paper's negative Poisson's ratio
    int increments = 6;     // m
    double sizeStiffening =
        1.0;  // E ~ (mean cell volume / cell volume)^sizeStiffening: small cells keep their shape
    double orthogonalityStiffening =
        1.0;                   // E *= 1 + c (1 - q), q = min scaled Jacobian of the cell in [0, 1]
    double tolerance = 1e-10;  // PCG relative residual
    int maxIterations = 20000;
    enum class Solver {
        Auto,       // conjugate gradients (incomplete block Cholesky in 3x3 node blocks, the earlier
                    // increments' solutions as the starting guess: mesh/BlockCg.h), and a sparse Cholesky of the same
                    // K when they have not converged in directAfter iterations
        Iterative,  // conjugate gradients only (up to maxIterations)
        Direct,     // supernodal sparse Cholesky (CHOLMOD) of every increment's K
    };
    Solver solver = Solver::Auto;
    int directAfter = 1500;    // Auto: PCG iterations before the direct fallback (the half-sphere's
                               // increments take 30-60; a wildly deformed design can take 20,000)
};

enum class SolveStatus { Converged, NotConverged, Cancelled, InvalidCell };

struct MoveReport {
    SolveStatus status = SolveStatus::Converged;
    std::vector<int> cgIterations;  // per increment
    int directSolves = 0;           // increments solved by the sparse Cholesky
    std::vector<double> residuals;  // final relative residual per increment
    int totalIterations = 0;
    int freeDofs = 0;
    double seconds = 0;
    std::string message;  // the reason, when not converged
};

/// Volume (sum over the 2x2x2 Gauss points of det J) and minimum scaled corner Jacobian of a
/// hexahedron with corners x (8 x 3, VTK order). Templated for complex step (the minimum takes
/// the active corner's value, so its derivative is that corner's).
template <class T>
void cellMetrics(const T* x, T& volume, T& minScaled);

/// The scaled Jacobian of each corner of a hexahedron (8 x 3 corners, VTK order).
template <class T>
void cornerScaledJacobians(const T* x, T* corners);

/// How sharply cellOrthogonality follows the worst corner.
inline constexpr double kOrthogonalitySharpness = 100.0;

/// The cell's orthogonality: a smooth minimum of its corner scaled Jacobians q_a,
///   -(1/r) log((1/8) sum_a exp(-r q_a)),  r = kOrthogonalitySharpness,
/// between the minimum and the mean (equal to q for eight equal corners, within log(8)/r = 0.021
/// above the minimum). Not the minimum itself: on a structured grid several corners tie for the
/// minimum, where the minimum has no derivative and the mesh adjoint would disagree with finite
/// differences (by 2e-4 on the half-sphere's control grid). Why 100: at r = 20 and 50 one random
/// design of the robustness suite (CaseEvaluatorTest) stalls, at 100 it converges as with the
/// minimum - that design is borderline for the flow solver (issue #14), and the grids of r = 100
/// are the closest to the minimum's.
template <class T>
T cellOrthogonality(const T* x);

/// Young's modulus of one control cell: (meanVolume / volume)^size_stiffening times
/// 1 + orthogonality_stiffening (1 - clamp(cellOrthogonality, 0, 1)). Differentiable in x
/// except where the clamp switches (a corner at a right angle to inverted); meanVolume is a
/// global quantity passed in: the mesh adjoint differentiates it (1/N sum of the cell volumes).
template <class T>
T cellModulus(const T* x, T meanVolume, const ElasticityOptions& o);

/// cellModulus and its exact derivatives with respect to the 24 corner coordinates, analytic
/// (the volume's through the Gauss points' cofactors, the corners' scaled Jacobians through their
/// edges, the smooth minimum through its weights): the mesh adjoint's inner loop, where complex
/// step cost 48 complex cell evaluations per cell. dE and dVolume: 24 values each (the cell
/// volume's derivative is a by-product the mean volume's term needs; `volume`, if given, gets the
/// volume itself). Returns E.
double cellModulusGradient(const double* x, double meanVolume, const ElasticityOptions& o, double* dE,
                           double* dVolume, double* volume = nullptr);

/// Young's modulus of every control cell of block `b` (in the block's cell order) for grid b.
std::vector<double> cellStiffness(const MultiBlockMesh& m, int block, const ElasticityOptions& o,
                                  double meanVolume);

/// 24x24 stiffness of a trilinear hexahedron with corners x (8 x 3, VTK order: (0,0,0), (1,0,0),
/// (1,1,0), (0,1,0), then the same at z = 1), Young's modulus E and Poisson's ratio nu; 2x2x2
/// Gauss. Row-major 24x24 into K; DOFs ordered node-major (3 per corner). Templated for complex
/// step.
template <class T>
void hexStiffness(const T* x, T E, double nu, T* K);

/// a^T K b for the stiffness K of hexStiffness without forming K (a, b: 24 values, node-major):
/// the bilinear form lambda tr(grad a) tr(grad b) + mu (grad a : grad b^T + grad a : grad b) at
/// the Gauss points. Templated for complex step on x and E.
template <class T>
T hexBilinear(const T* x, T E, double nu, const double* a, const double* b);

/// a^T K b of unit modulus (E = 1) and its gradient with respect to the 24 corner coordinates x,
/// analytic (d det J = det J G(n, r), dG = -G e_r G_n^T); returns a^T K b.
double hexBilinearGradient(const double* x, double nu, const double* a, const double* b, double* grad);

/// Solves one linear-elasticity problem on the current control grid: `prescribed` gives the
/// displacement (3 per global node) of every constrained DOF (others are ignored and solved for).
/// `constrained` flags the constrained DOFs (3 per node). Returns the displacement of all DOFs.
/// `initial` (optional) is a starting guess for the free DOFs.
struct IncrementResult {
    std::vector<double> u;
    int iterations = 0;
    double residual = 0;
    bool converged = false;
    bool direct = false;       // solved by the sparse Cholesky
    bool invalidCell = false;  // a control cell has non-positive volume (nothing solved)
    std::string message;       // why, when not converged
};
IncrementResult solveElasticity(const MultiBlockMesh& m, const std::vector<char>& constrained,
                                const std::vector<double>& prescribed, const ElasticityOptions& o,
                                const std::vector<double>* initial = nullptr);

/// Flags (3 per node) for the DOFs the face boundary conditions constrain: wall and farfield
/// nodes fully, symmetry nodes in y.
std::vector<char> boundaryConstraints(const MultiBlockMesh& m);

/// What the mesh adjoint needs of a move: the control grid b^(i-1) before every increment i and the
/// increment's displacement u^(i) (3 per control node each).
struct MoveHistory {
    std::vector<std::vector<double>> before, displacement;
    /// Identifies the move that recorded it, for the operators a MoveWorkspace kept of that move
    /// (0: none kept). Unique in the process.
    std::uint64_t stamp = 0;
    std::size_t bytes() const;
};

struct StiffnessLayout;  // Elasticity.cpp

/// What the moves and mesh adjoints of one control-grid topology share from one call to the next:
/// the stiffness matrix's block pattern and storage, the preconditioner's ordering and storage,
/// and the solvers' work vectors (at the paper level ~50 MB, 0.1-0.2 s to build and first touch).
/// Rebuilt when the cells or the boundary conditions differ from the last call's. The results
/// are the same bits with or without it. One call at a time.
class MoveWorkspace {
public:
    MoveWorkspace();
    ~MoveWorkspace();
    MoveWorkspace(MoveWorkspace&&) noexcept;
    MoveWorkspace& operator=(MoveWorkspace&&) noexcept;
    /// The layout for m's cells and `constrained` (3 flags per node): the kept one when they are
    /// unchanged, else a new one.
    StiffnessLayout& layoutFor(const MultiBlockMesh& m, const std::vector<char>& constrained);
    /// How many layouts have been built (a rebuild per call means the workspace is not reused).
    int builds() const { return builds_; }
    /// When set, a move that records a MoveHistory keeps each increment's stiffness matrix K_ff
    /// and its incomplete factorization here (6 matrices at ~1.7 KB per control node each: 138 MB
    /// at the paper level, 64 MB at the coarse one), and the mesh adjoint of that history with
    /// this workspace solves with them instead of assembling and factoring them again (the same
    /// bits). For a caller that computes gradients (the optimizer, `aeroform-cli gradient`, the
    /// GUI's sensitivities); a preview does not need the memory.
    void setKeepIncrements(bool keep) { keep_ = keep; }
    bool keepsIncrements() const { return keep_; }
    /// The memory of the kept increments' matrices and factors.
    std::size_t keptBytes() const;

private:
    std::unique_ptr<StiffnessLayout> layout_;
    int builds_ = 0;
    bool keep_ = false;
};

/// Moves b so that its surface nodes reach `surface` (3 per unique geometry control point), in
/// o.increments increments (Eq. 7). `progress(increment, m)` is called after each; `cancel`
/// stops between increments (status Cancelled, b left at the last completed increment).
/// `history` (optional) receives every increment's grid and displacement. `workspace` (optional)
/// is kept by a caller that moves the same grid again (the optimizer, the editor's preview).
MoveReport moveControlGrid(MultiBlockMesh& m, const std::vector<double>& surface,
                           const ElasticityOptions& o,
                           const std::function<void(int, int)>& progress = {},
                           const std::atomic<bool>* cancel = nullptr, MoveHistory* history = nullptr,
                           MoveWorkspace* workspace = nullptr);

/// d(lambda^T K(b) u)/db for the current control grid b of m (3 per control node): every cell's
/// 24x24 stiffness differentiated by complex step with respect to its corners, through its
/// modulus (size and orthogonality stiffening) and through the mean cell volume (a global
/// quantity, differentiated: d mean/db = (1/N) sum of the cells' d volume/db).
std::vector<double> stiffnessProductGradient(const MultiBlockMesh& m, const ElasticityOptions& o,
                                             const std::vector<double>& lambda, const std::vector<double>& u);
/// The same for several lambdas with one u (the derivatives of the moduli are shared).
std::vector<std::vector<double>> stiffnessProductGradients(const MultiBlockMesh& m, const ElasticityOptions& o,
                                                           const std::vector<std::vector<double>>& lambdas,
                                                           const std::vector<double>& u);

/// K(b) v for the current control grid b of m over all DOFs (constrained ones included).
std::vector<double> stiffnessProduct(const MultiBlockMesh& m, const ElasticityOptions& o, const std::vector<double>& v);

struct MeshAdjointReport {
    bool converged = true;
    std::vector<int> iterations;  // per increment (reverse order of the forward move)
    int directSolves = 0;
    int reusedIncrements = 0;     // increments solved with the forward move's kept K and factor
    std::size_t keptBytes = 0;    // the memory of those kept operators (MoveWorkspace::keptBytes)
    double seconds = 0;
    std::string message;          // the reason, when not converged
};

/// The mesh adjoint (the paper's Eq. 9): the reverse of moveControlGrid over its increments.
/// From gFinal = dL/db^(m) (3 per control node of the moved grid) to dL/dA (3 per unique
/// geometry control point, surfaceNode order). `m` gives the structure (blocks, boundary
/// conditions); the grids come from `history`. Each increment solves K(b^(i-1)) lambda = ubar on the
/// free DOFs (K is symmetric: the forward increment's operator) and adds
/// -d(lambda^T K(b^(i-1)) u^(i))/db^(i-1) to the gradient flowing to the previous increment.
std::vector<double> moveControlGridAdjoint(const MultiBlockMesh& m, const MoveHistory& history,
                                           const ElasticityOptions& o, const std::vector<double>& gFinal,
                                           MeshAdjointReport* report = nullptr);
/// The same for several functionals: each increment's K is assembled and factored once, or taken
/// from `workspace` when it kept them from `history`'s move (MoveWorkspace::setKeepIncrements)
/// with the same options.
std::vector<std::vector<double>> moveControlGridAdjoints(const MultiBlockMesh& m, const MoveHistory& history,
                                                         const ElasticityOptions& o,
                                                         const std::vector<std::vector<double>>& gFinals,
                                                         MeshAdjointReport* report = nullptr,
                                                         MoveWorkspace* workspace = nullptr);

}  // namespace aero::mesh
