// Block ILU and GMRES: exact where the theory says so, and the preconditioned solve converges.
#include <gtest/gtest.h>

#include <random>

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

std::vector<double> randomVector(long n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> v(n);
    for (double& x : v) x = u(rng);
    return v;
}

double maxError(const BlockSparseMatrix& A, const std::vector<double>& x, const std::vector<double>& b) {
    std::vector<double> Ax(b.size());
    A.mult(x.data(), Ax.data());
    double e = 0;
    for (std::size_t i = 0; i < b.size(); ++i) e = std::max(e, std::abs(Ax[i] - b[i]));
    return e;
}

}  // namespace

TEST(BlockIlu, IsExactOnABlockTridiagonalMatrix) {
    // ILU(0) of a chain has no dropped fill: it is the LU factorization.
    const BlockSparseMatrix A = gridMatrix(40, 1, 1);
    BlockIlu ilu;
    ASSERT_TRUE(ilu.factor(A, 0)) << ilu.message();
    const std::vector<double> b = randomVector(kBlock * A.rows, 2);
    std::vector<double> x(b.size());
    ilu.solve(b.data(), x.data());
    EXPECT_LT(maxError(A, x, b), 1e-12);
}

TEST(BlockIlu, WithEnoughFillIsTheCompleteFactorization) {
    // The complete LU of a banded matrix has finite fill levels: a large enough p keeps all.
    const BlockSparseMatrix A = gridMatrix(6, 5, 3);
    const std::vector<double> b = randomVector(kBlock * A.rows, 4);
    std::vector<double> x(b.size());
    BlockIlu partial, complete;
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

TEST(Gmres, PreconditionedByIluSolvesAGridSystem) {
    const BlockSparseMatrix A = gridMatrix(30, 20, 7);
    const std::vector<double> b = randomVector(kBlock * A.rows, 8);
    BlockIlu ilu;
    ASSERT_TRUE(ilu.factor(A, 1));
    const LinearMap Am = [&](const double* in, double* out) { A.mult(in, out); };
    const LinearMap M = [&](const double* in, double* out) { ilu.solve(in, out); };
    std::vector<double> x(b.size(), 0.0);
    const GmresReport r = gmres(kBlock * A.rows, Am, M, b.data(), x.data(), {30, 200, 1e-12});
    EXPECT_LE(r.relativeResidual, 1e-12);
    EXPECT_LT(r.iterations, 40);
    EXPECT_LT(maxError(A, x, b), 1e-10);
}
