#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <functional>
#include <numbers>
#include <numeric>

#include "common/Error.h"
#include "mesh/Quality.h"

using namespace aero;
using namespace aero::mesh;

namespace {

// Block of dims nodes with node (i, j, k) at f(i, j, k).
StructuredGrid makeGrid(const std::string& name, std::array<int, 3> dims,
                        const std::function<std::array<double, 3>(int, int, int)>& f) {
    StructuredGrid g;
    g.name = name;
    g.dims = dims;
    g.xyz.resize(3 * static_cast<std::size_t>(g.nodeCount()));
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            for (int i = 0; i < dims[0]; ++i) {
                const auto p = f(i, j, k);
                double* x = g.at(i, j, k);
                x[0] = p[0];
                x[1] = p[1];
                x[2] = p[2];
            }
        }
    }
    return g;
}

StructuredGrid uniformGrid(const std::string& name, std::array<int, 3> dims, double h) {
    return makeGrid(name, dims, [h](int i, int j, int k) {
        return std::array<double, 3>{h * i, h * j, h * k};
    });
}

void expectAll(const std::vector<double>& v, double value, double tol) {
    for (std::size_t a = 0; a < v.size(); ++a) ASSERT_NEAR(v[a], value, tol) << "cell " << a;
}

}  // namespace

TEST(Quality, UniformGridIsPerfectAndMinJacobianIsCellVolume) {
    const double h = 0.25;
    const StructuredGrid g = uniformGrid("cube", {5, 4, 3}, h);
    const CellQuality q = cellQuality(g);
    ASSERT_EQ(static_cast<long>(q.minJacobian.size()), g.cellCount());
    expectAll(q.minJacobian, h * h * h, 1e-15);
    expectAll(q.scaledJacobian, 1.0, 1e-15);
    expectAll(q.orthogonality, 1.0, 1e-15);
    expectAll(q.aspectRatio, 1.0, 1e-15);
    expectAll(q.skewness, 0.0, 1e-15);
    EXPECT_NO_THROW(requirePositiveJacobians({g}, {q}));
}

TEST(Quality, MetricsAreInvariantUnderRotationAndTranslation) {
    // Rotation about the axis (1, 2, 2)/3 by 0.7 rad (Rodrigues), then a shift.
    const double n[3] = {1.0 / 3, 2.0 / 3, 2.0 / 3}, c = std::cos(0.7), s = std::sin(0.7);
    double R[3][3];
    for (int r = 0; r < 3; ++r) {
        for (int col = 0; col < 3; ++col) {
            R[r][col] = (r == col ? c : 0.0) + (1 - c) * n[r] * n[col];
        }
    }
    R[0][1] -= s * n[2], R[0][2] += s * n[1], R[1][0] += s * n[2];
    R[1][2] -= s * n[0], R[2][0] -= s * n[1], R[2][1] += s * n[0];
    const double h = 0.5;
    const StructuredGrid g = makeGrid("rotated", {4, 4, 4}, [&](int i, int j, int k) {
        const double p[3] = {h * i, h * j, h * k};
        std::array<double, 3> x{10, -3, 7};
        for (int r = 0; r < 3; ++r) x[r] += R[r][0] * p[0] + R[r][1] * p[1] + R[r][2] * p[2];
        return x;
    });
    const CellQuality q = cellQuality(g);
    expectAll(q.minJacobian, h * h * h, 1e-13);
    expectAll(q.scaledJacobian, 1.0, 1e-13);
    expectAll(q.orthogonality, 1.0, 1e-13);
    expectAll(q.aspectRatio, 1.0, 1e-13);
    expectAll(q.skewness, 0.0, 1e-13);
}

