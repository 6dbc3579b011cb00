#include "flow/BlockSparse.h"

#include <algorithm>

#include "common/Error.h"

namespace aero::flow {

long BlockSparseMatrix::find(long row, long col) const {
    const auto first = cols.begin() + rowStart[row], last = cols.begin() + rowStart[row + 1];
    const auto it = std::lower_bound(first, last, col);
    return (it != last && *it == col) ? static_cast<long>(it - cols.begin()) : -1;
}

void BlockSparseMatrix::setZero() {
    std::vector<float>().swap(singleValues);  // before the doubles are allocated again
    if (hasValues()) {
        std::fill(values.begin(), values.end(), 0.0);
    } else {
        values.assign(kBlockSize * cols.size(), 0.0);
    }
}

void BlockSparseMatrix::releaseValues() {
    std::vector<double>().swap(values);
    std::vector<float>().swap(singleValues);
}

void BlockSparseMatrix::storeSingle() {
    if (!hasValues()) return;
    singleValues.resize(values.size());
    const long n = static_cast<long>(values.size());
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) singleValues[i] = static_cast<float>(values[i]);
    std::vector<double>().swap(values);
}

namespace {

template <class T>
void multRows(const BlockSparseMatrix& A, const T* values, const double* x, double* y) {
#pragma omp parallel for schedule(static)
    for (long r = 0; r < A.rows; ++r) {
        double acc[kBlock] = {};
        for (long b = A.rowStart[r]; b < A.rowStart[r + 1]; ++b) {
            const T* a = &values[kBlockSize * b];
            const double* xc = x + kBlock * A.cols[b];
            for (int v = 0; v < kBlock; ++v) {
                double s = 0;
                for (int w = 0; w < kBlock; ++w) s += static_cast<double>(a[kBlock * v + w]) * xc[w];
                acc[v] += s;
            }
        }
        for (int v = 0; v < kBlock; ++v) y[kBlock * r + v] = acc[v];
    }
}

}  // namespace

void BlockSparseMatrix::mult(const double* x, double* y) const {
    if (single()) {  // storeSingle() freed the doubles
        multRows(*this, singleValues.data(), x, y);
    } else {
        multRows(*this, values.data(), x, y);
    }
}

bool BlockSparseMatrix::prepareTranspose() {
    std::vector<long> t(cols.size());
    bool symmetric = true;
#pragma omp parallel for schedule(static) reduction(&& : symmetric)
    for (long r = 0; r < rows; ++r) {
        for (long b = rowStart[r]; b < rowStart[r + 1]; ++b) {
            t[b] = find(cols[b], r);
            symmetric = symmetric && t[b] >= 0;
        }
    }
    if (!symmetric) return false;
    transposeBlock = std::move(t);
    return true;
}

void BlockSparseMatrix::multTranspose(const double* x, double* y) const {
    if (static_cast<long>(transposeBlock.size()) == blockCount()) {
        // y_c = sum over the rows r of column c (= the columns of row c) of A_rc^T x_r, in
        // increasing r: the order in which the sequential scatter below adds them.
#pragma omp parallel for schedule(static)
        for (long c = 0; c < rows; ++c) {
            double acc[kBlock] = {};
            for (long e = rowStart[c]; e < rowStart[c + 1]; ++e) {
                const double* a = &values[kBlockSize * transposeBlock[e]];
                const double* xr = x + kBlock * cols[e];
                for (int v = 0; v < kBlock; ++v) {
                    for (int w = 0; w < kBlock; ++w) acc[w] += a[kBlock * v + w] * xr[v];
                }
            }
            for (int w = 0; w < kBlock; ++w) y[kBlock * c + w] = acc[w];
        }
        return;
    }
    std::fill(y, y + kBlock * rows, 0.0);
    for (long r = 0; r < rows; ++r) {
        const double* xr = x + kBlock * r;
        for (long b = rowStart[r]; b < rowStart[r + 1]; ++b) {
            const double* a = &values[kBlockSize * b];
            double* yc = y + kBlock * cols[b];
            for (int v = 0; v < kBlock; ++v) {
                for (int w = 0; w < kBlock; ++w) yc[w] += a[kBlock * v + w] * xr[v];
            }
        }
    }
}

bool BlockSparseMatrix::transposeInPlace() {
    // The partner of every block (pattern only: it stays valid for the transposed values).
    if (static_cast<long>(transposeBlock.size()) != blockCount() && !prepareTranspose()) return false;
    // Each pair {(r, c), (c, r)} once, from its upper block (c >= r); the diagonal blocks are
    // their own partners.
#pragma omp parallel for schedule(static)
    for (long r = 0; r < rows; ++r) {
        for (long b = rowStart[r]; b < rowStart[r + 1]; ++b) {
            if (cols[b] < r) continue;
            double* a = &values[kBlockSize * b];
            double* t = &values[kBlockSize * transposeBlock[b]];
            double at[kBlockSize], tt[kBlockSize];
            for (int v = 0; v < kBlock; ++v) {
                for (int w = 0; w < kBlock; ++w) {
                    at[kBlock * v + w] = a[kBlock * w + v];
                    tt[kBlock * v + w] = t[kBlock * w + v];
                }
            }
            std::copy(tt, tt + kBlockSize, a);
            std::copy(at, at + kBlockSize, t);  // a diagonal block (t == a): both are its transpose
        }
    }
    return true;
}

void BlockSparseMatrix::addDiagonal(const double* d) {
#pragma omp parallel for schedule(static)
    for (long r = 0; r < rows; ++r) {
        const long b = find(r, r);
        AERO_ASSERT(b >= 0);
        double* a = &values[kBlockSize * b];
        for (int v = 0; v < kBlock; ++v) a[kBlock * v + v] += d[r];
    }
}

BlockSparseMatrix makeBlockSparse(const std::vector<std::vector<long>>& columns, bool values) {
    BlockSparseMatrix A;
    A.rows = static_cast<long>(columns.size());
    A.rowStart.assign(A.rows + 1, 0);
    std::vector<long> row;
    for (long r = 0; r < A.rows; ++r) {
        row = columns[r];
        std::sort(row.begin(), row.end());
        row.erase(std::unique(row.begin(), row.end()), row.end());
        A.cols.insert(A.cols.end(), row.begin(), row.end());
        A.rowStart[r + 1] = static_cast<long>(A.cols.size());
    }
    if (values) A.values.assign(kBlockSize * A.cols.size(), 0.0);
    return A;
}

}  // namespace aero::flow
