#include "ffd/Injectivity.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

using namespace aero;
using namespace aero::ffd;

namespace {
Lattice unitLattice() { return makeLattice(LatticeBox{}, {6, 6, 2}, {3, 3, 1}); }
}  // namespace

TEST(Injectivity, UndeformedAndMildlyDeformedLatticesAreCertified) {
    Lattice L = unitLattice();
    InjectivityReport r = checkInjectivity(L);
    EXPECT_TRUE(r.certified);
    EXPECT_TRUE(r.injective);
    EXPECT_EQ(r.refinements, 0);
    EXPECT_NEAR(r.relativeMinJacobian, 1.0, 1e-12);  // affine map: det J constant
    // A smooth bend: the certificate may need refinement but must hold.
    for (int a = 0; a < L.controlCount(); ++a) {
        const double x = L.points[3 * a], y = L.points[3 * a + 1];
        L.points[3 * a + 2] += 0.3 * std::sin(3 * x) * y;
    }
    r = checkInjectivity(L);
    EXPECT_TRUE(r.injective);
    EXPECT_TRUE(r.certified);
    EXPECT_GT(r.minJacobian, 0.0);
}

TEST(Injectivity, FoldedLatticeIsRejectedWithItsLocation) {
    Lattice L = unitLattice();
    // Push one interior control plane far past its neighbour in x: the map folds over.
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < 6; ++j) L.points[3 * L.index(2, j, k)] += 0.8;
    }
    const InjectivityReport r = checkInjectivity(L);
    EXPECT_FALSE(r.injective);
    EXPECT_FALSE(r.certified);
    EXPECT_LE(r.minJacobian, 0.0);
    // The reported location is a genuine fold: det J there has the wrong sign, and the world
    // point is the lattice map of those parameters.
    nurbs::Vec3<double> P;
    Eigen::Matrix3d J;
    nurbs::evaluateJacobian(L, r.minAt[0], r.minAt[1], r.minAt[2], P, J);
    EXPECT_LE(J.determinant(), 0.0);
    for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(r.minPoint[k], P[k]);
}

TEST(Injectivity, LeftHandedLatticeIsStillInjective) {
    LatticeBox box;
    box.axes = {{{0, 1, 0}, {1, 0, 0}, {0, 0, 1}}};  // swapped axes: det J < 0 everywhere
    const InjectivityReport r = checkInjectivity(makeLattice(box, {4, 4, 3}, {2, 2, 2}));
    EXPECT_TRUE(r.certified);
    EXPECT_GT(r.minJacobian, 0.0);  // sign-normalized
}
