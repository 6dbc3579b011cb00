// The flow solver's mesh layout (flow/FlowMesh.h) on small hand-built blocks: face node lists
// and their positions, global offsets and counts, interface pairs grouped by face pair whatever
// the order of their sides, wall junctions where interface pairs join wall nodes (also through a
// third block), coordinates gathered in the global order, the block groups of the parallel ILU,
// and the errors for blocks and pairs that do not fit, each naming the block and face.
#include "flow/FlowMesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "common/Error.h"
#include "FlowFixtures.h"
#include "ErrorMessage.h"

using namespace aero;
using namespace aero::flow;
using mesh::BoundaryKind;
using mesh::NodePair;

namespace {

long local(const std::array<int, 3>& d, int i, int j, int k) {
    return i + static_cast<long>(d[0]) * (j + static_cast<long>(d[1]) * k);
}

FlowBlock block(const std::string& name, std::array<int, 3> dims) {
    FlowBlock b;
    b.name = name;
    b.dims = dims;
    for (auto& f : b.faces) f.kind = BoundaryKind::Farfield;
    return b;
}

// Two blocks side by side along i, A's face 1 against B's face 0, node (max, j, k) of A on
// (0, j, k) of B; both have a wall at j = 0.
std::vector<FlowBlock> sideBySide(std::array<int, 3> dims) {
    std::vector<FlowBlock> blocks{block("A", dims), block("B", dims)};
    blocks[0].faces[1] = {BoundaryKind::Interface, 1, 0};
    blocks[1].faces[0] = {BoundaryKind::Interface, 0, 1};
    blocks[0].faces[2].kind = blocks[1].faces[2].kind = BoundaryKind::Wall;
    return blocks;
}

std::vector<NodePair> sideBySidePairs(std::array<int, 3> d) {
    std::vector<NodePair> pairs;
    for (int k = 0; k < d[2]; ++k) {
        for (int j = 0; j < d[1]; ++j) pairs.push_back({0, local(d, d[0] - 1, j, k), 1, local(d, 0, j, k)});
    }
    return pairs;
}

}  // namespace

TEST(FlowMesh, FaceNodesListEachFaceOnceLowerTangentialIndexFastest) {
    const std::array<int, 3> d{4, 3, 5};
    const long total = 4 * 3 * 5;
    // Tangential directions of each normal direction (lower first) and their sizes.
    const int tangential[3][2] = {{1, 2}, {0, 2}, {0, 1}};
    for (int f = 0; f < 6; ++f) {
        const int dir = faceDirection(f);
        EXPECT_EQ(dir, f / 2);
        EXPECT_EQ(faceIsMax(f), f % 2 == 1);
        const std::vector<long> nodes = faceNodes(d, f);
        const int ta = tangential[dir][0], tb = tangential[dir][1];
        ASSERT_EQ(nodes.size(), static_cast<std::size_t>(d[ta] * d[tb])) << "face " << f;
        for (std::size_t a = 0; a < nodes.size(); ++a) {
            const auto idx = nodeIndex(d, nodes[a]);
            EXPECT_EQ(idx[dir], faceIsMax(f) ? d[dir] - 1 : 0);
            EXPECT_EQ(idx[ta], static_cast<int>(a % d[ta]));  // the lower tangential index fastest
            EXPECT_EQ(idx[tb], static_cast<int>(a / d[ta]));
            EXPECT_EQ(faceNodeIndex(d, f, nodes[a]), static_cast<long>(a));
        }
        // onFace holds for exactly these nodes.
        const std::set<long> listed(nodes.begin(), nodes.end());
        EXPECT_EQ(listed.size(), nodes.size());
        for (long n = 0; n < total; ++n) EXPECT_EQ(onFace(d, n, f), listed.count(n) == 1) << "face " << f << " node " << n;
    }
    // nodeIndex inverts the i-fastest numbering.
    for (long n = 0; n < total; ++n) {
        const auto idx = nodeIndex(d, n);
        EXPECT_EQ(local(d, idx[0], idx[1], idx[2]), n);
    }
}

