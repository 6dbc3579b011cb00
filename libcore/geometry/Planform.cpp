#include "geometry/Planform.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "common/Error.h"
#include "nurbs/Basis.h"
#include "nurbs/Surface.h"

namespace aero::geometry {

namespace {

constexpr int kSamplesPerPatch = 64;  // parameter intervals per direction, at most ...
constexpr long kSampleBudget = 1L << 21;  // ... and about this many samples over all patches (48 MB)
constexpr int kPixels = 1024;          // raster cells along the shadow's longer side

// Every knot span cut into equal parts, at least `total` intervals in all (nurbs::spanSamples);
// a patch of more than 1,024 spans is sampled uniformly at 1,024 intervals.
std::vector<double> parameterSamples(const std::vector<double>& knots, int total) {
    const int spans = std::max(1, nurbs::nonEmptySpans(knots));
    if (spans > 1024) {  // thousands of knot spans: uniform samples (the knots' kinks may fall between)
        std::vector<double> t(1025);
        for (int i = 0; i <= 1024; ++i) t[i] = knots.front() + (knots.back() - knots.front()) * i / 1024;
        return t;
    }
    return nurbs::spanSamples(knots, std::max(1, (total + spans - 1) / spans));
}

struct Sampled {
    std::vector<double> us, vs, xyz;  // xyz: 3 per sample, u fastest
};

// The largest y near sample (i, j) of patch s: the parameter window of its neighbours sampled
// 17 x 17, then around the best of those, three times (each round shrinks the window 8-fold).
double refineLargestY(const nurbs::Surface<double>& s, const Sampled& g, int i, int j, double best) {
    const int nu = static_cast<int>(g.us.size()), nv = static_cast<int>(g.vs.size());
    double u0 = g.us[std::max(0, i - 1)], u1 = g.us[std::min(nu - 1, i + 1)];
    double v0 = g.vs[std::max(0, j - 1)], v1 = g.vs[std::min(nv - 1, j + 1)];
    constexpr int n = 17;
    std::vector<double> us(n), vs(n), xyz(3 * n * n);
    for (int round = 0; round < 3; ++round) {
        for (int k = 0; k < n; ++k) {
            us[k] = u0 + (u1 - u0) * k / (n - 1);
            vs[k] = v0 + (v1 - v0) * k / (n - 1);
        }
        nurbs::sampleGrid(s, us, vs, xyz.data());
        int bi = 0, bj = 0;
        double b = -std::numeric_limits<double>::infinity();
        for (int b2 = 0; b2 < n; ++b2) {
            for (int a = 0; a < n; ++a) {
                const double y = xyz[3 * (a + n * b2) + 1];
                if (y > b) {
                    b = y;
                    bi = a;
                    bj = b2;
                }
            }
        }
        best = std::max(best, b);
        const double du = (u1 - u0) / (n - 1), dv = (v1 - v0) / (n - 1);
        const double cu = us[bi], cv = vs[bj];
        u0 = std::max(g.us.front(), cu - du);
        u1 = std::min(g.us.back(), cu + du);
        v0 = std::max(g.vs.front(), cv - dv);
        v1 = std::min(g.vs.back(), cv + dv);
    }
    return best;
}

// Marks the raster cells whose centres lie in the triangle (a, b, c) (x, y each; edges
// inclusive, so cells on an edge shared by two triangles are not lost between them).
void fillTriangle(const double* a, const double* b, const double* c, double x0, double y0, double h, int nx, int ny,
                  std::vector<char>& covered) {
    const double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (area == 0 || !std::isfinite(area)) return;
    const double s = area > 0 ? 1.0 : -1.0;
    const double xmin = std::min({a[0], b[0], c[0]}), xmax = std::max({a[0], b[0], c[0]});
    const double ymin = std::min({a[1], b[1], c[1]}), ymax = std::max({a[1], b[1], c[1]});
    const int i0 = std::max(0, static_cast<int>(std::ceil((xmin - x0) / h - 0.5)));
    const int i1 = std::min(nx - 1, static_cast<int>(std::floor((xmax - x0) / h - 0.5)));
    const int j0 = std::max(0, static_cast<int>(std::ceil((ymin - y0) / h - 0.5)));
    const int j1 = std::min(ny - 1, static_cast<int>(std::floor((ymax - y0) / h - 0.5)));
    auto edge = [s](const double* p, const double* q, double x, double y) {
        return s * ((q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]));
    };
    for (int j = j0; j <= j1; ++j) {
        const double y = y0 + (j + 0.5) * h;
        for (int i = i0; i <= i1; ++i) {
            const double x = x0 + (i + 0.5) * h;
            if (edge(a, b, x, y) >= 0 && edge(b, c, x, y) >= 0 && edge(c, a, x, y) >= 0) {
                covered[static_cast<std::size_t>(j) * nx + i] = 1;
            }
        }
    }
}

}  // namespace

