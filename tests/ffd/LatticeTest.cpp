#include "ffd/Lattice.h"

#include <gtest/gtest.h>

#include "common/Error.h"
#include "geometry/HalfSphere.h"
#include "nurbs/KnotInsertion.h"

using namespace aero;
using namespace aero::ffd;

TEST(Lattice, UndeformedMapIsTheAffineBoxMap) {
    LatticeBox box;
    box.origin = {1, -2, 0.5};
    box.size = {2, 3, 0.5};
    const double c = std::sqrt(0.5);
    box.axes = {{{c, c, 0}, {-c, c, 0}, {0, 0, 1}}};  // rotated 45 degrees about Z
    const Lattice L = makeLattice(box, {6, 5, 2}, {3, 2, 1});
    for (double a : {0.0, 0.3, 1.0}) {
        for (double b : {0.0, 0.77}) {
            for (double z : {0.0, 0.5, 1.0}) {
                const auto P = nurbs::evaluate(L, a, b, z);
                for (int k = 0; k < 3; ++k) {
                    const double expect = box.origin[k] + a * box.size[0] * box.axes[0][k] +
                                          b * box.size[1] * box.axes[1][k] + z * box.size[2] * box.axes[2][k];
                    EXPECT_NEAR(P[k], expect, 1e-14);
                }
            }
        }
    }
}

TEST(Lattice, BoxAroundEnclosesWithPadding) {
    const auto set = geometry::makeHalfSphere();
    const LatticeBox box = boxAround(set, {}, {0.1, 0.1, 0.1});
    const auto net = geometry::controlBoundingBox(set);
    for (int d = 0; d < 3; ++d) {
        EXPECT_LT(box.origin[d], net.min[d]);
        EXPECT_GT(box.origin[d] + box.size[d], net.max[d]);
        EXPECT_NEAR(box.size[d], 1.2 * (net.max[d] - net.min[d]), 1e-12);
    }
    EXPECT_THROW(boxAround(set, {25}, {0, 0, 0}), GeometryError);
}

TEST(Lattice, BadCountsAndBoxesAreRejected) {
    EXPECT_THROW(makeLattice(LatticeBox{}, {3, 3, 3}, {3, 1, 1}), GeometryError);
    LatticeBox flat;
    flat.size = {1, 0, 1};
    EXPECT_THROW(makeLattice(flat, {4, 4, 4}, {1, 1, 1}), GeometryError);
}

TEST(Lattice, CreaseMakesAControlPointInterpolateAndKeepsTheMap) {
    Lattice L = makeLattice(LatticeBox{}, {6, 4, 2}, {3, 3, 1});
    const Lattice before = L;
    creaseLattice(L, 0, 0.5);
    EXPECT_EQ(nurbs::multiplicity(L.knots[0], 0.5), 3);
    for (double a : {0.1, 0.5, 0.9}) {
        EXPECT_NEAR((nurbs::evaluate(L, a, 0.4, 0.6) - nurbs::evaluate(before, a, 0.4, 0.6)).norm(), 0.0, 1e-14);
    }
    // Moving the crease plane's control points now bends the map with a C0 kink at xi = 0.5:
    // the one-sided xi-derivatives differ there.
    for (int k = 0; k < L.count[2]; ++k) {
        for (int j = 0; j < L.count[1]; ++j) {
            // The control point interpolated at xi = 0.5 has index 4 after the insertion
            // (3 old functions before the knot, multiplicity 3).
            L.points[3 * L.index(4, j, k) + 2] += 0.2;
        }
    }
    nurbs::Vec3<double> P;
    Eigen::Matrix3d Jl, Jr;
    nurbs::evaluateJacobian(L, 0.5 - 1e-9, 0.4, 0.6, P, Jl);
    nurbs::evaluateJacobian(L, 0.5 + 1e-9, 0.4, 0.6, P, Jr);
    EXPECT_GT(std::abs(Jl(2, 0) - Jr(2, 0)), 0.1);
}
