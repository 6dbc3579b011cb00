#pragma once
// Block incomplete LU factorization ILU(p) of a BlockSparseMatrix (level-of-fill p: p = 0 keeps
// the matrix's pattern, p = 1, 2 add the fill of that level): L unit block lower, U block upper,
// the diagonal blocks of U stored inverted. The flow solver's preconditioner, built from the
// approximate Jacobian plus the time-step diagonal.
// Note: on a structured 7-point pattern, ILU(0) is the same for every lexicographic ordering
// (the lower neighbours are always i-1, j-1, k-1), so reordering axes does not help; fill does.
#include <string>
#include <vector>

#include "flow/BlockSparse.h"

namespace aero::flow {

class BlockIlu {
public:
    /// Symbolic phase: the pattern of L + U for A's pattern and fill level p. Needed once per
    /// pattern; factor() calls it when the pattern or p changed.
    void analyze(const BlockSparseMatrix& A, int fill);
    /// Numeric factorization of A with fill level p. Returns false, and names the row in
    /// message(), if a pivot block is singular or not finite.
    bool factor(const BlockSparseMatrix& A, int fill = 0);
    /// x = (L U)^-1 b (x and b: 5 per block row; may not alias). Sequential.
    void solve(const double* b, double* x) const;
    const std::string& message() const { return message_; }
    long storedBlocks() const { return lu_.blockCount(); }

private:
    BlockSparseMatrix lu_;
    std::vector<long> diag_;     // index of each row's diagonal block
    std::vector<double> dinv_;   // inverted diagonal blocks of U
    std::vector<long> source_;   // for each block of A, its index in lu_
    long analyzedRows_ = -1, analyzedBlocks_ = -1;
    int fill_ = -1;
    std::string message_;
};

}  // namespace aero::flow
