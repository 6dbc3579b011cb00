#pragma once
// A sparse matrix of dense 5x5 blocks (block compressed rows): the flow Jacobian's storage.
// Block row r couples node r's 5 residuals to the 5 states of the nodes in its row; block values
// are row-major 5x5 (value(v, w) = d R_v / d q_w). Column indices are sorted within each row.
#include <vector>

namespace aero::flow {

constexpr int kBlock = 5;
constexpr int kBlockSize = kBlock * kBlock;

struct BlockSparseMatrix {
    long rows = 0;                // block rows = block columns (nodes)
    std::vector<long> rowStart;   // rows + 1
    std::vector<long> cols;       // block column of each stored block
    std::vector<double> values;   // kBlockSize per stored block
    std::vector<float> singleValues;  // instead of values after storeSingle(), else empty

    long blockCount() const { return static_cast<long>(cols.size()); }
    /// Index of block (row, col) or -1 (binary search in the row).
    long find(long row, long col) const;
    double* block(long index) { return &values[kBlockSize * index]; }
    const double* block(long index) const { return &values[kBlockSize * index]; }

    /// Zeroes the values (allocating them again after releaseValues() or storeSingle()).
    void setZero();
    /// Frees the values, keeping the pattern (setZero() allocates them again): a matrix needed
    /// only until its preconditioner is factored need not stay beside the Krylov basis.
    void releaseValues();
    bool hasValues() const { return values.size() == kBlockSize * cols.size(); }
    /// Keeps the values only rounded to single precision (half the memory; double sums in mult()):
    /// a matrix needed after its preconditioner is factored only for products. setZero() returns
    /// to double storage. Nothing to do without values.
    void storeSingle();
    bool single() const { return singleValues.size() == kBlockSize * cols.size() && !cols.empty(); }

    /// y = A x (x, y: 5 * rows; y is overwritten). OpenMP over rows. With the single-precision
    /// values after storeSingle().
    void mult(const double* x, double* y) const;
    /// y = A^T x (for the adjoint). Parallel over rows once prepareTranspose() has run (the
    /// same sums in the same order as the sequential product, so bitwise the same result).
    void multTranspose(const double* x, double* y) const;
    /// Indexes, for every stored block (r, c), the block (c, r), so that multTranspose gathers
    /// rows in parallel. Needs a structurally symmetric pattern (the flow Jacobian's: stencils
    /// and interface pairs are symmetric); returns false, and changes nothing, otherwise. Call
    /// again after the pattern changes.
    bool prepareTranspose();
    std::vector<long> transposeBlock;  // from prepareTranspose (empty: sequential multTranspose)
    /// Replaces A by A^T in place (block (r, c) becomes block (c, r) transposed), so that products
    /// with A^T run at the speed of mult() (a gathering multTranspose reads its blocks scattered
    /// over the matrix: 4x slower at 98k nodes). Needs a structurally symmetric pattern; returns
    /// false, and changes nothing, otherwise. Prepares transposeBlock (multTranspose then gathers).
    bool transposeInPlace();
    /// A += diag(d_r I5) (d: one value per block row; every diagonal block must be stored).
    void addDiagonal(const double* d);
};

/// Builds the sparsity pattern (zero values, or none without `values`: the ILU's pattern, whose
/// values it keeps elsewhere, was 2.6 GB of doubles allocated and freed at once on the 903k grid)
/// from per-row column lists (unsorted, duplicates allowed).
BlockSparseMatrix makeBlockSparse(const std::vector<std::vector<long>>& columns, bool values = true);

}  // namespace aero::flow
