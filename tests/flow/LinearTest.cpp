// Block ILU and GMRES: exact where the theory says so, and the preconditioned solve converges.
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "RandomVector.h"
#include "flow/BlockIlu.h"
#include "flow/Gmres.h"

using namespace aero::flow;

namespace {

// A random, diagonally dominant block matrix on the pattern of an nx x ny 5-point grid
// (or a 1D chain when ny == 1).
BlockSparseMatrix gridMatrix(int nx, int ny, unsigned seed) {
    std::vector<std::vector<long>> cols(static_cast<std::size_t>(nx) * ny);
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            auto& c = cols[i + nx * j];
            c.push_back(i + nx * j);
            if (i > 0) c.push_back(i - 1 + nx * j);
            if (i < nx - 1) c.push_back(i + 1 + nx * j);
            if (j > 0) c.push_back(i + nx * (j - 1));
            if (j < ny - 1) c.push_back(i + nx * (j + 1));
        }
    }
    BlockSparseMatrix A = makeBlockSparse(cols);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    for (double& v : A.values) v = u(rng);
    std::vector<double> d(A.rows, 25.0);
    A.addDiagonal(d.data());
    return A;
}

using aero::test::randomVector;

double maxError(const BlockSparseMatrix& A, const std::vector<double>& x, const std::vector<double>& b) {
    std::vector<double> Ax(b.size());
    A.mult(x.data(), Ax.data());
    double e = 0;
    for (std::size_t i = 0; i < b.size(); ++i) e = std::max(e, std::abs(Ax[i] - b[i]));
    return e;
}

// Morgan's test matrix for deflated restarting: bidiagonal, diagonal 0.1 ... 0.5 then 1, 2, ...,
// superdiagonal 0.2; its few small eigenvalues make a restarted GMRES crawl.
LinearMap morganBidiagonal(long n) {
    std::vector<double> diag(n);
    for (long i = 0; i < n; ++i) diag[i] = i < 5 ? 0.1 * (i + 1) : static_cast<double>(i - 4);
    return [n, diag](const double* in, double* out) {
        for (long i = 0; i < n; ++i) out[i] = diag[i] * in[i] + (i + 1 < n ? 0.2 * in[i + 1] : 0.0);
    };
}

// ||rhs - op x|| / ||rhs|| (the true residual, not GMRES's estimate).
double relativeResidual(long size, const LinearMap& op, const std::vector<double>& x, const std::vector<double>& rhs) {
    std::vector<double> ax(size);
    op(x.data(), ax.data());
    double r = 0, s = 0;
    for (long i = 0; i < size; ++i) r += (rhs[i] - ax[i]) * (rhs[i] - ax[i]), s += rhs[i] * rhs[i];
    return std::sqrt(r / s);
}

}  // namespace

TEST(BlockIlu, IsExactOnABlockTridiagonalMatrix) {
    // ILU(0) of a chain has no dropped fill: it is the LU factorization.
    const BlockSparseMatrix A = gridMatrix(40, 1, 1);
    BlockIlu ilu;
    ilu.setPrecision(IluPrecision::Double);
    ASSERT_TRUE(ilu.factor(A, 0)) << ilu.message();
    const std::vector<double> b = randomVector(kBlock * A.rows, 2);
    std::vector<double> x(b.size());
    ilu.solve(b.data(), x.data());
    EXPECT_LT(maxError(A, x, b), 1e-12);
    // Stored in single precision (the default), the same factorization is exact to float rounding.
    BlockIlu single;
    ASSERT_TRUE(single.factor(A, 0)) << single.message();
    std::vector<double> xs(b.size());
    single.solve(b.data(), xs.data());
    const double e = maxError(A, xs, b);
    EXPECT_LT(e, 1e-5);
    EXPECT_GT(e, 1e-12);  // it really is rounded
    // In bfloat16 (8 significant bits): exact to that rounding, relative to the solution's size.
    BlockIlu half;
    half.setPrecision(IluPrecision::Bfloat16);
    ASSERT_TRUE(half.factor(A, 0)) << half.message();
    std::vector<double> xh(b.size());
    half.solve(b.data(), xh.data());
    const double eh = maxError(A, xh, b);
    EXPECT_LT(eh, 5e-2);
    EXPECT_GT(eh, 10 * e);
}

