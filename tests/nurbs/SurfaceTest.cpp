#include "nurbs/Surface.h"

#include <gtest/gtest.h>

#include <complex>

#include "RandomNurbs.h"
#include "common/Error.h"

using namespace aero;
using namespace aero::nurbs;
using cplx = std::complex<double>;

TEST(Surface, DerivativesAgreeWithComplexStep) {
    std::mt19937 rng(21);
    const double h = 1e-30;
    for (int trial = 0; trial < 60; ++trial) {
        const int pu = 1 + trial % 4, pv = 1 + (trial / 4) % 4;
        const Surface<double> s = test::randomSurface(rng, pu, pv, pu + 2 + trial % 3, pv + 1 + trial % 4, trial % 2 == 1);
        const Surface<cplx> sc = test::cast<cplx>(s);
        std::uniform_real_distribution<double> D(0.0, 1.0);
        const double u = D(rng), v = D(rng);
        const SurfaceDerivatives<double> d = evaluateDerivatives(s, u, v, 2);
        const SurfaceDerivatives<cplx> du = evaluateDerivatives(sc, cplx(u, h), cplx(v, 0.0), 1);
        const SurfaceDerivatives<cplx> dv = evaluateDerivatives(sc, cplx(u, 0.0), cplx(v, h), 1);
        const double s1 = std::max({1.0, d.Su.norm(), d.Sv.norm()});
        const double s2 = std::max({1.0, d.Suu.norm(), d.Suv.norm(), d.Svv.norm()});
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(d.Su[k], du.S[k].imag() / h, 1e-13 * s1);
            EXPECT_NEAR(d.Sv[k], dv.S[k].imag() / h, 1e-13 * s1);
            EXPECT_NEAR(d.Suu[k], du.Su[k].imag() / h, 1e-12 * s2);
            EXPECT_NEAR(d.Suv[k], dv.Su[k].imag() / h, 1e-12 * s2);
            EXPECT_NEAR(d.Svv[k], dv.Sv[k].imag() / h, 1e-12 * s2);
        }
        const Vec3<double> P = evaluate(s, u, v);
        EXPECT_NEAR((P - d.S).norm(), 0.0, 1e-14);
    }
}

TEST(Surface, ControlPointSensitivityIsTheBasisProduct) {
    // Complex step on one control-point coordinate: d S / d P_ij = N_i(u) N_j(v) for a polynomial patch.
    std::mt19937 rng(2);
    const Surface<double> s = test::randomSurface(rng, 3, 2, 6, 5, false);
    Surface<cplx> sc = test::cast<cplx>(s);
    const int idx = s.index(2, 3);
    sc.points[3 * idx + 1] += cplx(0.0, 1e-30);
    const double u = 0.43, v = 0.61;
    const Vec3<cplx> P = evaluate(sc, cplx(u), cplx(v));
    // Reference: evaluate the surface whose control points are zero except a unit y at idx.
    Surface<double> e = s;
    std::fill(e.points.begin(), e.points.end(), 0.0);
    e.points[3 * idx + 1] = 1.0;
    EXPECT_NEAR(P[1].imag() / 1e-30, evaluate(e, u, v)[1], 1e-15);
    EXPECT_EQ(P[0].imag(), 0.0);
}

TEST(Surface, StructuredSamplingEqualsPointEvaluation) {
    std::mt19937 rng(4);
    for (bool rational : {false, true}) {
        const Surface<double> s = test::randomSurface(rng, 3, 2, 9, 7, rational);
        std::vector<double> us(37), vs(23);
        for (std::size_t a = 0; a < us.size(); ++a) us[a] = static_cast<double>(a) / (us.size() - 1);
        for (std::size_t b = 0; b < vs.size(); ++b) vs[b] = static_cast<double>(b) / (vs.size() - 1);
        std::vector<double> out(3 * us.size() * vs.size());
        sampleGrid(s, us, vs, out.data());
        std::vector<double> uv, batch(out.size());
        for (double v : vs) {
            for (double u : us) {
                uv.push_back(u);
                uv.push_back(v);
            }
        }
        evaluate(s, uv, batch.data());
        for (std::size_t b = 0; b < vs.size(); ++b) {
            for (std::size_t a = 0; a < us.size(); ++a) {
                const Vec3<double> P = evaluate(s, us[a], vs[b]);
                for (int k = 0; k < 3; ++k) {
                    const std::size_t o = 3 * (b * us.size() + a) + k;
                    ASSERT_NEAR(out[o], P[k], 1e-14);
                    ASSERT_EQ(batch[o], P[k]);
                }
            }
        }
    }
}

TEST(Surface, BoundaryCurvesAreTheEdges) {
    std::mt19937 rng(6);
    const Surface<double> s = test::randomSurface(rng, 3, 2, 6, 5, true);
    for (double t : {0.0, 0.3, 0.77, 1.0}) {
        EXPECT_NEAR((evaluate(boundaryCurve(s, 0), t) - evaluate(s, t, 0.0)).norm(), 0.0, 1e-15);
        EXPECT_NEAR((evaluate(boundaryCurve(s, 1), t) - evaluate(s, 1.0, t)).norm(), 0.0, 1e-15);
        EXPECT_NEAR((evaluate(boundaryCurve(s, 2), t) - evaluate(s, t, 1.0)).norm(), 0.0, 1e-15);
        EXPECT_NEAR((evaluate(boundaryCurve(s, 3), t) - evaluate(s, 0.0, t)).norm(), 0.0, 1e-15);
    }
}

TEST(Surface, ValidationNamesDirection) {
    std::mt19937 rng(8);
    Surface<double> s = test::randomSurface(rng, 3, 3, 6, 6, false);
    s.knotsV[5] = 0.0;  // decreasing
    try {
        validate(s, "patch 4");
        FAIL();
    } catch (const GeometryError& e) {
        EXPECT_NE(std::string(e.what()).find("patch 4 (v direction)"), std::string::npos) << e.what();
    }
}
