#include "mesh/BlockCg.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#if defined(_OPENMP)
#include <omp.h>
#endif

using namespace aero::mesh;

namespace {

// A symmetric positive definite block matrix on an n x n x n node grid with the 27-point
// (trilinear element) pattern: off-diagonal blocks -(I + 0.2 S) w with S a random symmetric
// matrix and w a random weight, diagonal blocks dominant. `chain`: only the i-neighbours (a
// block tridiagonal matrix, which the incomplete factorization factors exactly).
Block3Matrix testMatrix(int n, bool chain, unsigned seed = 7) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1), w(0.5, 1.5);
    auto id = [n](int i, int j, int k) { return i + n * (j + n * k); };
    const int rows = n * n * n;
    std::vector<std::vector<int>> columns(rows);
    for (int k = 0; k < n; ++k) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                for (int dk = -1; dk <= 1; ++dk) {
                    for (int dj = -1; dj <= 1; ++dj) {
                        for (int di = -1; di <= 1; ++di) {
                            if (chain && (dj != 0 || dk != 0)) continue;
                            const int a = i + di, b = j + dj, c = k + dk;
                            if (a < 0 || b < 0 || c < 0 || a >= n || b >= n || c >= n) continue;
                            columns[id(i, j, k)].push_back(id(a, b, c));
                        }
                    }
                }
            }
        }
    }
    Block3Matrix A = makeBlock3Pattern(columns);
    // Off-diagonal blocks, set symmetrically from the upper triangle.
    auto find = [&A](int r, int c) {
        for (int t = A.rowStart[r]; t < A.rowStart[r + 1]; ++t) {
            if (A.cols[t] == c) return t;
        }
        return -1;
    };
    std::vector<double> rowSum(rows, 0.0);
    for (int r = 0; r < rows; ++r) {
        for (int t = A.rowStart[r]; t < A.rowStart[r + 1]; ++t) {
            const int c = A.cols[t];
            if (c <= r) continue;
            double S[9];
            for (int a = 0; a < 3; ++a) {
                for (int b = a; b < 3; ++b) S[3 * a + b] = S[3 * b + a] = u(rng);
            }
            const double weight = w(rng);
            const int tt = find(c, r);
            for (int a = 0; a < 3; ++a) {
                for (int b = 0; b < 3; ++b) {
                    const double v = -weight * ((a == b ? 1.0 : 0.0) + 0.2 * S[3 * a + b]);
                    A.values[9 * t + 3 * a + b] = v;
                    A.values[9 * tt + 3 * b + a] = v;
                }
            }
            rowSum[r] += 1.6 * weight;
            rowSum[c] += 1.6 * weight;
        }
    }
    for (int r = 0; r < rows; ++r) {
        const int t = find(r, r);
        for (int a = 0; a < 3; ++a) A.values[9 * t + 4 * a] = rowSum[r] + 0.01;
        A.values[9 * t + 1] = A.values[9 * t + 3] = 0.1;
    }
    return A;
}

Eigen::MatrixXd dense(const Block3Matrix& A) {
    Eigen::MatrixXd D = Eigen::MatrixXd::Zero(3 * A.rows, 3 * A.rows);
    for (int r = 0; r < A.rows; ++r) {
        for (int t = A.rowStart[r]; t < A.rowStart[r + 1]; ++t) {
            for (int e = 0; e < 9; ++e) D(3 * r + e / 3, 3 * A.cols[t] + e % 3) = A.values[9 * t + e];
        }
    }
    return D;
}

std::vector<double> randomVector(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> v(n);
    for (double& x : v) x = u(rng);
    return v;
}

}  // namespace

TEST(BlockCg, PatternIsSortedSymmetricWithTheDiagonal) {
    const Block3Matrix A = makeBlock3Pattern({{2, 1, 1}, {0}, {0}});
    EXPECT_EQ(A.rows, 3);
    EXPECT_EQ(A.rowStart, (std::vector<int>{0, 3, 5, 7}));
    EXPECT_EQ(A.cols, (std::vector<int>{0, 1, 2, 0, 1, 0, 2}));
    EXPECT_EQ(A.values.size(), 9u * 7);
}

