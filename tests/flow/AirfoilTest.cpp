// The NACA 0012 O-grid (mesh/AirfoilGrid) and the published-reference case of the Euler solver:
// Mach 0.5, alpha 1.25 deg, inviscid and subcritical (AGARD AR-211; fine-grid Euler CL 0.178 ..
// 0.180, CD 0, CM about the quarter chord ~ 0). See docs/validation.md for the refinement study.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "FlowFixtures.h"
#include "common/Error.h"
#include "flow/FlowSolver.h"
#include "flow/Outputs.h"
#include "flow/Residual.h"
#include "mesh/AirfoilGrid.h"
#include "mesh/Quality.h"

namespace aero::flow {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kReferenceCL = 0.1798;

// The CI grid: 65 nodes around, 33 to the farfield at 50 chords, span 1 with 2 node layers.
mesh::AirfoilGridOptions smallGrid() {
    mesh::AirfoilGridOptions o;
    o.aroundNodes = 65;
    o.normalNodes = 33;
    o.farfieldRadius = 50;
    o.wallSpacing = 4e-3;
    o.span = 1.0;
    o.spanNodes = 2;
    return o;
}

testing::FlowCase airfoilCase(const mesh::AirfoilGridOptions& o) {
    const mesh::AirfoilGrid g = mesh::makeAirfoilGrid(o);
    std::vector<FlowBlock> blocks(g.blocks.size());
    for (std::size_t b = 0; b < blocks.size(); ++b) {
        blocks[b].name = g.blocks[b].name;
        blocks[b].dims = g.blocks[b].dims;
        blocks[b].faces = g.faces[b];
    }
    testing::FlowCase c;
    c.fm = makeFlowMesh(blocks, g.interfaceNodes);
    c.x = gatherCoordinates(c.fm, g.blocks);
    c.metrics = computeMetrics(c.fm, c.x);
    return c;
}

// The solver settings of this case: kappa2 0.5 and kappa4 as given (default 0.05), the
// preconditioner's lumping factor 4 (with the former default 16 the ILU of the lumped Jacobian is
// too far from the exact Jacobian on this grid: the exact phase stalls at a relative residual of
// 1e-4) and the CFL capped at 1e4.
ResidualOptions caseOptions(double alphaDeg, double kappa4 = 0.05) {
    ResidualOptions o;
    o.dissipation.kappa4 = kappa4;
    o.freeStream.mach = 0.5;
    o.freeStream.alphaDeg = alphaDeg;
    o.dissipation.lumping = 4.0;
    return o;
}

NewtonOptions caseNewton() {
    NewtonOptions n;
    n.cflMax = 1e4;
    return n;
}

FlowReport solve(const testing::FlowCase& c, const ResidualOptions& o, std::vector<double>& q) {
    return solveFlow(c.fm, c.metrics, o, q, caseNewton(), [](const FlowIteration& it) {
        if (it.iteration % 10 == 0) {
            std::printf("  it %3d  |R|/|R0| %.3e  CFL %.2e  GMRES %3d (%.2e)  %.2f s\n", it.iteration,
                        it.relativeResidual, it.cfl, it.linearIterations, it.linearResidual, it.seconds);
        }
    });
}

ForceCoefficients forces(const testing::FlowCase& c, const ResidualOptions& o,
                         const std::vector<double>& q, double span) {
    ForceReference ref;
    ref.area = 1.0 * span;  // chord x span
    ref.length = 1.0;
    ref.point = {0.25, 0.0, 0.0};
    return integrateForces(c.fm, c.metrics, c.x, q, o.freeStream, ref);
}

TEST(AirfoilGrid, IsRightHandedWithTheWallOnTheProfileAndCoincidentCuts) {
    const mesh::AirfoilGridOptions o = smallGrid();
    const mesh::AirfoilGrid g = mesh::makeAirfoilGrid(o);
    ASSERT_EQ(g.blocks.size(), 2u);
    ASSERT_EQ(g.faces.size(), 2u);
    const int ni = (o.aroundNodes + 1) / 2;
    for (const auto& b : g.blocks) {
        EXPECT_EQ(b.dims, (std::array<int, 3>{ni, o.normalNodes, o.spanNodes}));
    }

    std::vector<mesh::CellQuality> q;
    for (const auto& b : g.blocks) q.push_back(mesh::cellQuality(b));
    EXPECT_NO_THROW(mesh::requirePositiveJacobians(g.blocks, q));
    const mesh::QualitySummary s = mesh::summarize(g.blocks, q, 1);
    EXPECT_EQ(s.nonPositiveJacobian, 0);
    // The sharp trailing edge makes a fan of cells; everywhere else the cells are near boxes.
    EXPECT_GT(s.scaledJacobian.min, 0.1);
    EXPECT_GT(s.scaledJacobian.mean, 0.9);

    // Wall nodes on the NACA 0012 profile, farfield nodes on the circle, first spacing as asked.
    for (int b = 0; b < 2; ++b) {
        const mesh::StructuredGrid& blk = g.blocks[b];
        for (int k = 0; k < o.spanNodes; ++k) {
            for (int i = 0; i < ni; ++i) {
                const int around = b == 0 ? i : ni - 1 + i;
                const auto p = mesh::nacaPoint(o.naca, 2 * kPi * around / (o.aroundNodes - 1));
                const double* w = blk.at(i, 0, k);
                EXPECT_NEAR(w[0], p[0], 1e-14);
                EXPECT_NEAR(w[2], p[1], 1e-14);
                EXPECT_NEAR(w[1], o.span * k / (o.spanNodes - 1), 1e-15);
                const double* f = blk.at(i, o.normalNodes - 1, k);
                EXPECT_NEAR(std::hypot(f[0] - 0.5, f[2]), o.farfieldRadius, 1e-12);
                const double* n1 = blk.at(i, 1, k);
                const double h = std::hypot(n1[0] - w[0], n1[2] - w[2]);
                EXPECT_NEAR(h, o.wallSpacing, 0.02 * o.wallSpacing);
            }
        }
    }
    // Closed trailing edge, leading edge at the origin, 12 % thickness at x = 0.3.
    EXPECT_NEAR(mesh::nacaPoint("0012", 0)[0], 1.0, 1e-15);
    EXPECT_NEAR(mesh::nacaPoint("0012", 0)[1], 0.0, 1e-15);
    EXPECT_NEAR(mesh::nacaPoint("0012", kPi)[0], 0.0, 1e-15);
    const double s03 = 2 * std::acos(std::sqrt(0.3));  // x = 0.3 on the upper surface
    EXPECT_NEAR(mesh::nacaPoint("0012", s03)[1] - mesh::nacaPoint("0012", 2 * kPi - s03)[1], 0.12, 2e-4);

    // Interface pairs coincide exactly and the flow layout accepts them.
    ASSERT_EQ(g.interfaceNodes.size(), 2u * o.normalNodes * o.spanNodes);
    for (const mesh::NodePair& p : g.interfaceNodes) {
        const double* a = &g.blocks[p.blockA].xyz[3 * p.nodeA];
        const double* b = &g.blocks[p.blockB].xyz[3 * p.nodeB];
        for (int c = 0; c < 3; ++c) EXPECT_EQ(a[c], b[c]);
    }
    const testing::FlowCase c = airfoilCase(o);
    EXPECT_EQ(c.fm.interfaces.size(), 2u);
    EXPECT_GT(checkVolumes(c.fm, c.metrics).minJinv, 0.0);
}

TEST(AirfoilGrid, RejectsBadOptionsNamingThem) {
    auto expectError = [](mesh::AirfoilGridOptions o, const std::string& key) {
        try {
            mesh::makeAirfoilGrid(o);
            ADD_FAILURE() << "no error for " << key;
        } catch (const CaseError& e) {
            EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
        }
    };
    mesh::AirfoilGridOptions o = smallGrid();
    o.naca = "012";
    expectError(o, "airfoil.naca");
    o = smallGrid();
    o.naca = "0000";
    expectError(o, "airfoil.naca");
    o = smallGrid();
    o.aroundNodes = 64;
    expectError(o, "airfoil.aroundNodes");
    o = smallGrid();
    o.spanNodes = 1;
    expectError(o, "airfoil.spanNodes");
    o = smallGrid();
    o.wallSpacing = 2.0;
    expectError(o, "airfoil.wallSpacing");
}

TEST(AirfoilGrid, CamberedProfilesGiveValidGrids) {
    for (const char* naca : {"2412", "4415"}) {
        mesh::AirfoilGridOptions o = smallGrid();
        o.naca = naca;
        const mesh::AirfoilGrid g = mesh::makeAirfoilGrid(o);
        std::vector<mesh::CellQuality> q;
        for (const auto& b : g.blocks) q.push_back(mesh::cellQuality(b));
        EXPECT_NO_THROW(mesh::requirePositiveJacobians(g.blocks, q)) << naca;
    }
}

// The two blocks meet on the wall at the leading edge (a smooth wall: one shared normal, along
// +X into the body by symmetry) and at the sharp trailing edge (a corner: each block keeps its
// own normal).
TEST(Airfoil, WallJunctionsAreTheSmoothLeadingEdgeAndTheTrailingEdgeCorner) {
    const testing::FlowCase c = airfoilCase(smallGrid());
    ASSERT_EQ(c.fm.wallJunctions.size(), 4u);  // 2 edges x 2 span layers
    const std::vector<double> jn = wallJunctionNormals(c.fm, c.metrics.data());
    int leading = 0, trailing = 0;
    for (std::size_t j = 0; j < c.fm.wallJunctions.size(); ++j) {
        ASSERT_EQ(c.fm.wallJunctions[j].members.size(), 2u);
        const double* x = &c.x[3 * c.fm.wallJunctions[j].members[0][0]];
        if (x[0] < 0.5) {
            ++leading;
            EXPECT_NEAR(jn[3 * j], 1.0, 1e-12);
            EXPECT_NEAR(jn[3 * j + 1], 0.0, 1e-12);
            EXPECT_NEAR(jn[3 * j + 2], 0.0, 1e-12);
        } else {
            ++trailing;
            for (int k = 0; k < 3; ++k) EXPECT_EQ(jn[3 * j + k], 0.0);
        }
    }
    EXPECT_EQ(leading, 2);
    EXPECT_EQ(trailing, 2);
}

TEST(Airfoil, FreeStreamIsPreserved) {
    // The wall becomes a farfield (a uniform flow crosses it); the curved metrics, both cuts, the
    // two symmetry planes, the dissipation and the farfield are all active.
    testing::FlowCase c = airfoilCase(smallGrid());
    for (FlowBlock& b : c.fm.blocks) {
        for (auto& f : b.faces) {
            if (f.kind == mesh::BoundaryKind::Wall) f.kind = mesh::BoundaryKind::Farfield;
        }
    }
    const ResidualOptions o = caseOptions(1.25);
    const auto q = freeStreamState(c.fm, o.freeStream);
    std::vector<double> r(q.size());
    residual(c.fm, c.metrics.data(), q.data(), o, r.data());
    double rmax = 0;
    for (double v : r) rmax = std::max(rmax, std::abs(v));
    std::printf("airfoil free stream: max |R| = %.3e\n", rmax);
    EXPECT_LT(rmax, 1e-13);
}

TEST(Airfoil, Naca0012AtMachHalfAndOneAndAQuarterDegreesMatchesTheReferenceLift) {
    // The solver's defaults (entropy-conservative scheme, kappa4 0.02) on two nested levels, 65 x 33
    // and 129 x 65 (h halved). The lift error falls at an order between 1 and 2 (the sharp
    // trailing edge); docs/validation.md measures 0.16701, 0.17223, 0.17448, 0.17687 on 65, 97,
    // 129 and 257 nodes around, order 1.6 and Richardson 0.1780 from the last three. So the
    // reference must lie between the Richardson extrapolations of these two levels for orders 2
    // and 1: that rejects thin-airfoil theory with Prandtl-Glauert (0.158) and any lift that
    // does not converge towards the reference.
    double previousCL = 0;
    std::array<double, 2> cl{};
    for (int level = 0; level < 2; ++level) {
        mesh::AirfoilGridOptions g = smallGrid();
        if (level == 1) {
            g.aroundNodes = 129;
            g.normalNodes = 65;
            g.wallSpacing = 1.87e-3;
        }
        const testing::FlowCase c = airfoilCase(g);
        const ResidualOptions o = caseOptions(1.25, 0.02);
        std::vector<double> q;
        const FlowReport rep = solve(c, o, q);
        std::printf("%s (%d GMRES iterations, %.1f s)\n", rep.message.c_str(), rep.linearIterations, rep.seconds);
        ASSERT_TRUE(rep.converged()) << rep.message;
        EXPECT_LE(rep.finalResidual, 1e-10 * rep.initialResidual);

        const ForceCoefficients f = forces(c, o, q, g.span);
        const auto mach = machNumber(c.fm, q, o.freeStream.gamma);
        const double mmax = *std::max_element(mach.begin(), mach.end());
        std::printf("NACA 0012 M 0.5 alpha 1.25 (%ld nodes): CL %.5f (reference %.4f)  CD %.6f  CM %.6f  max Mach %.3f\n",
                    c.fm.nodeCount, f.CL, kReferenceCL, f.CD, f.CM, mmax);
        cl[level] = f.CL;
        EXPECT_GT(f.CL, previousCL);       // approaches the reference from below
        EXPECT_LT(f.CL, kReferenceCL);
        EXPECT_LT(std::abs(f.CD), 2e-3);   // spurious drag: 1.0e-3 and 2.1e-4 measured
        EXPECT_LT(std::abs(f.CM), 5e-3);
        EXPECT_LT(std::abs(f.CY), 1e-10);  // the flow is two-dimensional
        EXPECT_GT(mmax, 0.6);              // subcritical but accelerated over the upper surface (0.65, 0.67)
        EXPECT_LT(mmax, 0.75);
        previousCL = f.CL;
    }
    const double d = cl[1] - cl[0];
    EXPECT_GT(kReferenceCL, cl[1] + d / 3.0);  // Richardson with order 2
    EXPECT_LT(kReferenceCL, cl[1] + d);        // ... and with order 1
}

TEST(Airfoil, Naca0012AtZeroIncidenceHasNoLift) {
    const mesh::AirfoilGridOptions g = smallGrid();
    const testing::FlowCase c = airfoilCase(g);
    const ResidualOptions o = caseOptions(0.0);
    std::vector<double> q;
    const FlowReport rep = solve(c, o, q);
    std::printf("%s (%d GMRES iterations, %.1f s)\n", rep.message.c_str(), rep.linearIterations, rep.seconds);
    ASSERT_TRUE(rep.converged()) << rep.message;
    const ForceCoefficients f = forces(c, o, q, g.span);
    std::printf("NACA 0012 M 0.5 alpha 0: CL %.3e  CD %.6f  CM %.3e\n", f.CL, f.CD, f.CM);
    // The grid is mirror-symmetric node for node; lift and moment vanish to the solver tolerance.
    EXPECT_LT(std::abs(f.CL), 1e-8);
    EXPECT_LT(std::abs(f.CM), 1e-8);
}

}  // namespace
}  // namespace aero::flow
