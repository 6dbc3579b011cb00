#include "flow/BlockIlu.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace aero::flow {

namespace {

// Rows [first, last) of the permuted vector w from b (w_i = b_order[i]), and back into x.
void gatherRows(const double* b, const long* order, long first, long last, double* w) {
    for (long i = first; i < last; ++i) {
        for (int v = 0; v < kBlock; ++v) w[kBlock * i + v] = b[kBlock * order[i] + v];
    }
}

void scatterRows(const double* w, const long* order, long first, long last, double* x) {
    for (long i = first; i < last; ++i) {
        for (int v = 0; v < kBlock; ++v) x[kBlock * order[i] + v] = w[kBlock * i + v];
    }
}
using Block = Eigen::Matrix<double, kBlock, kBlock, Eigen::RowMajor>;
// A factor value computed in double, stored in the factors' precision.
inline void storeRounded(double v, double& to) { to = v; }
inline void storeRounded(double v, float& to) { to = static_cast<float>(v); }
inline void storeRounded(double v, Bf16& to) { to = Bf16::round(static_cast<float>(v)); }
using Map = Eigen::Map<Block>;
using ConstMap = Eigen::Map<const Block>;
}  // namespace

IluOrdering partitionOrdering(const BlockSparseMatrix& A, const std::vector<int>& partOfRow,
                              int parts) {
    if (parts < 1 || static_cast<long>(partOfRow.size()) != A.rows) {
        throw std::invalid_argument("partitionOrdering: " + std::to_string(partOfRow.size()) +
                                    " part numbers for " + std::to_string(A.rows) + " rows, " +
                                    std::to_string(parts) + " parts");
    }
    // Of every stored block (r, c) linking two parts, the row of the higher part goes to the
    // separator; then no block links two parts' remaining rows. (One side of each cut suffices;
    // both sides double the separator, and on the small half-sphere took as many GMRES
    // iterations: 592 against 594, both about 27 % more than the natural order's 465.)
    std::vector<int> group(A.rows);
    for (long r = 0; r < A.rows; ++r) {
        const int p = partOfRow[r];
        if (p < 0 || p >= parts) {
            throw std::invalid_argument("partitionOrdering: row " + std::to_string(r) +
                                        " has part " + std::to_string(p));
        }
        group[r] = p;
    }
    for (long r = 0; r < A.rows; ++r) {
        for (long b = A.rowStart[r]; b < A.rowStart[r + 1]; ++b) {
            const long c = A.cols[b];
            if (partOfRow[c] == partOfRow[r]) continue;
            group[partOfRow[c] > partOfRow[r] ? c : r] = parts;
        }
    }
    IluOrdering o;
    o.partStart.assign(parts + 2, 0);
    for (long r = 0; r < A.rows; ++r) ++o.partStart[group[r] + 1];
    for (int p = 0; p <= parts; ++p) o.partStart[p + 1] += o.partStart[p];
    o.order.resize(A.rows);
    std::vector<long> next(o.partStart.begin(), o.partStart.end() - 1);
    for (long r = 0; r < A.rows; ++r) o.order[next[group[r]]++] = r;
    return o;
}

void BlockIlu::setOrdering(IluOrdering ordering) {
    ordering_ = std::move(ordering);
    analyzedRows_ = -1;  // the pattern must be analyzed again in the new order
}

