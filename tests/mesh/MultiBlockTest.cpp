// The multiblock control grid (mesh/MultiBlock.h) on two hand-built blocks that share the
// control nodes of their interface, the second one turned (its i, j, k run along x, z and -y):
// with control points at the Greville abscissae of an affine map the regenerated grid is that
// map (linear precision); interfaces are matched node for node within the tolerance (also across
// the cells of its spatial hash) and regenerateAll makes them coincide bit for bit;
// regenerateTranspose is the exact transpose of regenerate; validate and matchInterfaces name the
// block and face of every inconsistency.
#include "mesh/MultiBlock.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <set>
#include <string>

#include "common/Error.h"
#include "ErrorMessage.h"

using namespace aero;
using namespace aero::mesh;

namespace {

// Global control node (I, J, K) of the 7 x 3 x 2 net over the parameter box [0, 2] x [0, 1] x [0, 1].
int globalNode(int I, int J, int K) { return I + 7 * (J + 3 * K); }
const double kX[7] = {0.0, 0.25, 0.75, 1.0, 1.25, 1.75, 2.0};  // Greville points: 2 x (degree 2, 4 points)
const double kY[3] = {0.0, 0.5, 1.0};                          // degree 2, 3 points
const double kZ[2] = {0.0, 1.0};                               // degree 1, 2 points

// The affine map from parameters (X, Y, Z) to space.
Eigen::Vector3d affine(double X, double Y, double Z) {
    Eigen::Matrix3d M;
    M << 1.5, 0.2, 0.1, -0.3, 0.8, 0.25, 0.05, -0.1, 1.2;
    return M * Eigen::Vector3d(X, Y, Z) + Eigen::Vector3d(0.4, -0.2, 1.0);
}

// Block A covers X in [0, 1] with (i, j, k) along (X, Y, Z); block B covers X in [1, 2] with
// (i, j, k) along (X, Z, -Y). A's face 1 (i max) is B's face 0 (i = 0); the column I = 3 of
// control nodes belongs to both. A's grid-node parameters along Y are {0, 0.3, 1}; B samples
// the same nodes from the other end ({0, 0.7, 1} along -Y).
MultiBlockMesh twoBlocks() {
    MultiBlockMesh m;
    m.control.resize(3 * 42);
    for (int K = 0; K < 2; ++K) {
        for (int J = 0; J < 3; ++J) {
            for (int I = 0; I < 7; ++I) {
                const Eigen::Vector3d x = affine(kX[I], kY[J], kZ[K]);
                for (int c = 0; c < 3; ++c) m.control[3 * globalNode(I, J, K) + c] = x[c];
            }
        }
    }
    const std::vector<double> quadratic4{0, 0, 0, 0.5, 1, 1, 1}, quadratic3{0, 0, 0, 1, 1, 1}, linear2{0, 0, 1, 1};
    m.blocks.resize(2);
    ControlBlock& a = m.blocks[0];
    a.name = "A";
    a.degree = {2, 2, 1};
    a.count = {4, 3, 2};
    a.knots = {quadratic4, quadratic3, linear2};
    a.nodes.resize(24);
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < 3; ++j) {
            for (int i = 0; i < 4; ++i) a.nodes[a.local(i, j, k)] = globalNode(i, j, k);
        }
    }
    a.samples = {std::vector<double>{0, 0.2, 0.5, 0.7, 1}, std::vector<double>{0, 0.3, 1}, std::vector<double>{0, 0.4, 1}};
    ControlBlock& b = m.blocks[1];
    b.name = "B";
    b.degree = {2, 1, 2};
    b.count = {4, 2, 3};
    b.knots = {quadratic4, linear2, quadratic3};
    b.nodes.resize(24);
    for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 2; ++j) {
            for (int i = 0; i < 4; ++i) b.nodes[b.local(i, j, k)] = globalNode(3 + i, 2 - k, j);
        }
    }
    b.samples = {std::vector<double>{0, 0.5, 1}, std::vector<double>{0, 0.4, 1}, std::vector<double>{0, 0.7, 1}};
    a.faces[0].kind = BoundaryKind::Wall;
    a.faces[1] = {BoundaryKind::Interface, 1, 0};
    b.faces[0] = {BoundaryKind::Interface, 0, 1};
    b.faces[4].kind = b.faces[5].kind = BoundaryKind::Symmetry;
    return m;
}

