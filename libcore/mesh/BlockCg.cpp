#include "mesh/BlockCg.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace aero::mesh {

namespace {

// 3x3 row-major helpers.
// c -= a b^T
inline void subtractABt(const double* a, const double* b, double* c) {
    for (int r = 0; r < 3; ++r) {
        for (int s = 0; s < 3; ++s) c[3 * r + s] -= a[3 * r] * b[3 * s] + a[3 * r + 1] * b[3 * s + 1] + a[3 * r + 2] * b[3 * s + 2];
    }
}

// c = a b
inline void multiply(const double* a, const double* b, double* c) {
    for (int r = 0; r < 3; ++r) {
        for (int s = 0; s < 3; ++s) c[3 * r + s] = a[3 * r] * b[s] + a[3 * r + 1] * b[3 + s] + a[3 * r + 2] * b[6 + s];
    }
}

// y -= a x (a in double, or in float for the stored factor; sums in double)
template <class T>
inline void subtractAx(const T* a, const double* x, double* y) {
    y[0] -= a[0] * x[0] + a[1] * x[1] + a[2] * x[2];
    y[1] -= a[3] * x[0] + a[4] * x[1] + a[5] * x[2];
    y[2] -= a[6] * x[0] + a[7] * x[1] + a[8] * x[2];
}

// y -= a^T x
template <class T>
inline void subtractAtx(const T* a, const double* x, double* y) {
    y[0] -= a[0] * x[0] + a[3] * x[1] + a[6] * x[2];
    y[1] -= a[1] * x[0] + a[4] * x[1] + a[7] * x[2];
    y[2] -= a[2] * x[0] + a[5] * x[1] + a[8] * x[2];
}

// The inverse of the symmetric block d (its lower triangle is used) through its Cholesky factor;
// false when a pivot is not above `floor` (not positive definite to working accuracy).
bool invertSpd(const double* d, double floor, double* inv) {
    const double c00sq = d[0];
    if (!(c00sq > floor)) return false;
    const double c00 = std::sqrt(c00sq);
    const double c10 = d[3] / c00, c20 = d[6] / c00;
    const double c11sq = d[4] - c10 * c10;
    if (!(c11sq > floor)) return false;
    const double c11 = std::sqrt(c11sq);
    const double c21 = (d[7] - c20 * c10) / c11;
    const double c22sq = d[8] - c20 * c20 - c21 * c21;
    if (!(c22sq > floor)) return false;
    const double c22 = std::sqrt(c22sq);
    // G = C^{-1} (lower triangular), inv = G^T G.
    const double g00 = 1 / c00, g11 = 1 / c11, g22 = 1 / c22;
    const double g10 = -c10 * g00 * g11;
    const double g21 = -c21 * g11 * g22;
    const double g20 = -(c20 * g00 + c21 * g10) * g22;
    inv[0] = g00 * g00 + g10 * g10 + g20 * g20;
    inv[1] = inv[3] = g10 * g11 + g20 * g21;
    inv[2] = inv[6] = g20 * g22;
    inv[4] = g11 * g11 + g21 * g21;
    inv[5] = inv[7] = g21 * g22;
    inv[8] = g22 * g22;
    return true;
}

// Dot product in fixed chunks summed in order: the same bits for any thread count.
constexpr long kChunk = 4096;

double dot(const std::vector<double>& a, const std::vector<double>& b) {
    const long n = static_cast<long>(a.size());
    const long chunks = (n + kChunk - 1) / kChunk;
    std::vector<double> partial(chunks, 0.0);
#pragma omp parallel for schedule(static)
    for (long c = 0; c < chunks; ++c) {
        double s = 0;
        const long end = std::min(n, (c + 1) * kChunk);
        for (long i = c * kChunk; i < end; ++i) s += a[i] * b[i];
        partial[c] = s;
    }
    double s = 0;
    for (double p : partial) s += p;
    return s;
}

}  // namespace