TEST(BlockIlu, BfloatStorageRoundsToNearestEven) {
    EXPECT_EQ(static_cast<float>(Bf16::round(1.0f)), 1.0f);
    EXPECT_EQ(static_cast<float>(Bf16::round(-3.5f)), -3.5f);
    // 1 + 2^-8 is halfway between 1 and 1 + 2^-7: to the even one, 1; just above it rounds up.
    EXPECT_EQ(static_cast<float>(Bf16::round(1.0f + 0.00390625f)), 1.0f);
    EXPECT_EQ(static_cast<float>(Bf16::round(1.0f + 0.0040f)), 1.0f + 0.0078125f);
    const float x = 0.123456f;
    EXPECT_LE(std::abs(static_cast<float>(Bf16::round(x)) - x), x / 256);
    EXPECT_EQ(sizeof(Bf16), 2u);
}

TEST(BlockIlu, ReducedPrecisionStorageKeepsGmresIterations) {
    const BlockSparseMatrix A = gridMatrix(30, 20, 7);
    const std::vector<double> b = randomVector(kBlock * A.rows, 8);
    const LinearMap Am = [&](const double* in, double* out) { A.mult(in, out); };
    int iterations[3] = {0, 0, 0};
    for (int single : {0, 1, 2}) {
        BlockIlu ilu;
        ilu.setPrecision(single == 0 ? IluPrecision::Double
                                     : (single == 1 ? IluPrecision::Single : IluPrecision::Bfloat16));
        ASSERT_TRUE(ilu.factor(A, 1));
        const LinearMap M = [&](const double* in, double* out) { ilu.solve(in, out); };
        std::vector<double> x(b.size(), 0.0);
        const GmresReport r = gmres(kBlock * A.rows, Am, M, b.data(), x.data(), {30, 200, 1e-12});
        EXPECT_LE(r.relativeResidual, 1e-12);
        EXPECT_LT(maxError(A, x, b), 1e-10);
        iterations[single] = r.iterations;
    }
    EXPECT_LE(std::abs(iterations[1] - iterations[0]), 1) << iterations[0] << " vs " << iterations[1];
    // bfloat16 factors: a slightly weaker preconditioner, still to full accuracy.
    EXPECT_LE(iterations[2], iterations[0] + iterations[0] / 5 + 1) << iterations[0] << " vs " << iterations[2];
}

TEST(BlockIlu, WithEnoughFillIsTheCompleteFactorization) {
    // The complete LU of a banded matrix has finite fill levels: a large enough p keeps all.
    const BlockSparseMatrix A = gridMatrix(6, 5, 3);
    const std::vector<double> b = randomVector(kBlock * A.rows, 4);
    std::vector<double> x(b.size());
    BlockIlu partial, complete;
    complete.setPrecision(IluPrecision::Double);
    ASSERT_TRUE(partial.factor(A, 0));
    partial.solve(b.data(), x.data());
    EXPECT_GT(maxError(A, x, b), 1e-6);  // ILU(0) drops fill: not exact here
    ASSERT_TRUE(complete.factor(A, 30));
    complete.solve(b.data(), x.data());
    EXPECT_LT(maxError(A, x, b), 1e-12);
    EXPECT_GT(complete.storedBlocks(), partial.storedBlocks());
}

TEST(BlockIlu, ReportsASingularPivotNamingTheRow) {
    BlockSparseMatrix A = gridMatrix(5, 1, 5);
    std::fill(A.block(A.find(3, 3)), A.block(A.find(3, 3)) + kBlockSize, 0.0);
    std::fill(A.block(A.find(3, 2)), A.block(A.find(3, 2)) + kBlockSize, 0.0);
    BlockIlu ilu;
    EXPECT_FALSE(ilu.factor(A, 0));
    EXPECT_NE(ilu.message().find("row 3"), std::string::npos) << ilu.message();
}

// Parts of a grid matrix: the columns i < split of an nx-wide grid are part 0, the rest part 1.
std::vector<int> columnParts(const BlockSparseMatrix& A, int nx, int split) {
    std::vector<int> part(A.rows);
    for (long r = 0; r < A.rows; ++r) part[r] = (r % nx) < split ? 0 : 1;
    return part;
}