// The parameter point (X, Y, Z) of grid node (i, j, k) of block `blk`.
Eigen::Vector3d gridParameter(const MultiBlockMesh& m, int blk, int i, int j, int k) {
    const auto& s = m.blocks[blk].samples;
    if (blk == 0) return {s[0][i], s[1][j], s[2][k]};
    return {1.0 + s[0][i], 1.0 - s[2][k], s[1][j]};
}

}  // namespace

TEST(MultiBlock, BoundaryNamesRoundTripAndUnknownNamesAreCaseErrors) {
    for (BoundaryKind k : {BoundaryKind::Wall, BoundaryKind::Farfield, BoundaryKind::Symmetry, BoundaryKind::Interface}) {
        EXPECT_EQ(boundaryFromName(boundaryName(k), "key"), k);
    }
    EXPECT_STREQ(boundaryName(BoundaryKind::Symmetry), "symmetry");
    try {
        (void)boundaryFromName("outflow", "mesh.blocks[3].faces[1]");
        ADD_FAILURE() << "accepted";
    } catch (const CaseError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("mesh.blocks[3].faces[1]"), std::string::npos) << m;
        EXPECT_NE(m.find("'outflow'"), std::string::npos) << m;
    }
}

TEST(MultiBlock, CountsAndBlockVolumesComeFromTheSharedControlGrid) {
    const MultiBlockMesh m = twoBlocks();
    EXPECT_NO_THROW(validate(m));
    EXPECT_EQ(m.controlCount(), 42);
    EXPECT_EQ(m.gridNodeCount(), 5L * 3 * 3 + 3L * 3 * 3);
    EXPECT_EQ(m.blocks[1].gridDims(), (std::array<int, 3>{3, 3, 3}));
    const nurbs::Volume<double> va = blockVolume(m, 0), vb = blockVolume(m, 1);
    EXPECT_EQ(vb.count, m.blocks[1].count);
    EXPECT_EQ(vb.degree, m.blocks[1].degree);
    ASSERT_EQ(vb.points.size(), 3u * 24);
    for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 2; ++j) {
            for (int i = 0; i < 4; ++i) {
                const Eigen::Vector3d x = affine(kX[3 + i], kY[2 - k], kZ[j]);
                for (int c = 0; c < 3; ++c) EXPECT_EQ(vb.points[3 * vb.index(i, j, k) + c], x[c]);
            }
        }
    }
    // The interface column is one storage: A's (3, j, k) is B's (0, k, 2 - j).
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < 3; ++j) {
            EXPECT_EQ(m.blocks[0].nodes[m.blocks[0].local(3, j, k)], m.blocks[1].nodes[m.blocks[1].local(0, k, 2 - j)]);
            for (int c = 0; c < 3; ++c) EXPECT_EQ(va.points[3 * va.index(3, j, k) + c], vb.points[3 * vb.index(0, k, 2 - j) + c]);
        }
    }
}

TEST(MultiBlock, RegenerationReproducesAnAffineMapInBothBlocks) {
    const MultiBlockMesh m = twoBlocks();
    for (int blk = 0; blk < 2; ++blk) {
        StructuredGrid g;
        regenerate(m, blk, g);
        EXPECT_EQ(g.name, m.blocks[blk].name);
        EXPECT_EQ(g.dims, m.blocks[blk].gridDims());
        ASSERT_EQ(g.xyz.size(), 3u * static_cast<std::size_t>(g.nodeCount()));
        for (int k = 0; k < g.dims[2]; ++k) {
            for (int j = 0; j < g.dims[1]; ++j) {
                for (int i = 0; i < g.dims[0]; ++i) {
                    const Eigen::Vector3d P = gridParameter(m, blk, i, j, k);
                    const Eigen::Vector3d x = affine(P[0], P[1], P[2]);
                    for (int c = 0; c < 3; ++c) EXPECT_NEAR(g.at(i, j, k)[c], x[c], 1e-14) << "block " << blk;
                }
            }
        }
    }
}