TEST(Quality, ShearedStretchedGridMatchesHandValues) {
    // x = (hx i + t hy j, hy j, hz k): every cell is the parallelepiped spanned by
    // e_i = (1, 0, 0), e_j = (1.5, 2, 0) (length 2.5), e_k = (0, 0, 0.5).
    const double hx = 1.0, hy = 2.0, hz = 0.5, t = 0.75;
    const StructuredGrid g = makeGrid("sheared", {4, 3, 5}, [&](int i, int j, int k) {
        return std::array<double, 3>{hx * i + t * hy * j, hy * j, hz * k};
    });
    const CellQuality q = cellQuality(g);
    expectAll(q.minJacobian, 1.0, 1e-14);     // hx hy hz
    expectAll(q.scaledJacobian, 0.8, 1e-14);  // sin of the i-j angle: 2 / 2.5
    expectAll(q.orthogonality, 0.4, 1e-14);   // 1 - |cos| = 1 - 1.5 / 2.5
    expectAll(q.aspectRatio, 5.0, 1e-14);     // 2.5 / 0.5
    expectAll(q.skewness, 0.6, 1e-14);        // the principal axes are the edges
}

TEST(Quality, TaperedCellSeparatesOrthogonalityFromSkewness) {
    // One symmetric trapezoidal prism: bottom edge 2 long, top edge 1, height 1, depth 1.
    const double X[2][2] = {{0.0, 2.0}, {0.5, 1.5}};  // [j][i]
    const StructuredGrid g = makeGrid("trapezoid", {2, 2, 2}, [&](int i, int j, int k) {
        return std::array<double, 3>{X[j][i], static_cast<double>(j), static_cast<double>(k)};
    });
    const CellQuality q = cellQuality(g);
    // Corners on the long edge: det = 2, on the short one: det = 1. Side edges (+-0.5, 1, 0).
    EXPECT_NEAR(q.minJacobian[0], 1.0, 1e-15);
    EXPECT_NEAR(q.scaledJacobian[0], 2.0 / std::sqrt(5.0), 1e-15);
    EXPECT_NEAR(q.orthogonality[0], 1.0 - 1.0 / std::sqrt(5.0), 1e-15);
    EXPECT_NEAR(q.aspectRatio[0], 1.5, 1e-15);  // mean lengths 1.5, sqrt(1.25), 1
    EXPECT_NEAR(q.skewness[0], 0.0, 1e-15);     // the axes (6,0,0), (0,4,0), (0,0,4) are orthogonal
}

TEST(Quality, FoldedCellIsNamedWithItsLocation) {
    // Push node (2, 2, 2) of a unit-spacing grid 1.5 along x, past node (3, 2, 2): the four
    // cells with that node on their i-min side fold. The first in (k, j, i) order is
    // cell (2, 1, 1), det = -0.5 at its corners on the pushed node's i-edge.
    StructuredGrid g = uniformGrid("wing-root", {5, 5, 5}, 1.0);
    g.at(2, 2, 2)[0] += 1.5;
    const std::vector<StructuredGrid> blocks{uniformGrid("far-field", {3, 3, 3}, 2.0), g};
    const std::vector<CellQuality> q{cellQuality(blocks[0]), cellQuality(blocks[1])};
    EXPECT_DOUBLE_EQ(q[1].minJacobian[g.cell(2, 1, 1)], -0.5);
    try {
        requirePositiveJacobians(blocks, q);
        FAIL() << "expected GeometryError";
    } catch (const GeometryError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("block 1 'wing-root'"), std::string::npos) << m;
        EXPECT_NE(m.find("cell (2, 1, 1)"), std::string::npos) << m;
        EXPECT_NE(m.find("centroid (2.6875, 1.5, 1.5)"), std::string::npos) << m;
        EXPECT_NE(m.find("-0.5"), std::string::npos) << m;
        EXPECT_NE(m.find("4 of 72 cells"), std::string::npos) << m;
    }
    const QualitySummary s = summarize(blocks, q, 3);
    EXPECT_EQ(s.cellCount, 72);
    EXPECT_EQ(s.nonPositiveJacobian, 4);
    ASSERT_EQ(s.worst.size(), 3u);
    for (const CellLocation& w : s.worst) {
        EXPECT_EQ(w.block, 1);
        EXPECT_EQ(w.blockName, "wing-root");
        EXPECT_LT(w.value, 0.0);
        EXPECT_DOUBLE_EQ(w.value, q[1].scaledJacobian[g.cell(w.cell[0], w.cell[1], w.cell[2])]);
        EXPECT_EQ(w.cell[0], 2);  // all folded cells have i = 2
    }
    EXPECT_LE(s.worst[0].value, s.worst[1].value);
    EXPECT_LE(s.worst[1].value, s.worst[2].value);
    EXPECT_DOUBLE_EQ(s.scaledJacobian.min, s.worst[0].value);
}