Planform planform(const PatchSet& set) {
    requireUntrimmed(set, "the planform");
    if (set.patches.empty()) throw GeometryError("the planform of '" + set.source + "': no patches");
    std::vector<Sampled> grids(set.patches.size());
    // A file of thousands of patches gets fewer samples per patch (at least 8 intervals each).
    const int perPatch = std::clamp(
        static_cast<int>(std::sqrt(static_cast<double>(kSampleBudget) / static_cast<double>(set.patches.size()))), 8,
        kSamplesPerPatch);
    double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
    double zmin = xmin, zmax = -xmin;
    int bestPatch = 0, bestI = 0, bestJ = 0;
    for (std::size_t p = 0; p < set.patches.size(); ++p) {
        const nurbs::Surface<double>& s = set.patches[p];
        Sampled& g = grids[p];
        g.us = parameterSamples(s.knotsU, perPatch);
        g.vs = parameterSamples(s.knotsV, perPatch);
        g.xyz.resize(3 * g.us.size() * g.vs.size());
        nurbs::sampleGrid(s, g.us, g.vs, g.xyz.data());
        const int nu = static_cast<int>(g.us.size());
        for (std::size_t k = 0; k < g.xyz.size() / 3; ++k) {
            const double x = g.xyz[3 * k], y = g.xyz[3 * k + 1], z = g.xyz[3 * k + 2];
            if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
                throw GeometryError("the planform: " + set.describe(static_cast<int>(p)) +
                                    " evaluates to a non-finite point");
            }
            xmin = std::min(xmin, x);
            xmax = std::max(xmax, x);
            zmin = std::min(zmin, z);
            zmax = std::max(zmax, z);
            ymin = std::min(ymin, y);
            if (y > ymax) {
                ymax = y;
                bestPatch = static_cast<int>(p);
                bestI = static_cast<int>(k % nu);
                bestJ = static_cast<int>(k / nu);
            }
        }
    }
    Planform f;
    const double size = std::max({xmax - xmin, ymax - ymin, zmax - zmin});
    ymax = refineLargestY(set.patches[bestPatch], grids[bestPatch], bestI, bestJ, ymax);
    f.halfBody = ymin >= -1e-9 * size;
    f.halfSpan = f.halfBody ? ymax : 0.5 * (ymax - ymin);

    // The shadow: every sampled quadrilateral as two triangles on a square raster over the
    // extent (cells along the longer side: kPixels).
    const double h = std::max(xmax - xmin, ymax - ymin) / kPixels;
    if (!(h > 0)) return f;  // a shape without extent in x or y casts no shadow
    const int nx = std::max(1, static_cast<int>(std::ceil((xmax - xmin) / h)));
    const int ny = std::max(1, static_cast<int>(std::ceil((ymax - ymin) / h)));
    std::vector<char> covered(static_cast<std::size_t>(nx) * ny, 0);
    for (const Sampled& g : grids) {
        const int nu = static_cast<int>(g.us.size()), nv = static_cast<int>(g.vs.size());
        for (int j = 0; j + 1 < nv; ++j) {
            for (int i = 0; i + 1 < nu; ++i) {
                const double* p00 = &g.xyz[3 * (i + nu * j)];
                const double* p10 = &g.xyz[3 * (i + 1 + nu * j)];
                const double* p01 = &g.xyz[3 * (i + nu * (j + 1))];
                const double* p11 = &g.xyz[3 * (i + 1 + nu * (j + 1))];
                fillTriangle(p00, p10, p11, xmin, ymin, h, nx, ny, covered);
                fillTriangle(p00, p11, p01, xmin, ymin, h, nx, ny, covered);
            }
        }
    }
    long cells = 0;
    for (char c : covered) cells += c;
    f.projectedArea = static_cast<double>(cells) * h * h;
    if (f.projectedArea > 0) {
        f.aspectRatio = f.halfBody ? 2 * f.halfSpan * f.halfSpan / f.projectedArea
                                   : 4 * f.halfSpan * f.halfSpan / f.projectedArea;
    }
    return f;
}

}  // namespace aero::geometry