void Block3Matrix::mult(const double* x, double* y) const {
#pragma omp parallel for schedule(static)
    for (int r = 0; r < rows; ++r) {
        double acc[3] = {0, 0, 0};
        for (int t = rowStart[r]; t < rowStart[r + 1]; ++t) subtractAx(&values[9 * static_cast<std::size_t>(t)], x + 3 * static_cast<std::size_t>(cols[t]), acc);
        y[3 * static_cast<std::size_t>(r)] = -acc[0];
        y[3 * static_cast<std::size_t>(r) + 1] = -acc[1];
        y[3 * static_cast<std::size_t>(r) + 2] = -acc[2];
    }
}

Block3Matrix makeBlock3Pattern(std::vector<std::vector<int>> columns) {
    Block3Matrix A;
    A.rows = static_cast<int>(columns.size());
    A.rowStart.assign(A.rows + 1, 0);
    for (int r = 0; r < A.rows; ++r) {
        std::vector<int>& c = columns[r];
        c.push_back(r);
        std::sort(c.begin(), c.end());
        c.erase(std::unique(c.begin(), c.end()), c.end());
        A.rowStart[r + 1] = A.rowStart[r] + static_cast<int>(c.size());
    }
    A.cols.reserve(A.rowStart[A.rows]);
    for (const auto& c : columns) A.cols.insert(A.cols.end(), c.begin(), c.end());
    A.values.assign(9 * A.cols.size(), 0.0);
    return A;
}

void BlockIncompleteCholesky::order(const Block3Matrix& A) {
    const int n = A.rows;
    // Breadth-first levels from a peripheral row (the last row reached from row 0, then again
    // from there); a further component continues the numbering one level past the deepest, so
    // no level touches two components.
    std::vector<int> level(n, -1), queue;
    queue.reserve(n);
    auto sweep = [&](int start, int first) {
        level[start] = first;
        queue.assign(1, start);
        for (std::size_t h = 0; h < queue.size(); ++h) {
            const int v = queue[h];
            for (int t = A.rowStart[v]; t < A.rowStart[v + 1]; ++t) {
                const int w = A.cols[t];
                if (level[w] < 0) {
                    level[w] = level[v] + 1;
                    queue.push_back(w);
                }
            }
        }
        return queue.back();
    };
    int deepest = -1;
    for (int v = 0; v < n; ++v) {
        if (level[v] >= 0) continue;
        const int far = sweep(v, 0);
        for (int w : queue) level[w] = -1;  // the second sweep, from the far end, gives the levels
        sweep(far, deepest < 0 ? 0 : deepest + 2);
        for (int w : queue) deepest = std::max(deepest, level[w]);
    }
    // The separating level that balances the parts best (none for tiny matrices).
    int split = -1;
    if (n >= 64) {
        std::vector<int> count(std::max(0, deepest + 1), 0);
        for (int v = 0; v < n; ++v) ++count[level[v]];
        long below = 0, bestImbalance = n;
        for (int l = 0; l <= deepest; ++l) {
            const long above = n - below - count[l];
            const long imbalance = std::abs(above - below) + count[l];
            if (below > 0 && above > 0 && imbalance < bestImbalance) {
                bestImbalance = imbalance;
                split = l;
            }
            below += count[l];
        }
    }
    perm_.clear();
    perm_.reserve(n);
    for (int v = 0; v < n; ++v)
        if (split < 0 || level[v] < split) perm_.push_back(v);
    partEnd_[0] = static_cast<int>(perm_.size());
    for (int v = 0; v < n; ++v)
        if (split >= 0 && level[v] > split) perm_.push_back(v);
    partEnd_[1] = static_cast<int>(perm_.size());
    if (split >= 0) {
        std::stable_sort(perm_.begin(), perm_.begin() + partEnd_[0], [&](int a, int b) { return level[a] < level[b]; });
        std::stable_sort(perm_.begin() + partEnd_[0], perm_.end(), [&](int a, int b) { return level[a] > level[b]; });
    }
    for (int v = 0; v < n; ++v)
        if (split >= 0 && level[v] == split) perm_.push_back(v);
    // The lower pattern in the new numbering, each block's source in A.
    std::vector<int> inverse(n);
    for (int i = 0; i < n; ++i) inverse[perm_[i]] = i;
    lowerStart_.assign(n + 1, 0);
    lowerCols_.clear();
    lowerSource_.clear();
    diagSource_.assign(n, -1);
    std::vector<std::pair<int, int>> row;
    for (int i = 0; i < n; ++i) {
        const int v = perm_[i];
        row.clear();
        for (int t = A.rowStart[v]; t < A.rowStart[v + 1]; ++t) {
            const int j = inverse[A.cols[t]];
            if (j < i) row.emplace_back(j, t);
            if (j == i) diagSource_[i] = t;
        }
        std::sort(row.begin(), row.end());
        for (const auto& [j, t] : row) {
            lowerCols_.push_back(j);
            lowerSource_.push_back(t);
        }
        lowerStart_[i + 1] = static_cast<int>(lowerCols_.size());
    }
    patternStart_ = A.rowStart;
    patternCols_ = A.cols;
}

