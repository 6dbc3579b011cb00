#include "nurbs/KnotInsertion.h"

#include <gtest/gtest.h>

#include "RandomNurbs.h"
#include "common/Error.h"

using namespace aero;
using namespace aero::nurbs;

TEST(KnotInsertion, CurveShapeUnchanged) {
    std::mt19937 rng(41);
    for (int trial = 0; trial < 30; ++trial) {
        const int p = 1 + trial % 5;
        const Curve<double> c0 = test::randomCurve(rng, p, p + 3, trial % 2 == 0);
        Curve<double> c = c0;
        const double u = std::uniform_real_distribution<double>(0.05, 0.95)(rng);
        const int times = std::min(p - multiplicity(c.knots, u), 1 + trial % 3);
        insertKnot(c, u, times);
        EXPECT_EQ(c.count(), c0.count() + times);
        EXPECT_EQ(multiplicity(c.knots, u), times);
        EXPECT_NO_THROW(validate(c, "refined"));
        for (int s = 0; s <= 100; ++s) {
            const double t = s / 100.0;
            EXPECT_NEAR((evaluate(c, t) - evaluate(c0, t)).norm(), 0.0, 1e-14) << "u=" << t;
        }
    }
}

TEST(KnotInsertion, FullMultiplicityInterpolatesTheCurve) {
    // Inserting u p times makes a control point lie on the curve (a C0 crease point).
    std::mt19937 rng(42);
    Curve<double> c = test::randomCurve(rng, 3, 7, false);
    const double u = 0.3141;
    const Vec3<double> P = evaluate(c, u);
    insertKnot(c, u, 3);
    bool found = false;
    for (int i = 0; i < c.count(); ++i) {
        found = found || (Vec3<double>(c.points[3 * i], c.points[3 * i + 1], c.points[3 * i + 2]) - P).norm() < 1e-14;
    }
    EXPECT_TRUE(found);
}

TEST(KnotInsertion, SurfaceAndVolumeRefinementPreserveShape) {
    std::mt19937 rng(43);
    const Surface<double> s0 = test::randomSurface(rng, 3, 2, 6, 5, true);
    Surface<double> s = s0;
    const std::vector<double> ku = {0.11, 0.5, 0.93}, kv = {0.2, 0.2};
    refine(s, 0, ku);
    refine(s, 1, kv);
    EXPECT_EQ(s.countU, 9);
    EXPECT_EQ(s.countV, 7);
    EXPECT_NO_THROW(validate(s, "refined surface"));
    const Volume<double> v0 = test::randomVolume(rng, {3, 2, 1}, {5, 4, 3}, true);
    Volume<double> v = v0;
    for (int d = 0; d < 3; ++d) refine(v, d, ku);
    EXPECT_NO_THROW(validate(v, "refined volume"));
    std::uniform_real_distribution<double> D(0.0, 1.0);
    for (int t = 0; t < 200; ++t) {
        const double a = D(rng), b = D(rng), c = D(rng);
        EXPECT_NEAR((evaluate(s, a, b) - evaluate(s0, a, b)).norm(), 0.0, 1e-14);
        EXPECT_NEAR((evaluate(v, a, b, c) - evaluate(v0, a, b, c)).norm(), 0.0, 1e-14);
    }
}

TEST(KnotInsertion, RejectsOutOfRangeAndExcessMultiplicity) {
    std::mt19937 rng(44);
    Curve<double> c = test::randomCurve(rng, 2, 5, false);
    EXPECT_THROW(insertKnot(c, 1.0, 1), GeometryError);
    EXPECT_THROW(insertKnot(c, -0.2, 1), GeometryError);
    EXPECT_THROW(insertKnot(c, 0.5, 3), GeometryError);
}
