#include "ffd/FfdModel.h"

#include <gtest/gtest.h>

#include <complex>
#include <numbers>
#include <random>

#include "RandomNurbs.h"
#include "ffd/Injectivity.h"
#include "geometry/EnclosedVolume.h"
#include "PaperModel.h"
#include "geometry/HalfSphere.h"

using namespace aero;
using namespace aero::ffd;
using cplx = std::complex<double>;

namespace {

using test::paperModel;

std::vector<double> randomStep(const FfdModel& m, unsigned seed, double size) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-size, size);
    std::vector<double> v = m.design().baselineValues();
    for (double& x : v) x += U(rng);
    return v;
}

std::vector<nurbs::Surface<cplx>> complexPatches(const FfdModel& m, const std::vector<cplx>& A) {
    std::vector<nurbs::Surface<cplx>> out;
    const auto& idx = m.index();
    for (int p = 0; p < m.baseline().size(); ++p) {
        const auto& s = m.baseline().patches[p];
        nurbs::Surface<cplx> c = test::cast<cplx>(s);
        for (int a = idx.patchOffset[p]; a < idx.patchOffset[p + 1]; ++a) {
            for (int k = 0; k < 3; ++k) c.points[3 * (a - idx.patchOffset[p]) + k] = A[3 * idx.toUnique[a] + k];
        }
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace

TEST(FfdModel, PaperSampleHas89VariablesAndReproducesTheSphere) {
    const FfdModel m = paperModel();
    EXPECT_EQ(m.design().size(), 89);
    int translations = 0, scalings = 0;
    for (const auto& d : m.design().variables()) {
        translations += d.kind == VariableKind::Translate;
        scalings += d.kind == VariableKind::SectionScale || d.kind == VariableKind::Taper;
    }
    EXPECT_EQ(translations, 11);
    EXPECT_EQ(scalings, 78);
    EXPECT_EQ(m.summary().embedded, 521);
    EXPECT_TRUE(m.summary().failures.empty());
    EXPECT_LE(m.summary().maxError, 1e-12);
    const auto base = m.design().baselineValues();
    const geometry::PatchSet out = m.deform(base);
    for (int p = 0; p < out.size(); ++p) {
        for (std::size_t a = 0; a < out.patches[p].points.size(); ++a) {
            EXPECT_NEAR(out.patches[p].points[a], m.baseline().patches[p].points[a], 1e-12);
        }
    }
    EXPECT_NEAR(m.volume(base), 2 * std::numbers::pi / 3, 2e-4);
}

TEST(FfdModel, DesignJacobianAgreesWithComplexStep) {
    const FfdModel m = paperModel();
    const auto v = randomStep(m, 1, 0.1);
    const Eigen::SparseMatrix<double> J = m.design().jacobian(0);
    const Eigen::MatrixXd Jd(J);
    for (int i = 0; i < m.design().size(); ++i) {
        std::vector<cplx> vc(v.begin(), v.end());
        vc[i] += cplx(0, 1e-30);
        const auto B = m.design().latticePoints<cplx>(0, vc);
        for (std::size_t r = 0; r < B.size(); ++r) ASSERT_NEAR(Jd(static_cast<int>(r), i), B[r].imag() / 1e-30, 1e-15);
    }
}

TEST(FfdModel, SurfaceSensitivityAgreesWithComplexStep) {
    const FfdModel m = paperModel();
    const auto v = randomStep(m, 2, 0.1);
    const Eigen::MatrixXd D(m.dUniqueDv());
    for (int i = 0; i < m.design().size(); i += 4) {
        std::vector<cplx> vc(v.begin(), v.end());
        vc[i] += cplx(0, 1e-30);
        const auto A = m.uniquePoints<cplx>(vc);
        for (std::size_t r = 0; r < A.size(); ++r) ASSERT_NEAR(D(static_cast<int>(r), i), A[r].imag() / 1e-30, 1e-14);
    }
}

TEST(FfdModel, VolumeGradientAgreesWithComplexStep) {
    const FfdModel m = paperModel();
    const auto v = randomStep(m, 3, 0.15);
    const std::vector<double> g = m.volumeGradient(v);
    for (int i = 0; i < m.design().size(); i += 3) {
        std::vector<cplx> vc(v.begin(), v.end());
        vc[i] += cplx(0, 1e-30);
        const cplx V = geometry::enclosedVolume(complexPatches(m, m.uniquePoints<cplx>(vc)));
        EXPECT_NEAR(g[i], V.imag() / 1e-30, 1e-13 * std::max(1.0, std::abs(g[i]))) << m.design().variables()[i].name;
        EXPECT_NEAR(V.real(), m.volume(v), 1e-13);
    }
}

TEST(FfdModel, SymmetryConstraintsKeepThePlanePointsOnThePlane) {
    // The paper's lattice starts on the plane Y = 0: points there have eta = 0, where only the
    // root station acts, and the root does not translate in Y. A lattice that extends below the
    // plane couples the plane points to several stations: the constraint rows are then needed.
    const auto set = geometry::makeHalfSphere();
    LatticeSpec spec;
    spec.lattice = makeLattice(boxAround(set, {}, {0.05, 0.15, 0.05}), {6, 6, 2}, {3, 3, 1});
    FfdModel m(set, {spec});
    StationSpec st;
    st.bits = {"011", "011", "011", "011", "011", "011"};
    m.design().addStations(st);
    const auto rows = m.symmetryConstraints();
    ASSERT_FALSE(rows.empty());
    const int n = m.design().size();
    std::vector<double> v = randomStep(m, 4, 0.1);
    // The random step moves plane points off the plane...
    double off = 0;
    const auto A0 = m.uniquePoints<double>(v);
    for (int u = 0; u < m.index().uniqueCount(); ++u) {
        if (m.index().points[3 * u + 1] == 0.0) off = std::max(off, std::abs(A0[3 * u + 1]));
    }
    EXPECT_GT(off, 1e-3);
    // ...its projection onto the constraints keeps every one of them on it.
    Eigen::MatrixXd C(static_cast<int>(rows.size()), n);
    Eigen::VectorXd rhs(static_cast<int>(rows.size()));
    for (std::size_t r = 0; r < rows.size(); ++r) {
        C.row(static_cast<int>(r)) = Eigen::Map<const Eigen::VectorXd>(rows[r].row.data(), n).transpose();
        rhs[static_cast<int>(r)] = rows[r].lower;
    }
    Eigen::VectorXd x = Eigen::Map<Eigen::VectorXd>(v.data(), n);
    x -= C.transpose() * (C * C.transpose()).ldlt().solve(C * x - rhs);
    const std::vector<double> vp(x.data(), x.data() + n);
    const auto A = m.uniquePoints<double>(vp);
    int onPlane = 0;
    for (int u = 0; u < m.index().uniqueCount(); ++u) {
        if (m.index().points[3 * u + 1] == 0.0) {
            ++onPlane;
            EXPECT_NEAR(A[3 * u + 1], 0.0, 1e-13);
        }
    }
    EXPECT_EQ(onPlane, 8 * 4 + 8);  // a closed loop of 8 free edges (6 points each): 8 corners
}

TEST(FfdModel, StationGapConstraintsAreExactAndDetectOverlap) {
    const FfdModel m = paperModel();
    const auto gaps = m.stationGapConstraints(0.05);
    ASSERT_EQ(gaps.size(), 5u);
    const auto v0 = m.design().baselineValues();
    const int n = m.design().size();
    auto value = [&](const LinearConstraint& c, const std::vector<double>& v) {
        return Eigen::Map<const Eigen::VectorXd>(c.row.data(), n).dot(Eigen::Map<const Eigen::VectorXd>(v.data(), n));
    };
    for (const auto& c : gaps) EXPECT_GT(value(c, v0), c.lower);
    // Move station 2 in Y onto station 1: constraint [1,2] is violated.
    std::vector<double> v = v0;
    const int ty2 = m.design().find("L0.S2.ty");
    ASSERT_GE(ty2, 0);
    const auto& st = m.design().stations();
    v[ty2] = -(st[2].reference[1] - st[1].reference[1]);
    EXPECT_LT(value(gaps[1], v), gaps[1].lower);
    EXPECT_GT(value(gaps[0], v), gaps[0].lower);
}

TEST(FfdModel, StationSecondDifferencesBoundAZigzagAndLeaveAStraightChangeFree) {
    const FfdModel m = paperModel();
    const auto rows = m.stationSecondDifferenceConstraints(0.25);
    // 4 middle stations x 12 lattice points x 3 axes, less the rows others imply: a station's
    // points move together in y (1 row); in x by its translation and taper, so the two ends of
    // the chord bound the rest (2 rows); in z each point has its own section scaling (12 rows).
    EXPECT_EQ(rows.size(), 4u * 15u);
    const auto v0 = m.design().baselineValues();
    const int n = m.design().size();
    auto value = [&](const LinearConstraint& c, const std::vector<double>& v) {
        return Eigen::Map<const Eigen::VectorXd>(c.row.data(), n).dot(Eigen::Map<const Eigen::VectorXd>(v.data(), n));
    };
    auto violated = [&](const std::vector<double>& v) {
        int count = 0;
        for (const auto& c : rows) count += value(c, v) < c.lower - 1e-12 || value(c, v) > c.upper + 1e-12;
        return count;
    };
    EXPECT_EQ(violated(v0), 0);
    EXPECT_DOUBLE_EQ(m.largestStationSecondDifference(v0).first, 0.0);
    // A linear sweep and a linear span stretch bend nothing, however large.
    std::vector<double> v = v0;
    for (int s = 1; s < 6; ++s) {
        v[m.design().find("L0.S" + std::to_string(s) + ".tx")] = 0.5 * s;
        v[m.design().find("L0.S" + std::to_string(s) + ".ty")] = 0.4 * s;
    }
    EXPECT_EQ(violated(v), 0);
    EXPECT_NEAR(m.largestStationSecondDifference(v).first, 0.0, 1e-14);
    // One station pushed 0.2 aft of a straight sweep bends three triples: 0.2, -0.4, 0.2.
    v[m.design().find("L0.S3.tx")] += 0.2;
    const auto [largest, where] = m.largestStationSecondDifference(v);
    EXPECT_NEAR(largest, 0.4, 1e-14);
    EXPECT_NE(where.find("station_second_difference[3, "), std::string::npos) << where;
    EXPECT_NE(where.find(", x]"), std::string::npos) << where;
    EXPECT_EQ(violated(v), 2);  // only the middle triple exceeds 0.25 (at both ends of the chord)
    v[m.design().find("L0.S3.tx")] += 0.2;
    EXPECT_EQ(violated(v), 6);
    // Section scalings count too: one point's z scaling at a middle station.
    std::vector<double> w = v0;
    const int sz = m.design().find("L0.S2.P12.sz");
    ASSERT_GE(sz, 0);
    w[sz] = 2.0;
    EXPECT_GT(m.largestStationSecondDifference(w).first, 0.25);
    EXPECT_GT(violated(w), 0);
}

TEST(FfdModel, BlendedWingDeformationStaysInjective) {
    // Stretch the span and flatten the sections, as in Figure 1 of the paper.
    FfdModel m = paperModel();
    std::vector<double> v = m.design().baselineValues();
    for (int i = 0; i < m.design().size(); ++i) {
        const auto& d = m.design().variables()[i];
        const int s = m.design().stations()[d.station].ordinal;
        if (d.kind == VariableKind::Translate && d.axis == 1) v[i] = 0.35 * s;
        if (d.kind == VariableKind::SectionScale) v[i] = 0.6;
        if (d.kind == VariableKind::Taper) v[i] = 1.0 - 0.08 * s;
    }
    const InjectivityReport r = checkInjectivity(m.design().lattice(0, v));
    EXPECT_TRUE(r.injective);
    // Span stretched (root at Y = 0, tip past 2.5), thickness reduced.
    const geometry::BoundingBox b = geometry::surfaceBoundingBox(m.deform(v));
    EXPECT_NEAR(b.min[1], 0.0, 1e-12);
    EXPECT_GT(b.max[1], 2.5);
    EXPECT_LT(b.max[2] - b.min[2], 1.4);
}

// Trims live in parameter space: a deformation moves the base surface's control points and
// leaves the trims (and the unit) as they were, so the trimmed surface is S(trim region) for
// the deformed S.
TEST(FfdModel, DeformationKeepsTrimsAndUnitExactly) {
    auto set = geometry::makeHalfSphere();
    set.unit = "m";
    set.trims.resize(static_cast<std::size_t>(set.size()));
    const auto& p = set.patches[2];
    const double u0 = p.knotsU.front(), u1 = p.knotsU.back(), v0 = p.knotsV.front(), v1 = p.knotsV.back();
    set.trims[2].outer = geometry::rectangleLoop(u0 + 0.2 * (u1 - u0), u1, v0, v0 + 0.7 * (v1 - v0));
    geometry::validate(set);
    LatticeSpec spec;
    spec.name = "body";
    spec.lattice = makeLattice(boxAround(set, {}, {0.05, 0.0, 0.05}), {6, 6, 2}, {3, 3, 1});
    FfdModel m(set, {spec});
    StationSpec st;
    st.direction = 1;
    st.bits = {"001", "011", "011", "011", "011", "011"};
    m.design().addStations(st);
    const geometry::PatchSet d = m.deform(randomStep(m, 7, 0.2));
    EXPECT_EQ(d.unit, "m");
    ASSERT_EQ(d.trims.size(), set.trims.size());
    EXPECT_EQ(d.trims[2].outer.curves.size(), 4u);
    for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(d.trims[2].outer.curves[c].curve.points, set.trims[2].outer.curves[c].curve.points);
    EXPECT_NE(d.patches[2].points, set.patches[2].points);  // the surface moved
    EXPECT_NO_THROW(geometry::validate(d));                  // and its trim is still valid on it
}