TEST(Quality, LeftHandedAndCollapsedBlocksAreRejected) {
    // Mirror image of a good block: every determinant is negative.
    const StructuredGrid mirrored = makeGrid("mirrored", {3, 3, 3}, [](int i, int j, int k) {
        return std::array<double, 3>{-1.0 * i, 1.0 * j, 1.0 * k};
    });
    const CellQuality qm = cellQuality(mirrored);
    expectAll(qm.minJacobian, -1.0, 1e-15);
    expectAll(qm.scaledJacobian, -1.0, 1e-15);
    EXPECT_THROW(requirePositiveJacobians({mirrored}, {qm}), GeometryError);
    EXPECT_EQ(summarize({mirrored}, {qm}).nonPositiveJacobian, 8);

    // A wedge: the k-edges at i = 0 collapse onto the axis (as on a polar singular line).
    const StructuredGrid wedge = makeGrid("wedge", {2, 2, 2}, [](int i, int j, int k) {
        return std::array<double, 3>{1.0 * i, 1.0 * j, i == 0 ? 0.0 : 1.0 * k};
    });
    const CellQuality qw = cellQuality(wedge);
    EXPECT_EQ(qw.minJacobian[0], 0.0);
    EXPECT_EQ(qw.scaledJacobian[0], 0.0);
    EXPECT_EQ(qw.orthogonality[0], 0.0);  // angle at a zero-length edge counts as worst
    EXPECT_TRUE(std::isfinite(qw.aspectRatio[0]));
    EXPECT_THROW(requirePositiveJacobians({wedge}, {qw}), GeometryError);
}

TEST(Quality, NaNCoordinatesAreNeverSilentlyAccepted) {
    StructuredGrid g = uniformGrid("nan", {3, 3, 3}, 1.0);
    g.at(1, 1, 1)[2] = std::nan("");
    const CellQuality q = cellQuality(g);
    for (std::size_t c = 0; c < q.minJacobian.size(); ++c) {
        EXPECT_TRUE(std::isnan(q.minJacobian[c]));
    }
    EXPECT_THROW(requirePositiveJacobians({g}, {q}), GeometryError);
    const QualitySummary s = summarize({g}, {q});
    EXPECT_EQ(s.nonPositiveJacobian, 8);
    EXPECT_EQ(s.scaledJacobian.nonFinite, 8);
    EXPECT_TRUE(std::isnan(s.worst.front().value));
}