TEST(FlowMesh, OffsetsAndCountsFollowTheBlocksWhateverOffsetsTheyCarry) {
    std::vector<FlowBlock> blocks{block("a", {3, 4, 5}), block("b", {2, 2, 2}), block("c", {6, 2, 3})};
    blocks[0].offset = 99;
    blocks[2].offset = -7;
    const FlowMesh fm = makeFlowMesh(blocks, {});
    ASSERT_EQ(fm.blocks.size(), 3u);
    EXPECT_EQ(fm.blocks[0].offset, 0);
    EXPECT_EQ(fm.blocks[1].offset, 60);
    EXPECT_EQ(fm.blocks[2].offset, 68);
    EXPECT_EQ(fm.nodeCount, 104);
    EXPECT_EQ(fm.blocks[2].nodeCount(), 36);
    EXPECT_TRUE(fm.interfaces.empty());
    EXPECT_TRUE(fm.wallJunctions.empty());
    EXPECT_EQ(fm.blocks[1].name, "b");
}

TEST(FlowMesh, PairsFormOnePatchPerFacePairInEitherOrderOfTheirSides) {
    const std::array<int, 3> d{3, 4, 2};
    std::vector<NodePair> pairs = sideBySidePairs(d);
    // Give every other pair from B's side; the first one too, so the patch is stored B first.
    for (std::size_t p = 0; p < pairs.size(); p += 2) pairs[p] = {1, pairs[p].nodeB, 0, pairs[p].nodeA};
    const FlowMesh fm = makeFlowMesh(sideBySide(d), pairs);
    ASSERT_EQ(fm.interfaces.size(), 1u);
    const InterfacePatch& ip = fm.interfaces[0];
    EXPECT_EQ(ip.blockA, 1);
    EXPECT_EQ(ip.faceA, 0);
    EXPECT_EQ(ip.blockB, 0);
    EXPECT_EQ(ip.faceB, 1);
    ASSERT_EQ(ip.nodes.size(), 8u);
    std::set<long> seenA, seenB;
    for (const auto& nd : ip.nodes) {
        // Every pair is oriented (node of block 1, node of block 0): same j and k, i = 0 against i = max.
        const auto a = nodeIndex(d, nd[0]), b = nodeIndex(d, nd[1]);
        EXPECT_EQ(a[0], 0);
        EXPECT_EQ(b[0], d[0] - 1);
        EXPECT_EQ(a[1], b[1]);
        EXPECT_EQ(a[2], b[2]);
        seenA.insert(nd[0]);
        seenB.insert(nd[1]);
    }
    EXPECT_EQ(seenA.size(), 8u);
    EXPECT_EQ(seenB.size(), 8u);
}

TEST(FlowMesh, TheWavyBoxInterfaceJoinsCoincidentNodes) {
    const flow::testing::FlowCase c = flow::testing::wavyBox(5, BoundaryKind::Wall);
    ASSERT_EQ(c.fm.blocks.size(), 2u);
    EXPECT_EQ(c.fm.nodeCount, 2L * 5 * 4 * 6);
    ASSERT_EQ(c.fm.interfaces.size(), 1u);
    const InterfacePatch& ip = c.fm.interfaces[0];
    EXPECT_EQ(ip.nodes.size(), 4u * 6);
    for (const auto& nd : ip.nodes) {
        const long a = c.fm.blocks[ip.blockA].offset + nd[0], b = c.fm.blocks[ip.blockB].offset + nd[1];
        for (int x = 0; x < 3; ++x) EXPECT_EQ(c.x[3 * a + x], c.x[3 * b + x]);
    }
    // Walls y = 0 and y = 1 of both blocks meet the interface along 2 lines of 6 nodes (z).
    EXPECT_EQ(c.fm.wallJunctions.size(), 2u * 6);
    for (const WallJunction& j : c.fm.wallJunctions) {
        ASSERT_EQ(j.members.size(), 2u);
        const double* x0 = &c.x[3 * j.members[0][0]];
        const double* x1 = &c.x[3 * j.members[1][0]];
        EXPECT_TRUE(std::abs(x0[1]) < 1e-14 || std::abs(x0[1] - 1.0) < 1e-14) << x0[1];
        for (int x = 0; x < 3; ++x) EXPECT_EQ(x0[x], x1[x]);
    }
}