bool BlockIncompleteCholesky::compute(const Block3Matrix& A) {
    if (A.rows != rows_ || A.rowStart != patternStart_ || A.cols != patternCols_) {
        rows_ = A.rows;
        order(A);
    }
    // Overwritten before they are read; resize keeps the buffers of an earlier factorization.
    lower_.resize(9 * lowerCols_.size());
    pivotInv_.resize(9 * static_cast<std::size_t>(rows_));
    double sigma = 0;
    for (int attempt = 0; attempt <= 12; ++attempt) {
        if (factor(A, sigma)) {
            shift_ = sigma;
            // The solves read the factor rounded to float: half the memory traffic of the
            // triangular solves, which are most of a CG iteration; the vectors and sums stay double.
            lowerSingle_.assign(lower_.begin(), lower_.end());
            pivotSingle_.assign(pivotInv_.begin(), pivotInv_.end());
            return true;
        }
        sigma = sigma == 0 ? 1e-3 : 2 * sigma;
    }
    return false;
}

bool BlockIncompleteCholesky::factorRows(const Block3Matrix& A, double sigma, int begin, int end,
                                         std::vector<int>& position) {
    for (int i = begin; i < end; ++i) {
        const int b0 = lowerStart_[i], b1 = lowerStart_[i + 1];
        // W_ik = L_ik D_k = A_ik - sum_{j < k} W_ij L_kj^T over j in both rows' patterns.
        for (int t = b0; t < b1; ++t) {
            position[lowerCols_[t]] = t;
            std::copy_n(&A.values[9 * static_cast<std::size_t>(lowerSource_[t])], 9, &lower_[9 * static_cast<std::size_t>(t)]);
        }
        for (int t = b0; t < b1; ++t) {
            const int k = lowerCols_[t];
            double* w = &lower_[9 * static_cast<std::size_t>(t)];
            for (int s = lowerStart_[k]; s < lowerStart_[k + 1]; ++s) {
                const int p = position[lowerCols_[s]];
                if (p >= 0) subtractABt(&lower_[9 * static_cast<std::size_t>(p)], &lower_[9 * static_cast<std::size_t>(s)], w);
            }
        }
        // D_i = A_ii - sum_k W_ik L_ik^T, L_ik = W_ik D_k^{-1}.
        double d[9];
        std::copy_n(&A.values[9 * static_cast<std::size_t>(diagSource_[i])], 9, d);
        const double scale = std::max({std::abs(d[0]), std::abs(d[4]), std::abs(d[8])});
        for (int c = 0; c < 3; ++c) d[4 * c] *= 1 + sigma;
        for (int t = b0; t < b1; ++t) {
            double* w = &lower_[9 * static_cast<std::size_t>(t)];
            double l[9];
            multiply(w, &pivotInv_[9 * static_cast<std::size_t>(lowerCols_[t])], l);
            subtractABt(w, l, d);
            std::copy_n(l, 9, w);
            position[lowerCols_[t]] = -1;
        }
        if (!invertSpd(d, 1e-13 * scale, &pivotInv_[9 * static_cast<std::size_t>(i)])) return false;
    }
    return true;
}

