#include "geometry/EnclosedVolume.h"

#include <gtest/gtest.h>

#include <complex>
#include <numbers>

#include "RandomNurbs.h"
#include "geometry/HalfSphere.h"

using namespace aero;
using namespace aero::geometry;
using cplx = std::complex<double>;

namespace {

// The half y >= 0 of the box [0,a] x [-b,b] x [0,c] as 5 bilinear patches (the Y=0 face is the
// symmetry plane), outward normals. Volume a*b*c.
PatchSet halfBox(double a, double b, double c) {
    auto quad = [](std::array<double, 3> p00, std::array<double, 3> p10, std::array<double, 3> p01,
                   std::array<double, 3> p11) {
        Patch s;
        s.degreeU = s.degreeV = 1;
        s.countU = s.countV = 2;
        s.knotsU = s.knotsV = {0, 0, 1, 1};
        for (auto* p : {&p00, &p10, &p01, &p11}) s.points.insert(s.points.end(), p->begin(), p->end());
        return s;
    };
    PatchSet set;
    // u x v points outward for each face.
    set.patches.push_back(quad({0, b, 0}, {0, b, c}, {a, b, 0}, {a, b, c}));  // y = b
    set.patches.push_back(quad({0, 0, 0}, {0, 0, c}, {0, b, 0}, {0, b, c}));  // x = 0 (normal -x)
    set.patches.push_back(quad({a, 0, 0}, {a, b, 0}, {a, 0, c}, {a, b, c}));  // x = a
    set.patches.push_back(quad({0, 0, 0}, {0, b, 0}, {a, 0, 0}, {a, b, 0}));  // z = 0 (normal -z)
    set.patches.push_back(quad({0, 0, c}, {a, 0, c}, {0, b, c}, {a, b, c}));  // z = c
    return set;
}

}  // namespace

TEST(EnclosedVolume, GaussLegendreIsExactForPolynomials) {
    std::vector<double> x, w;
    for (int n = 1; n <= 8; ++n) {
        gaussLegendre(n, x, w);
        for (int deg = 0; deg <= 2 * n - 1; ++deg) {
            double q = 0;
            for (int i = 0; i < n; ++i) q += w[i] * std::pow(x[i], deg);
            EXPECT_NEAR(q, 1.0 / (deg + 1), 1e-15) << "n=" << n << " degree " << deg;
        }
    }
}

TEST(EnclosedVolume, HalfBoxIsExact) {
    EXPECT_NEAR(enclosedVolume(halfBox(2.0, 0.5, 3.0)), 3.0, 1e-14);
}

TEST(EnclosedVolume, HalfSphereSampleAgainstTheExactSphere) {
    const PatchSet set = makeHalfSphere();
    const double v = enclosedVolume(set), exact = 2.0 * std::numbers::pi / 3.0;
    RecordProperty("half_sphere_volume", std::to_string(v));
    // Radial deviation <= 1.95e-5 bounds the volume error by about area * deviation = 2 pi * 2e-5.
    EXPECT_NEAR(v, exact, 2 * std::numbers::pi * 2e-5);
    EXPECT_NE(v, exact);
}

TEST(EnclosedVolume, GradientAgreesWithComplexStep) {
    PatchSet set = makeHalfSphere();
    // Make one patch rational to exercise the rational basis derivatives too.
    set.patches[3].weights.assign(36, 1.0);
    set.patches[3].weights[14] = 1.3;
    const std::vector<double> g = enclosedVolumeGradient(set);
    std::vector<nurbs::Surface<cplx>> cs;
    for (const auto& p : set.patches) cs.push_back(test::cast<cplx>(p));
    std::size_t offset = 0;
    for (int p = 0; p < set.size(); p += 3) {
        offset = 0;
        for (int q = 0; q < p; ++q) offset += set.patches[q].points.size();
        for (std::size_t a = 0; a < set.patches[p].points.size(); a += 7) {
            cs[p].points[a] += cplx(0, 1e-30);
            const double cstep = enclosedVolume(cs).imag() / 1e-30;
            cs[p].points[a] -= cplx(0, 1e-30);
            EXPECT_NEAR(g[offset + a], cstep, 1e-14) << "patch " << p << " coordinate " << a;
        }
    }
}