void BlockIlu::analyze(const BlockSparseMatrix& A, int fill) {
    const long n = A.rows;
    if (static_cast<long>(ordering_.order.size()) != n) {
        // No (or a stale) ordering: the matrix's own order as one part.
        ordering_.order.resize(n);
        for (long i = 0; i < n; ++i) ordering_.order[i] = i;
        ordering_.partStart = {0, n, n};
    }
    position_.assign(n, -1);
    for (long i = 0; i < n; ++i) position_[ordering_.order[i]] = i;
    // Row by row in the new order: level(i, j) = min over k < i of level(i, k) + level(k, j) + 1
    // (pattern of A at level 0), keeping levels <= fill. Fill stays within a part and its
    // separator: row i's lower entries k are in i's part, whose upper entries are too.
    std::vector<std::vector<long>> cols(n);
    std::vector<std::vector<int>> levels(n);
    std::vector<int> level(n, -1);  // dense work row: -1 = absent
    std::vector<long> row;
    for (long i = 0; i < n; ++i) {
        const long src = ordering_.order[i];
        row.clear();
        for (long b = A.rowStart[src]; b < A.rowStart[src + 1]; ++b) row.push_back(position_[A.cols[b]]);
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
    lu_ = makeBlockSparse(cols, false);
    const std::size_t stored = kBlockSize * static_cast<std::size_t>(lu_.blockCount());
    values_.assign(precision_ == IluPrecision::Single ? stored : 0, 0.0f);
    valuesDouble_.assign(precision_ == IluPrecision::Double ? stored : 0, 0.0);
    valuesHalf_.assign(precision_ == IluPrecision::Bfloat16 ? stored : 0, Bf16{});
    source_.assign(lu_.blockCount(), -1);
    for (long r = 0; r < n; ++r) {
        for (long b = A.rowStart[r]; b < A.rowStart[r + 1]; ++b) {
            source_[lu_.find(position_[r], position_[A.cols[b]])] = b;
        }
    }
    // The column structure of the transposed solve is built by its first call (a forward solve
    // does not need its 16 bytes per stored block: 200 MB on the 903k grid).
    std::vector<long>().swap(colStart_);
    std::vector<long>().swap(colBlocks_);
    std::vector<long>().swap(colRows_);
    analyzedRows_ = n;
    analyzedBlocks_ = A.blockCount();
    fill_ = fill;
}

bool BlockIlu::factor(const BlockSparseMatrix& A, int fill) {
    if (analyzedRows_ != A.rows || analyzedBlocks_ != A.blockCount() || fill_ != fill) analyze(A, fill);
    const long n = lu_.rows;
    diag_.assign(n, -1);
    dinv_.assign(kBlockSize * static_cast<std::size_t>(n), 0.0);
    message_.clear();
    // The parts in parallel (they touch disjoint rows and read only their own), then the
    // separator, whose rows read every part's.
    const int P = ordering_.parts();
    const std::vector<long>& start = ordering_.partStart;
    std::vector<std::string> messages(P + 1);
#pragma omp parallel if (P > 1)
    {
        std::vector<long> where(n, -1);  // column -> block index in the current row
        std::vector<double> row;         // the current row's blocks in double precision
#pragma omp for schedule(dynamic, 1)
        for (int p = 0; p < P; ++p) factorRows(A, start[p], start[p + 1], where, row, messages[p]);
#pragma omp single
        {
            bool ok = true;
            for (int p = 0; p < P; ++p) ok = ok && messages[p].empty();
            if (ok) factorRows(A, start[P], start[P + 1], where, row, messages[P]);
        }
    }
    for (const std::string& m : messages) {
        if (!m.empty()) {
            message_ = m;
            return false;
        }
    }
    return true;
}

void BlockIlu::factorRows(const BlockSparseMatrix& A, long firstRow, long lastRow, std::vector<long>& where,
                          std::vector<double>& row, std::string& message) {
    for (long i = firstRow; i < lastRow; ++i) {
        const long first = lu_.rowStart[i], last = lu_.rowStart[i + 1];
        row.assign(kBlockSize * static_cast<std::size_t>(last - first), 0.0);
        for (long b = first; b < last; ++b) {
            where[lu_.cols[b]] = b;
            if (source_[b] >= 0) std::copy(A.block(source_[b]), A.block(source_[b]) + kBlockSize, &row[kBlockSize * (b - first)]);
        }
        for (long b = first; b < last; ++b) {
            const long k = lu_.cols[b];
            if (k >= i) break;
            // L_ik = A_ik U_kk^-1, then A_ij -= L_ik U_kj for the j > k stored in both rows.
            Map Lik(&row[kBlockSize * (b - first)]);
            const Block L = Lik * ConstMap(&dinv_[kBlockSize * k]);
            Lik = L;
            for (long c = diag_[k] + 1; c < lu_.rowStart[k + 1]; ++c) {
                const long t = where[lu_.cols[c]];
                if (t < 0) continue;
                Block U;  // U_kj as stored
                withValues([&](const auto* vals) {
                    for (int e = 0; e < kBlockSize; ++e) U.data()[e] = static_cast<double>(vals[kBlockSize * c + e]);
                });
                Map(&row[kBlockSize * (t - first)]).noalias() -= L * U;
            }
        }
        diag_[i] = where[i];
        for (long b = first; b < last; ++b) where[lu_.cols[b]] = -1;
        // Rows are named by their original number (the matrix's, e.g. the grid node).
        if (diag_[i] < 0) {
            message = "ILU: row " + std::to_string(ordering_.order[i]) + " has no diagonal block";
            return;
        }
        const Block D = ConstMap(&row[kBlockSize * (diag_[i] - first)]);
        Eigen::FullPivLU<Block> lu(D);
        if (!D.allFinite() || !lu.isInvertible()) {
            message = "ILU: singular or non-finite pivot block in row " + std::to_string(ordering_.order[i]);
            return;
        }
        Map dinv(&dinv_[kBlockSize * i]);
        dinv = lu.inverse();
        withValues([&](auto* vals) {
            for (std::size_t e = 0; e < row.size(); ++e) storeRounded(row[e], vals[kBlockSize * first + e]);
        });
    }
}

namespace {
// The triangular sweeps read each row's L (forward) or U (backward) blocks: a few hundred bytes
// per row, between which lie the other factor's blocks, and the backward sweep walks the rows
// downwards. The hardware prefetcher does not follow either pattern well, so each sweep asks for
// the blocks (and their column indices) of the row kPrefetchRows ahead: the solves ran 1.4x
// faster on 2 threads, 1.75x on one (bench_flow BM_IluSolve; docs/performance.md). The same
// arithmetic, so the same bits.
constexpr long kPrefetchRows = 4;

template <class V>
inline void prefetchBlocks(const V* vals, long firstBlock, long endBlock, const long* cols) {
    const char* a = reinterpret_cast<const char*>(vals + kBlockSize * firstBlock);
    const char* e = reinterpret_cast<const char*>(vals + kBlockSize * endBlock);
    for (; a < e; a += 64) __builtin_prefetch(a);
    __builtin_prefetch(cols + firstBlock);
}

// y -= A x for one 5x5 row-major block A (stored in double, single or bfloat16 precision).
template <class V>
inline void subtractBlockProduct(const V* a, const double* x, double* y) {
    for (int v = 0; v < kBlock; ++v) {
        double s = 0;
        for (int w = 0; w < kBlock; ++w) s += a[kBlock * v + w] * x[w];
        y[v] -= s;
    }
}
}  // namespace

template <class V>
void BlockIlu::forwardRows(const V* vals, long first, long last, double* x) const {
    // Plain loops over raw blocks (the compiler unrolls the 5x5 products fully); Eigen's
    // fixed-size 5-vectors made this 4-5x slower than a matrix product with as many blocks.
    const long* cols = lu_.cols.data();
    for (long i = first; i < last; ++i) {
        if (i + kPrefetchRows < last) prefetchBlocks(vals, lu_.rowStart[i + kPrefetchRows], diag_[i + kPrefetchRows], cols);
        double* xi = x + kBlock * i;
        for (long c = lu_.rowStart[i]; c < diag_[i]; ++c) {
            subtractBlockProduct(vals + kBlockSize * c, x + kBlock * cols[c], xi);
        }
    }
}

template <class V>
void BlockIlu::backwardRows(const V* vals, long first, long last, double* x) const {
    const long* cols = lu_.cols.data();
    for (long i = last - 1; i >= first; --i) {
        if (i - kPrefetchRows >= first) {
            prefetchBlocks(vals, diag_[i - kPrefetchRows] + 1, lu_.rowStart[i - kPrefetchRows + 1], cols);
            const char* d = reinterpret_cast<const char*>(&dinv_[kBlockSize * (i - kPrefetchRows)]);
            for (int l = 0; l < 4; ++l) __builtin_prefetch(d + 64 * l);  // its 200-byte inverse
        }
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

void BlockIlu::solve(const double* b, double* x) const {
    // In place on the permuted vector: L y = b forward (parts in parallel, then the
    // separator), U x = y backward (the separator, then the parts in parallel). Each part gathers
    // its own rows of b before its forward sweep and scatters them into x after its backward one
    // (its sweeps read only its rows), so the permutations need no phases of their own: three
    // barriers per solve instead of five, the same arithmetic.
    const long n = lu_.rows;
    const int P = ordering_.parts();
    const std::vector<long>& start = ordering_.partStart;
    const long* order = ordering_.order.data();
    work_.resize(kBlock * static_cast<std::size_t>(n));
    double* w = work_.data();
    auto gather = [&](long first, long last) { gatherRows(b, order, first, last, w); };
    auto scatter = [&](long first, long last) { scatterRows(w, order, first, last, x); };
#pragma omp parallel if (P > 1)
    {
#pragma omp for schedule(dynamic, 1)
        for (int p = 0; p < P; ++p) {
            gather(start[p], start[p + 1]);
            withValues([&](const auto* vals) {
                forwardRows(vals, start[p], start[p + 1], w);
            });
        }
#pragma omp single
        {
            gather(start[P], start[P + 1]);
            withValues([&](const auto* vals) {
                forwardRows(vals, start[P], start[P + 1], w);
                backwardRows(vals, start[P], start[P + 1], w);
            });
            scatter(start[P], start[P + 1]);  // (the parts read the separator's rows of w, not x)
        }
#pragma omp for schedule(dynamic, 1)
        for (int p = 0; p < P; ++p) {
            withValues([&](const auto* vals) {
                backwardRows(vals, start[p], start[p + 1], w);
            });
            scatter(start[p], start[p + 1]);
        }
    }
}

template <class V>
void BlockIlu::transposeForwardRows(const V* vals, long first, long last, double* x) const {
    // P A P^T = L U, so A^T = P^T U^T L^T P. U^T y = x forward: row i of U^T is column i of U,
    // the blocks U_ji (j < i), gathered in increasing j; then y_i = U_ii^-T (x_i - sum).
    for (long i = first; i < last; ++i) {
        double* xi = x + kBlock * i;
        for (long e = colStart_[i]; e < colStart_[i + 1]; ++e) {
            const long j = colRows_[e];
            if (j >= i) break;
            const V* a = vals + kBlockSize * colBlocks_[e];
            const double* yj = x + kBlock * j;
            for (int w = 0; w < kBlock; ++w) {
                double s = 0;
                for (int v = 0; v < kBlock; ++v) s += a[kBlock * v + w] * yj[v];  // U_ji^T y_j
                xi[w] -= s;
            }
        }
        const double* dinv = &dinv_[kBlockSize * static_cast<std::size_t>(i)];
        double y[kBlock];
        for (int v = 0; v < kBlock; ++v) {
            double s = 0;
            for (int w = 0; w < kBlock; ++w) s += dinv[kBlock * w + v] * xi[w];  // (U_ii^-1)^T
            y[v] = s;
        }
        for (int v = 0; v < kBlock; ++v) xi[v] = y[v];
    }
}

template <class V>
void BlockIlu::transposeBackwardRows(const V* vals, long first, long last, double* x) const {
    // L^T z = y backward: row k of L^T is column k of L, the blocks L_ik (i > k), gathered in
    // decreasing i (the order in which the column-oriented sweep used to scatter them).
    for (long k = last - 1; k >= first; --k) {
        double* xk = x + kBlock * k;
        for (long e = colStart_[k + 1] - 1; e >= colStart_[k]; --e) {
            const long i = colRows_[e];
            if (i <= k) break;
            const V* a = vals + kBlockSize * colBlocks_[e];
            const double* zi = x + kBlock * i;
            for (int w = 0; w < kBlock; ++w) {
                double s = 0;
                for (int v = 0; v < kBlock; ++v) s += a[kBlock * v + w] * zi[v];  // L_ik^T z_i
                xk[w] -= s;
            }
        }
    }
}

void BlockIlu::buildColumns() const {
    const long n = lu_.rows;
    // For every row i, the blocks (j, i), j != i, in increasing j (a counting sort over the
    // blocks in row order keeps j increasing).
    colStart_.assign(n + 1, 0);
    for (long b = 0; b < lu_.blockCount(); ++b) ++colStart_[lu_.cols[b] + 1];
    for (long i = 0; i < n; ++i) colStart_[i + 1] += colStart_[i];
    colBlocks_.resize(lu_.blockCount());
    colRows_.resize(lu_.blockCount());
    {
        std::vector<long> next(colStart_.begin(), colStart_.end() - 1);
        for (long r = 0; r < n; ++r) {
            for (long b = lu_.rowStart[r]; b < lu_.rowStart[r + 1]; ++b) {
                const long at = next[lu_.cols[b]]++;
                colBlocks_[at] = b;
                colRows_[at] = r;
            }
        }
    }
}

void BlockIlu::solveTranspose(const double* b, double* x) const {
    if (static_cast<long>(colStart_.size()) != lu_.rows + 1) buildColumns();
    // Mirrors solve(): the rows of part p meet only rows of part p (and the separator, which comes
    // last) in L and U, so U^T's forward sweep runs the parts in parallel and then the
    // separator; L^T's backward sweep the separator first, then the parts. The same arithmetic
    // in the same order on any number of threads.
    const long n = lu_.rows;
    const int P = ordering_.parts();
    const std::vector<long>& start = ordering_.partStart;
    const long* order = ordering_.order.data();
    work_.resize(kBlock * static_cast<std::size_t>(n));
    double* w = work_.data();
    auto gather = [&](long first, long last) { gatherRows(b, order, first, last, w); };
    auto scatter = [&](long first, long last) { scatterRows(w, order, first, last, x); };
#pragma omp parallel if (P > 1)
    {
#pragma omp for schedule(dynamic, 1)
        for (int p = 0; p < P; ++p) {
            gather(start[p], start[p + 1]);
            withValues([&](const auto* vals) {
                transposeForwardRows(vals, start[p], start[p + 1], w);
            });
        }
#pragma omp single
        {
            gather(start[P], start[P + 1]);
            withValues([&](const auto* vals) {
                transposeForwardRows(vals, start[P], start[P + 1], w);
                transposeBackwardRows(vals, start[P], start[P + 1], w);
            });
            scatter(start[P], start[P + 1]);
        }
#pragma omp for schedule(dynamic, 1)
        for (int p = 0; p < P; ++p) {
            withValues([&](const auto* vals) {
                transposeBackwardRows(vals, start[p], start[p + 1], w);
            });
            scatter(start[p], start[p + 1]);
        }
    }
}

}  // namespace aero::flow