TEST(FlowMesh, WallNodesOnAnInterfaceFormJunctionsMarkedOnTheirFaces) {
    const std::array<int, 3> d{3, 4, 2};
    const FlowMesh fm = makeFlowMesh(sideBySide(d), sideBySidePairs(d));
    // The wall j = 0 of both blocks meets the interface in the 2 nodes (k = 0, 1).
    ASSERT_EQ(fm.wallJunctions.size(), 2u);
    for (const WallJunction& j : fm.wallJunctions) {
        ASSERT_EQ(j.members.size(), 2u);
        std::set<long> nodes;
        for (const auto& m : j.members) {
            EXPECT_EQ(m[1], 2);  // the wall face j = 0
            nodes.insert(m[0]);
        }
        const long a = *nodes.begin(), b = *nodes.rbegin();  // block A's node, then block B's
        ASSERT_LT(a, fm.blocks[1].offset);
        ASSERT_GE(b, fm.blocks[1].offset);
        const auto ia = nodeIndex(d, a), ib = nodeIndex(d, b - fm.blocks[1].offset);
        EXPECT_EQ(ia[0], d[0] - 1);
        EXPECT_EQ(ib[0], 0);
        EXPECT_EQ(ia[1], 0);
        EXPECT_EQ(ib[1], 0);
        EXPECT_EQ(ia[2], ib[2]);
    }
    // Each block marks its 2 junction nodes on the wall face, in faceNodes order; no other face.
    for (int b = 0; b < 2; ++b) {
        const FlowBlock& blk = fm.blocks[b];
        const std::vector<long> nodes = faceNodes(d, 2);
        ASSERT_EQ(blk.junction[2].size(), nodes.size());
        int marked = 0;
        for (std::size_t a = 0; a < nodes.size(); ++a) {
            const int id = blk.junction[2][a];
            const bool onInterface = nodeIndex(d, nodes[a])[0] == (b == 0 ? d[0] - 1 : 0);
            EXPECT_EQ(id >= 0, onInterface);
            if (id < 0) continue;
            ++marked;
            const auto& members = fm.wallJunctions[id].members;
            const long g = blk.offset + nodes[a];
            EXPECT_TRUE(members[0][0] == g || members[1][0] == g);
        }
        EXPECT_EQ(marked, 2);
        for (int f : {0, 1, 3, 4, 5}) EXPECT_TRUE(blk.junction[f].empty()) << "block " << b << " face " << f;
    }
}

