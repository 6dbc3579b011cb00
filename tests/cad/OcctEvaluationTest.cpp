// Our NURBS surface evaluation against OpenCASCADE's Geom_BSplineSurface (an independent
// implementation) on random rational surfaces: values (D0) and first derivatives (D1).
#include <gtest/gtest.h>

#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <algorithm>
#include <cmath>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <random>
#include <vector>

#include "RandomNurbs.h"
#include "nurbs/Surface.h"

namespace aero::nurbs {
namespace {

constexpr double kTolerance = 1e-12;

/// Flat knot vector -> distinct knots and multiplicities (1-based, as OCCT wants them).
void compress(const std::vector<double>& flat, TColStd_Array1OfReal& knots,
              TColStd_Array1OfInteger& mults) {
    std::vector<double> distinct;
    std::vector<int> count;
    for (double k : flat) {
        if (distinct.empty() || k != distinct.back()) {
            distinct.push_back(k);
            count.push_back(0);
        }
        ++count.back();
    }
    knots.Resize(1, static_cast<int>(distinct.size()), Standard_False);
    mults.Resize(1, static_cast<int>(distinct.size()), Standard_False);
    for (std::size_t i = 0; i < distinct.size(); ++i) {
        knots(static_cast<int>(i) + 1) = distinct[i];
        mults(static_cast<int>(i) + 1) = count[i];
    }
}

Handle(Geom_BSplineSurface) toOcct(const Surface<double>& s) {
    TColStd_Array1OfReal ku(1, 1), kv(1, 1);
    TColStd_Array1OfInteger mu(1, 1), mv(1, 1);
    compress(s.knotsU, ku, mu);
    compress(s.knotsV, kv, mv);
    TColgp_Array2OfPnt poles(1, s.countU, 1, s.countV);
    TColStd_Array2OfReal weights(1, s.countU, 1, s.countV);
    for (int j = 0; j < s.countV; ++j)
        for (int i = 0; i < s.countU; ++i) {
            const int k = s.index(i, j);
            poles(i + 1, j + 1) = gp_Pnt(s.points[3 * k], s.points[3 * k + 1], s.points[3 * k + 2]);
            weights(i + 1, j + 1) = s.rational() ? s.weights[k] : 1.0;
        }
    return new Geom_BSplineSurface(poles, weights, ku, kv, mu, mv, s.degreeU, s.degreeV);
}

Vec3<double> toVec(const gp_XYZ& p) {
    return {p.X(), p.Y(), p.Z()};
}

/// Parameters on [a, b]: both ends, every distinct interior knot, and random values.
std::vector<double> parameters(std::mt19937& rng, const std::vector<double>& knots, int random) {
    std::vector<double> t(knots.begin(), knots.end());
    t.erase(std::unique(t.begin(), t.end()), t.end());
    std::uniform_real_distribution<double> U(knots.front(), knots.back());
    for (int i = 0; i < random; ++i) t.push_back(U(rng));
    return t;
}

/// Random rational surface: degrees 1..5, counts degree+1..degree+8, non-uniform knots with
/// interior multiplicities on a random interval, weights in [0.5, 2].
Surface<double> randomRationalSurface(std::mt19937& rng) {
    std::uniform_int_distribution<int> degree(1, 5), extra(0, 7);
    std::uniform_real_distribution<double> start(-3.0, 3.0), length(0.2, 10.0);
    const int pu = degree(rng), pv = degree(rng);
    Surface<double> s =
        test::randomSurface(rng, pu, pv, pu + 1 + extra(rng), pv + 1 + extra(rng), true);
    const double a = start(rng), c = start(rng);
    s.knotsU = test::randomKnots(rng, pu, s.countU, a, a + length(rng));
    s.knotsV = test::randomKnots(rng, pv, s.countV, c, c + length(rng));
    return s;
}

TEST(OcctEvaluation, ValuesMatchGeomBSplineSurfaceD0) {
    std::mt19937 rng(2024);
    int compared = 0;
    for (int n = 0; n < 60; ++n) {
        const Surface<double> s = randomRationalSurface(rng);
        validate(s, "random surface");
        const Handle(Geom_BSplineSurface) occt = toOcct(s);
        double scale = 0;  // size of the control net
        for (double x : s.points) scale = std::max(scale, std::abs(x));
        for (double u : parameters(rng, s.knotsU, 12))
            for (double v : parameters(rng, s.knotsV, 12)) {
                gp_Pnt p;
                occt->D0(u, v, p);
                const Vec3<double> ref = toVec(p.XYZ());
                const Vec3<double> ours = evaluate(s, u, v);
                ASSERT_LE((ours - ref).norm(), kTolerance * std::max(scale, ref.norm()))
                    << "surface " << n << " (degrees " << s.degreeU << ", " << s.degreeV
                    << ") at u " << u << " v " << v;
                ++compared;
            }
    }
    EXPECT_GT(compared, 10000);
}

TEST(OcctEvaluation, FirstDerivativesMatchGeomBSplineSurfaceD1) {
    std::mt19937 rng(77);
    int compared = 0;
    for (int n = 0; n < 60; ++n) {
        const Surface<double> s = randomRationalSurface(rng);
        const Handle(Geom_BSplineSurface) occt = toOcct(s);
        double scale = 0;
        for (double x : s.points) scale = std::max(scale, std::abs(x));
        // Ends and random points only: at an interior knot of full multiplicity the derivative
        // jumps and either one-sided value would be right.
        std::uniform_real_distribution<double> U(s.knotsU.front(), s.knotsU.back());
        std::uniform_real_distribution<double> V(s.knotsV.front(), s.knotsV.back());
        std::vector<double> us = {s.knotsU.front(), s.knotsU.back()},
                            vs = {s.knotsV.front(), s.knotsV.back()};
        for (int i = 0; i < 12; ++i) {
            us.push_back(U(rng));
            vs.push_back(V(rng));
        }
        for (double u : us)
            for (double v : vs) {
                gp_Pnt p;
                gp_Vec du, dv;
                occt->D1(u, v, p, du, dv);
                const SurfaceDerivatives<double> d = evaluateDerivatives(s, u, v, 1);
                const Vec3<double> refS = toVec(p.XYZ()), refU = toVec(du.XYZ()),
                                   refV = toVec(dv.XYZ());
                const auto where = [&] {
                    return "surface " + std::to_string(n) + " at u " + std::to_string(u) + " v " +
                           std::to_string(v);
                };
                ASSERT_LE((d.S - refS).norm(), kTolerance * std::max(scale, refS.norm()))
                    << where();
                ASSERT_LE((d.Su - refU).norm(), kTolerance * std::max(scale, refU.norm()))
                    << where();
                ASSERT_LE((d.Sv - refV).norm(), kTolerance * std::max(scale, refV.norm()))
                    << where();
                ++compared;
            }
    }
    EXPECT_GT(compared, 10000);
}

}  // namespace
}  // namespace aero::nurbs