TEST(BlockCg, ProductMatchesTheDenseMatrix) {
    const Block3Matrix A = testMatrix(4, false);
    const std::vector<double> x = randomVector(3 * A.rows, 1);
    std::vector<double> y(x.size());
    A.mult(x.data(), y.data());
    const Eigen::VectorXd ref = dense(A) * Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
    for (std::size_t i = 0; i < y.size(); ++i) EXPECT_NEAR(y[i], ref[i], 1e-13 * ref.norm());
    EXPECT_LT((dense(A) - dense(A).transpose()).norm(), 1e-15);
}

TEST(BlockCg, IncompleteFactorizationIsExactWithoutFill) {
    // Block tridiagonal chains have no fill in the preconditioner's ordering (each part runs
    // towards the separator): M = A up to the float rounding of the stored factor, so
    // M^{-1} A x = x to that accuracy.
    const Block3Matrix A = testMatrix(7, true);
    BlockIncompleteCholesky M;
    ASSERT_TRUE(M.compute(A));
    EXPECT_EQ(M.shift(), 0.0);
    const std::vector<double> x = randomVector(3 * A.rows, 2);
    std::vector<double> Ax(x.size()), back(x.size());
    A.mult(x.data(), Ax.data());
    M.solve(Ax.data(), back.data());
    double worst = 0;
    for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(back[i] - x[i]));
    EXPECT_LT(worst, 2e-6);
    EXPECT_GT(worst, 0.0);  // the factor is float: exact only to its rounding
    // The 49 chains of 7 are shared out between the two parts; the best balance cuts one chain
    // at one node (the separator), and that chain stays free of fill too.
    EXPECT_EQ(M.partSizes()[2], 1);
    EXPECT_EQ(M.partSizes()[0], M.partSizes()[1]);
    EXPECT_GT(M.partSizes()[0], 0);
    EXPECT_GT(M.partSizes()[1], 0);
}

TEST(BlockCg, OrderingSplitsAConnectedGridIntoTwoBalancedPartsAndASeparator) {
    // 13^3 nodes with the 27-point pattern: the separator is one breadth-first level (a shell
    // around the peripheral corner), the parts about equal.
    const Block3Matrix A = testMatrix(13, false);
    BlockIncompleteCholesky M;
    ASSERT_TRUE(M.compute(A));
    const auto [first, second, separator] = M.partSizes();
    EXPECT_EQ(first + second + separator, A.rows);
    EXPECT_GT(separator, 0);
    EXPECT_LT(separator, A.rows / 5);
    EXPECT_LT(std::abs(first - second), separator);
    // Tiny matrices are not split.
    const Block3Matrix small = testMatrix(3, false);
    ASSERT_TRUE(M.compute(small));
    EXPECT_EQ(M.partSizes(), (std::array<int, 3>{small.rows, 0, 0}));
    // A new pattern gets a new ordering; the same pattern keeps it.
    ASSERT_TRUE(M.compute(A));
    EXPECT_EQ(M.partSizes()[2], separator);
}

TEST(BlockCg, SolvesTheSystemToTheToleranceInFewerIterationsThanItsSize) {
    const Block3Matrix A = testMatrix(6, false);
    BlockIncompleteCholesky M;
    ASSERT_TRUE(M.compute(A));
    const std::vector<double> b = randomVector(3 * A.rows, 3);
    std::vector<double> x(b.size(), 0.0);
    const CgReport r = conjugateGradients(A, M, b, x, 1e-12, 1000);
    EXPECT_TRUE(r.converged);
    EXPECT_LE(r.residual, 1e-12);
    EXPECT_LT(r.iterations, 60);  // 648 unknowns
    const Eigen::MatrixXd D = dense(A);
    const Eigen::VectorXd ref = D.llt().solve(Eigen::Map<const Eigen::VectorXd>(b.data(), b.size()));
    EXPECT_LT((Eigen::Map<const Eigen::VectorXd>(x.data(), x.size()) - ref).norm(), 1e-10 * ref.norm());
    // The true residual agrees with the reported one.
    std::vector<double> Ax(x.size());
    A.mult(x.data(), Ax.data());
    double rr = 0, bb = 0;
    for (std::size_t i = 0; i < b.size(); ++i) {
        rr += (b[i] - Ax[i]) * (b[i] - Ax[i]);
        bb += b[i] * b[i];
    }
    EXPECT_LT(std::sqrt(rr / bb), 1e-11);
    // The iteration limit is obeyed and reported as not converged.
    std::vector<double> x2(b.size(), 0.0);
    const CgReport limited = conjugateGradients(A, M, b, x2, 1e-12, 3);
    EXPECT_FALSE(limited.converged);
    EXPECT_EQ(limited.iterations, 3);
    EXPECT_GT(limited.residual, 1e-12);
    // A zero right-hand side gives zero at once.
    std::vector<double> x3(b.size(), 1.0);
    const CgReport zero = conjugateGradients(A, M, std::vector<double>(b.size(), 0.0), x3, 1e-12, 10);
    EXPECT_TRUE(zero.converged);
    EXPECT_EQ(zero.iterations, 0);
    for (double v : x3) EXPECT_EQ(v, 0.0);
}