// Three blocks around an edge: A's face i = max against B's face i = 0, B's face j = 0 against
// C's face j = max. B's edge node (0, 0, k) is paired with both, so A's wall node (max, 0, k)
// (wall j = 0) and C's wall node (0, max, k) (wall i = 0) are one point although no pair joins
// them directly: one junction per k, with A's and C's wall nodes as members (B has no wall).
TEST(FlowMesh, JunctionsFollowPairsThroughABlockWithoutAWall) {
    const std::array<int, 3> d{2, 2, 3};
    std::vector<FlowBlock> blocks{block("A", d), block("B", d), block("C", d)};
    blocks[0].faces[1] = {BoundaryKind::Interface, 1, 0};
    blocks[1].faces[0] = {BoundaryKind::Interface, 0, 1};
    blocks[1].faces[2] = {BoundaryKind::Interface, 2, 3};
    blocks[2].faces[3] = {BoundaryKind::Interface, 1, 2};
    blocks[0].faces[2].kind = BoundaryKind::Wall;
    blocks[2].faces[0].kind = BoundaryKind::Wall;
    std::vector<NodePair> pairs;
    for (int k = 0; k < d[2]; ++k) {
        for (int t = 0; t < 2; ++t) {
            pairs.push_back({0, local(d, 1, t, k), 1, local(d, 0, t, k)});
            pairs.push_back({2, local(d, t, 1, k), 1, local(d, t, 0, k)});  // C's side first
        }
    }
    const FlowMesh fm = makeFlowMesh(blocks, pairs);
    ASSERT_EQ(fm.interfaces.size(), 2u);
    EXPECT_EQ(fm.interfaces[1].blockA, 2);
    EXPECT_EQ(fm.interfaces[1].faceA, 3);
    ASSERT_EQ(fm.wallJunctions.size(), static_cast<std::size_t>(d[2]));
    std::set<int> ks;
    for (const WallJunction& j : fm.wallJunctions) {
        ASSERT_EQ(j.members.size(), 2u);
        const auto& a = j.members[0];  // blocks in order: A's member first
        const auto& c = j.members[1];
        ASSERT_LT(a[0], fm.blocks[1].offset);
        ASSERT_GE(c[0], fm.blocks[2].offset);
        EXPECT_EQ(a[1], 2);
        EXPECT_EQ(c[1], 0);
        const auto ia = nodeIndex(d, a[0]), ic = nodeIndex(d, c[0] - fm.blocks[2].offset);
        EXPECT_EQ(ia[0], 1);
        EXPECT_EQ(ia[1], 0);
        EXPECT_EQ(ic[0], 0);
        EXPECT_EQ(ic[1], 1);
        EXPECT_EQ(ia[2], ic[2]);
        ks.insert(ia[2]);
    }
    EXPECT_EQ(ks.size(), static_cast<std::size_t>(d[2]));
    EXPECT_TRUE(fm.blocks[1].junction[2].empty());  // B: no wall, nothing marked

    // Without the B-C pairs' edge (C's wall turned into a farfield) nothing is left to join.
    blocks[2].faces[0].kind = BoundaryKind::Farfield;
    EXPECT_TRUE(makeFlowMesh(blocks, pairs).wallJunctions.empty());
}

TEST(FlowMesh, ABlockAgainstItselfFormsOnePeriodicPatch) {
    const std::array<int, 3> d{3, 2, 4};
    std::vector<FlowBlock> blocks{block("ring", d)};
    blocks[0].faces[4] = {BoundaryKind::Interface, 0, 5};
    blocks[0].faces[5] = {BoundaryKind::Interface, 0, 4};
    std::vector<NodePair> pairs;
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 3; ++i) pairs.push_back({0, local(d, i, j, 0), 0, local(d, i, j, 3)});
    }
    const FlowMesh fm = makeFlowMesh(blocks, pairs);
    ASSERT_EQ(fm.interfaces.size(), 1u);
    EXPECT_EQ(fm.interfaces[0].faceA, 4);
    EXPECT_EQ(fm.interfaces[0].faceB, 5);
    EXPECT_EQ(fm.interfaces[0].nodes.size(), 6u);
}

