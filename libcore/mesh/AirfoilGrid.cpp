#include "mesh/AirfoilGrid.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "common/Error.h"

namespace aero::mesh {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct NacaShape {
    double camber = 0;    // m, fraction of chord
    double position = 0;  // p, fraction of chord
    double thickness = 0; // t, fraction of chord
};

NacaShape parseNaca(const std::string& naca) {
    bool ok = naca.size() == 4;
    for (char ch : naca) ok = ok && std::isdigit(static_cast<unsigned char>(ch));
    if (!ok) throw CaseError("airfoil.naca: '" + naca + "' is not a NACA 4-digit designation");
    NacaShape s;
    s.camber = (naca[0] - '0') / 100.0;
    s.position = (naca[1] - '0') / 10.0;
    s.thickness = std::stoi(naca.substr(2)) / 100.0;
    if (s.thickness <= 0) throw CaseError("airfoil.naca: '" + naca + "' has zero thickness");
    if (s.camber > 0 && s.position <= 0) {
        throw CaseError("airfoil.naca: '" + naca + "' has camber but no camber position");
    }
    return s;
}

// The signed root r = cos(sigma / 2) is sqrt(x) on the upper surface and -sqrt(x) on the lower
// one, so the profile is a smooth function of sigma through the leading edge.
std::array<double, 2> profilePoint(const NacaShape& s, double sigma) {
    const double r = std::cos(0.5 * sigma);
    const double x = r * r;
    const double side = r >= 0 ? 1.0 : -1.0;
    const double poly = x * (-0.1260 + x * (-0.3516 + x * (0.2843 + x * -0.1036)));
    const double yt = 5.0 * s.thickness * (0.2969 * r + side * poly);  // signed half-thickness
    double yc = 0, slope = 0;
    if (s.camber > 0) {
        const double m = s.camber, p = s.position;
        if (x < p) {
            yc = m / (p * p) * (2 * p * x - x * x);
            slope = 2 * m / (p * p) * (p - x);
        } else {
            yc = m / ((1 - p) * (1 - p)) * (1 - 2 * p + 2 * p * x - x * x);
            slope = 2 * m / ((1 - p) * (1 - p)) * (p - x);
        }
    }
    const double theta = std::atan(slope);
    return {x - yt * std::sin(theta), yc + yt * std::cos(theta)};
}

// Unit tangent d(point)/d(sigma) (counterclockwise), by central differences of the analytic
// profile. At the trailing edge (sigma = 0 or 2 pi) dx/dsigma vanishes, so the one-sided limit
// direction is taken from a short secant instead (its error is of the order of the curvature
// times its length, 2.5e-7 chords).
std::array<double, 2> profileTangent(const NacaShape& s, double sigma) {
    std::array<double, 2> t;
    if (sigma <= 0 || sigma >= 2 * kPi) {
        const double h = 1e-3;
        const auto a = profilePoint(s, sigma <= 0 ? 0.0 : 2 * kPi);
        const auto b = profilePoint(s, sigma <= 0 ? h : 2 * kPi - h);
        const double sign = sigma <= 0 ? 1.0 : -1.0;
        for (int d = 0; d < 2; ++d) t[d] = sign * (b[d] - a[d]);
    } else {
        const double h = 1e-6;
        const auto a = profilePoint(s, sigma - h), b = profilePoint(s, sigma + h);
        for (int d = 0; d < 2; ++d) t[d] = b[d] - a[d];
    }
    const double len = std::hypot(t[0], t[1]);
    return {t[0] / len, t[1] / len};
}

// Ratio r of the geometric distances s_j = ds (r^j - 1) / (r - 1), j = 0 .. n - 1, with
// s_{n-1} = length (bisection; requires ds (n - 1) < length).
double stretchingRatio(double ds, int n, double length) {
    double lo = 1.0, hi = 2.0;
    auto reach = [&](double r) { return ds * (std::pow(r, n - 1) - 1.0) / (r - 1.0); };
    while (reach(hi) < length) hi *= 2.0;
    for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        (reach(mid) < length ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

void require(bool ok, const std::string& key, const std::string& what) {
    if (!ok) throw CaseError("airfoil." + key + ": " + what);
}

}  // namespace

std::array<double, 2> nacaPoint(const std::string& naca, double sigma) {
    return profilePoint(parseNaca(naca), sigma);
}

AirfoilGrid makeAirfoilGrid(const AirfoilGridOptions& o) {
    const NacaShape shape = parseNaca(o.naca);
    require(o.aroundNodes >= 9 && o.aroundNodes % 2 == 1, "aroundNodes", "must be odd and >= 9");
    require(o.normalNodes >= 3, "normalNodes", "must be >= 3");
    require(o.spanNodes >= 2, "spanNodes", "must be >= 2");
    require(o.span > 0, "span", "must be > 0");
    require(o.farfieldRadius > 2, "farfieldRadius", "must be > 2 chords");
    require(o.blendLength > 0, "blendLength", "must be > 0");
    require(o.wallSpacing > 0 && o.wallSpacing * (o.normalNodes - 1) < o.farfieldRadius,
            "wallSpacing", "must be > 0 and below farfieldRadius / (normalNodes - 1)");

    const int around = o.aroundNodes, nj = o.normalNodes, nk = o.spanNodes;
    const double R = o.farfieldRadius;
    const double ratio = stretchingRatio(o.wallSpacing, nj, R);
    std::vector<double> dist(nj);  // nominal distances, dist[nj - 1] = R
    for (int j = 0; j < nj; ++j) dist[j] = o.wallSpacing * (std::pow(ratio, j) - 1.0) / (ratio - 1.0);

    // The X-Z plane of the grid, column by column around the airfoil: plane[2 * (I * nj + j)].
    // Column around - 1 (the trailing edge again) is a copy of column 0.
    std::vector<double> plane(2 * static_cast<std::size_t>(around) * nj);
    for (int I = 0; I < around - 1; ++I) {
        const double sigma = 2 * kPi * I / (around - 1);
        const auto S = profilePoint(shape, sigma);
        std::array<double, 2> N;
        if (I == 0) {
            // Sharp trailing edge: the bisector of the two sides' normals.
            const auto tu = profileTangent(shape, 0.0), tl = profileTangent(shape, 2 * kPi);
            N = {tu[1] + tl[1], -tu[0] - tl[0]};
            const double len = std::hypot(N[0], N[1]);
            N = {N[0] / len, N[1] / len};
        } else {
            const auto t = profileTangent(shape, sigma);
            N = {t[1], -t[0]};  // right of the counterclockwise tangent: into the fluid
        }
        const std::array<double, 2> C = {0.5 + R * std::cos(sigma), R * std::sin(sigma)};
        const double L = std::hypot(C[0] - S[0], C[1] - S[1]);
        const std::array<double, 2> E = {(C[0] - S[0]) / L, (C[1] - S[1]) / L};
        const double wEnd = 1.0 - std::exp(-L / o.blendLength);
        for (int j = 0; j < nj; ++j) {
            double* p = &plane[2 * (static_cast<std::size_t>(I) * nj + j)];
            if (j == nj - 1) {
                p[0] = C[0];
                p[1] = C[1];
                continue;
            }
            const double s = dist[j] * L / R;
            const double w = (1.0 - std::exp(-s / o.blendLength)) / wEnd;
            p[0] = S[0] + s * ((1 - w) * N[0] + w * E[0]);
            p[1] = S[1] + s * ((1 - w) * N[1] + w * E[1]);
        }
    }
    std::copy(plane.begin(), plane.begin() + 2 * nj, plane.end() - 2 * nj);

    const int ni = (around + 1) / 2;
    AirfoilGrid g;
    g.blocks.resize(2);
    g.faces.resize(2);
    for (int b = 0; b < 2; ++b) {
        StructuredGrid& blk = g.blocks[b];
        blk.name = b == 0 ? "upper" : "lower";
        blk.dims = {ni, nj, nk};
        blk.xyz.resize(3 * static_cast<std::size_t>(blk.nodeCount()));
        for (int k = 0; k < nk; ++k) {
            const double y = o.span * k / (nk - 1);
            for (int j = 0; j < nj; ++j) {
                for (int i = 0; i < ni; ++i) {
                    const int I = b == 0 ? i : ni - 1 + i;
                    const double* p = &plane[2 * (static_cast<std::size_t>(I) * nj + j)];
                    double* x = blk.at(i, j, k);
                    x[0] = p[0];
                    x[1] = y;
                    x[2] = p[1];
                }
            }
        }
        auto& f = g.faces[b];
        f[static_cast<int>(Face::JMin)].kind = BoundaryKind::Wall;
        f[static_cast<int>(Face::JMax)].kind = BoundaryKind::Farfield;
        f[static_cast<int>(Face::KMin)].kind = BoundaryKind::Symmetry;
        f[static_cast<int>(Face::KMax)].kind = BoundaryKind::Symmetry;
    }
    // Upper i = 0 (trailing-edge cut) meets lower i = max; upper i = max (leading-edge cut) meets
    // lower i = 0.
    g.faces[0][0] = {BoundaryKind::Interface, 1, 1};
    g.faces[0][1] = {BoundaryKind::Interface, 1, 0};
    g.faces[1][0] = {BoundaryKind::Interface, 0, 1};
    g.faces[1][1] = {BoundaryKind::Interface, 0, 0};
    const StructuredGrid& up = g.blocks[0];
    const StructuredGrid& lo = g.blocks[1];
    g.interfaceNodes.reserve(2 * static_cast<std::size_t>(nj) * nk);
    for (int k = 0; k < nk; ++k) {
        for (int j = 0; j < nj; ++j) {
            g.interfaceNodes.push_back({0, up.node(0, j, k), 1, lo.node(ni - 1, j, k)});
            g.interfaceNodes.push_back({0, up.node(ni - 1, j, k), 1, lo.node(0, j, k)});
        }
    }
    return g;
}

}  // namespace aero::mesh
