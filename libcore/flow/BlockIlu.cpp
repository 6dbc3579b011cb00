#include "flow/BlockIlu.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace aero::flow {

namespace {
using Block = Eigen::Matrix<double, kBlock, kBlock, Eigen::RowMajor>;
using Map = Eigen::Map<Block>;
using ConstMap = Eigen::Map<const Block>;
using Vec = Eigen::Matrix<double, kBlock, 1>;
}  // namespace

void BlockIlu::analyze(const BlockSparseMatrix& A, int fill) {
    const long n = A.rows;
    // Row by row: level(i, j) = min over k < i of level(i, k) + level(k, j) + 1 (pattern of A
    // at level 0), keeping levels <= fill.
    std::vector<std::vector<long>> cols(n);
    std::vector<std::vector<int>> levels(n);
    std::vector<int> level(n, -1);  // dense work row: -1 = absent
    std::vector<long> row;
    for (long i = 0; i < n; ++i) {
        row.assign(A.cols.begin() + A.rowStart[i], A.cols.begin() + A.rowStart[i + 1]);
        for (long j : row) level[j] = 0;
        if (fill > 0) {
            // Process lower entries in increasing column order; new fill may add lower entries
            // that must be processed too, so keep `row` sorted as it grows.
            std::sort(row.begin(), row.end());
            for (std::size_t t = 0; t < row.size() && row[t] < i; ++t) {
                const long k = row[t];
                const int lik = level[k];
                const std::vector<long>& ck = cols[k];
                const std::vector<int>& lk = levels[k];
                for (std::size_t c = 0; c < ck.size(); ++c) {
                    const long j = ck[c];
                    if (j <= k) continue;
                    const int l = lik + lk[c] + 1;
                    if (l > fill) continue;
                    if (level[j] < 0) {
                        level[j] = l;
                        row.insert(std::upper_bound(row.begin(), row.end(), j), j);
                    } else if (l < level[j]) {
                        level[j] = l;
                    }
                }
            }
        }
        std::sort(row.begin(), row.end());
        cols[i] = row;
        levels[i].resize(row.size());
        for (std::size_t c = 0; c < row.size(); ++c) {
            levels[i][c] = level[row[c]];
            level[row[c]] = -1;
        }
    }
    lu_ = makeBlockSparse(cols);
    source_.resize(A.blockCount());
    for (long i = 0; i < n; ++i) {
        for (long b = A.rowStart[i]; b < A.rowStart[i + 1]; ++b) source_[b] = lu_.find(i, A.cols[b]);
    }
    analyzedRows_ = n;
    analyzedBlocks_ = A.blockCount();
    fill_ = fill;
}

bool BlockIlu::factor(const BlockSparseMatrix& A, int fill) {
    if (analyzedRows_ != A.rows || analyzedBlocks_ != A.blockCount() || fill_ != fill) analyze(A, fill);
    lu_.setZero();
    for (long b = 0; b < A.blockCount(); ++b) {
        std::copy(A.block(b), A.block(b) + kBlockSize, lu_.block(source_[b]));
    }
    const long n = lu_.rows;
    diag_.assign(n, -1);
    dinv_.assign(kBlockSize * static_cast<std::size_t>(n), 0.0);
    message_.clear();
    std::vector<long> where(n, -1);  // column -> block index in the current row
    for (long i = 0; i < n; ++i) {
        const long first = lu_.rowStart[i], last = lu_.rowStart[i + 1];
        for (long b = first; b < last; ++b) where[lu_.cols[b]] = b;
        for (long b = first; b < last; ++b) {
            const long k = lu_.cols[b];
            if (k >= i) break;
            // L_ik = A_ik U_kk^-1, then A_ij -= L_ik U_kj for the j > k stored in both rows.
            Map Lik(lu_.block(b));
            const Block L = Lik * ConstMap(&dinv_[kBlockSize * k]);
            Lik = L;
            for (long c = diag_[k] + 1; c < lu_.rowStart[k + 1]; ++c) {
                const long t = where[lu_.cols[c]];
                if (t < 0) continue;
                Map(lu_.block(t)).noalias() -= L * ConstMap(lu_.block(c));
            }
        }
        diag_[i] = where[i];
        if (diag_[i] < 0) {
            message_ = "ILU: row " + std::to_string(i) + " has no diagonal block";
            return false;
        }
        const Block D = ConstMap(lu_.block(diag_[i]));
        Eigen::FullPivLU<Block> lu(D);
        if (!D.allFinite() || !lu.isInvertible()) {
            message_ = "ILU: singular or non-finite pivot block in row " + std::to_string(i);
            return false;
        }
        Map dinv(&dinv_[kBlockSize * i]);
        dinv = lu.inverse();
        for (long b = first; b < last; ++b) where[lu_.cols[b]] = -1;
    }
    return true;
}

namespace {
// y -= A x for one 5x5 row-major block A.
inline void subtractBlockProduct(const double* a, const double* x, double* y) {
    for (int v = 0; v < kBlock; ++v) {
        double s = 0;
        for (int w = 0; w < kBlock; ++w) s += a[kBlock * v + w] * x[w];
        y[v] -= s;
    }
}
}  // namespace

void BlockIlu::solve(const double* b, double* x) const {
    // Plain loops over raw blocks (the compiler unrolls the 5x5 products fully); Eigen's
    // fixed-size 5-vectors made this 4-5x slower than a matrix product with as many blocks.
    const long n = lu_.rows;
    const long* cols = lu_.cols.data();
    const double* vals = lu_.values.data();
    for (long i = 0; i < n; ++i) {
        double y[kBlock];
        for (int v = 0; v < kBlock; ++v) y[v] = b[kBlock * i + v];
        for (long c = lu_.rowStart[i]; c < diag_[i]; ++c) {
            subtractBlockProduct(vals + kBlockSize * c, x + kBlock * cols[c], y);
        }
        for (int v = 0; v < kBlock; ++v) x[kBlock * i + v] = y[v];
    }
    for (long i = n - 1; i >= 0; --i) {
        double y[kBlock];
        for (int v = 0; v < kBlock; ++v) y[v] = x[kBlock * i + v];
        for (long c = diag_[i] + 1; c < lu_.rowStart[i + 1]; ++c) {
            subtractBlockProduct(vals + kBlockSize * c, x + kBlock * cols[c], y);
        }
        const double* d = &dinv_[kBlockSize * i];
        for (int v = 0; v < kBlock; ++v) {
            double s = 0;
            for (int w = 0; w < kBlock; ++w) s += d[kBlock * v + w] * y[w];
            x[kBlock * i + v] = s;
        }
    }
}

}  // namespace aero::flow
