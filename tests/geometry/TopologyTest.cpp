#include "geometry/Topology.h"

#include <gtest/gtest.h>

#include <cmath>

#include "nurbs/KnotInsertion.h"

using namespace aero;
using namespace aero::geometry;

namespace {

// A bicubic 4x4 patch over [x0, x0+1] x [0, 1] with a smooth bump: two of them share x = 1.
Patch bumpPatch(double x0, bool flipU, bool flipV = false) {
    Patch p;
    p.degreeU = p.degreeV = 3;
    p.countU = p.countV = 4;
    p.knotsU = p.knotsV = {0, 0, 0, 0, 1, 1, 1, 1};
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            const int ii = flipU ? 3 - i : i;
            const double x = x0 + ii / 3.0, y = (flipV ? 3 - j : j) / 3.0;
            p.points.insert(p.points.end(), {x, y, 0.2 * x * (2 - x) * y});
        }
    }
    return p;
}

}  // namespace

TEST(Topology, SharedEdgeIsFoundAndWatertight) {
    PatchSet set;
    // The second patch runs backwards in u (its u = u1 edge is the shared one) and in v
    // (so the shared edge runs opposite).
    set.patches = {bumpPatch(0.0, false), bumpPatch(1.0, true, true)};
    const Adjacency adj = buildAdjacency(set);
    ASSERT_EQ(adj.shared.size(), 1u);
    EXPECT_EQ(adj.free.size(), 6u);
    const SharedEdge& s = adj.shared[0];
    EXPECT_EQ(s.a.patch, 0);
    EXPECT_EQ(s.a.edge, 1);  // u = u1 of the first patch
    EXPECT_EQ(s.b.patch, 1);
    EXPECT_EQ(s.b.edge, 1);  // u = u1 of the second (flipped) patch
    EXPECT_TRUE(s.reversed);
    EXPECT_TRUE(s.identicalNets);
    EXPECT_EQ(adj.maxGap, 0.0);

    const ControlPointIndex idx = buildControlPointIndex(set);
    EXPECT_EQ(idx.uniqueCount(), 2 * 16 - 4);
    // The shared column maps to the same unique points from both sides (reversed in v).
    for (int j = 0; j < 4; ++j) {
        EXPECT_EQ(idx.toUnique[idx.patchOffset[0] + 3 + 4 * j], idx.toUnique[idx.patchOffset[1] + 3 + 4 * (3 - j)]);
    }
}

TEST(Topology, GapIsMeasuredWhenAnEdgeIsPerturbed) {
    PatchSet set;
    set.patches = {bumpPatch(0.0, false), bumpPatch(1.0, false)};
    // Move an inner control point of the shared edge of the second patch by 1e-3 in z.
    set.patches[1].points[3 * set.patches[1].index(0, 1) + 2] += 1e-3;
    const Adjacency adj = buildAdjacency(set);
    ASSERT_EQ(adj.shared.size(), 1u);
    EXPECT_FALSE(adj.shared[0].identicalNets);
    // The edge curve moves by at most 1e-3 * max N_1(v) = 1e-3 * 4/9 (cubic Bernstein, at v = 1/3)
    // in z; the edge itself is the line z = 0.2 y, so the normal distance is that / sqrt(1.04).
    EXPECT_NEAR(adj.maxGap, 1e-3 * 4.0 / 9.0 / std::sqrt(1.04), 1e-10);
}

TEST(Topology, GapIsZeroForDifferentButEquivalentEdgeParameterizations) {
    // Refining one side changes its control net but not the curve: the gap stays at round-off.
    PatchSet set;
    set.patches = {bumpPatch(0.0, false), bumpPatch(1.0, false)};
    nurbs::insertKnot(set.patches[1], 1, 0.5, 1);
    const Adjacency adj = buildAdjacency(set);
    ASSERT_EQ(adj.shared.size(), 1u);
    EXPECT_FALSE(adj.shared[0].identicalNets);
    EXPECT_LT(adj.maxGap, 1e-12);
}

namespace {

// A bilinear patch over [x0, x1] x [y0, y1] in the plane z = 0.
Patch rectangle(double x0, double x1, double y0, double y1) {
    Patch p;
    p.degreeU = p.degreeV = 1;
    p.countU = p.countV = 2;
    p.knotsU = p.knotsV = {0, 0, 1, 1};
    p.points = {x0, y0, 0, x1, y0, 0, x0, y1, 0, x1, y1, 0};
    return p;
}

}  // namespace