TEST(MultiBlock, InterfacesAreMatchedNodeForNodeAndRegeneratedIdentically) {
    MultiBlockMesh m = twoBlocks();
    m.interfaceNodes.push_back({1, 0, 0, 0});  // stale: matchInterfaces replaces the list
    matchInterfaces(m, regenerateAll(m));
    ASSERT_EQ(m.interfaceNodes.size(), 9u);
    std::set<long> seenA, seenB;
    for (const NodePair& p : m.interfaceNodes) {
        EXPECT_EQ(p.blockA, 0);  // the owner: the block whose face is listed first
        EXPECT_EQ(p.blockB, 1);
        // A's node (4, j, k) is B's node (0, k, 2 - j).
        const int i = static_cast<int>(p.nodeA % 5), j = static_cast<int>(p.nodeA / 5 % 3), k = static_cast<int>(p.nodeA / 15);
        EXPECT_EQ(i, 4);
        EXPECT_EQ(p.nodeB, 0 + 3L * (k + 3L * (2 - j)));
        seenA.insert(p.nodeA);
        seenB.insert(p.nodeB);
    }
    EXPECT_EQ(seenA.size(), 9u);
    EXPECT_EQ(seenB.size(), 9u);

    // Move every control node at random (the interface column stays shared): the two blocks
    // evaluate the interface from different parameter directions, and regenerateAll copies the
    // owner's nodes so that they coincide exactly.
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> U(-0.05, 0.05);
    for (double& x : m.control) x += U(rng);
    const std::vector<StructuredGrid> grids = regenerateAll(m);
    StructuredGrid ownA;
    regenerate(m, 0, ownA);
    for (const NodePair& p : m.interfaceNodes) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(grids[1].xyz[3 * p.nodeB + c], grids[0].xyz[3 * p.nodeA + c]);
            EXPECT_EQ(grids[0].xyz[3 * p.nodeA + c], ownA.xyz[3 * p.nodeA + c]);
        }
    }
}

// Nodes within the tolerance in every coordinate are partners even when they fall into
// neighbouring cells of the hash grid (cell size 4 x tolerance); a node farther away in one
// coordinate leaves the interface mismatched, and the message names both faces and the counts.
TEST(MultiBlock, MatchingHonoursTheToleranceAcrossHashCells) {
    MultiBlockMesh m = twoBlocks();
    std::vector<StructuredGrid> grids = regenerateAll(m);
    const double tol = 1e-6, h = 4 * tol;
    // A's interface node (4, 1, 1) placed just below hash-cell boundaries, B's partner (0, 1, 1)
    // just above them, 0.9 tol away in each coordinate.
    const long na = 4 + 5L * (1 + 3L * 1), nb = 0 + 3L * (1 + 3L * 1);
    const double xa[3] = {250 * h - 0.3 * tol, 100 * h + 0.45 * tol, -30 * h - 0.2 * tol};
    const double xb[3] = {xa[0] + 0.9 * tol, xa[1] - 0.9 * tol, xa[2] + 0.9 * tol};
    for (int c = 0; c < 3; ++c) {
        grids[0].xyz[3 * na + c] = xa[c];
        grids[1].xyz[3 * nb + c] = xb[c];
    }
    // The other nodes: offsets of 0.9 tol in alternating directions.
    for (long n = 0; n < grids[1].nodeCount(); ++n) {
        if (n == nb) continue;
        for (int c = 0; c < 3; ++c) grids[1].xyz[3 * n + c] += ((n + c) % 2 == 0 ? 0.9 : -0.9) * tol;
    }
    matchInterfaces(m, grids, tol);
    ASSERT_EQ(m.interfaceNodes.size(), 9u);
    int found = 0;
    for (const NodePair& p : m.interfaceNodes) {
        EXPECT_EQ(p.nodeB, 3L * (p.nodeA / 15 + 3L * (2 - p.nodeA / 5 % 3)));  // the same partners as without offsets
        found += p.nodeA == na && p.nodeB == nb;
    }
    EXPECT_EQ(found, 1);

    grids[1].xyz[3 * nb + 1] = xa[1] - 1.5 * tol;
    try {
        matchInterfaces(m, grids, tol);
        ADD_FAILURE() << "a node 1.5 tolerances away was matched";
    } catch (const GeometryError& e) {
        const std::string s = e.what();
        EXPECT_NE(s.find("block 1 ('A') face 1 and block 2 ('B') face 0: 1 of 9 nodes have no coincident partner (9 on the other side)"),
                  std::string::npos)
            << s;
    }
}