TEST(BlockIlu, PartitionOrderingLeavesNoCouplingBetweenTheParts) {
    const BlockSparseMatrix A = gridMatrix(12, 8, 9);
    const IluOrdering o = partitionOrdering(A, columnParts(A, 12, 5), 2);
    ASSERT_EQ(o.parts(), 2);
    ASSERT_EQ(o.partStart.size(), 4u);
    std::vector<long> sorted = o.order;
    std::sort(sorted.begin(), sorted.end());
    for (long r = 0; r < A.rows; ++r) ASSERT_EQ(sorted[r], r);  // a permutation
    // One side of the cut only: the 8 rows of column 5 (part 1 next to part 0).
    EXPECT_EQ(o.partStart[3] - o.partStart[2], 8);
    std::vector<int> group(A.rows);
    for (int g = 0; g < 3; ++g) {
        for (long i = o.partStart[g]; i < o.partStart[g + 1]; ++i) group[o.order[i]] = g;
    }
    for (long r = 0; r < A.rows; ++r) {
        for (long b = A.rowStart[r]; b < A.rowStart[r + 1]; ++b) {
            const int gr = group[r], gc = group[A.cols[b]];
            EXPECT_TRUE(gr == gc || gr == 2 || gc == 2) << "rows " << r << " and " << A.cols[b];
        }
    }
    EXPECT_THROW(partitionOrdering(A, std::vector<int>(3, 0), 2), std::invalid_argument);
    EXPECT_THROW(partitionOrdering(A, std::vector<int>(A.rows, 2), 2), std::invalid_argument);
}

TEST(BlockIlu, OrderedFactorizationIsExactWithFullFillAndTheSameOnAnyThreadCount) {
    const BlockSparseMatrix A = gridMatrix(10, 7, 11);
    const std::vector<double> b = randomVector(kBlock * A.rows, 12);
    // Complete fill: the ordered factorization is an exact LU of the permuted matrix.
    BlockIlu complete;
    complete.setPrecision(IluPrecision::Double);
    complete.setOrdering(partitionOrdering(A, columnParts(A, 10, 4), 2));
    ASSERT_TRUE(complete.factor(A, 40)) << complete.message();
    std::vector<double> x(b.size());
    complete.solve(b.data(), x.data());
    EXPECT_LT(maxError(A, x, b), 1e-12);
    // ILU(1): the parts run on separate threads, with identical results on one.
    std::vector<double> x1(b.size()), x2(b.size());
    const int before = omp_get_max_threads();
    for (int threads : {1, 2}) {
        omp_set_num_threads(threads);
        BlockIlu ilu;
        ilu.setOrdering(partitionOrdering(A, columnParts(A, 10, 4), 2));
        ASSERT_TRUE(ilu.factor(A, 1)) << ilu.message();
        ilu.solve(b.data(), (threads == 1 ? x1 : x2).data());
    }
    omp_set_num_threads(before);
    EXPECT_EQ(x1, x2);
    EXPECT_LT(maxError(A, x1, b), 0.5 * maxError(A, std::vector<double>(b.size(), 0.0), b));
}

