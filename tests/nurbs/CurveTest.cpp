#include "nurbs/Curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "RandomNurbs.h"
#include "common/Error.h"

using namespace aero;
using namespace aero::nurbs;
using cplx = std::complex<double>;

TEST(Curve, RationalQuadraticReproducesACircleExactly) {
    // Quarter circle of radius 2 as a rational quadratic: weights 1, sqrt(2)/2, 1.
    Curve<double> c;
    c.degree = 2;
    c.knots = {0, 0, 0, 1, 1, 1};
    c.points = {2, 0, 0, 2, 2, 0, 0, 2, 0};
    c.weights = {1, std::sqrt(0.5), 1};
    for (int s = 0; s <= 50; ++s) {
        EXPECT_NEAR(evaluate(c, s / 50.0).norm(), 2.0, 1e-15);
    }
}

TEST(Curve, DerivativesAgreeWithComplexStep) {
    std::mt19937 rng(5);
    const double h = 1e-30;
    for (int trial = 0; trial < 60; ++trial) {
        const int p = 1 + trial % 5;
        const Curve<double> c = test::randomCurve(rng, p, p + 1 + trial % 7, trial % 2 == 0);
        const Curve<cplx> cc = test::cast<cplx>(c);
        const double u = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
        Vec3<double> d[3];
        evaluateDerivatives(c, u, 2, d);
        Vec3<cplx> dc[2];
        evaluateDerivatives(cc, cplx(u, h), 1, dc);
        for (int k = 0; k < 3; ++k) {
            const double s1 = std::max(1.0, d[1].norm()), s2 = std::max(1.0, d[2].norm());
            EXPECT_NEAR(d[1][k], dc[0][k].imag() / h, 1e-13 * s1);
            EXPECT_NEAR(d[2][k], dc[1][k].imag() / h, 1e-12 * s2);
            EXPECT_NEAR(d[0][k], dc[0][k].real(), 1e-14);
        }
    }
}

TEST(Curve, EndsInterpolateAndBatchedMatchesSingle) {
    std::mt19937 rng(9);
    // Polynomial: the ends are the end control points exactly; rational: to round-off (w P / w).
    const Curve<double> poly = test::randomCurve(rng, 3, 9, false);
    EXPECT_EQ(evaluate(poly, 0.0), Vec3<double>(poly.points[0], poly.points[1], poly.points[2]));
    EXPECT_EQ(evaluate(poly, 1.0), Vec3<double>(poly.points[24], poly.points[25], poly.points[26]));
    const Curve<double> c = test::randomCurve(rng, 3, 9, true);
    const Vec3<double> end = evaluate(c, 1.0);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(end[k], c.points[3 * 8 + k], 1e-15);
    std::vector<double> us(5000), out(3 * us.size());
    for (std::size_t i = 0; i < us.size(); ++i) us[i] = static_cast<double>(i) / (us.size() - 1);
    evaluate(c, us, out.data());
    for (std::size_t i = 0; i < us.size(); ++i) {
        const Vec3<double> P = evaluate(c, us[i]);
        for (int k = 0; k < 3; ++k) ASSERT_EQ(out[3 * i + k], P[k]);
    }
}

TEST(Curve, ValidationRejectsBadWeightsAndCoordinates) {
    std::mt19937 rng(1);
    Curve<double> c = test::randomCurve(rng, 2, 5, true);
    EXPECT_NO_THROW(validate(c, "c"));
    c.weights[2] = -1.0;
    EXPECT_THROW(validate(c, "c"), GeometryError);
    c.weights[2] = 1.0;
    c.points[4] = std::nan("");
    EXPECT_THROW(validate(c, "c"), GeometryError);
}