TEST(MultiBlock, MatchingRefusesFacesOfDifferentSizes) {
    MultiBlockMesh m = twoBlocks();
    m.blocks[1].samples[1] = {0, 0.4, 0.8, 1};  // B's interface face gets a row more than A's
    const std::string s = aero::test::messageOf<GeometryError>([&] { matchInterfaces(m, regenerateAll(m)); });
    EXPECT_NE(s.find("mismatched interface between block 1 ('A') face 1 and block 2 ('B') face 0"), std::string::npos) << s;
    EXPECT_NE(s.find("(12 on the other side)"), std::string::npos) << s;
}

// <N b, g> = <b, N^T g> summed over both blocks, for a random control grid b and grid vector g;
// controlGradient is accumulated into (+=), so shared nodes collect both blocks' parts.
TEST(MultiBlock, RegenerateTransposeIsTheTransposeOfRegenerate) {
    MultiBlockMesh m = twoBlocks();
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (double& x : m.control) x = U(rng);
    std::vector<double> control0(m.control.size());
    for (double& x : control0) x = U(rng);
    std::vector<double> gradient = control0;
    double lhs = 0;
    for (int blk = 0; blk < 2; ++blk) {
        StructuredGrid g;
        regenerate(m, blk, g);
        std::vector<double> gv(g.xyz.size());
        for (std::size_t e = 0; e < gv.size(); ++e) {
            gv[e] = U(rng);
            lhs += g.xyz[e] * gv[e];
        }
        regenerateTranspose(m, blk, gv.data(), gradient);
    }
    double rhs = 0;
    for (std::size_t e = 0; e < m.control.size(); ++e) rhs += m.control[e] * (gradient[e] - control0[e]);
    EXPECT_NEAR(lhs, rhs, 1e-13 * std::abs(lhs) + 1e-14);
    EXPECT_GT(std::abs(lhs), 1e-2);
}

TEST(MultiBlock, ValidateNamesTheBlockAndFaceOfEachInconsistency) {
    const MultiBlockMesh good = twoBlocks();
    EXPECT_NO_THROW(validate(good));
    {
        MultiBlockMesh m = good;
        m.blocks[1].nodes.pop_back();
        EXPECT_NE(aero::test::messageOf<GeometryError>([&] { validate(m); }).find("block 2 ('B'): 23 control nodes for a 4x2x3 net"), std::string::npos);
    }
    {
        MultiBlockMesh m = good;
        m.blocks[0].nodes[5] = 42;
        EXPECT_NE(aero::test::messageOf<GeometryError>([&] { validate(m); }).find("block 1 ('A'): control node 42 does not exist"), std::string::npos);
        m.blocks[0].nodes[5] = -1;
        EXPECT_NE(aero::test::messageOf<GeometryError>([&] { validate(m); }).find("control node -1 does not exist"), std::string::npos);
    }
    {
        MultiBlockMesh m = good;
        m.blocks[1].faces[0].neighbourFace = 0;  // points at A's face 0, a wall
        EXPECT_NE(aero::test::messageOf<GeometryError>([&] { validate(m); })
                      .find("block 1 ('A') face 1: interface is not mutual (block 2 face 0 does not point back)"),
                  std::string::npos);
    }
    {
        MultiBlockMesh m = good;
        m.blocks[0].faces[1].neighbour = 2;
        EXPECT_NE(aero::test::messageOf<GeometryError>([&] { validate(m); }).find("block 1 ('A') face 1: interface to a block or face that does not exist"),
                  std::string::npos);
        m = good;
        m.blocks[0].faces[1].neighbourFace = 6;
        EXPECT_NE(aero::test::messageOf<GeometryError>([&] { validate(m); }).find("does not exist"), std::string::npos);
    }
    {
        MultiBlockMesh m = good;
        m.blocks[1].samples[2] = {0.5};
        EXPECT_NE(aero::test::messageOf<GeometryError>([&] { validate(m); }).find("block 2 ('B'): fewer than 2 grid nodes in direction 2"),
                  std::string::npos);
    }
    {
        MultiBlockMesh m = good;
        m.blocks[0].knots[1] = {0, 0, 0, 1, 1};  // one knot short for 3 points of degree 2
        const std::string s = aero::test::messageOf<GeometryError>([&] { validate(m); });
        EXPECT_NE(s.find("block 1 ('A') (eta direction)"), std::string::npos) << s;
    }
}
