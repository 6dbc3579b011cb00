// Design variables (ffd/DesignVariables.h) on a small, irregular 3 x 4 x 2 lattice with its
// stations along Y: names, kinds, bounds and baselines as documented; the baseline reproduces the
// lattice bit for bit; a translation moves its whole station, a section scaling one point's
// vertical coordinate about the station centroid, a taper the station's streamwise coordinates
// about it (keeping their mean), a point coordinate one coordinate; the map is affine with the
// analytic Jacobian as its exact derivative (complex step, finite differences of any size);
// variables of another lattice leave a lattice alone; bad input is a CaseError naming the key,
// and a refused addition leaves the design space as it was.
#include "ffd/DesignVariables.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <string>

#include "common/Error.h"
#include "ErrorMessage.h"

using namespace aero;
using namespace aero::ffd;
using cplx = std::complex<double>;

namespace {

// A 3 x 4 x 2 lattice (degrees 2, 3, 1) over a box at (1, -1, 0.5) of size (2, 3, 1), its points
// then moved off the box grid so that station centroids are not grid values.
Lattice irregularLattice() {
    LatticeBox box;
    box.origin = {1.0, -1.0, 0.5};
    box.size = {2.0, 3.0, 1.0};
    Lattice L = makeLattice(box, {3, 4, 2}, {2, 3, 1});
    for (int a = 0; a < L.controlCount(); ++a) {
        for (int c = 0; c < 3; ++c) L.points[3 * a + c] += 0.07 * std::sin(1.3 * a + 2.1 * c);
    }
    return L;
}

StationSpec wingSpec() {
    StationSpec s;
    s.prefix = "wing";
    s.direction = 1;
    s.bits = {"001", "011", "111", "000"};
    s.translationBound = 0.4;
    s.scalingBounds = {0.6, 1.8};
    s.taperBounds = {0.7, 1.5};
    return s;
}

// Lattice point indices whose j index is s (the station's points), in index order.
std::vector<int> stationPoints(const Lattice& L, int s) {
    std::vector<int> out;
    for (int k = 0; k < L.count[2]; ++k) {
        for (int i = 0; i < L.count[0]; ++i) out.push_back(L.index(i, s, k));
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::array<double, 3> centroid(const Lattice& L, const std::vector<int>& points) {
    std::array<double, 3> c{0, 0, 0};
    for (int a : points) {
        for (int d = 0; d < 3; ++d) c[d] += L.points[3 * a + d];
    }
    for (double& x : c) x /= static_cast<double>(points.size());
    return c;
}

}  // namespace

TEST(DesignVariables, StationVariablesAreNamedCountedAndBoundedAsDocumented) {
    const Lattice L = irregularLattice();
    DesignSpace ds({L});
    // Translations 1 + 2 + 3 + 0, a section scaling per point (24), a taper per station (4).
    EXPECT_EQ(ds.addStations(wingSpec()), 34);
    ASSERT_EQ(ds.size(), 34);
    const auto& v = ds.variables();
    const char* translations[] = {"wing.S0.tx", "wing.S1.tx", "wing.S1.ty", "wing.S2.tx", "wing.S2.ty", "wing.S2.tz"};
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(v[i].name, translations[i]);
        EXPECT_EQ(v[i].kind, VariableKind::Translate);
        EXPECT_EQ(v[i].baseline, 0.0);
        EXPECT_EQ(v[i].lower, -0.4);
        EXPECT_EQ(v[i].upper, 0.4);
        EXPECT_EQ(v[i].scale, 0.4);
    }
    EXPECT_EQ(v[2].axis, 1);
    EXPECT_EQ(v[5].axis, 2);
    EXPECT_EQ(ds.find("wing.S3.tx"), -1);  // bits "000"
    EXPECT_EQ(ds.find("wing.S1.ty"), 2);
    // Section scalings: station by station, the points in index order, about the vertical Z.
    EXPECT_EQ(v[6].name, "wing.S0.P0.sz");
    EXPECT_EQ(v[11].name, "wing.S0.P14.sz");
    EXPECT_EQ(v[12].name, "wing.S1.P3.sz");
    for (int i = 6; i < 30; ++i) {
        EXPECT_EQ(v[i].kind, VariableKind::SectionScale);
        EXPECT_EQ(v[i].axis, 2);
        EXPECT_EQ(v[i].baseline, 1.0);
        EXPECT_EQ(v[i].lower, 0.6);
        EXPECT_EQ(v[i].upper, 1.8);
        EXPECT_EQ(ds.find(v[i].name), i);
    }
    for (int s = 0; s < 4; ++s) {
        const int t = ds.find("wing.S" + std::to_string(s) + ".taperx");
        ASSERT_EQ(t, 30 + s);
        EXPECT_EQ(v[t].kind, VariableKind::Taper);
        EXPECT_EQ(v[t].axis, 0);
        EXPECT_EQ(v[t].lower, 0.7);
        EXPECT_EQ(v[t].upper, 1.5);
    }
    EXPECT_EQ(ds.find("wing.S0.tz"), -1);
    EXPECT_EQ(ds.find(""), -1);
    // Baselines: 0 for displacements, 1 for factors.
    const std::vector<double> b = ds.baselineValues();
    ASSERT_EQ(b.size(), 34u);
    for (int i = 0; i < 34; ++i) EXPECT_EQ(b[i], i < 6 ? 0.0 : 1.0);
    // Stations: the points with j = s and their centroid.
    ASSERT_EQ(ds.stations().size(), 4u);
    for (int s = 0; s < 4; ++s) {
        const Station& st = ds.stations()[s];
        EXPECT_EQ(st.ordinal, s);
        EXPECT_EQ(st.group, 0);
        std::vector<int> pts = st.points;
        std::sort(pts.begin(), pts.end());
        EXPECT_EQ(pts, stationPoints(L, s));
        const auto c = centroid(L, pts);
        for (int d = 0; d < 3; ++d) EXPECT_NEAR(st.reference[d], c[d], 1e-15);
    }
    // Without a prefix the lattice is named by its index.
    DesignSpace plain({L});
    StationSpec spec;
    spec.bits = {"100", "000", "000", "000"};
    plain.addStations(spec);
    EXPECT_EQ(plain.variables()[0].name, "L0.S0.tz");
}

TEST(DesignVariables, TheBaselineReproducesTheLatticeBitForBit) {
    const Lattice L = irregularLattice();
    DesignSpace ds({L});
    ds.addStations(wingSpec());
    ds.addPointCoordinate(0, 5, 1, -0.2, 0.2);
    const std::vector<double> v = ds.baselineValues();
    EXPECT_EQ(ds.latticePoints<double>(0, v), L.points);
    const Lattice moved = ds.lattice(0, v);
    EXPECT_EQ(moved.points, L.points);
    EXPECT_EQ(moved.knots, L.knots);
    EXPECT_EQ(moved.count, L.count);
    EXPECT_EQ(moved.degree, L.degree);
}

TEST(DesignVariables, ATranslationMovesItsWholeStationAlongItsAxis) {
    const Lattice L = irregularLattice();
    DesignSpace ds({L});
    ds.addStations(wingSpec());
    std::vector<double> v = ds.baselineValues();
    v[ds.find("wing.S1.ty")] = 0.3;
    v[ds.find("wing.S2.tz")] = -0.25;
    const std::vector<double> B = ds.latticePoints<double>(0, v);
    const std::vector<int> s1 = stationPoints(L, 1), s2 = stationPoints(L, 2);
    for (int a = 0; a < L.controlCount(); ++a) {
        const bool in1 = std::count(s1.begin(), s1.end(), a) > 0, in2 = std::count(s2.begin(), s2.end(), a) > 0;
        EXPECT_EQ(B[3 * a + 0], L.points[3 * a + 0]);
        EXPECT_NEAR(B[3 * a + 1], L.points[3 * a + 1] + (in1 ? 0.3 : 0.0), 1e-15);
        EXPECT_NEAR(B[3 * a + 2], L.points[3 * a + 2] + (in2 ? -0.25 : 0.0), 1e-15);
    }
}

TEST(DesignVariables, ASectionScalingScalesOnePointsVerticalCoordinateAboutItsStationCentroid) {
    const Lattice L = irregularLattice();
    DesignSpace ds({L});
    ds.addStations(wingSpec());
    const int point = L.index(2, 1, 1);  // in station 1
    const int var = ds.find("wing.S1.P" + std::to_string(point) + ".sz");
    ASSERT_GE(var, 0);
    const double ref = centroid(L, stationPoints(L, 1))[2];
    for (double factor : {1.5, 0.6, 0.0}) {
        std::vector<double> v = ds.baselineValues();
        v[var] = factor;
        const std::vector<double> B = ds.latticePoints<double>(0, v);
        for (int a = 0; a < L.controlCount(); ++a) {
            for (int c = 0; c < 3; ++c) {
                const double expected = (a == point && c == 2) ? ref + factor * (L.points[3 * a + 2] - ref) : L.points[3 * a + c];
                EXPECT_NEAR(B[3 * a + c], expected, 1e-15) << "factor " << factor << " point " << a;
            }
        }
    }
}

TEST(DesignVariables, ATaperScalesAStationStreamwiseAboutItsCentroid) {
    const Lattice L = irregularLattice();
    DesignSpace ds({L});
    ds.addStations(wingSpec());
    std::vector<double> v = ds.baselineValues();
    v[ds.find("wing.S3.taperx")] = 0.8;
    const std::vector<double> B = ds.latticePoints<double>(0, v);
    const std::vector<int> s3 = stationPoints(L, 3);
    const double ref = centroid(L, s3)[0];
    double meanBefore = 0, meanAfter = 0, spreadBefore = 0, spreadAfter = 0;
    for (int a = 0; a < L.controlCount(); ++a) {
        const bool in = std::count(s3.begin(), s3.end(), a) > 0;
        EXPECT_NEAR(B[3 * a], in ? ref + 0.8 * (L.points[3 * a] - ref) : L.points[3 * a], 1e-15);
        EXPECT_EQ(B[3 * a + 1], L.points[3 * a + 1]);
        EXPECT_EQ(B[3 * a + 2], L.points[3 * a + 2]);
        if (in) {
            meanBefore += L.points[3 * a] / 6;
            meanAfter += B[3 * a] / 6;
        }
    }
    for (int a : s3) {
        spreadBefore = std::max(spreadBefore, std::abs(L.points[3 * a] - meanBefore));
        spreadAfter = std::max(spreadAfter, std::abs(B[3 * a] - meanAfter));
    }
    EXPECT_NEAR(meanAfter, meanBefore, 1e-14);        // the chord's centre stays
    EXPECT_NEAR(spreadAfter, 0.8 * spreadBefore, 1e-14);  // the chord shrinks by the factor
    EXPECT_GT(spreadBefore, 0.5);
}

TEST(DesignVariables, PointCoordinatesMoveOneCoordinateAndAreNamedByPointAndAxis) {
    const Lattice L = irregularLattice();
    DesignSpace ds({L});
    ds.addPointCoordinate(0, 7, 2, -0.3, 0.5);
    ds.addPointCoordinate(0, 7, 0, -0.6, 0.0, "tail");
    ASSERT_EQ(ds.size(), 2);
    const DesignVariable& z = ds.variables()[0];
    EXPECT_EQ(z.name, "L0.P7.z");
    EXPECT_EQ(z.kind, VariableKind::PointCoordinate);
    EXPECT_EQ(z.point, 7);
    EXPECT_EQ(z.baseline, 0.0);
    EXPECT_EQ(z.lower, -0.3);
    EXPECT_EQ(z.upper, 0.5);
    EXPECT_EQ(z.scale, 0.5);  // the larger bound
    EXPECT_EQ(ds.variables()[1].name, "tail.P7.x");
    EXPECT_EQ(ds.variables()[1].scale, 0.6);
    EXPECT_EQ(ds.find("tail.P7.x"), 1);
    const std::vector<double> B = ds.latticePoints<double>(0, std::vector<double>{0.2, -0.1});
    for (int a = 0; a < L.controlCount(); ++a) {
        for (int c = 0; c < 3; ++c) {
            const double d = a != 7 ? 0.0 : c == 2 ? 0.2 : c == 0 ? -0.1 : 0.0;
            EXPECT_NEAR(B[3 * a + c], L.points[3 * a + c] + d, 1e-15);
        }
    }
}

// B(v) = B(v0) + J (v - v0) for any v (steps of any size: the map is affine), J is the complex-step
// derivative of latticePoints, and B of a combination of designs is the combination of their B.
TEST(DesignVariables, TheMapIsAffineWithTheAnalyticJacobianAsItsExactDerivative) {
    const Lattice L = irregularLattice();
    DesignSpace ds({L});
    StationSpec spec = wingSpec();
    spec.vertical = 0;  // section scaling and taper on the same axis: their effects add
    ds.addStations(spec);
    ds.addPointCoordinate(0, 11, 1, -0.5, 0.5);
    const int n = ds.size(), rows = 3 * L.controlCount();
    const Eigen::SparseMatrix<double> J = ds.jacobian(0);
    ASSERT_EQ(J.rows(), rows);
    ASSERT_EQ(J.cols(), n);
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    const std::vector<double> v0 = ds.baselineValues();
    std::vector<double> v1(n), v2(n);
    for (int i = 0; i < n; ++i) {
        v1[i] = v0[i] + 0.5 * U(rng);
        v2[i] = v0[i] + 2.0 * U(rng);
    }
    const std::vector<double> B0 = ds.latticePoints<double>(0, v0), B1 = ds.latticePoints<double>(0, v1),
                              B2 = ds.latticePoints<double>(0, v2);
    const Eigen::VectorXd dv = Eigen::Map<const Eigen::VectorXd>(v2.data(), n) - Eigen::Map<const Eigen::VectorXd>(v0.data(), n);
    const Eigen::VectorXd predicted = Eigen::Map<const Eigen::VectorXd>(B0.data(), rows) + J * dv;
    for (int r = 0; r < rows; ++r) EXPECT_NEAR(B2[r], predicted[r], 1e-13);
    const double a = 0.3;
    std::vector<double> mix(n);
    for (int i = 0; i < n; ++i) mix[i] = a * v1[i] + (1 - a) * v2[i];
    const std::vector<double> Bm = ds.latticePoints<double>(0, mix);
    for (int r = 0; r < rows; ++r) EXPECT_NEAR(Bm[r], a * B1[r] + (1 - a) * B2[r], 1e-13);
    // Complex step at v1, one column at a time.
    const Eigen::MatrixXd Jd(J);
    for (int i = 0; i < n; ++i) {
        std::vector<cplx> z(v1.begin(), v1.end());
        z[i] += cplx(0, 1e-30);
        const std::vector<cplx> Bz = ds.latticePoints<cplx>(0, z);
        for (int r = 0; r < rows; ++r) {
            ASSERT_NEAR(Bz[r].imag() / 1e-30, Jd(r, i), 1e-14) << ds.variables()[i].name << " row " << r;
            ASSERT_EQ(Bz[r].real(), B1[r]);
        }
    }
    // Each translation column has one entry of 1 per point of its station.
    const int ty = ds.find("wing.S2.ty");
    EXPECT_EQ(Jd.col(ty).sum(), 6.0);
    EXPECT_EQ(Jd.col(ty).cwiseAbs().sum(), 6.0);
}

TEST(DesignVariables, VariablesOfAnotherLatticeLeaveThisOneAlone) {
    const Lattice L = irregularLattice();
    LatticeBox box;
    box.origin = {5, 0, 0};
    const Lattice tail = makeLattice(box, {2, 2, 2}, {1, 1, 1});
    DesignSpace ds({L, tail});
    ds.addStations(wingSpec());
    StationSpec t;
    t.lattice = 1;
    t.prefix = "tail";
    t.direction = 0;
    t.bits = {"111", "010"};
    EXPECT_EQ(ds.addStations(t), 4 + 8 + 2);
    ASSERT_EQ(ds.stations().size(), 6u);
    EXPECT_EQ(ds.stations()[4].group, 1);
    EXPECT_EQ(ds.stations()[5].lattice, 1);
    EXPECT_EQ(ds.stations()[5].ordinal, 1);
    EXPECT_EQ(ds.stations()[5].points.size(), 4u);
    std::vector<double> v = ds.baselineValues();
    for (int i = 34; i < ds.size(); ++i) v[i] += 0.2;
    EXPECT_EQ(ds.latticePoints<double>(0, v), L.points);
    const std::vector<double> B = ds.latticePoints<double>(1, v);
    // The tail's own variables move it: tail.S1.ty (Y) acts on its points with i = 1.
    const Eigen::MatrixXd J0(ds.jacobian(0)), J1(ds.jacobian(1));
    EXPECT_EQ(J0.rows(), 3 * L.controlCount());
    EXPECT_EQ(J1.rows(), 3 * 8);
    EXPECT_EQ(J0.rightCols(ds.size() - 34).norm(), 0.0);
    EXPECT_EQ(J1.leftCols(34).norm(), 0.0);
    EXPECT_EQ(ds.find("tail.S1.ty"), 37);
    EXPECT_NEAR(B[3 * tail.index(1, 1, 1) + 1] - tail.points[3 * tail.index(1, 1, 1) + 1], 0.2, 1e-15);
}

TEST(DesignVariables, BadInputIsACaseErrorNamingTheKey) {
    const Lattice L = irregularLattice();
    DesignSpace ds({L});
    StationSpec s = wingSpec();
    s.lattice = 1;
    EXPECT_NE(aero::test::messageOf<CaseError>([&] { ds.addStations(s); }).find("design_variables.stations.lattice: no lattice 1"), std::string::npos);
    s = wingSpec();
    s.direction = 3;
    EXPECT_NE(aero::test::messageOf<CaseError>([&] { ds.addStations(s); }).find("design_variables.stations.direction: must be 0, 1 or 2, got 3"),
              std::string::npos);
    s = wingSpec();
    s.vertical = -1;
    EXPECT_NE(aero::test::messageOf<CaseError>([&] { ds.addStations(s); }).find("vertical and streamwise axes"), std::string::npos);
    s = wingSpec();
    s.bits.pop_back();
    EXPECT_NE(aero::test::messageOf<CaseError>([&] { ds.addStations(s); }).find("design_variables.stations.bits: 3 bit strings for 4 stations"),
              std::string::npos);
    for (const std::string bad : {"0a1", "0011", "01", ""}) {
        s = wingSpec();
        s.bits[2] = bad;
        const std::string m = aero::test::messageOf<CaseError>([&] { ds.addStations(s); });
        EXPECT_NE(m.find("design_variables.stations.bits[2]: expected three 0/1 digits (zyx), got '" + bad + "'"), std::string::npos)
            << m;
    }
    EXPECT_NE(aero::test::messageOf<CaseError>([&] { ds.addPointCoordinate(0, 24, 0, -1, 1); }).find("no lattice point 24"), std::string::npos);
    EXPECT_NE(aero::test::messageOf<CaseError>([&] { ds.addPointCoordinate(0, -1, 0, -1, 1); }).find("no lattice point -1"), std::string::npos);
    EXPECT_NE(aero::test::messageOf<CaseError>([&] { ds.addPointCoordinate(0, 3, 3, -1, 1); }).find("axis 3"), std::string::npos);
    EXPECT_NE(aero::test::messageOf<CaseError>([&] { ds.addPointCoordinate(1, 3, 0, -1, 1); }).find("in lattice 1"), std::string::npos);
    const std::string m = aero::test::messageOf<CaseError>([&] { ds.addPointCoordinate(0, 3, 0, 0.1, 0.5); });
    EXPECT_NE(m.find("lattice point 3"), std::string::npos) << m;
    EXPECT_NE(m.find("must contain 0"), std::string::npos) << m;
    EXPECT_NO_THROW(ds.addPointCoordinate(0, 3, 0, 0.0, 0.0));  // a closed interval at the baseline
}

// A refused addition changes nothing: a case editor that catches the error and carries on must
// not be left with the stations and translations made before the bad bit string was reached.
TEST(DesignVariables, ARefusedStationSpecLeavesTheDesignSpaceAsItWas) {
    const Lattice L = irregularLattice();
    DesignSpace ds({L});
    ds.addPointCoordinate(0, 2, 1, -1, 1);
    StationSpec s = wingSpec();
    s.bits[2] = "1x1";
    EXPECT_THROW(ds.addStations(s), CaseError);
    EXPECT_EQ(ds.size(), 1);
    EXPECT_EQ(ds.stations().size(), 0u);
    // A good spec afterwards is the first group and names its variables as usual.
    EXPECT_EQ(ds.addStations(wingSpec()), 34);
    EXPECT_EQ(ds.stations()[0].group, 0);
    EXPECT_EQ(ds.find("wing.S0.tx"), 1);
}
