#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "RandomNurbs.h"
#include "common/Error.h"
#include "mesh/VolumeFit.h"
#include "nurbs/Basis.h"

using namespace aero;
using namespace aero::mesh;

namespace {

std::vector<double> uniformParams(int n) {
    std::vector<double> u(n);
    for (int i = 0; i < n; ++i) u[i] = static_cast<double>(i) / (n - 1);
    return u;
}

// Grid of `dims` nodes sampled from v at the given parameters.
StructuredGrid sample(const nurbs::Volume<double>& v, const std::array<std::vector<double>, 3>& u,
                      const std::string& name) {
    StructuredGrid g;
    g.name = name;
    g.dims = {static_cast<int>(u[0].size()), static_cast<int>(u[1].size()),
              static_cast<int>(u[2].size())};
    g.xyz.resize(3 * static_cast<std::size_t>(g.nodeCount()));
    nurbs::sampleGrid(v, u[0], u[1], u[2], g.xyz.data());
    return g;
}

// Annular sector: radius 1..2 over i, angle theta0..theta1 over j, height 0..1 over k.
StructuredGrid annulus(std::array<int, 3> dims, double theta0, double theta1,
                       const std::string& name) {
    StructuredGrid g;
    g.name = name;
    g.dims = dims;
    g.xyz.resize(3 * static_cast<std::size_t>(g.nodeCount()));
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            for (int i = 0; i < dims[0]; ++i) {
                const double r = 1.0 + static_cast<double>(i) / (dims[0] - 1);
                const double t = theta0 + (theta1 - theta0) * j / (dims[1] - 1);
                double* x = g.at(i, j, k);
                x[0] = r * std::cos(t);
                x[1] = r * std::sin(t);
                x[2] = static_cast<double>(k) / (dims[2] - 1);
            }
        }
    }
    return g;
}

}  // namespace

TEST(VolumeFit, SampledCubicVolumeIsReproduced) {
    // A random cubic volume with uniform knots, sampled at uniform parameters: fitting with the
    // same degree, counts, parameters and knots must return the same control net.
    std::mt19937 rng(3);
    nurbs::Volume<double> v;
    v.degree = {3, 3, 2};
    v.count = {6, 5, 7};
    for (int d = 0; d < 3; ++d) v.knots[d] = nurbs::uniformKnots(v.degree[d], v.count[d]);
    v.points = test::randomPoints(rng, v.controlCount());
    const std::array<std::vector<double>, 3> u{uniformParams(13), uniformParams(11),
                                               uniformParams(15)};
    const StructuredGrid g = sample(v, u, "sampled");

    FitOptions o;
    o.degree = v.degree;
    o.count = v.count;
    o.parameterization = Parameterization::Uniform;
    o.knots = KnotPlacement::Uniform;
    const FitResult f = fitVolume(g, o);
    EXPECT_EQ(f.volume.count, v.count);
    EXPECT_EQ(f.volume.degree, v.degree);
    EXPECT_FALSE(f.volume.rational());
    for (int d = 0; d < 3; ++d) {
        EXPECT_EQ(f.params[d], u[d]);
        EXPECT_EQ(f.volume.knots[d], v.knots[d]);
    }
    ASSERT_EQ(f.volume.points.size(), v.points.size());
    for (std::size_t a = 0; a < v.points.size(); ++a) {
        EXPECT_NEAR(f.volume.points[a], v.points[a], 1e-13) << a;
    }
    EXPECT_LT(f.maxError, 1e-13);
    EXPECT_LE(f.rmsError, f.maxError);

    // Interpolation (count == dims) through averaged knots reproduces the nodes too.
    const nurbs::Volume<double>& w = f.volume;
    const StructuredGrid small =
        sample(w, {uniformParams(6), uniformParams(5), uniformParams(7)}, "small");
    FitOptions all;
    all.degree = w.degree;
    all.count = small.dims;
    EXPECT_LT(fitVolume(small, all).maxError, 1e-13);
}