// The adjoint's preconditioner: ((L U)^T)^-1 is exact for a complete factorization (also in a
// partition ordering), and for an incomplete one it is the transpose of solve():
// <solveTranspose(a), b> = <a, solve(b)> for any a, b.
TEST(BlockIlu, TransposedSolveIsExactWithFullFillAndTheAdjointOfSolve) {
    const BlockSparseMatrix A = gridMatrix(10, 7, 11);
    const std::vector<double> b = randomVector(kBlock * A.rows, 21);
    BlockIlu complete;
    complete.setPrecision(IluPrecision::Double);
    complete.setOrdering(partitionOrdering(A, columnParts(A, 10, 4), 2));
    ASSERT_TRUE(complete.factor(A, 40)) << complete.message();
    std::vector<double> x(b.size()), Atx(b.size());
    complete.solveTranspose(b.data(), x.data());
    A.multTranspose(x.data(), Atx.data());
    double e = 0;
    for (std::size_t i = 0; i < b.size(); ++i) e = std::max(e, std::abs(Atx[i] - b[i]));
    EXPECT_LT(e, 1e-11);

    BlockIlu ilu;
    ilu.setOrdering(partitionOrdering(A, columnParts(A, 10, 4), 2));
    ASSERT_TRUE(ilu.factor(A, 1));
    const std::vector<double> a = randomVector(kBlock * A.rows, 22);
    std::vector<double> Ma(b.size()), MTa(b.size()), Mb(b.size());
    ilu.solve(b.data(), Mb.data());
    ilu.solveTranspose(a.data(), MTa.data());
    double lhs = 0, rhs = 0;
    for (std::size_t i = 0; i < b.size(); ++i) {
        lhs += MTa[i] * b[i];
        rhs += a[i] * Mb[i];
    }
    EXPECT_NEAR(lhs, rhs, 1e-12 * std::abs(rhs)) << lhs << " vs " << rhs;

    // The parts run in parallel: the same result on one thread and on two.
    const int before = omp_get_max_threads();
    std::vector<double> one(b.size()), two(b.size());
    omp_set_num_threads(1);
    ilu.solveTranspose(a.data(), one.data());
    omp_set_num_threads(2);
    ilu.solveTranspose(a.data(), two.data());
    omp_set_num_threads(before);
    EXPECT_EQ(one, two);
    EXPECT_EQ(one, MTa);
}

// A structurally unsymmetric pattern cannot be gathered by rows: prepareTranspose refuses it and
// multTranspose stays the sequential scatter.
TEST(BlockSparse, PrepareTransposeRefusesAnUnsymmetricPattern) {
    BlockSparseMatrix A = makeBlockSparse({{0, 1}, {1}});
    for (double& v : A.values) v = 1.0;
    EXPECT_FALSE(A.prepareTranspose());
    EXPECT_TRUE(A.transposeBlock.empty());
    const std::vector<double> x(10, 1.0);
    std::vector<double> y(10);
    A.multTranspose(x.data(), y.data());
    EXPECT_DOUBLE_EQ(y[0], 5.0);   // column 0: block (0, 0) only
    EXPECT_DOUBLE_EQ(y[5], 10.0);  // column 1: blocks (0, 1) and (1, 1)
}

// The adjoint stores J^T and the ILU of P^T instead of gathering transposed blocks: A^T in place
// multiplies like multTranspose, twice is the original bit for bit, and the ILU of A^T solves
// like the transposed solve of A's ILU (the incomplete factorization on a symmetric pattern with
// a unit block-diagonal L is unique: ILU(A^T) = (ILU(A))^T), also in a partition ordering.
TEST(BlockSparse, TransposeInPlaceIsTheTransposeAndItsIluTheTransposedIlu) {
    const BlockSparseMatrix A = gridMatrix(10, 7, 31);
    BlockSparseMatrix At = A;
    ASSERT_TRUE(At.transposeInPlace());
    const std::vector<double> x = randomVector(kBlock * A.rows, 32);
    std::vector<double> y1(x.size()), y2(x.size());
    A.multTranspose(x.data(), y1.data());
    At.mult(x.data(), y2.data());
    for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(y1[i], y2[i], 1e-13 * (1 + std::abs(y1[i]))) << i;
    BlockSparseMatrix back = At;
    ASSERT_TRUE(back.transposeInPlace());
    EXPECT_EQ(back.values, A.values);

    for (int fill : {0, 1}) {
        BlockIlu ilu, iluT;
        ilu.setPrecision(IluPrecision::Double);
        iluT.setPrecision(IluPrecision::Double);
        ilu.setOrdering(partitionOrdering(A, columnParts(A, 10, 4), 2));
        iluT.setOrdering(partitionOrdering(At, columnParts(At, 10, 4), 2));
        ASSERT_TRUE(ilu.factor(A, fill));
        ASSERT_TRUE(iluT.factor(At, fill));
        ilu.solveTranspose(x.data(), y1.data());
        iluT.solve(x.data(), y2.data());
        double e = 0, s = 0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            e = std::max(e, std::abs(y1[i] - y2[i]));
            s = std::max(s, std::abs(y1[i]));
        }
        EXPECT_LT(e, 1e-12 * s) << "fill " << fill;
    }

    BlockSparseMatrix unsymmetric = makeBlockSparse({{0, 1}, {1}});
    for (double& v : unsymmetric.values) v = 1.0;
    const std::vector<double> before = unsymmetric.values;
    EXPECT_FALSE(unsymmetric.transposeInPlace());
    EXPECT_EQ(unsymmetric.values, before);
}

