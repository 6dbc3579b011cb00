#pragma once
// Block incomplete LU factorization ILU(p) of a BlockSparseMatrix (level-of-fill p: p = 0 keeps
// the matrix's pattern, p = 1, 2 add the fill of that level): L unit block lower, U block upper,
// the diagonal blocks of U stored inverted. The factors are computed in double precision row by
// row and stored in single precision or bfloat16 (IluPrecision). The flow solver's preconditioner, built from the
// approximate Jacobian plus the time-step diagonal.
// Note: on a structured 7-point pattern, ILU(0) is the same for every lexicographic ordering
// (the lower neighbours are always i-1, j-1, k-1), so reordering axes does not help; fill does.
#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "flow/BlockSparse.h"

namespace aero::flow {

/// A symmetric permutation for the factorization that lets it run in parallel: rows of part 0,
/// part 1, ..., part P-1, then the separator (every row coupled to a row of another part). A
/// part's rows couple only to their own part and to the separator, so the parts' factorizations
/// and triangular solves are independent (one thread each) and only the separator's rows run
/// after them: the same preconditioner on 1 or P threads, with the coupling between the parts
/// kept (not a block-Jacobi that drops it).
struct IluOrdering {
    std::vector<long> order;      // order[new row] = original row
    std::vector<long> partStart;  // P + 2 entries: part p is [partStart[p], partStart[p+1]); the
                                  // separator is [partStart[P], partStart[P+1] = rows)
    int parts() const { return static_cast<int>(partStart.size()) - 2; }
};

/// The ordering for a row -> part assignment (values 0..parts-1) of A's rows; parts must be >= 1.
IluOrdering partitionOrdering(const BlockSparseMatrix& A, const std::vector<int>& partOfRow,
                              int parts);

/// Storage of the factors' blocks. Each row is factored in double precision and stored rounded;
/// the inverted diagonal blocks stay double. Single halves the memory and the triangular solves'
/// traffic against Double with the same GMRES iterations (standard for preconditioners);
/// Bfloat16 (8 significant bits, the exponent range of float) halves the memory again with the
/// same iterations on the flow samples, but the sweeps are not faster than with Single (widening
/// each value costs what the halved traffic saves): a memory option (docs/performance.md).
enum class IluPrecision { Double, Single, Bfloat16 };

/// A bfloat16 value: the upper 16 bits of a float (round to nearest even when stored).
struct Bf16 {
    std::uint16_t bits = 0;
    static Bf16 round(float f) {
        std::uint32_t u = std::bit_cast<std::uint32_t>(f);
        u += 0x7FFFu + ((u >> 16) & 1u);  // finite values only (the factors are checked)
        return Bf16{static_cast<std::uint16_t>(u >> 16)};
    }
    operator float() const { return std::bit_cast<float>(static_cast<std::uint32_t>(bits) << 16); }
};

class BlockIlu {
public:
    /// Factor and solve in this row order (empty ordering: the matrix's own order, sequential).
    /// Takes effect at the next factor().
    void setOrdering(IluOrdering ordering);
    /// How the factors' L and U blocks are stored (default Single); takes effect at the next
    /// analyze.
    void setPrecision(IluPrecision precision) {
        precision_ = precision;
        analyzedRows_ = -1;
    }
    IluPrecision precision() const { return precision_; }
    /// Symbolic phase: the pattern of L + U for A's pattern and fill level p. Needed once per
    /// pattern; factor() calls it when the pattern or p changed.
    void analyze(const BlockSparseMatrix& A, int fill);
    /// Numeric factorization of A with fill level p. Returns false, and names the row in
    /// message(), if a pivot block is singular or not finite.
    bool factor(const BlockSparseMatrix& A, int fill = 0);
    /// x = (L U)^-1 b (x and b: 5 per block row; may not alias). Parallel over the ordering's
    /// parts. Uses a work vector of the object: not for concurrent calls on one BlockIlu.
    void solve(const double* b, double* x) const;
    /// x = ((L U)^T)^-1 b: the transposed preconditioner (the adjoint's, for GMRES on J^T).
    /// Parallel over the parts like solve() (row-oriented sweeps over the factors' columns);
    /// the same work vector as solve(). The first call after analyze() builds the factors' column
    /// structure.
    void solveTranspose(const double* b, double* x) const;
    const std::string& message() const { return message_; }
    long storedBlocks() const { return lu_.blockCount(); }
    const IluOrdering& ordering() const { return ordering_; }

private:
    void factorRows(const BlockSparseMatrix& A, long first, long last, std::vector<long>& where,
                    std::vector<double>& row, std::string& message);
    template <class V>
    void forwardRows(const V* vals, long first, long last, double* x) const;
    template <class V>
    void backwardRows(const V* vals, long first, long last, double* x) const;
    template <class V>
    void transposeForwardRows(const V* vals, long first, long last, double* x) const;
    template <class V>
    void transposeBackwardRows(const V* vals, long first, long last, double* x) const;

    IluOrdering ordering_;
    std::vector<long> position_;  // position_[original row] = new row
    mutable std::vector<double> work_;
    BlockSparseMatrix lu_;       // pattern of L + U in the new row order (values unused)
    std::vector<float> values_;  // L and U blocks in single precision (kBlockSize per block of
                                 // lu_): each row is factored in double and stored rounded, which
                                 // halves the preconditioner's memory and the solves' traffic
    std::vector<double> valuesDouble_;  // ... or in double precision
    std::vector<Bf16> valuesHalf_;      // ... or in bfloat16
    IluPrecision precision_ = IluPrecision::Single;
    /// f(vals) with the stored blocks of the chosen precision (const pointers, or writable ones
    /// for the factorization).
    template <class F>
    void withValues(F&& f) const {
        withValuesOf(*this, f);
    }
    template <class F>
    void withValues(F&& f) {
        withValuesOf(*this, f);
    }
    template <class Self, class F>
    static void withValuesOf(Self& self, F& f) {
        switch (self.precision_) {
        case IluPrecision::Double: f(self.valuesDouble_.data()); break;
        case IluPrecision::Single: f(self.values_.data()); break;
        case IluPrecision::Bfloat16: f(self.valuesHalf_.data()); break;
        }
    }
    std::vector<long> diag_;     // index of each row's diagonal block
    std::vector<double> dinv_;   // inverted diagonal blocks of U (double)
    std::vector<long> source_;   // for each block of lu_, the block of A it starts from (-1: fill)
    mutable std::vector<long> colStart_, colBlocks_, colRows_;  // lu_ by columns: for row i, the
                                 // blocks (j, i) at colBlocks_[colStart_[i] .. colStart_[i+1]), j
                                 // increasing (colRows_ = j); built by the first solveTranspose()
    void buildColumns() const;
    long analyzedRows_ = -1, analyzedBlocks_ = -1;
    int fill_ = -1;
    std::string message_;
};

}  // namespace aero::flow