bool BlockIncompleteCholesky::factor(const Block3Matrix& A, double sigma) {
    // The parts' rows reach only their own part's columns, so they share `position` without
    // touching the same entries.
    positionWork_.assign(rows_, -1);
    bool ok[2] = {true, true};
#pragma omp parallel for schedule(static, 1)
    for (int p = 0; p < 2; ++p) ok[p] = factorRows(A, sigma, p == 0 ? 0 : partEnd_[0], partEnd_[p], positionWork_);
    return ok[0] && ok[1] && factorRows(A, sigma, partEnd_[1], rows_, positionWork_);
}

void BlockIncompleteCholesky::solve(const double* r, double* z) const {
    const std::size_t n = 3 * static_cast<std::size_t>(rows_);
    work_.resize(2 * n);
    double* y = work_.data();
    double* x = y + n;
    // (I + L) y = P r, then x = D^{-1} y: the parts at once, then the separator.
    auto forward = [&](int begin, int end) {
        for (int i = begin; i < end; ++i) {
            // The row's sums in registers (y_i cannot alias the y_j it reads, but the compiler
            // cannot know that): the same operations in the same order as in memory.
            const double* ri = r + 3 * static_cast<std::size_t>(perm_[i]);
            double yi[3] = {ri[0], ri[1], ri[2]};
            for (int t = lowerStart_[i]; t < lowerStart_[i + 1]; ++t) {
                subtractAx(&lowerSingle_[9 * static_cast<std::size_t>(t)], y + 3 * static_cast<std::size_t>(lowerCols_[t]), yi);
            }
            std::copy_n(yi, 3, y + 3 * static_cast<std::size_t>(i));
            const float* p = &pivotSingle_[9 * static_cast<std::size_t>(i)];
            double* xi = x + 3 * static_cast<std::size_t>(i);
            xi[0] = p[0] * yi[0] + p[1] * yi[1] + p[2] * yi[2];
            xi[1] = p[3] * yi[0] + p[4] * yi[1] + p[5] * yi[2];
            xi[2] = p[6] * yi[0] + p[7] * yi[1] + p[8] * yi[2];
        }
    };
    // (I + L)^T x = D^{-1} y in place, by columns (x_i is final once the rows below have passed),
    // then z = P^T x: the separator first, then the parts at once.
    auto backward = [&](int begin, int end) {
        for (int i = end - 1; i >= begin; --i) {
            const double xi[3] = {x[3 * static_cast<std::size_t>(i)], x[3 * static_cast<std::size_t>(i) + 1],
                                  x[3 * static_cast<std::size_t>(i) + 2]};  // final: read once
            for (int t = lowerStart_[i]; t < lowerStart_[i + 1]; ++t) {
                subtractAtx(&lowerSingle_[9 * static_cast<std::size_t>(t)], xi, x + 3 * static_cast<std::size_t>(lowerCols_[t]));
            }
            double* zi = z + 3 * static_cast<std::size_t>(perm_[i]);
            zi[0] = xi[0];
            zi[1] = xi[1];
            zi[2] = xi[2];
        }
    };
#pragma omp parallel for schedule(static, 1)
    for (int p = 0; p < 2; ++p) forward(p == 0 ? 0 : partEnd_[0], partEnd_[p]);
    forward(partEnd_[1], rows_);
    backward(partEnd_[1], rows_);
#pragma omp parallel for schedule(static, 1)
    for (int p = 0; p < 2; ++p) backward(p == 0 ? 0 : partEnd_[0], partEnd_[p]);
}

CgReport conjugateGradients(const Block3Matrix& A, const BlockIncompleteCholesky& M, const std::vector<double>& b,
                            std::vector<double>& x, double tolerance, int maxIterations) {
    CgWorkspace work;
    return conjugateGradients(A, M, b, x, tolerance, maxIterations, work);
}

