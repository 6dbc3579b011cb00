#pragma once
// Preconditioned conjugate gradients for the control grid's elasticity systems, stored in 3x3
// node blocks (a node's three displacement components together): block compressed rows, an
// incomplete block Cholesky factorization without fill (L D L^T on the pattern of K), and CG with
// a parallel product. Every sum runs in a fixed order (dot products in fixed chunks), so a solve
// gives the same bits whatever the thread count: the optimizer's kill-and-resume replay relies
// on identical runs.
//
// Why not Eigen's scalar IncompleteCholesky: on the paper-size control grid (13,546 nodes) its
// factorization (linked lists, diagonal scaling, re-factoring with doubled shifts) took a third
// of the move, and the scalar pattern carries 9 column indices where the block pattern carries 1.
#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace aero::mesh {

/// A symmetric matrix of 3x3 blocks (both triangles stored, block columns sorted in each row,
/// every diagonal block present); block values row-major.
struct Block3Matrix {
    int rows = 0;
    std::vector<int> rowStart;   // rows + 1
    std::vector<int> cols;       // block column of each stored block
    std::vector<double> values;  // 9 per stored block

    int blockCount() const { return static_cast<int>(cols.size()); }
    /// y = A x (3 * rows values each); rows in parallel, each row's sum in column order.
    void mult(const double* x, double* y) const;
};

/// Builds the pattern (zero values) from per-row block column lists (unsorted, duplicates
/// allowed; the diagonal is added). The pattern must be symmetric.
Block3Matrix makeBlock3Pattern(std::vector<std::vector<int>> columns);

/// Incomplete block Cholesky without fill: P A P^T ~ (I + L) D (I + L)^T with L strictly block
/// lower on the permuted lower pattern and D block diagonal. The ordering P splits the matrix
/// graph in two parts that share no entry and a separator between them (a breadth-first level
/// set from a peripheral row, chosen to balance the parts), separator last: the factorization and
/// both triangular solves then run the two parts at once and the separator after (before, going
/// back). Each part runs in breadth-first level order towards the separator (rows of one level
/// in A's order), so a chain has no fill. The arithmetic does not depend on the thread count.
/// A pivot block that is not positive definite (the incomplete factorization can break down on
/// distorted cells) restarts the factorization with the diagonal blocks shifted by sigma times
/// their diagonal, sigma = 1e-3 doubling, at most 12 times.
class BlockIncompleteCholesky {
public:
    /// False when it broke down even with the largest shift. The ordering is kept while A's
    /// pattern stays the same (the move's increments).
    bool compute(const Block3Matrix& A);
    /// z = M^{-1} r (3 * rows values each). Uses work buffers of the object: one solve at a
    /// time per object.
    void solve(const double* r, double* z) const;
    double shift() const { return shift_; }
    /// The factor the solves read (rounded to float) and its shift, held apart from the object.
    struct Factor {
        std::vector<float> lower, pivot;
        double shift = 0;
        std::size_t bytes() const { return (lower.capacity() + pivot.capacity()) * sizeof(float); }
    };
    /// Exchanges the solves' factor with f (no copy): a caller that factors a sequence of matrices
    /// of one pattern (the move's increments) keeps each factor and swaps it back in for later
    /// solves with the same matrix (the mesh adjoint's). compute() into a swapped-in Factor reuses
    /// its buffers. The ordering stays the object's: only for matrices of the pattern it was
    /// computed for.
    void swapFactor(Factor& f) {
        lowerSingle_.swap(f.lower);
        pivotSingle_.swap(f.pivot);
        std::swap(shift_, f.shift);
    }
    /// Rows in the first part, the second part and the separator.
    std::array<int, 3> partSizes() const { return {partEnd_[0], partEnd_[1] - partEnd_[0], rows_ - partEnd_[1]}; }

private:
    void order(const Block3Matrix& A);
    bool factorRows(const Block3Matrix& A, double sigma, int begin, int end, std::vector<int>& position);
    bool factor(const Block3Matrix& A, double sigma);
    int rows_ = 0;
    std::vector<int> patternStart_, patternCols_;  // A's pattern the ordering was made for
    std::vector<int> perm_;                        // new row -> A's row
    std::array<int, 2> partEnd_{0, 0};             // [0, e0) part 1, [e0, e1) part 2, [e1, rows) separator
    std::vector<int> lowerStart_, lowerCols_;      // new numbering
    std::vector<int> lowerSource_, diagSource_;    // A's block of each L block and of each diagonal
    std::vector<double> lower_;     // L blocks, 9 each
    std::vector<double> pivotInv_;  // D^{-1} blocks, 9 each
    std::vector<float> lowerSingle_, pivotSingle_;  // the same rounded to float, for the solves
    double shift_ = 0;
    mutable std::vector<double> work_;
    mutable std::vector<int> positionWork_;
};

struct CgReport {
    int iterations = 0;
    double residual = 0;  // ||b - A x|| / ||b|| as CG's recurrence tracks it (0 for b = 0)
    bool converged = false;
};

/// Work vectors of conjugateGradients and galerkinGuess, kept by a caller that solves a sequence
/// of systems (the move's increments): fresh vectors of this size cost page faults on every
/// solve (on this project's VMs, ~3 ms per MB touched for the first time).
struct CgWorkspace {
    std::vector<double> r, z, p, q;
    std::vector<std::vector<double>> w, Aw;  // galerkinGuess: the A-orthonormal basis and its products
};

/// Solves A x = b from the guess in x; stops when the relative residual reaches `tolerance` or
/// after maxIterations.
CgReport conjugateGradients(const Block3Matrix& A, const BlockIncompleteCholesky& M, const std::vector<double>& b,
                            std::vector<double>& x, double tolerance, int maxIterations, CgWorkspace& work);
CgReport conjugateGradients(const Block3Matrix& A, const BlockIncompleteCholesky& M, const std::vector<double>& b,
                            std::vector<double>& x, double tolerance, int maxIterations);

/// The starting guess of smallest error in the A-norm within span(basis): the basis is
/// A-orthonormalized (modified Gram-Schmidt; a vector whose A-norm falls below 1e-8 of its own
/// on the way is dropped as dependent) and x0 = sum_j (w_j . b) w_j. For a sequence of similar
/// systems (the move's increments) the earlier solutions give a guess one or two orders better
/// than the last solution alone.
std::vector<double> galerkinGuess(const Block3Matrix& A, const std::vector<std::vector<double>>& basis,
                                  const std::vector<double>& b, CgWorkspace& work);
std::vector<double> galerkinGuess(const Block3Matrix& A, const std::vector<std::vector<double>>& basis,
                                  const std::vector<double>& b);

}  // namespace aero::mesh
