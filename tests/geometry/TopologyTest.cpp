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