TEST(VolumeFit, AffineGridIsExactWithChordLengthAndAveragedKnots) {
    // Uniformly spaced sheared box: chord length gives uniform parameters and the trilinear map
    // lies in every spline space of degree >= 1.
    StructuredGrid g;
    g.name = "box";
    g.dims = {9, 7, 5};
    g.xyz.resize(3 * static_cast<std::size_t>(g.nodeCount()));
    for (int k = 0; k < 5; ++k) {
        for (int j = 0; j < 7; ++j) {
            for (int i = 0; i < 9; ++i) {
                double* x = g.at(i, j, k);
                x[0] = 0.5 * i + 0.2 * j;
                x[1] = 0.3 * j - 0.1 * k;
                x[2] = 0.25 * k + 0.05 * i;
            }
        }
    }
    FitOptions o;
    o.count = {5, 4, 4};
    const FitResult f = fitVolume(g, o);
    for (int d = 0; d < 3; ++d) {
        const std::vector<double> u = uniformParams(g.dims[d]);
        for (int i = 0; i < g.dims[d]; ++i) EXPECT_NEAR(f.params[d][i], u[i], 1e-15);
    }
    EXPECT_LT(f.maxError, 1e-14);
}

TEST(VolumeFit, CornersAreExactAndFacesDependOnlyOnFaceNodes) {
    StructuredGrid g = annulus({9, 17, 6}, 0.0, 1.2, "sector");
    // Perturb the interior so the data are not in the spline space.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(-0.01, 0.01);
    for (int k = 1; k < 5; ++k) {
        for (int j = 1; j < 16; ++j) {
            for (int i = 1; i < 8; ++i) {
                for (int c = 0; c < 3; ++c) g.at(i, j, k)[c] += U(rng);
            }
        }
    }
    FitOptions o;
    o.count = {5, 7, 4};
    o.parameterization = Parameterization::Uniform;
    const FitResult f = fitVolume(g, o);
    const nurbs::Volume<double>& v = f.volume;
    EXPECT_GT(f.maxError, 1e-4);  // a genuine approximation
    for (int c = 0; c < 8; ++c) {
        const int i = (c & 1) ? g.dims[0] - 1 : 0, j = (c & 2) ? g.dims[1] - 1 : 0,
                  k = (c & 4) ? g.dims[2] - 1 : 0;
        const int a = v.index((c & 1) ? v.count[0] - 1 : 0, (c & 2) ? v.count[1] - 1 : 0,
                              (c & 4) ? v.count[2] - 1 : 0);
        const nurbs::Vec3<double> P =
            nurbs::evaluate(v, f.params[0][i], f.params[1][j], f.params[2][k]);
        for (int d = 0; d < 3; ++d) {
            EXPECT_EQ(v.points[3 * a + d], g.at(i, j, k)[d]);  // bitwise
            EXPECT_NEAR(P[d], g.at(i, j, k)[d], 1e-15);        // basis round-off only
        }
    }
    // Moving every node off the i = 0 face leaves that face's control points unchanged.
    StructuredGrid moved = g;
    for (int k = 0; k < 6; ++k) {
        for (int j = 0; j < 17; ++j) {
            for (int i = 1; i < 9; ++i) moved.at(i, j, k)[2] += 0.3 * i;
        }
    }
    const nurbs::Volume<double> w = fitVolume(moved, o).volume;
    for (int k = 0; k < v.count[2]; ++k) {
        for (int j = 0; j < v.count[1]; ++j) {
            for (int d = 0; d < 3; ++d) {
                EXPECT_EQ(w.points[3 * w.index(0, j, k) + d], v.points[3 * v.index(0, j, k) + d]);
            }
        }
    }
}

TEST(VolumeFit, NeighbouringBlocksShareTheirFace) {
    // Two sectors meeting at theta = 0.6: block a's j = max face is block b's j = 0 face.
    const StructuredGrid a = annulus({9, 13, 5}, 0.0, 0.6, "a");
    const StructuredGrid b = annulus({9, 21, 5}, 0.6, 1.5, "b");
    FitOptions oa, ob;
    oa.count = {5, 6, 4};
    ob.count = {5, 9, 4};
    const FitResult fa = fitVolume(a, oa), fb = fitVolume(b, ob);
    for (int i = 0; i < 9; ++i) {
        ASSERT_NEAR(fa.params[0][i], fb.params[0][i], 1e-15);  // radial chords agree
    }
    for (int k = 0; k < 4; ++k) {
        for (int i = 0; i < 5; ++i) {
            for (int d = 0; d < 3; ++d) {
                EXPECT_NEAR(fa.volume.points[3 * fa.volume.index(i, 5, k) + d],
                            fb.volume.points[3 * fb.volume.index(i, 0, k) + d], 1e-14);
            }
        }
    }
}

