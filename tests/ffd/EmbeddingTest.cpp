#include "ffd/Embedding.h"

#include <gtest/gtest.h>

#include <complex>

#include "RandomNurbs.h"
#include "geometry/HalfSphere.h"

using namespace aero;
using namespace aero::ffd;
using cplx = std::complex<double>;

namespace {

// The paper's first-level lattice: 6x6x2, cubic in X and Y, linear in Z, around the half-sphere.
Lattice paperLattice(const geometry::PatchSet& set) {
    return makeLattice(boxAround(set, {}, {0.05, 0.05, 0.05}), {6, 6, 2}, {3, 3, 1});
}

}  // namespace

TEST(Embedding, UndeformedLatticeReproducesEveryPoint) {
    const auto set = geometry::makeHalfSphere();
    const Lattice L = paperLattice(set);
    const Embedding e = embed(set, L);
    EXPECT_TRUE(e.failures.empty());
    EXPECT_EQ(static_cast<int>(e.points.size()), 521);
    EXPECT_LE(e.maxError, 1e-12);
    std::vector<double> A = e.index.points;
    deformUnique(L, e, A);
    for (std::size_t i = 0; i < A.size(); ++i) EXPECT_NEAR(A[i], e.index.points[i], 1e-12);
    geometry::PatchSet out = set;
    scatter(e.index, A, out);
    for (int p = 0; p < set.size(); ++p) {
        for (std::size_t a = 0; a < set.patches[p].points.size(); ++a) {
            EXPECT_NEAR(out.patches[p].points[a], set.patches[p].points[a], 1e-12);
        }
    }
}

TEST(Embedding, AffineLatticeMotionMovesTheGeometryAffinely) {
    const auto set = geometry::makeHalfSphere();
    const Lattice L = paperLattice(set);
    const Embedding e = embed(set, L);
    // Rotate about Z by 30 degrees, scale, translate: every lattice point, hence every embedded
    // control point (linear precision of B-splines), moves by the same affine map.
    const double c = std::cos(0.5236), s = std::sin(0.5236);
    Eigen::Matrix3d M;
    M << 1.3 * c, -s, 0.1, s, 0.8 * c, 0, 0, 0.2, 1.1;
    const Eigen::Vector3d t(0.4, -1.0, 2.5);
    Lattice moved = L;
    for (int a = 0; a < L.controlCount(); ++a) {
        const Eigen::Vector3d b = M * Eigen::Vector3d(L.points[3 * a], L.points[3 * a + 1], L.points[3 * a + 2]) + t;
        for (int k = 0; k < 3; ++k) moved.points[3 * a + k] = b[k];
    }
    std::vector<double> A = e.index.points;
    deformUnique(moved, e, A);
    for (int u = 0; u < e.index.uniqueCount(); ++u) {
        const Eigen::Vector3d expect = M * Eigen::Vector3d(e.index.points[3 * u], e.index.points[3 * u + 1], e.index.points[3 * u + 2]) + t;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(A[3 * u + k], expect[k], 1e-12);
    }
}

TEST(Embedding, SensitivityAgreesWithComplexStep) {
    const auto set = geometry::makeHalfSphere();
    Lattice L = paperLattice(set);
    L.weights.assign(L.controlCount(), 1.0);  // rational lattice: Eq. 3 with rational basis
    L.weights[40] = 1.4;
    L.weights[7] = 0.7;
    const Embedding e = embed(set, L);
    ASSERT_TRUE(e.failures.empty());
    const auto W = sensitivity(L, e);
    EXPECT_EQ(W.rows(), static_cast<int>(e.points.size()));
    for (int a : {0, 7, 40, 71}) {
        nurbs::Volume<cplx> Lc;
        Lc.degree = L.degree;
        Lc.count = L.count;
        Lc.knots = L.knots;
        Lc.points.assign(L.points.begin(), L.points.end());
        Lc.weights.assign(L.weights.begin(), L.weights.end());
        Lc.points[3 * a + 1] += cplx(0, 1e-30);
        for (std::size_t p = 0; p < e.points.size(); p += 13) {
            const auto P = nurbs::evaluate(Lc, cplx(e.params[3 * p]), cplx(e.params[3 * p + 1]), cplx(e.params[3 * p + 2]));
            EXPECT_NEAR(P[1].imag() / 1e-30, W.coeff(static_cast<int>(p), a), 1e-15);
            EXPECT_EQ(P[0].imag(), 0.0);
        }
    }
}

TEST(Embedding, PointsOutsideAreListedWithTheirDistance) {
    const auto set = geometry::makeHalfSphere();
    // A lattice that cuts off the top of the sphere (z > 0.5).
    LatticeBox box = boxAround(set, {}, {0.05, 0.05, 0.05});
    box.size[2] = 0.5 - box.origin[2];
    const Embedding e = embed(set, makeLattice(box, {6, 6, 2}, {3, 3, 1}));
    ASSERT_FALSE(e.failures.empty());
    for (const auto& f : e.failures) {
        EXPECT_TRUE(f.outside);
        const double z = e.index.points[3 * f.point + 2];
        EXPECT_GT(z, 0.5);
        EXPECT_NEAR(f.distance, z - 0.5, 1e-9);
        EXPECT_GE(f.patch, 0);
    }
    EXPECT_EQ(e.points.size() + e.failures.size(), 521u);
}
