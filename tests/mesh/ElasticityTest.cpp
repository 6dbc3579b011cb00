#include "mesh/Elasticity.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>

#include "geometry/HalfSphere.h"
#include "mesh/Extrusion.h"
#include "mesh/Quality.h"
#include "nurbs/Basis.h"

#if defined(_OPENMP)
#include <omp.h>
#endif

using namespace aero;
using namespace aero::mesh;

namespace {

// One block: a box [0,2]x[0,1]x[0,1.5] control net of 4x3x5 nodes (trilinear-irrelevant knots),
// all faces fixed boundaries except as set by the test.
MultiBlockMesh boxMesh() {
    MultiBlockMesh m;
    ControlBlock b;
    b.name = "box";
    b.degree = {2, 2, 2};
    b.count = {4, 3, 5};
    for (int d = 0; d < 3; ++d) {
        b.knots[d] = nurbs::uniformKnots(2, b.count[d]);
        b.samples[d] = {0.0, 0.5, 1.0};
    }
    for (int k = 0; k < 5; ++k) {
        for (int j = 0; j < 3; ++j) {
            for (int i = 0; i < 4; ++i) {
                // Slightly irregular interior so the elements are not all alike.
                const double w = (i > 0 && i < 3 && j == 1 && k > 0 && k < 4) ? 0.05 * (i - k) : 0.0;
                m.control.insert(m.control.end(), {2.0 * i / 3 + w, 0.5 * j - w, 1.5 * k / 4 + w});
                b.nodes.push_back(static_cast<int>(b.nodes.size()));
            }
        }
    }
    for (auto& f : b.faces) f.kind = BoundaryKind::Farfield;
    m.blocks.push_back(b);
    return m;
}

}  // namespace