TEST(Topology, EdgesSplitDifferentlyOnTheTwoSidesAreMeasuredAgainstAllTheirNeighbours) {
    // A T-junction: one patch's edge x = 1, y in [0, 2] runs along two patches on the other side
    // (y in [0, 1] and [1, 2]). The end-point pairing finds no shared edge there; the boundary
    // measure finds all three pieces along other patches, with no gap.
    PatchSet set;
    set.patches = {rectangle(0, 1, 0, 2), rectangle(1, 2, 0, 1), rectangle(1, 2, 1, 2)};
    const Adjacency adj = buildAdjacency(set);
    EXPECT_EQ(adj.shared.size(), 1u);  // only the two small patches' edge y = 1 pairs
    BoundaryGaps gaps = boundaryGaps(set);
    EXPECT_EQ(gaps.pieces, 12);
    EXPECT_EQ(gaps.matched, 5);  // x = 1 on the three patches, y = 1 on the two small ones
    EXPECT_EQ(gaps.partlyFree, 0);
    EXPECT_LT(gaps.maxGap, 1e-14);
    // Open the junction by 1e-3 along the upper small patch: the long edge measures it there
    // (against the one patch it was not matched to at its midpoint), and says where.
    set.patches[2].points[0] += 1e-3;
    set.patches[2].points[6] += 1e-3;
    gaps = boundaryGaps(set);
    EXPECT_NEAR(gaps.maxGap, 1e-3, 1e-12);
    ASSERT_GE(gaps.worstPatch, 0);
    EXPECT_GT(gaps.worstPoint[1], 1.0);
    // The long edge running on past its neighbours (y up to 3): its free part is not a gap.
    set.patches[2].points[0] -= 1e-3;
    set.patches[2].points[6] -= 1e-3;
    set.patches[0] = rectangle(0, 1, 0, 2.1);
    gaps = boundaryGaps(set);
    EXPECT_EQ(gaps.partlyFree, 1);
    EXPECT_LT(gaps.maxGap, 1e-14);
}

namespace {

// The ellipse (cos t, thickness sin t) as a rational quadratic NURBS of `arcs` equal arcs (3 or
// 4), starting at angle `start`, swept along z from z0 to z1: a thin closed wing skin whose two
// u ends meet at the seam.
Patch ellipticTube(int arcs, double start, double thickness, double z0, double z1) {
    Patch p;
    p.degreeU = 2;
    p.degreeV = 1;
    p.countU = 2 * arcs + 1;
    p.countV = 2;
    p.knotsU = {0, 0, 0};
    for (int a = 1; a < arcs; ++a) p.knotsU.insert(p.knotsU.end(), {double(a), double(a)});
    p.knotsU.insert(p.knotsU.end(), {double(arcs), double(arcs), double(arcs)});
    p.knotsV = {0, 0, 1, 1};
    const double half = M_PI / arcs;  // half an arc's angle
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < p.countU; ++i) {
            const double angle = start + i * half, r = i % 2 ? 1 / std::cos(half) : 1.0;
            p.points.insert(p.points.end(), {r * std::cos(angle), thickness * r * std::sin(angle), j ? z1 : z0});
            p.weights.push_back(i % 2 ? std::cos(half) : 1.0);
        }
    return p;
}

}  // namespace

TEST(Topology, ASeamAndAThinTrailingEdgeAreNotGaps) {
    // One closed skin: its two u ends coincide (the seam) and pair with each other, while its
    // circular ends are free.
    PatchSet set;
    set.patches = {ellipticTube(4, 0.0, 0.01, 0, 1)};
    BoundaryGaps gaps = boundaryGaps(set);
    EXPECT_EQ(gaps.pieces, 4);
    EXPECT_EQ(gaps.matched, 2);
    EXPECT_EQ(gaps.free, 2);
    EXPECT_LT(gaps.maxGap, 1e-12);
    // A second skin on top, the same thin ellipse parameterized otherwise (three arcs from
    // another angle): near the trailing edge, the nearest of a closed edge's samples can lie on
    // the other surface, one thickness away; the distance is still measured to the right one.
    set.patches.push_back(ellipticTube(3, 0.3, 0.01, 1, 2));
    gaps = boundaryGaps(set);
    EXPECT_EQ(gaps.matched, 6);  // two seams, the shared ellipse on both sides
    EXPECT_EQ(gaps.free, 2);
    EXPECT_LT(gaps.maxGap, 1e-10);
}