TEST(BlockIlu, OrderedFactorizationNamesTheOriginalRowOfASingularPivot) {
    BlockSparseMatrix A = gridMatrix(6, 4, 13);
    const long bad = 2 + 6 * 3;  // in part 0, numbered differently in the ordering
    for (long c : {bad, bad - 1, bad + 1, bad - 6}) std::fill(A.block(A.find(bad, c)), A.block(A.find(bad, c)) + kBlockSize, 0.0);
    BlockIlu ilu;
    ilu.setOrdering(partitionOrdering(A, columnParts(A, 6, 3), 2));
    EXPECT_FALSE(ilu.factor(A, 0));
    EXPECT_NE(ilu.message().find("row " + std::to_string(bad)), std::string::npos) << ilu.message();
}

// The GMRES tests' system: a 30 x 20 grid of 5 x 5 blocks, a random right-hand side, and its
// ILU(1) as the preconditioner.
struct GridSystem {
    const BlockSparseMatrix A = gridMatrix(30, 20, 7);
    const long n = kBlock * A.rows;
    const std::vector<double> b = randomVector(n, 8);
    BlockIlu ilu;
    const LinearMap product = [this](const double* in, double* out) { A.mult(in, out); };
    const LinearMap preconditioner = [this](const double* in, double* out) { ilu.solve(in, out); };
    GridSystem() { EXPECT_TRUE(ilu.factor(A, 1)); }
    GridSystem(const GridSystem&) = delete;  // (the maps point at this one)
};

TEST(Gmres, PreconditionedByIluSolvesAGridSystem) {
    const GridSystem g;
    const BlockSparseMatrix& A = g.A;
    const std::vector<double>& b = g.b;
    const LinearMap &Am = g.product, &M = g.preconditioner;
    std::vector<double> x(b.size(), 0.0);
    const GmresReport r = gmres(kBlock * A.rows, Am, M, b.data(), x.data(), {30, 200, 1e-12});
    EXPECT_LE(r.relativeResidual, 1e-12);
    EXPECT_LT(r.iterations, 40);
    EXPECT_LT(maxError(A, x, b), 1e-10);
    // Giving up on hopeless systems does not touch one that converges.
    std::vector<double> x2(b.size(), 0.0);
    const GmresReport r2 = gmres(kBlock * A.rows, Am, M, b.data(), x2.data(), {30, 200, 1e-12, 0.5});
    EXPECT_FALSE(r2.gaveUp);
    EXPECT_EQ(r2.iterations, r.iterations);
    EXPECT_EQ(x2, x);
}

// Every Newton step starts GMRES from dq = 0, where the residual is b: no product is spent on
// A 0 (on the flow's exact systems a product is a complex residual evaluation). A restart and a
// nonzero initial guess still use the true residual b - A x.
TEST(Gmres, AZeroInitialGuessSpendsNoProductOnItsResidual) {
    const GridSystem g;
    const BlockSparseMatrix& A = g.A;
    const long n = g.n;
    const std::vector<double>& b = g.b;
    int products = 0, zeroInputs = 0;
    const LinearMap Am = [&](const double* in, double* out) {
        ++products;
        zeroInputs += std::all_of(in, in + n, [](double v) { return v == 0.0; });
        A.mult(in, out);
    };
    const LinearMap& M = g.preconditioner;
    std::vector<double> x(n, 0.0);
    const GmresReport r = gmres(n, Am, M, b.data(), x.data(), {2, 400, 1e-12});
    EXPECT_TRUE(r.converged);
    EXPECT_GT(r.iterations, 2);  // restarted at least once
    EXPECT_EQ(zeroInputs, 0);
    EXPECT_LT(maxError(A, x, b), 1e-8);
    // One product per iteration and one per restart's true residual (GMRES(2): a restart after
    // every second iteration).
    const int restarts = (r.iterations + 1) / 2 - 1;
    EXPECT_EQ(products, r.iterations + restarts);
    // From the converged x as the guess, the true residual is checked with a product and nothing
    // else is done.
    products = 0;
    const GmresReport again = gmres(n, Am, M, b.data(), x.data(), {8, 400, 1e-8});
    EXPECT_EQ(again.iterations, 0);
    EXPECT_EQ(products, 1);
}