TEST(FlowMesh, RejectsBlocksAndPairsThatDoNotFitNamingBlockAndFace) {
    const std::array<int, 3> d{3, 4, 2};
    // A block one node thin.
    {
        std::vector<FlowBlock> blocks{block("A", d), block("thin", {3, 1, 2})};
        const std::string m = aero::test::messageOf<GeometryError>([&] { makeFlowMesh(blocks, {}); });
        EXPECT_NE(m.find("block 2 ('thin')"), std::string::npos) << m;
        EXPECT_NE(m.find("at least 2 nodes"), std::string::npos) << m;
    }
    // A pair naming a block that does not exist.
    {
        std::vector<NodePair> pairs = sideBySidePairs(d);
        pairs[3].blockB = 2;
        EXPECT_NE(aero::test::messageOf<GeometryError>([&] { makeFlowMesh(sideBySide(d), pairs); }).find("does not exist"), std::string::npos);
        pairs[3].blockB = -1;
        EXPECT_NE(aero::test::messageOf<GeometryError>([&] { makeFlowMesh(sideBySide(d), pairs); }).find("does not exist"), std::string::npos);
    }
    // A pair whose node of A is not on the interface face (i = 1 instead of i = 2).
    {
        std::vector<NodePair> pairs = sideBySidePairs(d);
        pairs[5].nodeA = local(d, 1, 1, 1);
        const std::string m = aero::test::messageOf<GeometryError>([&] { makeFlowMesh(sideBySide(d), pairs); });
        EXPECT_NE(m.find("interface node " + std::to_string(local(d, 1, 1, 1))), std::string::npos) << m;
        EXPECT_NE(m.find("block 1 ('A')"), std::string::npos) << m;
        EXPECT_NE(m.find("against block 2 ('B')"), std::string::npos) << m;
        EXPECT_NE(m.find("lies on no interface face"), std::string::npos) << m;
    }
    // An interface face with a node left without a partner.
    {
        std::vector<NodePair> pairs = sideBySidePairs(d);
        pairs.pop_back();
        const std::string m = aero::test::messageOf<GeometryError>([&] { makeFlowMesh(sideBySide(d), pairs); });
        EXPECT_NE(m.find("block 1 ('A') face 1 is an interface but 7 of its 8 nodes"), std::string::npos) << m;
    }
    // A node on the edge of two interface faces joining the same blocks: ambiguous.
    {
        std::vector<FlowBlock> blocks = sideBySide(d);
        blocks[0].faces[3] = {BoundaryKind::Interface, 1, 3};
        blocks[1].faces[3] = {BoundaryKind::Interface, 0, 3};
        std::vector<NodePair> pairs = sideBySidePairs(d);
        pairs.insert(pairs.begin(), {0, local(d, 2, 3, 0), 1, local(d, 0, 3, 0)});  // on faces 1 and 3 of both
        const std::string m = aero::test::messageOf<GeometryError>([&] { makeFlowMesh(blocks, pairs); });
        EXPECT_NE(m.find("lies on several interface faces"), std::string::npos) << m;
    }
    // A face declared as an interface to a block whose pairs go elsewhere: no pairs at all.
    {
        std::vector<FlowBlock> blocks = sideBySide(d);
        blocks[0].faces[4] = {BoundaryKind::Interface, 1, 5};
        blocks[1].faces[5] = {BoundaryKind::Interface, 0, 4};
        const std::string m = aero::test::messageOf<GeometryError>([&] { makeFlowMesh(blocks, sideBySidePairs(d)); });
        EXPECT_NE(m.find("block 1 ('A') face 4 is an interface but 0 of its 12 nodes"), std::string::npos) << m;
    }
}

// A face whose pairs are as many as its nodes but repeat one node and miss another is not
// "paired node for node"; nor is one with every node paired and one pair given twice (its SAT
// would be applied twice).
TEST(FlowMesh, RejectsAnInterfaceFaceWithARepeatedPair) {
    const std::array<int, 3> d{3, 4, 2};
    std::vector<NodePair> pairs = sideBySidePairs(d);
    pairs.back() = pairs.front();
    std::string m = aero::test::messageOf<GeometryError>([&] { makeFlowMesh(sideBySide(d), pairs); });
    EXPECT_NE(m.find("block 1 ('A') face 1 is an interface but 7 of its 8 nodes have an interface partner (8 pairs"),
              std::string::npos)
        << "message: '" << m << "'";
    pairs = sideBySidePairs(d);
    pairs.push_back(pairs[3]);
    m = aero::test::messageOf<GeometryError>([&] { makeFlowMesh(sideBySide(d), pairs); });
    EXPECT_NE(m.find("block 1 ('A') face 1 is an interface but 8 of its 8 nodes have an interface partner (9 pairs: a node is "
                     "paired more than once)"),
              std::string::npos)
        << "message: '" << m << "'";
}

