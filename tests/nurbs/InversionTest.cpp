#include "nurbs/Inversion.h"

#include <gtest/gtest.h>

#include "RandomNurbs.h"

using namespace aero;
using namespace aero::nurbs;

TEST(Inversion, CurveClosestPointRecoversTheParameter) {
    // A gently curved cubic (no self-approach), points on the curve and offset along the normal.
    Curve<double> c;
    c.degree = 3;
    c.knots = {0, 0, 0, 0, 0.4, 1, 1, 1, 1};
    c.points = {0, 0, 0, 1, 0.3, 0, 2, 0.4, 0.1, 3, 0.2, 0.2, 4, 0, 0.2};
    for (double u : {0.0, 0.05, 0.4, 0.63, 0.99, 1.0}) {
        const CurveProjection r = project(c, evaluate(c, u));
        EXPECT_TRUE(r.converged);
        EXPECT_NEAR(r.u, u, 1e-10);
        EXPECT_LT(r.distance, 1e-12);
    }
}

TEST(Inversion, SurfaceClosestPointRecoversTheParameters) {
    std::mt19937 rng(51);
    Surface<double> s;
    s.degreeU = s.degreeV = 3;
    s.countU = s.countV = 5;
    s.knotsU = s.knotsV = {0, 0, 0, 0, 0.5, 1, 1, 1, 1};
    std::uniform_real_distribution<double> W(-0.1, 0.1);
    for (int j = 0; j < 5; ++j) {
        for (int i = 0; i < 5; ++i) s.points.insert(s.points.end(), {i * 0.5, j * 0.5, 0.3 * std::sin(i + j) + W(rng)});
    }
    std::uniform_real_distribution<double> D(0.0, 1.0);
    for (int t = 0; t < 100; ++t) {
        const double u = D(rng), v = D(rng);
        const SurfaceProjection r = project(s, evaluate(s, u, v));
        EXPECT_TRUE(r.converged);
        EXPECT_LT(r.distance, 1e-12);
        EXPECT_NEAR(r.u, u, 1e-9);
        EXPECT_NEAR(r.v, v, 1e-9);
    }
    // A point above the surface projects along the normal.
    const SurfaceDerivatives<double> d = evaluateDerivatives(s, 0.4, 0.6, 1);
    const Vec3<double> n = d.Su.cross(d.Sv).normalized();
    const SurfaceProjection r = project(s, d.S + 0.01 * n);
    EXPECT_NEAR(r.u, 0.4, 1e-8);
    EXPECT_NEAR(r.v, 0.6, 1e-8);
    EXPECT_NEAR(r.distance, 0.01, 1e-10);
}

TEST(Inversion, VolumeEmbeddingToMachineAccuracy) {
    for (bool rational : {false, true}) {
        const Volume<double> v = test::boxVolume({3, 3, 1}, {6, 6, 2}, {2.0, 3.0, 1.0}, 0.15, rational);
        const VolumeInverter inv(v);
        std::mt19937 rng(52);
        std::uniform_real_distribution<double> D(0.0, 1.0);
        for (int t = 0; t < 300; ++t) {
            // Interior points, and points on the boundary faces and corners.
            double x[3] = {D(rng), D(rng), D(rng)};
            if (t % 10 == 0) x[t % 3] = 0.0;
            if (t % 10 == 1) x[t % 3] = 1.0;
            if (t == 2) x[0] = x[1] = x[2] = 1.0;
            const Vec3<double> P = evaluate(v, x[0], x[1], x[2]);
            const VolumeInversion r = inv(P);
            ASSERT_TRUE(r.converged) << "residual " << r.residual;
            EXPECT_TRUE(r.inside);
            EXPECT_LE(r.residual, 1e-12);
            for (int d = 0; d < 3; ++d) EXPECT_NEAR(r.xi[d], x[d], 1e-10);
        }
    }
}

TEST(Inversion, VolumePointsOutsideAreReportedNotDropped) {
    const Volume<double> v = test::boxVolume({2, 2, 2}, {4, 4, 4}, {1.0, 1.0, 1.0}, 0.0, false);
    const VolumeInversion r = invert(v, Vec3<double>(0.5, 0.5, 1.25));
    EXPECT_FALSE(r.converged);
    EXPECT_FALSE(r.inside);
    EXPECT_NEAR(r.residual, 0.25, 1e-9);  // distance to the closest point of the volume
    EXPECT_NEAR(r.xi[2], 1.0, 1e-12);
}

TEST(Inversion, BatchedInversionMatchesSingle) {
    const Volume<double> v = test::boxVolume({3, 3, 3}, {5, 5, 5}, {1.0, 2.0, 1.0}, 0.1, false);
    const VolumeInverter inv(v);
    std::mt19937 rng(53);
    std::uniform_real_distribution<double> D(0.0, 1.0);
    std::vector<double> pts;
    for (int t = 0; t < 500; ++t) {
        const Vec3<double> P = evaluate(v, D(rng), D(rng), D(rng));
        pts.insert(pts.end(), {P[0], P[1], P[2]});
    }
    std::vector<VolumeInversion> out(500);
    inv.invertAll(pts, out.data());
    for (int t = 0; t < 500; ++t) {
        const VolumeInversion r = inv(Vec3<double>(pts[3 * t], pts[3 * t + 1], pts[3 * t + 2]));
        EXPECT_EQ(out[t].xi, r.xi);
        EXPECT_TRUE(out[t].converged);
    }
}
