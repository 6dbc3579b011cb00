#include "geometry/HalfSphere.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include "common/Error.h"
#include "nurbs/Basis.h"

namespace aero::geometry {

using nurbs::Vec3;

namespace {

// The half-sphere is tiled like a cube-sphere: the +Y face of the cube (2x2 patches) and the
// y >= 0 halves of the +-X and +-Z faces (2x2 patches each): 4 + 4*4 = 20 patches. On each
// cube face, points are n + tan(a) t1 + tan(b) t2 with equiangular coordinates (a, b), so
// patch edges are great-circle arcs and neighbouring patches parameterize a shared edge alike.
struct Face {
    Vec3<double> n, t1, t2;  // t1 x t2 = n: (u, v) = (t1, t2) gives outward normals
    double a0, a1, b0, b1;   // angle ranges on this face (the y >= 0 half)
    const char* name;
};

constexpr double kQ = std::numbers::pi / 4;

const Face kFaces[5] = {
    {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}, -kQ, kQ, -kQ, kQ, "Y+"},
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0, kQ, -kQ, kQ, "X+"},
    {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}, -kQ, kQ, 0, kQ, "X-"},
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}, -kQ, kQ, 0, kQ, "Z+"},
    {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}, 0, kQ, -kQ, kQ, "Z-"},
};

// tan with exact values at the patch corners, so a cube point computed from two faces is the
// same permutation of the same numbers.
double tanExact(double a) {
    if (a == kQ) return 1.0;
    if (a == -kQ) return -1.0;
    if (a == 0.0) return 0.0;
    return std::tan(a);
}

Vec3<double> spherePoint(const Face& f, double a, double b, double r) {
    const Vec3<double> c = f.n + tanExact(a) * f.t1 + tanExact(b) * f.t2;
    // Norm summed in a canonical (sorted) order: identical on every face.
    std::array<double, 3> sq = {c[0] * c[0], c[1] * c[1], c[2] * c[2]};
    std::sort(sq.begin(), sq.end());
    return (r / std::sqrt((sq[0] + sq[1]) + sq[2])) * c;
}

// Key of a point for edge sharing (rounded coordinates).
std::array<long long, 3> pointKey(const Vec3<double>& p) {
    return {std::llround(p[0] * 1e9), std::llround(p[1] * 1e9), std::llround(p[2] * 1e9)};
}

// Least-squares fit of n control points of a degree-p B-spline (uniform knots) to the
// samples X(t_s), t_s uniform in [0,1], with the end points interpolated.
std::vector<Vec3<double>> fitCurve(const std::vector<Vec3<double>>& samples, int p, int n) {
    const std::vector<double> U = nurbs::uniformKnots(p, n);
    const int m = static_cast<int>(samples.size());
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, n - 2);
    Eigen::MatrixXd rhs(m, 3);
    double N[nurbs::kMaxDegree + 1];
    for (int s = 0; s < m; ++s) {
        const double t = static_cast<double>(s) / (m - 1);
        const int span = nurbs::findSpan(U, p, n, t);
        nurbs::basisFunctions(U, p, span, t, N);
        Vec3<double> r = samples[s];
        for (int j = 0; j <= p; ++j) {
            const int i = span - p + j;
            if (i == 0) {
                r -= N[j] * samples.front();
            } else if (i == n - 1) {
                r -= N[j] * samples.back();
            } else {
                A(s, i - 1) = N[j];
            }
        }
        rhs.row(s) = r.transpose();
    }
    const Eigen::MatrixXd X = A.colPivHouseholderQr().solve(rhs);
    std::vector<Vec3<double>> cp(n);
    cp.front() = samples.front();
    cp.back() = samples.back();
    for (int i = 1; i < n - 1; ++i) cp[i] = X.row(i - 1).transpose();
    return cp;
}

}  // namespace