TEST(Quality, SummaryStatisticsAndHistograms) {
    // Block a: 2 x 1 x 1 unit cubes; block b: one cell spanned by (1, 0, 0), (1, 2, 0), (0, 0,
    // 0.5).
    const StructuredGrid a = uniformGrid("a", {3, 2, 2}, 1.0);
    const StructuredGrid b = makeGrid("b", {2, 2, 2}, [](int i, int j, int k) {
        return std::array<double, 3>{1.0 * i + 1.0 * j, 2.0 * j, 0.5 * k};
    });
    const double r5 = std::sqrt(5.0);  // |e_j|; cos(e_i, e_j) = 1 / r5
    const std::vector<StructuredGrid> blocks{a, b};
    const std::vector<CellQuality> q{cellQuality(a), cellQuality(b)};
    EXPECT_NEAR(q[1].scaledJacobian[0], 2 / r5, 1e-15);
    const QualitySummary s = summarize(blocks, q, 10);
    EXPECT_EQ(s.cellCount, 3);
    EXPECT_EQ(s.nonPositiveJacobian, 0);
    ASSERT_EQ(s.worst.size(), 3u);  // fewer cells than asked for
    EXPECT_EQ(s.worst[0].block, 1);
    EXPECT_EQ(s.worst[0].blockName, "b");
    EXPECT_NEAR(s.worst[0].value, 2 / r5, 1e-15);
    EXPECT_NEAR(s.worst[0].centroid[0], 1.0, 1e-15);
    EXPECT_NEAR(s.worst[0].centroid[1], 1.0, 1e-15);
    EXPECT_NEAR(s.worst[0].centroid[2], 0.25, 1e-15);
    EXPECT_EQ(s.worst[1].block, 0);  // ties broken by block, then cell index
    EXPECT_EQ(s.worst[1].cell, (std::array<int, 3>{0, 0, 0}));
    EXPECT_EQ(s.worst[2].cell, (std::array<int, 3>{1, 0, 0}));

    EXPECT_NEAR(s.scaledJacobian.min, 2 / r5, 1e-15);
    EXPECT_NEAR(s.scaledJacobian.max, 1.0, 1e-15);
    EXPECT_NEAR(s.scaledJacobian.mean, (2 + 2 / r5) / 3, 1e-15);
    EXPECT_EQ(s.scaledJacobian.lo, -1.0);
    EXPECT_EQ(s.scaledJacobian.hi, 1.0);
    EXPECT_EQ(s.scaledJacobian.histogram[9],
              3);  // 0.894 and 1 (the end point goes to the last bin)
    EXPECT_NEAR(s.aspectRatio.max, 2 * r5, 1e-14);
    EXPECT_EQ(s.aspectRatio.lo, 1.0);
    EXPECT_NEAR(s.aspectRatio.hi, 2 * r5, 1e-14);
    EXPECT_EQ(s.aspectRatio.histogram[0], 2);
    EXPECT_EQ(s.aspectRatio.histogram[9], 1);
    EXPECT_NEAR(s.skewness.mean, 1 / r5 / 3, 1e-15);
    EXPECT_EQ(s.skewness.histogram[0], 2);
    EXPECT_EQ(s.skewness.histogram[4], 1);       // 0.447
    EXPECT_EQ(s.orthogonality.histogram[5], 1);  // 0.553
    EXPECT_EQ(s.orthogonality.histogram[9], 2);
    // All three cells have volume 1: a zero-width range puts them in bin 0.
    EXPECT_EQ(s.minJacobian.histogram[0], 3);
    EXPECT_EQ(s.minJacobian.lo, s.minJacobian.hi);
    for (const MetricSummary* m :
         {&s.minJacobian, &s.scaledJacobian, &s.orthogonality, &s.aspectRatio, &s.skewness}) {
        EXPECT_EQ(std::accumulate(m->histogram.begin(), m->histogram.end(), 0L), 3);
        EXPECT_EQ(m->nonFinite, 0);
    }
}

TEST(Quality, BadInputIsRejected) {
    StructuredGrid g = uniformGrid("short", {3, 3, 3}, 1.0);
    g.xyz.pop_back();
    EXPECT_THROW(cellQuality(g), GeometryError);
    const StructuredGrid flat = uniformGrid("flat", {3, 3, 1}, 1.0);
    EXPECT_THROW(cellQuality(flat), GeometryError);
    const StructuredGrid ok = uniformGrid("ok", {3, 3, 3}, 1.0);
    EXPECT_THROW(summarize({ok, ok}, {cellQuality(ok)}), Error);
    CellQuality truncated = cellQuality(ok);
    truncated.skewness.pop_back();
    EXPECT_THROW(requirePositiveJacobians({ok}, {truncated}), Error);
}

