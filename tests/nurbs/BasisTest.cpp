#include "nurbs/Basis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>

#include "RandomNurbs.h"
#include "common/Error.h"

using namespace aero;
using namespace aero::nurbs;
using cplx = std::complex<double>;

namespace {

// Independent reference: the Cox-de Boor recursion of the paper, evaluated for every function.
double coxDeBoor(const std::vector<double>& U, int i, int p, double u, bool lastSpan) {
    if (p == 0) {
        if (U[i] <= u && u < U[i + 1]) return 1.0;
        // The right end belongs to the last non-empty span.
        if (lastSpan && u == U[i + 1] && U[i] < U[i + 1]) return 1.0;
        return 0.0;
    }
    double a = 0, b = 0;
    if (U[i + p] > U[i]) a = (u - U[i]) / (U[i + p] - U[i]) * coxDeBoor(U, i, p - 1, u, lastSpan);
    if (U[i + p + 1] > U[i + 1]) b = (U[i + p + 1] - u) / (U[i + p + 1] - U[i + 1]) * coxDeBoor(U, i + 1, p - 1, u, lastSpan);
    return a + b;
}

}  // namespace

TEST(Basis, PartitionOfUnityNonNegativityAndLocalSupport) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 200; ++trial) {
        const int p = 1 + trial % 5;
        const int n = p + 1 + static_cast<int>(rng() % 8);
        const std::vector<double> U = test::randomKnots(rng, p, n);
        std::uniform_real_distribution<double> D(0.0, 1.0);
        for (int s = 0; s < 20; ++s) {
            const double u = (s == 0) ? 0.0 : (s == 1) ? 1.0 : D(rng);
            const int span = findSpan(U, p, n, u);
            ASSERT_LE(U[span], u);
            ASSERT_TRUE(u < U[span + 1] || (u == 1.0 && U[span] < U[span + 1]));
            double N[kMaxDegree + 1];
            basisFunctions(U, p, span, u, N);
            double sum = 0;
            for (int j = 0; j <= p; ++j) {
                EXPECT_GE(N[j], 0.0);
                sum += N[j];
            }
            EXPECT_NEAR(sum, 1.0, 1e-14);
            // Local support: exactly the functions span-p..span are non-zero, and they agree with
            // the Cox-de Boor recursion; every other function is zero there.
            for (int i = 0; i < n; ++i) {
                const double ref = coxDeBoor(U, i, p, u, u == U.back());
                const double got = (i >= span - p && i <= span) ? N[i - (span - p)] : 0.0;
                EXPECT_NEAR(got, ref, 1e-14) << "function " << i << " at u=" << u;
            }
        }
    }
}

TEST(Basis, ClampedEndsInterpolate) {
    std::mt19937 rng(3);
    for (int p = 1; p <= 5; ++p) {
        const int n = p + 4;
        const std::vector<double> U = test::randomKnots(rng, p, n);
        double N[kMaxDegree + 1];
        basisFunctions(U, p, findSpan(U, p, n, 0.0), 0.0, N);
        EXPECT_EQ(N[0], 1.0);
        basisFunctions(U, p, findSpan(U, p, n, 1.0), 1.0, N);
        EXPECT_EQ(N[p], 1.0);
    }
}

TEST(Basis, DerivativesAgreeWithComplexStep) {
    std::mt19937 rng(11);
    const double h = 1e-30;
    for (int trial = 0; trial < 100; ++trial) {
        const int p = 1 + trial % 6;
        const int n = p + 1 + static_cast<int>(rng() % 6);
        const std::vector<double> U = test::randomKnots(rng, p, n);
        const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
        const int span = findSpan(U, p, n, u);
        double d[3 * (kMaxDegree + 1)];
        basisDerivatives(U, p, span, u, 2, d);
        // Values agree with basisFunctions.
        double N[kMaxDegree + 1];
        basisFunctions(U, p, span, u, N);
        // First derivative: Im N(u + ih) / h. Second: Im N'(u + ih) / h.
        cplx Nc[kMaxDegree + 1], dc[3 * (kMaxDegree + 1)];
        basisFunctions(U, p, span, cplx(u, h), Nc);
        basisDerivatives(U, p, span, cplx(u, h), 1, dc);
        for (int j = 0; j <= p; ++j) {
            EXPECT_NEAR(d[j], N[j], 1e-15);
            const double scale1 = std::max(1.0, std::abs(d[(p + 1) + j]));
            const double scale2 = std::max(1.0, std::abs(d[2 * (p + 1) + j]));
            EXPECT_NEAR(d[(p + 1) + j], Nc[j].imag() / h, 1e-13 * scale1);
            EXPECT_NEAR(d[2 * (p + 1) + j], dc[(p + 1) + j].imag() / h, 1e-12 * scale2);
        }
    }
}

TEST(Basis, DerivativesAboveDegreeAreZero) {
    const std::vector<double> U = uniformKnots(2, 5);
    double d[5 * 3];
    basisDerivatives(U, 2, findSpan(U, 2, 5, 0.4), 0.4, 4, d);
    for (int k = 3; k <= 4; ++k) {
        for (int j = 0; j <= 2; ++j) EXPECT_EQ(d[k * 3 + j], 0.0);
    }
}

TEST(Basis, FindSpanAtInteriorKnotsAndEnds) {
    const std::vector<double> U = {0, 0, 0, 0.25, 0.5, 0.5, 1, 1, 1};  // degree 2, 6 functions
    EXPECT_EQ(findSpan(U, 2, 6, 0.0), 2);
    EXPECT_EQ(findSpan(U, 2, 6, 0.25), 3);
    EXPECT_EQ(findSpan(U, 2, 6, 0.5), 5);
    EXPECT_EQ(findSpan(U, 2, 6, 0.49), 3);
    EXPECT_EQ(findSpan(U, 2, 6, 1.0), 5);
    EXPECT_EQ(findSpan(U, 2, 6, 1.5), 5);
    EXPECT_EQ(findSpan(U, 2, 6, -0.5), 2);
}

TEST(Basis, ValidationNamesTheEntityAndTheProblem) {
    auto expectError = [](std::vector<double> U, int p, int n, const char* fragment) {
        try {
            validateKnotVector(U, p, n, "curve 'c7'");
            ADD_FAILURE() << "no error for " << fragment;
        } catch (const GeometryError& e) {
            EXPECT_NE(std::string(e.what()).find("curve 'c7'"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    expectError({0, 0, 0, 0.6, 0.4, 1, 1, 1}, 2, 5, "decreases");
    expectError({0, 0, 0.2, 0.5, 0.8, 1, 1, 1}, 2, 5, "not clamped");
    expectError({0, 0, 0, 0.5, 1, 1, 1}, 2, 5, "expected 8");
    expectError({0, 0, 0, std::nan(""), 0.5, 1, 1, 1}, 2, 5, "not finite");
    expectError({0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}, 2, 6, "multiplicity");
    expectError({0, 0, 1, 1}, 0, 3, "degree");
    expectError({0, 0, 0, 0, 0, 0}, 2, 3, "empty parameter range");
    EXPECT_NO_THROW(validateKnotVector(uniformKnots(3, 6), 3, 6, "ok"));
}