PatchSet makeHalfSphere(const HalfSphereOptions& o) {
    const int p = o.degree, n = o.controlPoints;
    if (n < p + 1 || p < 1 || p > nurbs::kMaxDegree || !(o.radius > 0)) {
        throw GeometryError("half-sphere: invalid options (radius " + std::to_string(o.radius) + ", degree " +
                            std::to_string(p) + ", control points " + std::to_string(n) + ")");
    }
    constexpr int kEdgeSamples = 81, kSurfSamples = 41;
    PatchSet set;
    set.source = "half-sphere sample";
    // Shared edges are fitted once and copied, so both neighbours hold identical numbers.
    std::map<std::pair<std::array<long long, 3>, std::array<long long, 3>>, std::vector<Vec3<double>>> edgeCache;
    auto edgeNet = [&](const Face& f, double a0, double b0, double a1, double b1) {
        const Vec3<double> P0 = spherePoint(f, a0, b0, o.radius), P1 = spherePoint(f, a1, b1, o.radius);
        const auto k0 = pointKey(P0), k1 = pointKey(P1);
        if (auto it = edgeCache.find({k1, k0}); it != edgeCache.end()) {
            return std::vector<Vec3<double>>(it->second.rbegin(), it->second.rend());
        }
        if (auto it = edgeCache.find({k0, k1}); it != edgeCache.end()) return it->second;
        std::vector<Vec3<double>> samples(kEdgeSamples);
        for (int s = 0; s < kEdgeSamples; ++s) {
            const double t = static_cast<double>(s) / (kEdgeSamples - 1);
            samples[s] = spherePoint(f, a0 + t * (a1 - a0), b0 + t * (b1 - b0), o.radius);
        }
        std::vector<Vec3<double>> cp = fitCurve(samples, p, n);
        // Points on the symmetry plane stay exactly on it.
        if (P0[1] == 0.0 && P1[1] == 0.0) {
            for (auto& c : cp) c[1] = 0.0;
        }
        edgeCache[{k0, k1}] = cp;
        return cp;
    };

    const std::vector<double> U = nurbs::uniformKnots(p, n);
    for (const Face& f : kFaces) {
        for (int jb = 0; jb < 2; ++jb) {
            for (int ia = 0; ia < 2; ++ia) {
                const double a0 = f.a0 + (f.a1 - f.a0) * ia / 2, a1 = f.a0 + (f.a1 - f.a0) * (ia + 1) / 2;
                const double b0 = f.b0 + (f.b1 - f.b0) * jb / 2, b1 = f.b0 + (f.b1 - f.b0) * (jb + 1) / 2;
                Patch patch;
                patch.degreeU = patch.degreeV = p;
                patch.countU = patch.countV = n;
                patch.knotsU = patch.knotsV = U;
                std::vector<Vec3<double>> net(n * n);
                // Boundary rows and columns from the shared edge fits (u along a, v along b).
                const auto e0 = edgeNet(f, a0, b0, a1, b0), e2 = edgeNet(f, a0, b1, a1, b1);
                const auto e3 = edgeNet(f, a0, b0, a0, b1), e1 = edgeNet(f, a1, b0, a1, b1);
                for (int t = 0; t < n; ++t) {
                    net[t] = e0[t];
                    net[t + n * (n - 1)] = e2[t];
                    net[n * t] = e3[t];
                    net[n - 1 + n * t] = e1[t];
                }
                // Interior control points: least squares on a dense sample, boundary fixed.
                const int m = kSurfSamples * kSurfSamples, ni = (n - 2) * (n - 2);
                Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, ni);
                Eigen::MatrixXd rhs(m, 3);
                double Nu[nurbs::kMaxDegree + 1], Nv[nurbs::kMaxDegree + 1];
                for (int sb = 0; sb < kSurfSamples; ++sb) {
                    const double v = static_cast<double>(sb) / (kSurfSamples - 1);
                    const int spv = nurbs::findSpan(U, p, n, v);
                    nurbs::basisFunctions(U, p, spv, v, Nv);
                    for (int sa = 0; sa < kSurfSamples; ++sa) {
                        const double u = static_cast<double>(sa) / (kSurfSamples - 1);
                        const int spu = nurbs::findSpan(U, p, n, u);
                        nurbs::basisFunctions(U, p, spu, u, Nu);
                        const int row = sa + kSurfSamples * sb;
                        Vec3<double> r = spherePoint(f, a0 + u * (a1 - a0), b0 + v * (b1 - b0), o.radius);
                        for (int l = 0; l <= p; ++l) {
                            for (int k = 0; k <= p; ++k) {
                                const int i = spu - p + k, j = spv - p + l;
                                const double w = Nu[k] * Nv[l];
                                if (i == 0 || j == 0 || i == n - 1 || j == n - 1) {
                                    r -= w * net[i + n * j];
                                } else {
                                    A(row, (i - 1) + (n - 2) * (j - 1)) = w;
                                }
                            }
                        }
                        rhs.row(row) = r.transpose();
                    }
                }
                const Eigen::MatrixXd X = A.colPivHouseholderQr().solve(rhs);
                for (int j = 1; j < n - 1; ++j) {
                    for (int i = 1; i < n - 1; ++i) net[i + n * j] = X.row((i - 1) + (n - 2) * (j - 1)).transpose();
                }
                patch.points.resize(3 * n * n);
                for (int c = 0; c < n * n; ++c) {
                    for (int d = 0; d < 3; ++d) patch.points[3 * c + d] = net[c][d];
                }
                set.patches.push_back(std::move(patch));
                set.names.push_back(std::string(f.name) + "-" + std::to_string(2 * jb + ia + 1));
            }
        }
    }
    return set;
}

double maxRadialDeviation(const PatchSet& set, double radius, int samplesPerDirection) {
    double dev = 0;
    std::vector<double> out;
    for (const Patch& patch : set.patches) {
        std::vector<double> us(samplesPerDirection), vs(samplesPerDirection);
        for (int s = 0; s < samplesPerDirection; ++s) {
            const double t = static_cast<double>(s) / (samplesPerDirection - 1);
            us[s] = patch.knotsU.front() + t * (patch.knotsU.back() - patch.knotsU.front());
            vs[s] = patch.knotsV.front() + t * (patch.knotsV.back() - patch.knotsV.front());
        }
        out.resize(3 * us.size() * vs.size());
        nurbs::sampleGrid(patch, us, vs, out.data());
        for (std::size_t a = 0; a < out.size(); a += 3) {
            const double r = std::sqrt(out[a] * out[a] + out[a + 1] * out[a + 1] + out[a + 2] * out[a + 2]);
            dev = std::max(dev, std::abs(r - radius));
        }
    }
    return dev;
}

}  // namespace aero::geometry
