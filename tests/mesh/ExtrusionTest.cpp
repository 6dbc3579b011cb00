#include "mesh/Extrusion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/Error.h"
#include "geometry/HalfSphere.h"
#include "geometry/Topology.h"
#include "mesh/Quality.h"

using namespace aero;
using namespace aero::mesh;

namespace {
const MultiBlockMesh& coarse() {
    static const MultiBlockMesh m = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    return m;
}
}  // namespace

TEST(Extrusion, HalfSphereBlocksCountsAndBoundaries) {
    const MultiBlockMesh& m = coarse();
    ASSERT_EQ(m.blocks.size(), 20u);
    EXPECT_EQ(m.controlCount(), 521 * 12);
    EXPECT_EQ(m.gridNodeCount(), 20L * 17 * 17 * 17);
    int wall = 0, far = 0, sym = 0, iface = 0;
    for (const auto& b : m.blocks) {
        for (const auto& f : b.faces) {
            wall += f.kind == BoundaryKind::Wall;
            far += f.kind == BoundaryKind::Farfield;
            sym += f.kind == BoundaryKind::Symmetry;
            iface += f.kind == BoundaryKind::Interface;
        }
    }
    EXPECT_EQ(wall, 20);
    EXPECT_EQ(far, 20);
    EXPECT_EQ(sym, 8);
    EXPECT_EQ(iface, 72);  // 36 shared patch edges, seen from both sides
    EXPECT_EQ(m.interfaceNodes.size(), 36u * 17 * 17);
    EXPECT_NO_THROW(validate(m));
}

TEST(Extrusion, WallControlNodesAreTheGeometryControlPoints) {
    // A = [0 I] b: the wall layer of every block's control net is the patch's control net itself.
    const auto set = geometry::makeHalfSphere();
    const MultiBlockMesh& m = coarse();
    const auto idx = geometry::buildControlPointIndex(set);
    for (int u = 0; u < idx.uniqueCount(); ++u) {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(m.control[3 * m.surfaceNode[u] + c], idx.points[3 * u + c]);
    }
    for (int p = 0; p < set.size(); ++p) {
        const nurbs::Volume<double> v = blockVolume(m, p);
        const auto& patch = set.patches[p];
        for (int j = 0; j < patch.countV; ++j) {
            for (int i = 0; i < patch.countU; ++i) {
                for (int c = 0; c < 3; ++c) EXPECT_EQ(v.points[3 * v.index(i, j, 0) + c], patch.points[3 * patch.index(i, j) + c]);
            }
        }
    }
}

TEST(Extrusion, GridWallIsTheExactSurfaceAndInterfacesCoincide) {
    const auto set = geometry::makeHalfSphere();
    const MultiBlockMesh& m = coarse();
    const auto grids = regenerateAll(m);
    for (int p = 0; p < set.size(); p += 3) {
        const auto& g = grids[p];
        const auto& b = m.blocks[p];
        for (int j = 0; j < g.dims[1]; j += 4) {
            for (int i = 0; i < g.dims[0]; i += 4) {
                const auto S = nurbs::evaluate(set.patches[p], b.samples[0][i], b.samples[1][j]);
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(g.at(i, j, 0)[c], S[c], 1e-15);
            }
        }
        // The farfield face lies near the farfield sphere (20 body radii).
        const double* f = g.at(g.dims[0] / 2, g.dims[1] / 2, g.dims[2] - 1);
        EXPECT_NEAR(std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]), 20.0, 0.5);
    }
    for (const NodePair& q : m.interfaceNodes) {
        for (int c = 0; c < 3; ++c) ASSERT_EQ(grids[q.blockA].xyz[3 * q.nodeA + c], grids[q.blockB].xyz[3 * q.nodeB + c]);
    }
}

TEST(Extrusion, RegenerationEqualsPointEvaluation) {
    const MultiBlockMesh& m = coarse();
    StructuredGrid g;
    regenerate(m, 7, g);
    const nurbs::Volume<double> v = blockVolume(m, 7);
    const auto& s = m.blocks[7].samples;
    for (int k = 0; k < g.dims[2]; k += 3) {
        for (int j = 0; j < g.dims[1]; j += 2) {
            for (int i = 0; i < g.dims[0]; i += 2) {
                const auto P = nurbs::evaluate(v, s[0][i], s[1][j], s[2][k]);
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(g.at(i, j, k)[c], P[c], 1e-13 * std::max(1.0, std::abs(P[c])));
            }
        }
    }
}