TEST(BlockCg, SameBitsOnOneAndTwoThreads) {
#if defined(_OPENMP)
    // Sizes above the dot product's chunk (4096 values), so the chunking is exercised.
    const Block3Matrix A = testMatrix(13, false);
    BlockIncompleteCholesky M;
    ASSERT_TRUE(M.compute(A));
    const std::vector<double> b = randomVector(3 * A.rows, 4);
    const int threads = omp_get_max_threads();
    std::vector<double> x1(b.size(), 0.0), x2(b.size(), 0.0);
    omp_set_num_threads(1);
    const CgReport r1 = conjugateGradients(A, M, b, x1, 1e-10, 1000);
    omp_set_num_threads(2);
    const CgReport r2 = conjugateGradients(A, M, b, x2, 1e-10, 1000);
    omp_set_num_threads(threads);
    EXPECT_EQ(r1.iterations, r2.iterations);
    EXPECT_EQ(r1.residual, r2.residual);
    EXPECT_EQ(x1, x2);
#else
    GTEST_SKIP() << "built without OpenMP";
#endif
}

TEST(BlockCg, AnIndefiniteMatrixIsRefused) {
    Block3Matrix A = testMatrix(3, false);
    for (int t = A.rowStart[13]; t < A.rowStart[14]; ++t) {
        if (A.cols[t] == 13) A.values[9 * t + 4] = -50;  // a negative diagonal entry: not positive definite
    }
    BlockIncompleteCholesky M;
    EXPECT_FALSE(M.compute(A));
}

TEST(BlockCg, GalerkinGuessIsExactInTheSpanAndDropsDependentVectors) {
    const Block3Matrix A = testMatrix(4, false);
    const std::size_t n = 3 * A.rows;
    const std::vector<double> v1 = randomVector(n, 5), v2 = randomVector(n, 6);
    std::vector<double> target(n), combo(n);
    for (std::size_t i = 0; i < n; ++i) {
        target[i] = 0.3 * v1[i] - 2.0 * v2[i];
        combo[i] = 2.0 * v2[i] + v1[i];
    }
    std::vector<double> b(n);
    A.mult(target.data(), b.data());
    const std::vector<double> x0 = galerkinGuess(A, {v1, v2, v1, combo, std::vector<double>(n, 0.0)}, b);
    for (std::size_t i = 0; i < n; ++i) EXPECT_NEAR(x0[i], target[i], 1e-11);
    // No basis: zero.
    const std::vector<double> none = galerkinGuess(A, {}, b);
    for (double v : none) EXPECT_EQ(v, 0.0);
    // The guess minimizes the A-norm of the error over the span: better than the basis vector alone.
    const std::vector<double> x1 = galerkinGuess(A, {v1}, b);
    auto energyError = [&](const std::vector<double>& x) {
        std::vector<double> e(n), Ae(n);
        for (std::size_t i = 0; i < n; ++i) e[i] = x[i] - target[i];
        A.mult(e.data(), Ae.data());
        double s = 0;
        for (std::size_t i = 0; i < n; ++i) s += e[i] * Ae[i];
        return s;
    };
    EXPECT_LT(energyError(x1), energyError(v1));
}