TEST(Quality, LargestSpacingJumpIsFoundWithItsNode) {
    // A uniform block has no jump; a second block grows its k spacing geometrically by 1.5 up to
    // k = 4 and then jumps: z = 0, 1, 2.5, 4.75, 8.125, then + 40.5 (12 x 3.375).
    EXPECT_EQ(largestSpacingJump({uniformGrid("u", {4, 3, 5}, 0.5)}).ratio, 1.0);
    const double z[6] = {0, 1, 2.5, 4.75, 8.125, 48.625};
    const StructuredGrid graded = makeGrid("graded", {3, 2, 6}, [&](int i, int j, int k) {
        return std::array<double, 3>{0.1 * i, 0.1 * j, z[k]};
    });
    const SpacingJump s = largestSpacingJump({uniformGrid("u", {3, 3, 3}, 1.0), graded});
    EXPECT_NEAR(s.ratio, 12.0, 1e-12);
    EXPECT_EQ(s.block, 1);
    EXPECT_EQ(s.blockName, "graded");
    EXPECT_EQ(s.direction, 2);
    EXPECT_EQ(s.node[2], 4);
    EXPECT_DOUBLE_EQ(s.x[2], 8.125);
    // Without the last node the largest jump is the geometric ratio.
    const StructuredGrid smooth = makeGrid("smooth", {2, 2, 5}, [&](int i, int j, int k) {
        return std::array<double, 3>{0.1 * i, 0.1 * j, z[k]};
    });
    EXPECT_NEAR(largestSpacingJump({smooth}).ratio, 1.5, 1e-12);
    // A collapsed line (all nodes on the axis) is skipped; one zero edge next to a finite one is
    // an infinite jump.
    StructuredGrid axis = makeGrid("axis", {2, 2, 3}, [&](int i, int j, int k) {
        return std::array<double, 3>{0.1 * i, 0.1 * j, i + j > 0 ? 1.0 * k : 0.0};
    });
    EXPECT_EQ(largestSpacingJump({axis}).ratio, 1.0);
    axis.at(1, 0, 1)[2] = 0.0;  // node k = 1 on top of k = 0 on the line (1, 0, .)
    EXPECT_TRUE(std::isinf(largestSpacingJump({axis}).ratio));
    StructuredGrid shortGrid = uniformGrid("short", {3, 3, 3}, 1.0);
    shortGrid.xyz.pop_back();
    EXPECT_THROW(largestSpacingJump({shortGrid}), Error);
}

TEST(Quality, SharpestWallBendFindsAFoldAndTheTurnOfACurvedWall) {
    // A cylinder wall (face k = 0) with nodes every 10 degrees: interior nodes have the exact
    // radial normal (central differences), so neighbours turn by 10 degrees; the edge nodes'
    // one-sided normals by 5.
    const StructuredGrid cylinder = makeGrid("cylinder", {7, 3, 3}, [](int i, int j, int k) {
        const double phi = i * 10.0 * std::numbers::pi / 180.0, r = 1.0 + 0.1 * k;
        return std::array<double, 3>{r * std::cos(phi), r * std::sin(phi), 0.2 * j};
    });
    std::array<bool, 6> kMin{false, false, false, false, true, false};
    const WallBend c = sharpestWallBend({cylinder}, {kMin});
    EXPECT_NEAR(c.degrees, 10.0, 1e-9);
    EXPECT_EQ(c.block, 0);
    EXPECT_EQ(c.blockName, "cylinder");
    EXPECT_EQ(c.node[2], 0);
    EXPECT_EQ(c.neighbour[0], c.node[0] + 1);  // the pair lies along i, around the cylinder
    EXPECT_GE(c.node[0], 1);
    EXPECT_LE(c.node[0], 4);
    // The same block without a wall face, and the radial faces (flat planes) as walls: no bend.
    EXPECT_EQ(sharpestWallBend({cylinder}, {{false, false, false, false, false, false}}).degrees, 0.0);
    EXPECT_NEAR(sharpestWallBend({cylinder}, {{true, true, false, false, false, false}}).degrees, 0.0, 1e-9);

    // A plane folded by 60 degrees at i = 3 (unit spacing on both sides) in the second block:
    // the apex node's normal is halfway, so the wall turns by 30 degrees twice, at nodes 2 and 3.
    const double theta = 60.0 * std::numbers::pi / 180.0;
    const StructuredGrid folded = makeGrid("folded", {7, 2, 2}, [&](int i, int j, int k) {
        const double x = i <= 3 ? i : 3.0 + (i - 3) * std::cos(theta), z = i <= 3 ? 0.0 : (i - 3) * std::sin(theta);
        return std::array<double, 3>{x - 0.1 * k * (i <= 3 ? 0.0 : std::sin(theta)), 0.5 * j, z + 0.1 * k};
    });
    const WallBend f = sharpestWallBend({cylinder, folded}, {kMin, kMin});
    EXPECT_NEAR(f.degrees, 30.0, 1e-9);
    EXPECT_EQ(f.block, 1);
    EXPECT_TRUE(f.node[0] == 2 || f.node[0] == 3) << f.node[0];
    EXPECT_DOUBLE_EQ(f.x[0], f.node[0]);

    EXPECT_THROW(sharpestWallBend({cylinder, folded}, {kMin}), Error);
}

