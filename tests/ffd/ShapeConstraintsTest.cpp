#include "ffd/ShapeConstraints.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>

#include "common/Error.h"
#include "ffd/Injectivity.h"
#include "PaperModel.h"

using namespace aero;
using namespace aero::ffd;
using cplx = std::complex<double>;

namespace {

using test::paperModel;

std::vector<double> randomDesign(const FfdModel& m, unsigned seed, double fraction) {
    std::mt19937 rng(seed);
    std::vector<double> v = m.design().baselineValues();
    const auto& vars = m.design().variables();
    for (std::size_t i = 0; i < v.size(); ++i) {
        std::uniform_real_distribution<double> U(-fraction, fraction);
        v[i] += U(rng) * (vars[i].upper - vars[i].lower);
    }
    return v;
}

// d f / dv_i by complex step for every i.
template <class F>
std::vector<double> complexStep(const std::vector<double>& v, F f) {
    std::vector<double> g(v.size());
    const double h = 1e-30;
    for (std::size_t i = 0; i < v.size(); ++i) {
        std::vector<cplx> z(v.begin(), v.end());
        z[i] += cplx(0, h);
        g[i] = std::imag(f(z)) / h;
    }
    return g;
}

}  // namespace

TEST(ThicknessConstraints, SphereThicknessAtStationsAndPoints) {
    const FfdModel m = paperModel();
    ThicknessSpec spec;
    spec.stations = {0.0, 0.5};
    spec.chordFractions = {0.25, 0.5};
    spec.points = {{0.3, 0.2}};
    const ThicknessConstraints t(m, spec);
    ASSERT_EQ(t.size(), 5);
    EXPECT_EQ(t.points()[0].name, "thickness y=0 x/c=0.25");
    EXPECT_EQ(t.points()[4].name, "thickness (0.3, 0.2)");
    // Sphere of radius 1: the section y = ys spans |x| <= sqrt(1 - ys^2) and is 2 sqrt(1 - x^2 - y^2)
    // thick. The sample's cubic patches approximate the sphere to ~1e-3.
    for (const ThicknessPoint& p : t.points()) {
        EXPECT_NEAR(p.baseline, 2 * std::sqrt(1 - p.x * p.x - p.y * p.y), 5e-3) << p.name;
    }
    EXPECT_NEAR(t.points()[0].x, -0.5, 5e-3);
    EXPECT_NEAR(t.points()[3].x, 0.0, 5e-3);
    EXPECT_NEAR(t.points()[4].x, 0.3, 1e-15);
    const std::vector<double> r = t.ratios(m.design().baselineValues());
    for (double x : r) EXPECT_NEAR(x, 1.0, 1e-12);
}

TEST(ThicknessConstraints, FollowsTheDeformationAndItsGradientMatchesComplexStep) {
    const FfdModel m = paperModel();
    ThicknessSpec spec;
    spec.stations = {0.2, 0.6};
    spec.chordFractions = {0.3, 0.7};
    const ThicknessConstraints t(m, spec);
    const std::vector<double> v = randomDesign(m, 7, 0.05);
    // The value is the distance between the two surface points at their kept parameters.
    const geometry::PatchSet moved = m.deform(v);
    const ThicknessPoint& p0 = t.points()[0];
    const auto top = nurbs::evaluate(moved.patches[p0.topPatch], p0.topUv[0], p0.topUv[1]);
    const auto bottom = nurbs::evaluate(moved.patches[p0.bottomPatch], p0.bottomUv[0], p0.bottomUv[1]);
    const std::vector<double> r = t.ratios(v);
    EXPECT_NEAR(r[0] * p0.baseline, (top - bottom).norm(), 1e-12);
    EXPECT_GT(std::abs(r[0] - 1.0), 1e-3);  // the design changed it
    const std::vector<std::vector<double>> g = t.ratioGradients(v);
    for (int k = 0; k < t.size(); ++k) {
        const std::vector<double> cs = complexStep(v, [&](const std::vector<cplx>& z) {
            return t.thickness<cplx>(k, z) / t.points()[k].baseline;
        });
        double scale = 0;
        for (double x : cs) scale = std::max(scale, std::abs(x));
        ASSERT_GT(scale, 0.0);
        for (std::size_t i = 0; i < v.size(); ++i) EXPECT_NEAR(g[k][i], cs[i], 1e-12 * scale) << t.points()[k].name << " variable " << i;
    }
    // And the scaling variable of a station's vertical points thickens its section.
    const std::vector<double> base = m.design().baselineValues();
    std::vector<double> thick = base;
    for (std::size_t i = 0; i < thick.size(); ++i) {
        if (m.design().variables()[i].kind == VariableKind::SectionScale) thick[i] = 1.2 * base[i];
    }
    for (double x : t.ratios(thick)) EXPECT_GT(x, 1.1);
}

