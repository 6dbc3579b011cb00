#include "geometry/Planform.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <numbers>

#include "common/Error.h"
#include "geometry/HalfSphere.h"

using namespace aero;
using namespace aero::geometry;

namespace {

// The set with every control point mapped by x -> (sx x, sy y, sz z): an exact affine image of
// each NURBS patch (weights unchanged).
PatchSet scaled(PatchSet set, double sx, double sy, double sz) {
    for (Patch& p : set.patches) {
        for (std::size_t k = 0; k < p.points.size(); k += 3) {
            p.points[k] *= sx;
            p.points[k + 1] *= sy;
            p.points[k + 2] *= sz;
        }
    }
    return set;
}

}  // namespace

TEST(Planform, TheHalfSphereCastsAHalfDisk) {
    const PatchSet sphere = makeHalfSphere();
    const Planform f = planform(sphere);
    EXPECT_TRUE(f.halfBody);
    // The bicubic patches approximate the unit sphere: the largest y is 1 to their accuracy.
    const double deviation = maxRadialDeviation(sphere, 1.0);
    EXPECT_NEAR(f.halfSpan, 1.0, deviation + 1e-9);
    EXPECT_NEAR(f.projectedArea, std::numbers::pi / 2, 5e-4 * std::numbers::pi / 2);
    std::printf("half-sphere: half-span %.12f (patches' radial deviation %.2e), area %.8f (pi/2 %.8f), AR %.6f\n",
                f.halfSpan, deviation, f.projectedArea, std::numbers::pi / 2, f.aspectRatio);
    // The whole sphere: span 2, shadow pi.
    EXPECT_NEAR(f.aspectRatio, 4 / std::numbers::pi, 1e-3);
}

TEST(Planform, AStretchedHalfSphereScalesSpanAreaAndAspectRatio) {
    // An ellipsoid's half: semi-axes 1.5 (x), 2.5 (y), 0.4 (z).
    const PatchSet sphere = makeHalfSphere();
    const Planform f = planform(scaled(sphere, 1.5, 2.5, 0.4));
    EXPECT_TRUE(f.halfBody);
    EXPECT_NEAR(f.halfSpan, 2.5, 2.5 * maxRadialDeviation(sphere, 1.0) + 1e-9);
    const double area = std::numbers::pi * 1.5 * 2.5 / 2;
    EXPECT_NEAR(f.projectedArea, area, 5e-4 * area);
    EXPECT_NEAR(f.aspectRatio, 2 * 2.5 * 2.5 / area, 2e-3);
}

TEST(Planform, AWholeBodyIsMeasuredAcrossTheSymmetryPlane) {
    // The half-sphere and its mirror image in Y = 0: the whole sphere, shifted to y in [-0.5, 1.5].
    PatchSet whole = makeHalfSphere();
    const PatchSet mirror = scaled(whole, 1, -1, 1);
    whole.patches.insert(whole.patches.end(), mirror.patches.begin(), mirror.patches.end());
    whole.names.insert(whole.names.end(), mirror.names.begin(), mirror.names.end());
    for (Patch& p : whole.patches) {
        for (std::size_t k = 1; k < p.points.size(); k += 3) p.points[k] += 0.5;
    }
    const Planform f = planform(whole);
    EXPECT_FALSE(f.halfBody);
    EXPECT_NEAR(f.halfSpan, 1.0, 1e-4);  // the lowest y is sampled, not refined
    EXPECT_NEAR(f.projectedArea, std::numbers::pi, 5e-4 * std::numbers::pi);
    EXPECT_NEAR(f.aspectRatio, 4 / std::numbers::pi, 2e-3);
}

TEST(Planform, AnEmptySetIsAnErrorNamingIt) {
    PatchSet empty;
    empty.source = "nothing.igs";
    try {
        planform(empty);
        FAIL() << "no error";
    } catch (const GeometryError& e) {
        EXPECT_NE(std::string(e.what()).find("nothing.igs"), std::string::npos) << e.what();
    }
}

TEST(Planform, ThousandsOfPatchesShareASampleBudget) {
    // A 2 x 1 plate at z = 0 in y >= 0 as 64 x 64 bilinear patches: 4,096 patches get fewer
    // samples each (memory stays bounded), and a flat tiling's shadow is still its area.
    PatchSet plate;
    plate.source = "plate";
    const int n = 64;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            Patch p;
            p.degreeU = p.degreeV = 1;
            p.countU = p.countV = 2;
            p.knotsU = p.knotsV = {0, 0, 1, 1};
            const double x0 = 2.0 * i / n, x1 = 2.0 * (i + 1) / n, y0 = 1.0 * j / n, y1 = 1.0 * (j + 1) / n;
            p.points = {x0, y0, 0, x1, y0, 0, x0, y1, 0, x1, y1, 0};
            plate.patches.push_back(p);
            plate.names.emplace_back();
        }
    }
    const Planform f = planform(plate);
    EXPECT_TRUE(f.halfBody);
    EXPECT_NEAR(f.halfSpan, 1.0, 1e-12);
    EXPECT_NEAR(f.projectedArea, 2.0, 2e-3);
    EXPECT_NEAR(f.aspectRatio, 1.0, 2e-3);
}