TEST(FlowMesh, GathersCoordinatesInTheGlobalOrderAndChecksTheGrids) {
    std::vector<mesh::StructuredGrid> grids(2);
    grids[0].name = "a";
    grids[0].dims = {2, 3, 2};
    grids[1].name = "b";
    grids[1].dims = {2, 2, 2};
    for (int g = 0; g < 2; ++g) {
        grids[g].xyz.resize(3 * static_cast<std::size_t>(grids[g].nodeCount()));
        for (std::size_t e = 0; e < grids[g].xyz.size(); ++e) grids[g].xyz[e] = 1000.0 * g + static_cast<double>(e);
    }
    const FlowMesh fm = makeFlowMesh({block("a", grids[0].dims), block("b", grids[1].dims)}, {});
    const std::vector<double> x = gatherCoordinates(fm, grids);
    ASSERT_EQ(x.size(), 3u * 20);
    EXPECT_EQ(x[0], 0.0);
    EXPECT_EQ(x[3 * 12 - 1], 35.0);  // the last coordinate of block a
    EXPECT_EQ(x[3 * 12], 1000.0);    // block b starts at node 12
    EXPECT_EQ(x[3 * 20 - 1], 1023.0);

    grids[1].dims = {2, 4, 1};  // as many nodes, another shape
    const std::string m = aero::test::messageOf<GeometryError>([&] { gatherCoordinates(fm, grids); });
    EXPECT_NE(m.find("block 2 ('b')"), std::string::npos) << m;

    mesh::MultiBlockMesh one;
    one.blocks.resize(1);
    EXPECT_NE(aero::test::messageOf<GeometryError>([&] { makeFlowMesh(one, grids); }).find("2 grids for 1 mesh blocks"), std::string::npos);
}

TEST(FlowMesh, BlockGroupsSplitConsecutiveBlocksByNodeCount) {
    // Node counts 8, 8, 8, 8 (offsets 0, 8, 16, 24; middles 4, 12, 20, 28 of 32).
    const std::array<int, 3> d{2, 2, 2};
    const FlowMesh even = makeFlowMesh({block("a", d), block("b", d), block("c", d), block("d", d)}, {});
    auto groupsOfBlocks = [](const FlowMesh& fm, int groups) {
        const std::vector<int> g = blockGroups(fm, groups);
        EXPECT_EQ(g.size(), static_cast<std::size_t>(fm.nodeCount));
        std::vector<int> out;
        for (const FlowBlock& b : fm.blocks) {
            for (long n = b.offset; n < b.offset + b.nodeCount(); ++n) EXPECT_EQ(g[n], g[b.offset]);
            out.push_back(g[b.offset]);
        }
        return out;
    };
    EXPECT_EQ(groupsOfBlocks(even, 1), (std::vector<int>{0, 0, 0, 0}));
    EXPECT_EQ(groupsOfBlocks(even, 2), (std::vector<int>{0, 0, 1, 1}));
    EXPECT_EQ(groupsOfBlocks(even, 4), (std::vector<int>{0, 1, 2, 3}));
    EXPECT_EQ(groupsOfBlocks(even, 8), (std::vector<int>{1, 3, 5, 7}));
    // One big block (64 nodes) among small ones: its middle (8 + 32 = 40 of 80) is in group 1 of 2.
    const FlowMesh uneven = makeFlowMesh({block("a", d), block("big", {4, 4, 4}), block("c", d)}, {});
    EXPECT_EQ(groupsOfBlocks(uneven, 2), (std::vector<int>{0, 1, 1}));
    EXPECT_EQ(groupsOfBlocks(uneven, 3), (std::vector<int>{0, 1, 2}));
}