TEST(Quality, WallBendSmoothMaxBoundsTheSharpestBendAndItsGradientIsExact) {
    // A wavy wall (face j = max of the second block, face k = 0 of the first): bends of a few
    // to tens of degrees, no symmetry that could hide a wrong term.
    const StructuredGrid a = makeGrid("a", {6, 5, 3}, [](int i, int j, int k) {
        const double x = 0.3 * i, y = 0.25 * j;
        return std::array<double, 3>{x, y + 0.05 * x * x, 0.4 * std::sin(2.1 * x + 0.7 * y) + 0.2 * k};
    });
    const StructuredGrid b = makeGrid("b", {5, 4, 4}, [](int i, int j, int k) {
        const double x = 0.35 * i, z = 0.3 * k;
        return std::array<double, 3>{x, 0.2 * j + 0.25 * std::cos(1.7 * x - 0.9 * z) * (j == 3 ? 1.0 : 0.3), z + 0.02 * x * z};
    });
    const std::vector<StructuredGrid> blocks{a, b};
    const std::vector<std::array<bool, 6>> walls{{false, false, false, false, true, false},
                                                 {false, false, false, true, false, false}};
    const WallBend sharpest = sharpestWallBend(blocks, walls);
    ASSERT_GT(sharpest.degrees, 5.0);
    const double rho = 1000;
    std::vector<std::vector<double>> grad;
    const double smooth = wallBendSmoothMax(blocks, walls, rho, &grad);
    // An upper bound within log(pairs) / rho of the largest 1 - cos.
    const double pairs = 4 * 5 + 5 * 4 + 3 * 4 + 4 * 3;  // (ni-1) nj + ni (nj-1) per face
    const double cosTop = std::cos(sharpest.degrees * std::numbers::pi / 180);
    const double cosSmooth = std::cos(smooth * std::numbers::pi / 180);
    EXPECT_GE(smooth, sharpest.degrees - 1e-9);
    EXPECT_LE((1 - cosSmooth) - (1 - cosTop), std::log(pairs) / rho + 1e-12);
    // Every coordinate's derivative against complex step.
    std::vector<std::vector<std::complex<double>>> z(2);
    for (int k = 0; k < 2; ++k) z[k].assign(blocks[k].xyz.begin(), blocks[k].xyz.end());
    EXPECT_NEAR(wallBendSmoothMax(blocks, z, walls, rho).real(), smooth, 1e-12);
    const double h = 1e-30;
    double worst = 0, largest = 0;
    int nonzero = 0;
    for (int k = 0; k < 2; ++k) {
        for (std::size_t c = 0; c < z[k].size(); ++c) {
            z[k][c] += std::complex<double>(0, h);
            const double cs = wallBendSmoothMax(blocks, z, walls, rho).imag() / h;
            z[k][c] -= std::complex<double>(0, h);
            worst = std::max(worst, std::abs(cs - grad[k][c]));
            largest = std::max(largest, std::abs(cs));
            if (grad[k][c] != 0) ++nonzero;
        }
    }
    EXPECT_GT(largest, 1.0);
    EXPECT_LT(worst, 1e-10 * largest) << worst << " of " << largest;
    EXPECT_GT(nonzero, 40);
    // Interior nodes off the walls have no derivative.
    EXPECT_EQ(grad[0][3 * a.node(2, 2, 2)], 0.0);
    // A flat wall (12 pairs, all s = 0): the bound's own margin, acos(1 - log(12) / rho), and a
    // zero gradient (s is smallest there).
    std::vector<std::vector<double>> flat;
    EXPECT_NEAR(wallBendSmoothMax({uniformGrid("u", {3, 3, 3}, 1.0)}, {{false, false, false, false, true, false}}, rho, &flat),
                std::acos(1 - std::log(12.0) / rho) * 180 / std::numbers::pi, 1e-9);
    for (double v : flat[0]) EXPECT_NEAR(v, 0.0, 1e-12);
}