TEST(Elasticity, HexStiffnessIsSymmetricWithRigidBodyNullSpaceAndTheRightEnergy) {
    // Unit cube, E = 2, nu = 0.3.
    const double x[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    double K[24 * 24];
    hexStiffness<double>(x, 2.0, 0.3, K);
    Eigen::Map<Eigen::Matrix<double, 24, 24, Eigen::RowMajor>> M(K);
    EXPECT_LT((M - M.transpose()).norm(), 1e-13 * M.norm());
    // Translations and infinitesimal rotations store no energy.
    for (int c = 0; c < 3; ++c) {
        Eigen::Matrix<double, 24, 1> t = Eigen::Matrix<double, 24, 1>::Zero();
        for (int a = 0; a < 8; ++a) t[3 * a + c] = 1.0;
        EXPECT_LT((M * t).norm(), 1e-13);
        Eigen::Matrix<double, 24, 1> r;
        for (int a = 0; a < 8; ++a) {
            const Eigen::Vector3d p(x[3 * a], x[3 * a + 1], x[3 * a + 2]);
            r.segment<3>(3 * a) = Eigen::Vector3d::Unit(c).cross(p);
        }
        EXPECT_LT((M * r).norm(), 1e-13);
    }
    // Uniaxial strain u = (e x, 0, 0): energy u.K.u = (lambda + 2 mu) e^2 V.
    const double E = 2.0, nu = 0.3, e = 0.01;
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    Eigen::Matrix<double, 24, 1> u = Eigen::Matrix<double, 24, 1>::Zero();
    for (int a = 0; a < 8; ++a) u[3 * a] = e * x[3 * a];
    EXPECT_NEAR(u.dot(M * u), (lambda + 2 * mu) * e * e, 1e-15);
}

TEST(Elasticity, HexStiffnessDerivativeAgreesWithComplexStep) {
    // dK/dx exists for the adjoint through the mesh movement: the template runs in complex arithmetic.
    const double x[24] = {0, 0, 0, 1.1, 0, 0, 1, 1.2, 0, 0, 1, 0.1, 0, 0, 1, 1, 0, 1, 1.3, 1, 1, 0, 1, 1.1};
    std::complex<double> xc[24], Kc[24 * 24];
    for (int i = 0; i < 24; ++i) xc[i] = x[i];
    xc[7] += std::complex<double>(0, 1e-30);
    hexStiffness<std::complex<double>>(xc, 1.0, -0.2, Kc);
    double Kp[24 * 24], Km[24 * 24], xp[24], xm[24];
    std::copy(x, x + 24, xp);
    std::copy(x, x + 24, xm);
    xp[7] += 1e-6;
    xm[7] -= 1e-6;
    hexStiffness<double>(xp, 1.0, -0.2, Kp);
    hexStiffness<double>(xm, 1.0, -0.2, Km);
    for (int i = 0; i < 24 * 24; i += 7) EXPECT_NEAR(Kc[i].imag() / 1e-30, (Kp[i] - Km[i]) / 2e-6, 1e-7);
}

// The stiffening (cell size and orthogonality, issue #16's building block for the mesh adjoint) is
// differentiable through the template: complex step against central differences for every corner
// coordinate of a skewed cell, with both factors active.
TEST(Elasticity, CellModulusDerivativeAgreesWithComplexStep) {
    const double x[24] = {0, 0, 0, 1.1, 0, 0, 1, 1.2, 0, 0, 1, 0.1, 0, 0, 1, 1, 0, 1, 1.3, 1, 1, 0, 1, 1.1};
    ElasticityOptions o;
    o.sizeStiffening = 1.0;
    o.orthogonalityStiffening = 1.0;
    const double mean = 0.8;
    double vol = 0, q = 0;
    cellMetrics(x, vol, q);
    ASSERT_GT(q, 0.0);
    ASSERT_LT(q, 1.0);  // the orthogonality factor is active, not clamped
    for (int i = 0; i < 24; ++i) {
        std::complex<double> xc[24];
        for (int k = 0; k < 24; ++k) xc[k] = x[k];
        xc[i] += std::complex<double>(0, 1e-30);
        const double cs = cellModulus<std::complex<double>>(xc, mean, o).imag() / 1e-30;
        double xp[24], xm[24];
        std::copy(x, x + 24, xp);
        std::copy(x, x + 24, xm);
        xp[i] += 1e-6;
        xm[i] -= 1e-6;
        const double fd = (cellModulus<double>(xp, mean, o) - cellModulus<double>(xm, mean, o)) / 2e-6;
        EXPECT_NEAR(cs, fd, 1e-7 * (1 + std::abs(fd))) << "coordinate " << i;
    }
    const std::vector<std::complex<double>> xc(x, x + 24);
    EXPECT_NEAR(cellModulus<double>(x, mean, o), cellModulus<std::complex<double>>(xc.data(), mean, o).real(), 1e-14);
}

// The mesh adjoint's analytic modulus and volume derivatives (cellModulusGradient) against
// complex step of cellModulus and cellMetrics, on a distorted cell (orthogonality active) and a
// cube (orthogonality exactly 1, the end of the clamp's range), with the size stiffening off, on
// and doubled.
TEST(Elasticity, AnalyticModulusGradientAgreesWithComplexStep) {
    const double distorted[24] = {0, 0, 0, 1.1, 0, 0, 1, 1.2, 0, 0, 1, 0.1, 0, 0, 1, 1, 0, 1, 1.3, 1, 1, 0, 1, 1.1};
    const double cube[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    for (const double* x : {distorted, cube}) {
        for (double size : {1.0, 0.0, 2.0}) {
            ElasticityOptions o;
            o.sizeStiffening = size;
            o.orthogonalityStiffening = 1.5;
            const double mean = 0.8;
            double dE[24], dV[24], volume = 0;
            const double E = cellModulusGradient(x, mean, o, dE, dV, &volume);
            EXPECT_NEAR(E, cellModulus<double>(x, mean, o), 1e-14);
            for (int i = 0; i < 24; ++i) {
                std::complex<double> xc[24];
                for (int k = 0; k < 24; ++k) xc[k] = x[k];
                xc[i] += std::complex<double>(0, 1e-30);
                const double cs = cellModulus<std::complex<double>>(xc, mean, o).imag() / 1e-30;
                std::complex<double> v, q;
                cellMetrics(xc, v, q);
                EXPECT_NEAR(volume, v.real(), 1e-14);
                EXPECT_NEAR(dE[i], cs, 1e-12 * (1 + std::abs(cs))) << "coordinate " << i << ", size " << size;
                EXPECT_NEAR(dV[i], v.imag() / 1e-30, 1e-13) << "coordinate " << i;
            }
        }
    }
}

TEST(Elasticity, PatchTestReproducesALinearField) {
    // Uniform modulus (no stiffening): a linear displacement on the boundary gives the same linear
    // field inside (constant strain is an exact FE solution).
    MultiBlockMesh m = boxMesh();
    ElasticityOptions o;
    o.sizeStiffening = o.orthogonalityStiffening = 0.0;
    o.poisson = -0.2;
    const std::vector<char> constrained = boundaryConstraints(m);
    Eigen::Matrix3d G;
    G << 0.01, 0.02, -0.01, 0.0, 0.015, 0.005, -0.02, 0.01, 0.03;
    std::vector<double> prescribed(m.control.size());
    for (std::size_t n = 0; n < m.control.size() / 3; ++n) {
        const Eigen::Vector3d u = G * Eigen::Vector3d(m.control[3 * n], m.control[3 * n + 1], m.control[3 * n + 2]);
        for (int c = 0; c < 3; ++c) prescribed[3 * n + c] = u[c];
    }
    int interior = 0;
    for (char c : constrained) interior += c ? 0 : 1;
    ASSERT_EQ(interior, 3 * 2 * 1 * 3);  // 2 x 1 x 3 interior nodes
    const IncrementResult r = solveElasticity(m, constrained, prescribed, o);
    EXPECT_TRUE(r.converged);
    for (std::size_t d = 0; d < r.u.size(); ++d) EXPECT_NEAR(r.u[d], prescribed[d], 1e-12);
}

TEST(Elasticity, ZeroMotionAndRigidTranslation) {
    MultiBlockMesh m = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    const std::vector<double> b0 = m.control;
    std::vector<double> surface(3 * m.surfaceNode.size());
    for (std::size_t u = 0; u < m.surfaceNode.size(); ++u) {
        for (int c = 0; c < 3; ++c) surface[3 * u + c] = m.control[3 * m.surfaceNode[u] + c];
    }
    const MoveReport zero = moveControlGrid(m, surface, ElasticityOptions{});
    EXPECT_EQ(zero.status, SolveStatus::Converged);
    EXPECT_EQ(m.control, b0);
    // All constrained DOFs translate by the same x offset (symmetry nodes are free in x): every
    // node translates rigidly.
    const std::vector<char> constrained = boundaryConstraints(m);
    std::vector<double> prescribed(m.control.size(), 0.0);
    for (std::size_t n = 0; n < prescribed.size() / 3; ++n) prescribed[3 * n] = 0.3;
    ElasticityOptions o;
    o.tolerance = 1e-13;
    const IncrementResult r = solveElasticity(m, constrained, prescribed, o);
    ASSERT_TRUE(r.converged);
    for (std::size_t n = 0; n < prescribed.size() / 3; ++n) {
        EXPECT_NEAR(r.u[3 * n], 0.3, 1e-9);
        EXPECT_NEAR(r.u[3 * n + 1], 0.0, 1e-9);
        EXPECT_NEAR(r.u[3 * n + 2], 0.0, 1e-9);
    }
}

TEST(Elasticity, LargeMoveKeepsInterfacesCoincidentAndCellsValid) {
    // Stretch the wall spanwise by 1.6 and flatten it to 0.6 (a blended-wing-like planform):
    // blocks regenerated independently (no interface copy) still meet to round-off, because they
    // share their interface control nodes, and every cell stays valid.
    MultiBlockMesh m = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    std::vector<double> surface(3 * m.surfaceNode.size());
    for (std::size_t u = 0; u < m.surfaceNode.size(); ++u) {
        const double* p = &m.control[3 * m.surfaceNode[u]];
        surface[3 * u] = p[0];
        surface[3 * u + 1] = 1.6 * p[1];
        surface[3 * u + 2] = 0.6 * p[2];
    }
    const MoveReport r = moveControlGrid(m, surface, ElasticityOptions{});
    ASSERT_EQ(r.status, SolveStatus::Converged) << r.message;
    EXPECT_EQ(r.cgIterations.size(), 6u);
    std::vector<StructuredGrid> grids(m.blocks.size());
    for (std::size_t b = 0; b < m.blocks.size(); ++b) regenerate(m, static_cast<int>(b), grids[b]);
    double gap = 0;
    for (const NodePair& q : m.interfaceNodes) {
        for (int c = 0; c < 3; ++c) gap = std::max(gap, std::abs(grids[q.blockA].xyz[3 * q.nodeA + c] - grids[q.blockB].xyz[3 * q.nodeB + c]));
    }
    EXPECT_LT(gap, 1e-12);
    std::vector<CellQuality> q;
    for (const auto& g : grids) q.push_back(cellQuality(g));
    EXPECT_NO_THROW(requirePositiveJacobians(grids, q));
    EXPECT_GT(summarize(grids, q).scaledJacobian.min, 0.1);
    // The wall ends exactly on the new surface (A = [0 I] b).
    for (std::size_t u = 0; u < m.surfaceNode.size(); ++u) {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(m.control[3 * m.surfaceNode[u] + c], surface[3 * u + c]);
    }
}

// The move is the same to the bit on 1 and 2 threads: the element scatter is split by rows and the
// incomplete Cholesky by a separator that depend on the grid only, never on the thread count (the
// optimizer's kill-and-resume replay compares runs bit for bit).
TEST(Elasticity, MoveGivesTheSameBitsOnOneAndTwoThreads) {
#if defined(_OPENMP)
    const MultiBlockMesh base = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    std::vector<double> surface(3 * base.surfaceNode.size());
    for (std::size_t u = 0; u < base.surfaceNode.size(); ++u) {
        const double* p = &base.control[3 * base.surfaceNode[u]];
        surface[3 * u] = p[0] * (1 + 0.2 * p[1]);
        surface[3 * u + 1] = 1.4 * p[1];
        surface[3 * u + 2] = 0.7 * p[2];
    }
    const int threads = omp_get_max_threads();
    MultiBlockMesh one = base, two = base;
    omp_set_num_threads(1);
    const MoveReport r1 = moveControlGrid(one, surface, ElasticityOptions{});
    omp_set_num_threads(2);
    const MoveReport r2 = moveControlGrid(two, surface, ElasticityOptions{});
    omp_set_num_threads(threads);
    ASSERT_EQ(r1.status, SolveStatus::Converged) << r1.message;
    EXPECT_EQ(r1.cgIterations, r2.cgIterations);
    EXPECT_EQ(r1.residuals, r2.residuals);
    EXPECT_EQ(one.control, two.control);
    EXPECT_NE(one.control, base.control);
#else
    GTEST_SKIP() << "built without OpenMP";
#endif
}

// A control cell turned inside out before an increment is a status naming the block and the cell
// (it was skipped in the assembly without a word, leaving K indefinite), not a PCG run on it.
TEST(Elasticity, AnInvertedControlCellIsReportedWithItsBlockAndCell) {
    MultiBlockMesh m = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    // Push one interior control node of block 0 through the wall, past its inner neighbours.
    const auto& blk = m.blocks[0];
    const int i = blk.count[0] / 2, j = blk.count[1] / 2, k = 1;
    const int node = blk.nodes[blk.local(i, j, k)];
    for (int c = 0; c < 3; ++c) m.control[3 * node + c] *= 0.5;  // from r ~ 1.01 to r ~ 0.5
    std::vector<double> surface(3 * m.surfaceNode.size());
    for (std::size_t u = 0; u < m.surfaceNode.size(); ++u) {
        for (int c = 0; c < 3; ++c) surface[3 * u + c] = 1.01 * m.control[3 * m.surfaceNode[u] + c];
    }
    const MoveReport r = moveControlGrid(m, surface, ElasticityOptions{});
    EXPECT_EQ(r.status, SolveStatus::InvalidCell);
    EXPECT_NE(r.message.find("increment 1 of 6"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("of block '" + blk.name + "'"), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("(inverted)"), std::string::npos) << r.message;
}

// The sparse Cholesky (the fallback when PCG stalls) solves the same increment as PCG.
TEST(Elasticity, DirectSolveAgreesWithConjugateGradients) {
    MultiBlockMesh m = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    const std::vector<char> constrained = boundaryConstraints(m);
    std::vector<double> prescribed(m.control.size(), 0.0);
    for (int u : m.surfaceNode) {
        const double* p = &m.control[3 * static_cast<std::size_t>(u)];
        prescribed[3 * static_cast<std::size_t>(u) + 1] = 0.1 * p[1];   // span +10 %
        prescribed[3 * static_cast<std::size_t>(u) + 2] = -0.1 * p[2];  // thickness -10 %
    }
    ElasticityOptions iterative, direct;
    iterative.tolerance = 1e-12;
    iterative.solver = ElasticityOptions::Solver::Iterative;
    direct.solver = ElasticityOptions::Solver::Direct;
    const IncrementResult a = solveElasticity(m, constrained, prescribed, iterative);
    const IncrementResult b = solveElasticity(m, constrained, prescribed, direct);
    ASSERT_TRUE(a.converged) << a.message;
    ASSERT_TRUE(b.converged) << b.message;
    EXPECT_FALSE(a.direct);
    EXPECT_TRUE(b.direct);
    EXPECT_LT(b.residual, 1e-10);
    double diff = 0, size = 0;
    for (std::size_t d = 0; d < a.u.size(); ++d) {
        diff = std::max(diff, std::abs(a.u[d] - b.u[d]));
        size = std::max(size, std::abs(a.u[d]));
    }
    EXPECT_GT(size, 0.01);
    EXPECT_LT(diff, 1e-8 * size);
}

namespace {

std::vector<double> seededVector(std::size_t n, unsigned seed) {
    std::vector<double> v(n);
    unsigned s = seed * 2654435761u + 12345u;
    for (double& x : v) {
        s = s * 1103515245u + 12345u;
        x = static_cast<double>((s >> 8) & 0xffff) / 65535.0 - 0.5;
    }
    return v;
}

double dotProduct(const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
    return s;
}

// The coarse half-sphere grid with its wall stretched (a deformed start, so no term of the
// adjoint vanishes by symmetry), and the moved surface.
std::vector<double> stretchedSurface(const MultiBlockMesh& m, double eps, const std::vector<double>& dir) {
    std::vector<double> surface(3 * m.surfaceNode.size());
    for (std::size_t u = 0; u < m.surfaceNode.size(); ++u) {
        const double* p = &m.control[3 * m.surfaceNode[u]];
        surface[3 * u] = 1.1 * p[0] + eps * dir[3 * u];
        surface[3 * u + 1] = 1.3 * p[1] + (p[1] > 1e-12 ? eps * dir[3 * u + 1] : 0.0);  // y = 0 stays
        surface[3 * u + 2] = 0.8 * p[2] + eps * dir[3 * u + 2];
    }
    return surface;
}

}  // namespace

TEST(MeshAdjoint, RegenerationTransposeIsTheTransposeOfTheRegeneration) {
    MultiBlockMesh m = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    const std::vector<double> b = seededVector(m.control.size(), 1);
    MultiBlockMesh r = m;
    r.control = b;
    double lhs = 0;
    std::vector<double> gb(m.control.size(), 0.0);
    for (std::size_t k = 0; k < m.blocks.size(); ++k) {
        StructuredGrid g;
        regenerate(r, static_cast<int>(k), g);
        const std::vector<double> gx = seededVector(g.xyz.size(), 10 + static_cast<unsigned>(k));
        lhs += dotProduct(gx, g.xyz);
        regenerateTranspose(m, static_cast<int>(k), gx.data(), gb);
    }
    EXPECT_NEAR(dotProduct(gb, b), lhs, 1e-12 * std::abs(lhs));
}

TEST(MeshAdjoint, BilinearFormIsTheStiffnessMatrixProduct) {
    const MultiBlockMesh m = boxMesh();
    double x[24];
    const int off[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int a = 0; a < 8; ++a) {
        const int g = m.blocks[0].local(1 + off[a][0], 1 + off[a][1], 1 + off[a][2]);
        for (int c = 0; c < 3; ++c) x[3 * a + c] = m.control[3 * g + c];
    }
    const std::vector<double> a = seededVector(24, 7), b = seededVector(24, 8);
    double K[24 * 24];
    hexStiffness<double>(x, 1.7, -0.2, K);
    double ref = 0;
    for (int r = 0; r < 24; ++r) {
        for (int c = 0; c < 24; ++c) ref += a[r] * K[24 * r + c] * b[c];
    }
    EXPECT_NEAR(hexBilinear<double>(x, 1.7, -0.2, a.data(), b.data()), ref, 1e-13 * std::abs(ref));
    // Its analytic coordinate gradient against complex step.
    x[5] += 0.07;  // a less regular cell
    double grad[24];
    const double s1 = hexBilinearGradient(x, -0.2, a.data(), b.data(), grad);
    EXPECT_NEAR(s1, hexBilinear<double>(x, 1.0, -0.2, a.data(), b.data()), 1e-13 * std::abs(s1));
    for (int i = 0; i < 24; ++i) {
        std::complex<double> xc[24];
        for (int k = 0; k < 24; ++k) xc[k] = x[k];
        xc[i] += std::complex<double>(0, 1e-30);
        const double cs = hexBilinear<std::complex<double>>(xc, 1.0, -0.2, a.data(), b.data()).imag() / 1e-30;
        EXPECT_NEAR(grad[i], cs, 1e-12 * (std::abs(cs) + 1e-3)) << "coordinate " << i;
    }
    // The orthogonality is a smooth minimum: eight equal corners give their value, one bad corner
    // pulls it within log(8)/r of the minimum.
    const double cube[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    EXPECT_NEAR(cellOrthogonality(cube), 1.0, 1e-14);
    double sheared[24];
    std::copy(cube, cube + 24, sheared);
    sheared[18] = 0.4;  // corner 6 moves in x
    double corners[8];
    cornerScaledJacobians(sheared, corners);
    const double lowest = *std::min_element(corners, corners + 8);
    EXPECT_LT(lowest, 0.95);
    EXPECT_GE(cellOrthogonality(sheared), lowest);
    EXPECT_LE(cellOrthogonality(sheared), lowest + std::log(8.0) / kOrthogonalitySharpness);
}

TEST(MeshAdjoint, StiffnessProductGradientMatchesFiniteDifferencesWithTheMeanVolume) {
    MultiBlockMesh m = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    ElasticityOptions o;
    const std::vector<double> lambda = seededVector(m.control.size(), 2), u = seededVector(m.control.size(), 3);
    const std::vector<double> v = seededVector(m.control.size(), 4);
    const std::vector<double> g = stiffnessProductGradient(m, o, lambda, u);
    auto product = [&](double eps) {
        MultiBlockMesh p = m;
        for (std::size_t i = 0; i < p.control.size(); ++i) p.control[i] += eps * v[i];
        return dotProduct(lambda, stiffnessProduct(p, o, u));
    };
    const double h = 1e-6;
    const double fd = (product(h) - product(-h)) / (2 * h);
    EXPECT_NEAR(dotProduct(g, v), fd, 1e-7 * std::abs(fd));
    // The mean volume's part is not negligible: without it the derivative differs.
    ElasticityOptions noSize = o;
    noSize.sizeStiffening = 0;
    EXPECT_GT(std::abs(dotProduct(stiffnessProductGradient(m, noSize, lambda, u), v) - fd), 1e-3 * std::abs(fd));
}

TEST(MeshAdjoint, ReverseSweepMatchesFiniteDifferencesOfTheMove) {
    // L(A) = gbar . b^(m)(A) for a random gbar: the adjoint's dL/dA . dA against a centred
    // difference of two moves. The moves of the difference are solved directly (sparse Cholesky):
    // conjugate gradients to 1e-13 leave a noise of 4e-6 in the difference at h = 1e-5, direct
    // solves 3e-9.
    const MultiBlockMesh base = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    ElasticityOptions o;
    o.tolerance = 1e-13;
    const std::vector<double> dir = seededVector(3 * base.surfaceNode.size(), 5);
    const std::vector<double> gbar = seededVector(base.control.size(), 6);
    MultiBlockMesh m = base;
    MoveHistory history;
    const MoveReport r = moveControlGrid(m, stretchedSurface(base, 0, dir), o, {}, nullptr, &history);
    ASSERT_EQ(r.status, SolveStatus::Converged) << r.message;
    ASSERT_EQ(history.before.size(), 6u);
    MeshAdjointReport rep;
    const std::vector<double> gA = moveControlGridAdjoint(base, history, o, gbar, &rep);
    ASSERT_TRUE(rep.converged) << rep.message;
    EXPECT_EQ(rep.iterations.size(), 6u);
    std::printf("move %.2f s (%d PCG iterations), adjoint %.2f s\n", r.seconds, r.totalIterations, rep.seconds);
    std::vector<double> dA = dir;
    for (std::size_t u = 0; u < base.surfaceNode.size(); ++u) {
        if (base.control[3 * base.surfaceNode[u] + 1] <= 1e-12) dA[3 * u + 1] = 0;
    }
    ElasticityOptions direct = o;
    direct.solver = ElasticityOptions::Solver::Direct;
    auto L = [&](double eps) {
        MultiBlockMesh p = base;
        const MoveReport rp = moveControlGrid(p, stretchedSurface(base, eps, dir), direct);
        EXPECT_EQ(rp.status, SolveStatus::Converged);
        return dotProduct(gbar, p.control);
    };
    const double h = 1e-5;
    const double fd = (L(h) - L(-h)) / (2 * h);
    const double adj = dotProduct(gA, dA);
    EXPECT_NEAR(adj, fd, 1e-6 * std::abs(fd)) << "adjoint " << adj << " finite difference " << fd;
    // The stiffness's dependence on the grid matters: one increment alone (linear move) differs.
    ElasticityOptions one = o;
    one.increments = 1;
    MultiBlockMesh m1 = base;
    MoveHistory h1;
    ASSERT_EQ(moveControlGrid(m1, stretchedSurface(base, 0, dir), one, {}, nullptr, &h1).status, SolveStatus::Converged);
    const std::vector<double> gA1 = moveControlGridAdjoint(base, h1, one, gbar);
    EXPECT_GT(std::abs(dotProduct(gA1, dA) - fd), 1e-4 * std::abs(fd));
}

// The wall control points of `base` stretched and skewed by `a` (x grows with y, y stretched,
// z squashed) and tilted by `tilt` a x in z: the kept-workspace tests' deformations.
namespace {
std::vector<double> skewedSurface(const MultiBlockMesh& base, double a, double tilt) {
    std::vector<double> surface(3 * base.surfaceNode.size());
    for (std::size_t u = 0; u < base.surfaceNode.size(); ++u) {
        const double* p = &base.control[3 * base.surfaceNode[u]];
        surface[3 * u] = p[0] * (1 + a * p[1]);
        surface[3 * u + 1] = (1 + 2 * a) * p[1];
        surface[3 * u + 2] = (1 - 1.5 * a) * p[2] + tilt * a * p[0];
    }
    return surface;
}
}  // namespace

// MoveWorkspace::setKeepIncrements: the move keeps each increment's K and factor, and the mesh
// adjoint of that move's history solves with them instead of assembling and factoring again -
// the same bits as the adjoint that assembles (and as the move without keeping). Only the history
// whose move filled them is served: after another recorded move (or with other options) the
// adjoint assembles again, and a move that records no history leaves them alone.
TEST(Elasticity, KeptIncrementsServeTheMeshAdjointOfTheirOwnMoveOnly) {
    const MultiBlockMesh base = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    auto deformed = [&](double a) { return skewedSurface(base, a, 0.2); };
    const ElasticityOptions o;
    const std::vector<double> gbar = seededVector(base.control.size(), 9);
    const std::vector<double> gbar2 = seededVector(base.control.size(), 10);
    // The references: no workspace, so everything is assembled.
    MultiBlockMesh plain = base;
    MoveHistory hPlain;
    ASSERT_EQ(moveControlGrid(plain, deformed(0.2), o, {}, nullptr, &hPlain).status, SolveStatus::Converged);
    EXPECT_EQ(hPlain.stamp, 0u);
    const auto reference = moveControlGridAdjoints(base, hPlain, o, {gbar, gbar2});

    MoveWorkspace kept;
    kept.setKeepIncrements(true);
    MultiBlockMesh m = base;
    MoveHistory h;
    const MoveReport r = moveControlGrid(m, deformed(0.2), o, {}, nullptr, &h, &kept);
    ASSERT_EQ(r.status, SolveStatus::Converged) << r.message;
    EXPECT_EQ(m.control, plain.control);
    EXPECT_NE(h.stamp, 0u);
    EXPECT_GT(kept.keptBytes(), static_cast<std::size_t>(o.increments) * 9 * sizeof(double) * base.controlCount());
    MeshAdjointReport rep;
    const auto gKept = moveControlGridAdjoints(base, h, o, {gbar, gbar2}, &rep, &kept);
    ASSERT_TRUE(rep.converged) << rep.message;
    EXPECT_EQ(rep.reusedIncrements, o.increments);
    EXPECT_EQ(rep.keptBytes, kept.keptBytes());
    EXPECT_EQ(gKept, reference);
    // Served again (the buffers went back to where they were kept), also across a move that
    // records no history in the same workspace.
    MultiBlockMesh preview = base;
    ASSERT_EQ(moveControlGrid(preview, deformed(0.1), o, {}, nullptr, nullptr, &kept).status, SolveStatus::Converged);
    const auto again = moveControlGridAdjoints(base, h, o, {gbar, gbar2}, &rep, &kept);
    EXPECT_EQ(rep.reusedIncrements, o.increments);
    EXPECT_EQ(again, reference);
    // Other options: assembled with those options.
    ElasticityOptions stiffer = o;
    stiffer.sizeStiffening = 1.5;
    const auto otherOptions = moveControlGridAdjoints(base, h, stiffer, {gbar}, &rep, &kept);
    EXPECT_EQ(rep.reusedIncrements, 0);
    EXPECT_EQ(otherOptions.front(), moveControlGridAdjoints(base, h, stiffer, {gbar}).front());
    // Another recorded move takes the buffers: the first history is assembled again, the second
    // is served.
    MultiBlockMesh m2 = base, plain2 = base;
    MoveHistory h2, hPlain2;
    ASSERT_EQ(moveControlGrid(m2, deformed(0.1), o, {}, nullptr, &h2, &kept).status, SolveStatus::Converged);
    ASSERT_EQ(moveControlGrid(plain2, deformed(0.1), o, {}, nullptr, &hPlain2).status, SolveStatus::Converged);
    EXPECT_NE(h2.stamp, h.stamp);
    const auto stale = moveControlGridAdjoints(base, h, o, {gbar, gbar2}, &rep, &kept);
    EXPECT_EQ(rep.reusedIncrements, 0);
    EXPECT_EQ(stale, reference);
    const auto second = moveControlGridAdjoints(base, h2, o, {gbar}, &rep, &kept);
    EXPECT_EQ(rep.reusedIncrements, o.increments);
    EXPECT_EQ(second.front(), moveControlGridAdjoint(base, hPlain2, o, gbar));
    EXPECT_EQ(kept.builds(), 1);
}

// A kept MoveWorkspace (the optimizer's evaluations, the gradient's mesh adjoint) reuses the
// stiffness layout and its buffers: the same bits as a move without one, whatever the earlier
// moves left in the buffers; a grid of another topology gets a layout of its own.
TEST(Elasticity, AKeptWorkspaceGivesTheSameBitsAndIsRebuiltForAnotherGrid) {
    const MultiBlockMesh base = extrudeToFarfield(geometry::makeHalfSphere(), extrusionLevel("coarse"));
    auto deformed = [&](double a) { return skewedSurface(base, a, 0.0); };
    MoveWorkspace kept;
    MultiBlockMesh first = base;
    ASSERT_EQ(moveControlGrid(first, deformed(0.3), ElasticityOptions{}, {}, nullptr, nullptr, &kept).status,
              SolveStatus::Converged);
    MultiBlockMesh fresh = base, reused = base;
    MoveHistory hFresh, hReused;
    const MoveReport rFresh = moveControlGrid(fresh, deformed(0.15), ElasticityOptions{}, {}, nullptr, &hFresh);
    const MoveReport rReused = moveControlGrid(reused, deformed(0.15), ElasticityOptions{}, {}, nullptr, &hReused, &kept);
    ASSERT_EQ(rReused.status, SolveStatus::Converged) << rReused.message;
    EXPECT_EQ(kept.builds(), 1);
    EXPECT_EQ(rFresh.cgIterations, rReused.cgIterations);
    EXPECT_EQ(rFresh.residuals, rReused.residuals);
    EXPECT_EQ(fresh.control, reused.control);
    EXPECT_NE(fresh.control, first.control);
    // The mesh adjoint with the forward move's workspace: the same bits as with its own layout.
    const std::vector<double> gbar = seededVector(base.control.size(), 8);
    MeshAdjointReport aFresh, aReused;
    const std::vector<double> gFresh = moveControlGridAdjoint(base, hFresh, ElasticityOptions{}, gbar, &aFresh);
    const std::vector<double> gReused = moveControlGridAdjoints(base, hReused, ElasticityOptions{}, {gbar}, &aReused, &kept).front();
    ASSERT_TRUE(aReused.converged) << aReused.message;
    EXPECT_EQ(aFresh.iterations, aReused.iterations);
    EXPECT_EQ(gFresh, gReused);
    EXPECT_EQ(kept.builds(), 1);
    // Another topology (the box) gets its own layout, and moving it agrees with a fresh move.
    MultiBlockMesh box = boxMesh(), boxFresh = boxMesh();
    box.surfaceNode = {0};
    boxFresh.surfaceNode = {0};
    const std::vector<double> corner = {0.05, -0.02, 0.03};
    const MoveReport rBox = moveControlGrid(box, corner, ElasticityOptions{}, {}, nullptr, nullptr, &kept);
    const MoveReport rBoxFresh = moveControlGrid(boxFresh, corner, ElasticityOptions{});
    EXPECT_EQ(kept.builds(), 2);
    EXPECT_EQ(rBox.status, rBoxFresh.status);
    EXPECT_EQ(box.control, boxFresh.control);
}