CgReport conjugateGradients(const Block3Matrix& A, const BlockIncompleteCholesky& M, const std::vector<double>& b,
                            std::vector<double>& x, double tolerance, int maxIterations, CgWorkspace& work) {
    CgReport rep;
    const long n = static_cast<long>(b.size());
    x.resize(n, 0.0);
    const double bb = dot(b, b);
    if (bb == 0) {
        std::fill(x.begin(), x.end(), 0.0);
        rep.converged = true;
        return rep;
    }
    // Every element of the work vectors is written before it is read.
    for (std::vector<double>* v : {&work.r, &work.z, &work.p, &work.q}) v->resize(n);
    std::vector<double>& r = work.r;
    std::vector<double>& z = work.z;
    std::vector<double>& p = work.p;
    std::vector<double>& q = work.q;
    A.mult(x.data(), q.data());
    for (long i = 0; i < n; ++i) r[i] = b[i] - q[i];
    const double threshold = std::max(tolerance * tolerance * bb, std::numeric_limits<double>::min());
    double rr = dot(r, r);
    if (rr >= threshold) {
        M.solve(r.data(), p.data());
        double rz = dot(r, p);
        while (rep.iterations < maxIterations) {
            A.mult(p.data(), q.data());
            const double alpha = rz / dot(p, q);
            ++rep.iterations;
#pragma omp parallel for schedule(static)
            for (long i = 0; i < n; ++i) {
                x[i] += alpha * p[i];
                r[i] -= alpha * q[i];
            }
            rr = dot(r, r);
            if (!(rr >= threshold)) break;  // converged, or NaN (reported by the residual)
            M.solve(r.data(), z.data());
            const double rzNew = dot(r, z);
            const double beta = rzNew / rz;
            rz = rzNew;
#pragma omp parallel for schedule(static)
            for (long i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
        }
    }
    rep.residual = std::sqrt(rr / bb);
    rep.converged = rep.residual <= tolerance;
    return rep;
}

std::vector<double> galerkinGuess(const Block3Matrix& A, const std::vector<std::vector<double>>& basis,
                                  const std::vector<double>& b) {
    CgWorkspace work;
    return galerkinGuess(A, basis, b, work);
}

std::vector<double> galerkinGuess(const Block3Matrix& A, const std::vector<std::vector<double>>& basis,
                                  const std::vector<double>& b, CgWorkspace& work) {
    const std::size_t n = b.size();
    std::vector<double> x(n, 0.0);
    // The A-orthonormal vectors and their products: the first `count` entries of work.w and
    // work.Aw, whose vectors are kept for the next call.
    std::vector<std::vector<double>>& w = work.w;
    std::vector<std::vector<double>>& Aw = work.Aw;
    std::size_t count = 0;
    for (const std::vector<double>& v0 : basis) {
        if (w.size() <= count) {
            w.emplace_back();
            Aw.emplace_back();
        }
        std::vector<double>& v = w[count];
        std::vector<double>& Av = Aw[count];
        v.assign(v0.begin(), v0.end());
        Av.resize(n);
        A.mult(v.data(), Av.data());
        const double norm0 = dot(v, Av);
        if (!(norm0 > 0)) continue;
        for (std::size_t j = 0; j < count; ++j) {
            const double c = dot(Aw[j], v);
            for (std::size_t i = 0; i < n; ++i) {
                v[i] -= c * w[j][i];
                Av[i] -= c * Aw[j][i];
            }
        }
        const double norm = dot(v, Av);
        if (!(norm > 1e-16 * norm0)) continue;
        const double s = 1 / std::sqrt(norm);
        for (std::size_t i = 0; i < n; ++i) {
            v[i] *= s;
            Av[i] *= s;
        }
        const double c = dot(v, b);
        for (std::size_t i = 0; i < n; ++i) x[i] += c * v[i];
        ++count;  // kept: the next basis vector is orthogonalized against it
    }
    return x;
}

}  // namespace aero::mesh