// A float basis: the same systems to the same tight tolerance (GMRES checks the true residual
// before it reports convergence and restarts from it in double, so the basis's round-off does
// not limit the accuracy), with and without deflation: an ILU-preconditioned grid system (a few
// products) and Morgan's bidiagonal matrix with small eigenvalues (hundreds of products over many
// restarts).
TEST(Gmres, SingleBasisReachesTheSameAccuracy) {
    const GridSystem g;
    const BlockSparseMatrix& A = g.A;
    const std::vector<double>& b = g.b;
    const LinearMap &Am = g.product, &M = g.preconditioner;
    const long n = 1000;
    const LinearMap B = morganBidiagonal(n);
    const std::vector<double> ones(n, 1.0);
    for (int deflation : {0, 6}) {
        std::vector<double> xd(b.size(), 0.0), xs(b.size(), 0.0);
        const GmresReport d = gmres(kBlock * A.rows, Am, M, b.data(), xd.data(), {20, 400, 1e-12, 0.0, deflation});
        GmresWorkspace ws;
        const GmresReport s =
            gmres(kBlock * A.rows, Am, M, b.data(), xs.data(), {20, 400, 1e-12, 0.0, deflation, true}, &ws);
        EXPECT_TRUE(d.converged);
        EXPECT_TRUE(s.converged) << "deflation " << deflation << ": " << s.relativeResidual;
        EXPECT_LT(relativeResidual(kBlock * A.rows, Am, xs, b), 1e-11);
        EXPECT_LE(s.iterations, d.iterations + 5) << "deflation " << deflation;
        EXPECT_EQ(ws.singleVectors(), 21);
        EXPECT_EQ(ws.vectors(), 3);
        std::vector<double> yd(n, 0.0), ys(n, 0.0);
        const GmresReport bd = gmres(n, B, {}, ones.data(), yd.data(), {20, 8000, 1e-10, 0.0, deflation});
        const GmresReport bs = gmres(n, B, {}, ones.data(), ys.data(), {20, 8000, 1e-10, 0.0, deflation, true});
        EXPECT_TRUE(bs.converged) << "deflation " << deflation << ": " << bs.relativeResidual;
        EXPECT_LT(relativeResidual(n, B, ys, ones), 1e-9);
        // At a Newton step's tolerance the float basis costs no more products; at 1e-10 with
        // deflation it does (the deflated restarts' carried Arnoldi relations hold only to float
        // round-off, and after a failed true-residual check GMRES goes on with plain restarts):
        // why the adjoint keeps a double basis.
        std::vector<double> ld(n, 0.0), ls(n, 0.0);
        const GmresReport loose = gmres(n, B, {}, ones.data(), ld.data(), {20, 8000, 1e-3, 0.0, deflation});
        const GmresReport looseSingle =
            gmres(n, B, {}, ones.data(), ls.data(), {20, 8000, 1e-3, 0.0, deflation, true});
        EXPECT_TRUE(looseSingle.converged);
        EXPECT_LE(looseSingle.iterations, loose.iterations + 2) << "deflation " << deflation;
        if (deflation == 0) {
            EXPECT_LE(bs.iterations, bd.iterations + 20);
        }
        std::printf("deflation %d: grid system %d / %d products, bidiagonal to 1e-10 %d / %d, to 1e-3 %d / %d "
                    "(double / float basis)\n",
                    deflation, d.iterations, s.iterations, bd.iterations, bs.iterations, loose.iterations,
                    looseSingle.iterations);
    }
}