TEST(Extrusion, RefinementResamplesTheSameAnalyticGrid) {
    ExtrusionOptions o = extrusionLevel("coarse");
    const auto set = geometry::makeHalfSphere();
    const MultiBlockMesh base = extrudeToFarfield(set, o);
    o.refine = 2.0;
    const MultiBlockMesh fine = extrudeToFarfield(set, o);
    EXPECT_EQ(fine.controlCount(), base.controlCount());
    const auto gb = regenerateAll(base), gf = regenerateAll(fine);
    EXPECT_EQ(gf[0].dims[0], 2 * (gb[0].dims[0] - 1) + 1);
    EXPECT_EQ(gf[0].dims[2], 2 * (gb[0].dims[2] - 1) + 1);
    for (int k = 0; k < gb[3].dims[2]; ++k) {
        for (int j = 0; j < gb[3].dims[1]; j += 3) {
            for (int i = 0; i < gb[3].dims[0]; i += 3) {
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(gf[3].at(2 * i, 2 * j, 2 * k)[c], gb[3].at(i, j, k)[c], 1e-13);
            }
        }
    }
    // Refinement shrinks the first radial interval: to at most half, since the stretching
    // function is convex (zeta(h/2) <= zeta(h)/2), and not far below half.
    auto spacing = [](const StructuredGrid& g) {
        const double* a = g.at(g.dims[0] / 2, g.dims[1] / 2, 0);
        const double* b = g.at(g.dims[0] / 2, g.dims[1] / 2, 1);
        return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
    };
    EXPECT_NEAR(spacing(gb[3]), 1e-2, 1e-3);  // the level's off-wall spacing
    EXPECT_LE(spacing(gf[3]) / spacing(gb[3]), 0.5 + 1e-9);
    EXPECT_GT(spacing(gf[3]) / spacing(gb[3]), 0.4);
}

// Every named level's radial spacing grows smoothly: the ratio of neighbouring spacings along any
// grid line stays below 1.6 (the former law multiplied two exponentials, and the coarse level's
// last radial cell was 18.5 times its neighbour).
TEST(Extrusion, NamedLevelsHaveNoSpacingJump) {
    const auto set = geometry::makeHalfSphere();
    for (const char* level : {"coarse", "medium"}) {
        const SpacingJump j = largestSpacingJump(regenerateAll(extrudeToFarfield(set, extrusionLevel(level))));
        std::printf("level %s: largest spacing jump %.3f (block %d, direction %d)\n", level, j.ratio, j.block, j.direction);
        EXPECT_LT(j.ratio, 1.6) << level;
        EXPECT_EQ(j.direction, 2) << level;  // the largest is radial
    }
}

TEST(Extrusion, BadInputIsRejected) {
    EXPECT_THROW(extrusionLevel("huge"), CaseError);
    EXPECT_THROW(boundaryFromName("inflow", "mesh.faces[0]"), CaseError);
    // An open patch network (a patch edge neither shared nor on the symmetry plane).
    auto set = geometry::makeHalfSphere();
    set.patches.erase(set.patches.begin());
    set.names.erase(set.names.begin());
    EXPECT_THROW(extrudeToFarfield(set, extrusionLevel("coarse")), GeometryError);
    // A trimmed patch: blocks are extruded from whole patch nets, so it is refused by name.
    auto trimmed = geometry::makeHalfSphere();
    trimmed.source = "wing.igs";
    trimmed.trims.resize(static_cast<std::size_t>(trimmed.size()));
    const auto& p = trimmed.patches[4];
    trimmed.trims[4].outer = geometry::rectangleLoop(p.knotsU.front(), 0.5 * (p.knotsU.front() + p.knotsU.back()), p.knotsV.front(),
                                                     p.knotsV.back());
    try {
        extrudeToFarfield(trimmed, extrusionLevel("coarse"));
        ADD_FAILURE() << "a trimmed patch was extruded";
    } catch (const GeometryError& e) {
        EXPECT_NE(std::string(e.what()).find("mesh generation (extrusion of whole patch nets) needs untrimmed patches: patch 5 ('" +
                                             trimmed.names[4] + "') of 'wing.igs' is trimmed"),
                  std::string::npos)
            << e.what();
    }
    // A mismatched interface: change one block's samples so its face nodes no longer meet.
    MultiBlockMesh m = coarse();
    m.interfaceNodes.clear();  // otherwise regenerateAll copies the old pairs and hides the mismatch
    m.blocks[0].samples[0][3] += 1e-3;
    EXPECT_THROW(matchInterfaces(m, regenerateAll(m)), GeometryError);
}

// Hostile sizes are refused before anything is allocated, with the sizes and keys named
// (mesh.refine 1e6 took 6.9 GB before the message; issue #20).
TEST(Extrusion, RefusesGridsBeyondTheLimitNamingTheSizes) {
    ExtrusionOptions o = extrusionLevel("coarse");
    o.refine = 1e6;
    try {
        (void)extrudeToFarfield(geometry::makeHalfSphere(), o);
        ADD_FAILURE() << "accepted";
    } catch (const CaseError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("more than the 30 million accepted"), std::string::npos) << m;
        EXPECT_NE(m.find("refine 1e+06"), std::string::npos) << m;
    }
    o = extrusionLevel("paper");
    EXPECT_NO_THROW((void)extrudeToFarfield(geometry::makeHalfSphere(), o));  // 903,340 nodes
    o = extrusionLevel("coarse");
    o.radialControlPoints = 100000;
    EXPECT_THROW((void)extrudeToFarfield(geometry::makeHalfSphere(), o), CaseError);
}