TEST(VolumeFit, ErrorFallsAtTheExpectedRateUnderRefinement) {
    // Quarter annulus, 321 nodes around: the error comes from the circular arcs only (radius
    // and height are linear). Doubling the number of knot spans around divides it by ~2^(p+1).
    const StructuredGrid g = annulus({5, 321, 5}, 0.0, std::numbers::pi / 2, "quarter");
    for (int p : {2, 3}) {
        std::vector<double> errors;
        for (int spans : {4, 8, 16}) {
            FitOptions o;
            o.degree = {p, p, p};
            o.count = {p + 1, p + spans, p + 1};
            errors.push_back(fitVolume(g, o).maxError);
        }
        const double expected = std::pow(2.0, p + 1);
        for (std::size_t r = 1; r < errors.size(); ++r) {
            const double ratio = errors[r - 1] / errors[r];
            std::printf("degree %d: error %.3e -> %.3e, ratio %.2f\n", p, errors[r - 1], errors[r],
                        ratio);
            EXPECT_GT(ratio, 0.7 * expected)
                << "degree " << p << ", errors " << errors[r - 1] << " -> " << errors[r];
            EXPECT_LT(ratio, 1.5 * expected) << "degree " << p;
        }
        if (p == 3) {
            EXPECT_LT(errors.back(), 1e-6);
        }
    }
}

TEST(VolumeFit, AutomaticCountsAndParameters) {
    const StructuredGrid g = annulus({9, 41, 6}, 0.0, 1.0, "auto");
    const FitResult f = fitVolume(g);  // count 0: one span per ~4 intervals, at least degree + 1
    EXPECT_EQ(f.volume.count, (std::array<int, 3>{5, 13, 4}));  // 8/4 + 3, 40/4 + 3, 5/4 + 3
    EXPECT_LT(f.maxError, 1e-4);
    // Chord length along the arcs is uniform in angle.
    for (int j = 0; j < 41; ++j) EXPECT_NEAR(f.params[1][j], j / 40.0, 1e-14);
    // Two nodes cannot carry a cubic, automatic count or not.
    const StructuredGrid thin = annulus({9, 41, 2}, 0.0, 1.0, "thin");
    EXPECT_THROW(fitVolume(thin), GeometryError);
    FitOptions linear;
    linear.degree = {3, 3, 1};
    EXPECT_EQ(fitVolume(thin, linear).volume.count[2], 2);
}

TEST(VolumeFit, BadOptionsAreRejectedNamingTheBlock) {
    const StructuredGrid g = annulus({9, 11, 6}, 0.0, 1.0, "inlet");
    auto expectError = [&](const FitOptions& o, const std::string& fragment) {
        try {
            fitVolume(g, o);
            ADD_FAILURE() << "no error for " << fragment;
        } catch (const GeometryError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("'inlet'"), std::string::npos) << m;
            EXPECT_NE(m.find(fragment), std::string::npos) << m;
        }
    };
    FitOptions o;
    o.count = {3, 6, 5};
    expectError(o, "direction i: count 3 < degree + 1 = 4");
    o.count = {9, 12, 5};
    expectError(o, "direction j: count 12 > grid dims 11");
    o.count = {5, 5, 5};
    o.degree = {3, 0, 3};
    expectError(o, "direction j: degree 0");
    o.degree = {3, 3, 10};
    expectError(o, "direction k: degree 10");
    o.degree = {3, 3, 3};
    o.params[2] = {0.0, 0.5, 1.0};
    expectError(o, "direction k: explicit params must be 6");
    o.params[2] = {0.0, 0.2, 0.1, 0.5, 0.7, 1.0};
    expectError(o, "non-decreasing");
    o.params[2].clear();

    StructuredGrid flat = g;
    flat.dims = {9, 11, 1};
    flat.xyz.resize(3 * 99);
    EXPECT_THROW(fitVolume(flat, o), GeometryError);
    StructuredGrid bad = g;
    bad.xyz[7] = std::nan("");
    EXPECT_THROW(fitVolume(bad, o), GeometryError);
    // Every node of the k = 1 plane coincides with k = 0: no parameter between them, so with
    // uniform knots the first span of 3 holds no data.
    StructuredGrid doubled = g;
    for (int j = 0; j < 11; ++j) {
        for (int i = 0; i < 9; ++i) {
            for (int c = 0; c < 3; ++c) doubled.at(i, j, 1)[c] = doubled.at(i, j, 0)[c];
        }
    }
    o.count = {5, 5, 6};
    o.knots = KnotPlacement::Uniform;
    EXPECT_THROW(fitVolume(doubled, o), GeometryError);
}