// The flow's Newton steps repeat a Gram-Schmidt pass only where the first cancelled 90 % of the
// new vector (GmresOptions::reorthogonalizeBelow 0.1), and a single pass always is the limit of
// that: at a Newton step's tolerances both solve as far as the DGKS GMRES in as many products,
// to a true residual at their tolerance, with either basis and with deflated restarts (a random
// grid system and Morgan's bidiagonal matrix, unpreconditioned); and they are other computations
// (DGKS's second pass ran, so the iterates differ).
TEST(Gmres, FewerGramSchmidtPassesServeANewtonStepsTolerance) {
    const GridSystem g;
    const long gn = kBlock * g.A.rows;
    const long n = 1000;  // Morgan's bidiagonal matrix
    const LinearMap B = morganBidiagonal(n);
    const std::vector<double> ones(n, 1.0);
    bool differs = false;
    for (bool once10 : {true, false}) {
        for (double tolerance : {0.05, 1e-3}) {
            for (int deflation : {0, 6}) {
                for (bool single : {false, true}) {
                    const GmresOptions twice{20, 2000, tolerance, 0.0, deflation, single, 0.7071067811865476};
                    const GmresOptions once{20, 2000, tolerance, 0.0, deflation, single, once10 ? 0.1 : 0.0};
                    const std::string what = std::string(once10 ? "below 0.1" : "one pass") + ", tolerance " +
                                             std::to_string(tolerance) + ", deflation " +
                                             std::to_string(deflation) + (single ? ", float basis" : ", double basis");
                    std::vector<double> x2(gn, 0.0), x1(gn, 0.0);
                    // Without its ILU: the preconditioned system converges in one product.
                    const GmresReport r2 = gmres(gn, g.product, {}, g.b.data(), x2.data(), twice);
                    const GmresReport r1 = gmres(gn, g.product, {}, g.b.data(), x1.data(), once);
                    EXPECT_TRUE(r1.converged) << what;
                    EXPECT_LE(r1.iterations, r2.iterations + 1) << what;
                    EXPECT_LT(relativeResidual(gn, g.product, x1, g.b), 1.01 * tolerance) << what;
                    std::vector<double> y2(n, 0.0), y1(n, 0.0);
                    const GmresReport b2 = gmres(n, B, {}, ones.data(), y2.data(), twice);
                    const GmresReport b1 = gmres(n, B, {}, ones.data(), y1.data(), once);
                    EXPECT_TRUE(b1.converged) << what;
                    EXPECT_LE(b1.iterations, b2.iterations + 2) << what;
                    EXPECT_LT(relativeResidual(n, B, y1, ones), 1.01 * tolerance) << what;
                    differs = differs || y1 != y2 || x1 != x2;
                    std::printf("%s: grid system %d / %d products, bidiagonal %d / %d (DGKS / fewer passes)\n", what.c_str(),
                                r2.iterations, r1.iterations, b2.iterations, b1.iterations);
                }
            }
        }
    }
    EXPECT_TRUE(differs) << "the option changed nothing: the second pass never ran";
}

TEST(Gmres, AFloatBasisUsesLentStorageWhenItIsLargeEnough) {
    // The low-memory flow steps lend the approximate Jacobian's block to the basis
    // (StepSystem): the solve must run in that storage, bitwise as in its own allocation, and
    // fall back to its own when the storage is too small; release() forgets the loan.
    const GridSystem g;
    const long n = g.n;
    const std::vector<double>& b = g.b;
    const LinearMap &Am = g.product, &M = g.preconditioner;
    const GmresOptions o{20, 400, 1e-10, 0.0, 0, true};
    const std::size_t bytes = GmresWorkspace::singleBytes(n, 21);
    EXPECT_EQ(bytes, static_cast<std::size_t>((n + 15) / 16 * 16) * 21 * sizeof(float));

    GmresWorkspace own;
    std::vector<double> x0(n, 0.0);
    const GmresReport r0 = gmres(n, Am, M, b.data(), x0.data(), o, &own);
    EXPECT_FALSE(own.usesLent());

    std::vector<double> storage((bytes + 7) / 8);  // as the matrix's values lend it
    GmresWorkspace lent;
    lent.lend(storage.data(), storage.size() * sizeof(double));
    std::vector<double> x1(n, 0.0);
    const GmresReport r1 = gmres(n, Am, M, b.data(), x1.data(), o, &lent);
    EXPECT_TRUE(lent.usesLent());
    EXPECT_EQ(static_cast<void*>(lent.singleVector(0)), static_cast<void*>(storage.data()));
    EXPECT_EQ(r1.iterations, r0.iterations);
    EXPECT_EQ(x1, x0);
    lent.release();
    EXPECT_FALSE(lent.usesLent());

    GmresWorkspace small;
    small.lend(storage.data(), bytes - 1);
    std::vector<double> x2(n, 0.0);
    gmres(n, Am, M, b.data(), x2.data(), o, &small);
    EXPECT_FALSE(small.usesLent());
    EXPECT_EQ(x2, x0);
}