TEST(ThicknessConstraints, PointsOffThePlanformAreRefusedByName) {
    const FfdModel m = paperModel();
    ThicknessSpec outside;
    outside.points = {{1.5, 0.5}};
    try {
        ThicknessConstraints t(m, outside);
        FAIL() << "accepted a point outside the planform";
    } catch (const GeometryError& e) {
        EXPECT_NE(std::string(e.what()).find("thickness (1.5, 0.5)"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("neither above nor below"), std::string::npos) << e.what();
    }
    ThicknessSpec beyond;
    beyond.stations = {1.5};
    beyond.chordFractions = {0.5};
    EXPECT_THROW(ThicknessConstraints(m, beyond), GeometryError);
    ThicknessSpec badFraction;
    badFraction.stations = {0.5};
    badFraction.chordFractions = {1.0};
    EXPECT_THROW(ThicknessConstraints(m, badFraction), GeometryError);
}

TEST(LatticeJacobianBound, OneMinusLogNOverRhoAtTheBaselineAndAGradientMatchingComplexStep) {
    const FfdModel m = paperModel();
    const LatticeJacobianBound b(m);
    const std::vector<double> base = m.design().baselineValues();
    EXPECT_NEAR(b.value(base), 1.0 - std::log(static_cast<double>(b.sampleCount())) / b.rho(), 1e-12);
    EXPECT_NEAR(b.minimum(base).ratio, 1.0, 1e-12);
    const std::vector<double> v = randomDesign(m, 3, 0.03);
    const std::vector<double> g = b.gradient(v);
    const std::vector<double> cs = complexStep(v, [&](const std::vector<cplx>& z) { return b.value<cplx>(v, z); });
    double scale = 0;
    for (double x : cs) scale = std::max(scale, std::abs(x));
    ASSERT_GT(scale, 0.0);
    for (std::size_t i = 0; i < v.size(); ++i) EXPECT_NEAR(g[i], cs[i], 1e-10 * scale) << "variable " << i;
}

TEST(LatticeJacobianBound, GoesNegativeWhereTheCertificateFails) {
    const FfdModel m = paperModel();
    const LatticeJacobianBound b(m);
    // Pull adjacent stations through each other: the lattice folds.
    std::vector<double> v = m.design().baselineValues();
    const auto& vars = m.design().variables();
    int moved = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (vars[i].kind == VariableKind::Translate && vars[i].axis == 1 && vars[i].station == 2) {
            v[i] += 0.9;  // station 2 past station 3 and 4 (0.2 apart)
            ++moved;
        }
    }
    ASSERT_EQ(moved, 1);
    const bool injective = checkInjectivity(m.design().lattice(0, v)).injective;
    EXPECT_FALSE(injective);
    EXPECT_LT(b.value(v), 0.0);
    EXPECT_LT(b.minimum(v).ratio, 0.0);
    EXPECT_EQ(b.minimum(v).lattice, 0);
}
