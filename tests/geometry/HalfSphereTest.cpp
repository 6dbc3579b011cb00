#include "geometry/HalfSphere.h"

#include <gtest/gtest.h>

#include "geometry/Topology.h"

using namespace aero;
using namespace aero::geometry;

TEST(HalfSphere, PaperCountsAndWatertightness) {
    const PatchSet set = makeHalfSphere();
    ASSERT_EQ(set.size(), 20);
    EXPECT_EQ(set.controlPointCount(), 720);
    for (const Patch& p : set.patches) {
        EXPECT_EQ(p.countU, 6);
        EXPECT_EQ(p.countV, 6);
        EXPECT_EQ(p.degreeU, 3);
        EXPECT_EQ(p.degreeV, 3);
        EXPECT_FALSE(p.rational());
    }
    EXPECT_NO_THROW(validate(set));
    // A disk-like network of 20 quads: 44 edges (36 shared + 8 on the symmetry plane) and
    // V = 1 + E - F = 25 corners (Euler), so 20*16 interior + 44*4 edge + 25 corner points.
    const Adjacency adj = buildAdjacency(set);
    EXPECT_EQ(adj.shared.size(), 36u);
    EXPECT_EQ(adj.free.size(), 8u);
    EXPECT_EQ(adj.maxGap, 0.0);
    for (const SharedEdge& s : adj.shared) EXPECT_TRUE(s.identicalNets);
    EXPECT_EQ(buildControlPointIndex(set).uniqueCount(), 20 * 16 + 44 * 4 + 25);
    // Free edges lie exactly on the symmetry plane.
    for (const EdgeRef& e : adj.free) {
        const nurbs::Curve<double> c = nurbs::boundaryCurve(set.patches[e.patch], e.edge);
        for (int i = 0; i < c.count(); ++i) EXPECT_EQ(c.points[3 * i + 1], 0.0);
    }
}

TEST(HalfSphere, CloseToTheExactSphereAndOutwardOriented) {
    const PatchSet set = makeHalfSphere();
    const double dev = maxRadialDeviation(set, 1.0, 61);
    RecordProperty("max_radial_deviation", std::to_string(dev));
    // A bicubic 6x6 net over a 45-degree patch approximates the sphere to O(h^4) ~ 1e-4 or better.
    EXPECT_LT(dev, 2e-4);
    for (const Patch& p : set.patches) {
        const nurbs::SurfaceDerivatives<double> d = nurbs::evaluateDerivatives(p, 0.5, 0.5, 1);
        EXPECT_GT(d.Su.cross(d.Sv).dot(d.S), 0.0) << "normal must point outward";
        for (std::size_t a = 1; a < p.points.size(); a += 3) EXPECT_GE(p.points[a], 0.0);
    }
    // Scaling: radius 2.5 scales the deviation too.
    EXPECT_NEAR(maxRadialDeviation(makeHalfSphere({2.5, 6, 3}), 2.5, 61), 2.5 * dev, 1e-12);
}