// A cyclic shift makes no progress in fewer than n iterations: with `hopeless` GMRES stops after
// its first restart cycle instead of spending the whole budget.
TEST(Gmres, GivesUpWhenItCannotReachTheHopelessThreshold) {
    const long n = 200;
    const LinearMap shift = [&](const double* in, double* out) {
        for (long i = 0; i < n; ++i) out[(i + 1) % n] = in[i];
    };
    std::vector<double> b(n, 0.0);
    b[0] = 1.0;
    std::vector<double> x(n, 0.0);
    const GmresReport full = gmres(n, shift, {}, b.data(), x.data(), {40, 120, 1e-2});
    EXPECT_EQ(full.iterations, 120);
    EXPECT_FALSE(full.gaveUp);
    std::fill(x.begin(), x.end(), 0.0);
    const GmresReport early = gmres(n, shift, {}, b.data(), x.data(), {40, 120, 1e-2, 0.5});
    EXPECT_EQ(early.iterations, 40);
    EXPECT_TRUE(early.gaveUp);
    EXPECT_FALSE(early.converged);
    EXPECT_NEAR(early.relativeResidual, 1.0, 1e-12);
}

// Morgan's test for deflated restarting: a bidiagonal matrix whose few small eigenvalues make a
// restarted GMRES(20) crawl. GMRES-DR(20, 6) keeps their harmonic Ritz vectors over the restarts
// and needs far fewer products; both solutions are right (true residual), a workspace reused
// across solves gives the same bits, and so does a second thread (chunked sums).
TEST(Gmres, DeflatedRestartsKeepTheSlowEigenvectors) {
    const long n = 1000;
    const LinearMap A = morganBidiagonal(n);
    const std::vector<double> b(n, 1.0);
    auto trueResidual = [&](const std::vector<double>& x) {
        std::vector<double> ax(n);
        A(x.data(), ax.data());
        double s = 0;
        for (long i = 0; i < n; ++i) s += (b[i] - ax[i]) * (b[i] - ax[i]);
        return std::sqrt(s / n);
    };
    std::vector<double> plain(n, 0.0), deflated(n, 0.0), again(n, 0.0), twoThreads(n, 0.0);
    const GmresReport p = gmres(n, A, {}, b.data(), plain.data(), {20, 5000, 1e-10});
    GmresWorkspace ws;
    const GmresReport d = gmres(n, A, {}, b.data(), deflated.data(), {20, 5000, 1e-10, 0.0, 6}, &ws);
    const GmresReport d2 = gmres(n, A, {}, b.data(), again.data(), {20, 5000, 1e-10, 0.0, 6}, &ws);
    const int before = omp_get_max_threads();
    omp_set_num_threads(before == 1 ? 2 : 1);
    (void)gmres(n, A, {}, b.data(), twoThreads.data(), {20, 5000, 1e-10, 0.0, 6});
    omp_set_num_threads(before);
    std::printf("GMRES(20): %d products, GMRES-DR(20, 6): %d\n", p.iterations, d.iterations);
    EXPECT_TRUE(p.converged);
    EXPECT_TRUE(d.converged);
    EXPECT_GT(p.iterations, 4 * d.iterations);  // 4,339 against 558
    EXPECT_LT(trueResidual(plain), 1e-9);
    EXPECT_LT(trueResidual(deflated), 1e-9);
    EXPECT_EQ(d2.iterations, d.iterations);
    EXPECT_EQ(again, deflated);
    EXPECT_EQ(twoThreads, deflated);
}