// Timing on the paper's grid size (900,000 nodes). Run with --gtest_also_run_disabled_tests.
TEST(Quality, DISABLED_Timing900kNodes) {
    std::vector<StructuredGrid> blocks{makeGrid("big", {100, 100, 90}, [](int i, int j, int k) {
        const double r = 1.0 + 0.01 * i, t = 0.015 * j;
        return std::array<double, 3>{r * std::cos(t), r * std::sin(t), 0.01 * k};
    })};
    const StructuredGrid& g = blocks[0];
    std::vector<CellQuality> q{cellQuality(g)};  // warm-up (page faults)
    const int reps = 5;
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) q[0] = cellQuality(g);
    const auto t1 = std::chrono::steady_clock::now();
    const QualitySummary s = summarize(blocks, q);
    const auto t2 = std::chrono::steady_clock::now();
    std::printf("cellQuality, %ld cells: %.2f ms; summarize: %.2f ms\n", g.cellCount(),
                std::chrono::duration<double, std::milli>(t1 - t0).count() / reps,
                std::chrono::duration<double, std::milli>(t2 - t1).count());
    EXPECT_EQ(s.nonPositiveJacobian, 0);
}

// The optimizer's grid-validity constraint: the smooth minimum of log(corner Jacobian / baseline's)
// is the exact minimum within log(corners)/rho, 0 for the baseline itself, -inf for a folded
// cell, and its gradient matches centred differences.
TEST(Quality, CornerRatioSmoothMinBoundsTheMinimumAndHasItsGradient) {
    const std::vector<StructuredGrid> base{uniformGrid("a", {4, 3, 3}, 0.5), uniformGrid("b", {3, 3, 2}, 0.25)};
    const double rho = 20;
    EXPECT_NEAR(cornerRatioSmoothMin(base, base, rho), -std::log(8.0 * (3 * 2 * 2 + 2 * 2 * 1)) / rho, 1e-14);
    std::vector<StructuredGrid> moved = base;
    for (StructuredGrid& g : moved) {
        for (std::size_t n = 0; n < g.xyz.size(); ++n) g.xyz[n] += 0.03 * std::sin(1.7 * static_cast<double>(n) + 0.3);
    }
    std::vector<std::vector<double>> grad;
    const double ks = cornerRatioSmoothMin(moved, base, rho, &grad);
    // The exact minimum, from cellQuality-style determinants: KS lies within log(N)/rho below it.
    double exactMin = 1e300;
    for (std::size_t b = 0; b < moved.size(); ++b) {
        const CellQuality q = cellQuality(moved[b]), q0 = cellQuality(base[b]);
        for (std::size_t c = 0; c < q.minJacobian.size(); ++c) exactMin = std::min(exactMin, std::log(q.minJacobian[c] / q0.minJacobian[c]));
    }
    EXPECT_LE(ks, exactMin + 1e-12);
    EXPECT_GE(ks, exactMin - std::log(8.0 * 16) / rho);
    ASSERT_EQ(grad.size(), 2u);
    double exact = 0, fd = 0;
    const double h = 1e-6;
    for (std::size_t b = 0; b < moved.size(); ++b) {
        for (std::size_t n = 0; n < moved[b].xyz.size(); ++n) {
            const double dir = std::cos(0.9 * static_cast<double>(n + 7 * b));
            exact += grad[b][n] * dir;
        }
    }
    auto along = [&](double s) {
        std::vector<StructuredGrid> g = moved;
        for (std::size_t b = 0; b < g.size(); ++b) {
            for (std::size_t n = 0; n < g[b].xyz.size(); ++n) g[b].xyz[n] += s * std::cos(0.9 * static_cast<double>(n + 7 * b));
        }
        return cornerRatioSmoothMin(g, base, rho);
    };
    fd = (along(h) - along(-h)) / (2 * h);
    EXPECT_NEAR(exact, fd, 1e-7 * std::abs(fd));
    // Folded: a node pushed through its neighbour.
    std::vector<StructuredGrid> folded = base;
    folded[0].at(1, 1, 1)[0] += 0.8;
    EXPECT_EQ(cornerRatioSmoothMin(folded, base, rho, &grad), -std::numeric_limits<double>::infinity());
    EXPECT_TRUE(grad.empty());
    EXPECT_THROW((void)cornerRatioSmoothMin({base[0]}, base, rho), Error);
}
