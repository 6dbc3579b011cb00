#include "ffd/ShapeConstraints.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <map>
#include <type_traits>

#include "common/Error.h"
#include "common/Format.h"
#include "nurbs/Basis.h"

namespace aero::ffd {

namespace {

using geometry::Patch;

std::string formatNumber(double x) {
    return format("%.6g", x);
}

// A point of the surface with its patch and parameters.
struct SurfaceHit {
    int patch = -1;
    double u = 0, v = 0;
    nurbs::Vec3<double> point;
};

// Parameters of patch p where S_x = x0 and S_y = y0 (Newton on the 2 x 2 system from the sampled
// cells whose xy box holds the point). Every distinct solution inside the domain is returned.
void intersectVertical(const Patch& s, int p, double x0, double y0, double tol, std::vector<SurfaceHit>& hits) {
    constexpr int n = 24;
    const double u0 = s.knotsU.front(), u1 = s.knotsU.back(), v0 = s.knotsV.front(), v1 = s.knotsV.back();
    std::vector<double> us(n + 1), vs(n + 1);
    for (int i = 0; i <= n; ++i) {
        us[i] = u0 + (u1 - u0) * i / n;
        vs[i] = v0 + (v1 - v0) * i / n;
    }
    std::vector<double> xyz(3 * (n + 1) * (n + 1));
    nurbs::sampleGrid(s, us, vs, xyz.data());
    auto at = [&](int i, int j) { return &xyz[3 * (i + (n + 1) * j)]; };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            double xl = std::numeric_limits<double>::infinity(), xh = -xl, yl = xl, yh = -xl;
            for (int c = 0; c < 4; ++c) {
                const double* q = at(i + (c & 1), j + (c >> 1));
                xl = std::min(xl, q[0]);
                xh = std::max(xh, q[0]);
                yl = std::min(yl, q[1]);
                yh = std::max(yh, q[1]);
            }
            const double margin = 0.25 * std::max(xh - xl, yh - yl) + tol;
            if (x0 < xl - margin || x0 > xh + margin || y0 < yl - margin || y0 > yh + margin) continue;
            double u = 0.5 * (us[i] + us[i + 1]), v = 0.5 * (vs[j] + vs[j + 1]);
            bool converged = false;
            for (int it = 0; it < 40; ++it) {
                const nurbs::SurfaceDerivatives<double> d = nurbs::evaluateDerivatives(s, u, v, 1);
                const double fx = d.S[0] - x0, fy = d.S[1] - y0;
                if (std::hypot(fx, fy) <= tol) {
                    converged = true;
                    break;
                }
                const double a = d.Su[0], b = d.Sv[0], c = d.Su[1], e = d.Sv[1];
                const double det = a * e - b * c;
                if (!(std::abs(det) > 1e-300)) break;
                u = std::clamp(u - (e * fx - b * fy) / det, u0, u1);
                v = std::clamp(v - (a * fy - c * fx) / det, v0, v1);
            }
            if (!converged) continue;
            const nurbs::Vec3<double> P = nurbs::evaluate(s, u, v);
            bool known = false;
            for (const SurfaceHit& h : hits) known = known || (h.point - P).norm() <= 1e3 * tol;
            if (!known) hits.push_back({p, u, v, P});
        }
    }
}

// R_ij(u, v) of patch p accumulated onto unique control points with factor `sign`.
void addWeights(const geometry::PatchSet& set, const geometry::ControlPointIndex& index, int p, double u, double v,
                double sign, std::map<int, double>& out) {
    const Patch& s = set.patches[p];
    const int su = nurbs::findSpan(s.knotsU, s.degreeU, s.countU, u), sv = nurbs::findSpan(s.knotsV, s.degreeV, s.countV, v);
    std::vector<double> Nu(s.degreeU + 1), Nv(s.degreeV + 1);
    nurbs::basisFunctions(s.knotsU, s.degreeU, su, u, Nu.data());
    nurbs::basisFunctions(s.knotsV, s.degreeV, sv, v, Nv.data());
    double total = 0;
    for (int b = 0; b <= s.degreeV; ++b) {
        for (int a = 0; a <= s.degreeU; ++a) {
            const int i = su - s.degreeU + a, j = sv - s.degreeV + b;
            total += Nu[a] * Nv[b] * (s.rational() ? s.weights[s.index(i, j)] : 1.0);
        }
    }
    for (int b = 0; b <= s.degreeV; ++b) {
        for (int a = 0; a <= s.degreeU; ++a) {
            const int i = su - s.degreeU + a, j = sv - s.degreeV + b;
            const double R = Nu[a] * Nv[b] * (s.rational() ? s.weights[s.index(i, j)] : 1.0) / total;
            out[index.toUnique[index.patchOffset[p] + s.index(i, j)]] += sign * R;
        }
    }
}

// The smallest and largest x of the baseline's section y = ys (sampled crossings of every patch).
std::array<double, 2> sectionExtent(const geometry::PatchSet& set, double ys) {
    constexpr int n = 64;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Patch& s : set.patches) {
        std::vector<double> us(n + 1), vs(n + 1);
        for (int i = 0; i <= n; ++i) {
            us[i] = s.knotsU.front() + (s.knotsU.back() - s.knotsU.front()) * i / n;
            vs[i] = s.knotsV.front() + (s.knotsV.back() - s.knotsV.front()) * i / n;
        }
        std::vector<double> xyz(3 * (n + 1) * (n + 1));
        nurbs::sampleGrid(s, us, vs, xyz.data());
        auto at = [&](int i, int j) { return &xyz[3 * (i + (n + 1) * j)]; };
        auto edge = [&](const double* a, const double* b) {
            const double da = a[1] - ys, db = b[1] - ys;
            if (da * db > 0) return;
            const double t = da == db ? 0.0 : da / (da - db);
            const double x = a[0] + t * (b[0] - a[0]);
            lo = std::min(lo, x);
            hi = std::max(hi, x);
        };
        for (int j = 0; j <= n; ++j) {
            for (int i = 0; i <= n; ++i) {
                if (i < n) edge(at(i, j), at(i + 1, j));
                if (j < n) edge(at(i, j), at(i, j + 1));
            }
        }
    }
    return {lo, hi};
}

}  // namespace

// ---- Thickness ---------------------------------------------------------------------------------

ThicknessConstraints::ThicknessConstraints(const FfdModel& model, const ThicknessSpec& spec)
    : model_(model), dAdv_(model.dUniqueDv()) {
    const geometry::PatchSet& set = model.baseline();
    double size = 0;
    for (double c : model.index().points) size = std::max(size, std::abs(c));
    const double tol = 1e-12 * std::max(size, 1.0);
    std::vector<std::pair<std::array<double, 2>, std::string>> wanted;
    if (!spec.chordFractions.empty() && spec.stations.empty()) {
        throw GeometryError("thickness: chord fractions are given without stations");
    }
    for (double ys : spec.stations) {
        if (spec.chordFractions.empty()) throw GeometryError("thickness: stations are given without chord fractions");
        const std::array<double, 2> ext = sectionExtent(set, ys);
        if (!(ext[1] > ext[0])) {
            throw GeometryError("thickness station y = " + formatNumber(ys) + ": the geometry '" + set.source +
                                "' has no section there (its y range does not reach it)");
        }
        for (double f : spec.chordFractions) {
            if (!(f > 0 && f < 1)) throw GeometryError("thickness chord fraction " + formatNumber(f) + ": must lie in (0, 1)");
            wanted.push_back({{ext[0] + f * (ext[1] - ext[0]), ys}, "thickness y=" + formatNumber(ys) + " x/c=" + formatNumber(f)});
        }
    }
    for (const auto& q : spec.points) {
        wanted.push_back({q, "thickness (" + formatNumber(q[0]) + ", " + formatNumber(q[1]) + ")"});
    }
    std::vector<geometry::TrimPolygons> trims(static_cast<std::size_t>(set.size()));
    for (int p = 0; p < set.size(); ++p) {
        if (set.trimmed(p)) trims[p] = geometry::polygonize(set.trims[p], set.patches[p]);
    }
    for (const auto& [xy, name] : wanted) {
        std::vector<SurfaceHit> hits;
        for (int p = 0; p < set.size(); ++p) {
            std::vector<SurfaceHit> mine;
            intersectVertical(set.patches[p], p, xy[0], xy[1], tol, mine);
            for (const SurfaceHit& h : mine) {
                if (set.trimmed(p) && !geometry::contains(trims[p], h.u, h.v)) continue;  // trimmed away
                bool known = false;
                for (const SurfaceHit& k : hits) known = known || (k.point - h.point).norm() <= 1e3 * tol;
                if (!known) hits.push_back(h);
            }
        }
        if (hits.size() < 2) {
            throw GeometryError(name + " at (x, y) = (" + formatNumber(xy[0]) + ", " + formatNumber(xy[1]) + "): the surface of '" +
                                set.source + "' is found " + (hits.empty() ? "neither above nor below" : "only once") +
                                " along z there (a point outside the planform, or on its edge)");
        }
        const auto [lo, hi] = std::minmax_element(hits.begin(), hits.end(),
                                                  [](const SurfaceHit& a, const SurfaceHit& b) { return a.point[2] < b.point[2]; });
        ThicknessPoint t;
        t.name = name;
        t.x = xy[0];
        t.y = xy[1];
        t.topPatch = hi->patch;
        t.topUv = {hi->u, hi->v};
        t.bottomPatch = lo->patch;
        t.bottomUv = {lo->u, lo->v};
        std::map<int, double> w;
        addWeights(set, model.index(), hi->patch, hi->u, hi->v, 1.0, w);
        addWeights(set, model.index(), lo->patch, lo->u, lo->v, -1.0, w);
        for (const auto& [k, c] : w) {
            if (c != 0) t.weights.push_back({k, c});
        }
        t.baseline = (hi->point - lo->point).norm();
        if (!(t.baseline > 1e6 * tol)) {
            throw GeometryError(name + ": the baseline thickness is zero (the surface's top and bottom meet there)");
        }
        points_.push_back(std::move(t));
    }
}

template <class T>
std::array<T, 3> ThicknessConstraints::difference(const ThicknessPoint& p, std::span<const T> unique) const {
    std::array<T, 3> d{T(0), T(0), T(0)};
    for (const auto& [k, c] : p.weights) {
        for (int a = 0; a < 3; ++a) d[a] += c * unique[3 * k + a];
    }
    return d;
}

template <class T>
T ThicknessConstraints::thickness(int k, std::span<const T> v) const {
    const std::vector<T> A = model_.uniquePoints<T>(v);
    const std::array<T, 3> d = difference<T>(points_[k], A);
    return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

std::vector<double> ThicknessConstraints::ratios(std::span<const double> v) const {
    const std::vector<double> A = model_.uniquePoints<double>(v);
    std::vector<double> r;
    for (const ThicknessPoint& p : points_) {
        const std::array<double, 3> d = difference<double>(p, A);
        r.push_back(std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / p.baseline);
    }
    return r;
}

std::vector<std::vector<double>> ThicknessConstraints::ratioGradients(std::span<const double> v) const {
    const std::vector<double> A = model_.uniquePoints<double>(v);
    std::vector<std::vector<double>> rows;
    for (const ThicknessPoint& p : points_) {
        const std::array<double, 3> d = difference<double>(p, A);
        const double t = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        Eigen::VectorXd g = Eigen::VectorXd::Zero(dAdv_.rows());
        if (t > 0) {
            for (const auto& [k, c] : p.weights) {
                for (int a = 0; a < 3; ++a) g[3 * k + a] += c * d[a] / (t * p.baseline);
            }
        }
        const Eigen::VectorXd dv = dAdv_.transpose() * g;
        rows.emplace_back(dv.data(), dv.data() + dv.size());
    }
    return rows;
}

template double ThicknessConstraints::thickness(int, std::span<const double>) const;
template std::complex<double> ThicknessConstraints::thickness(int, std::span<const std::complex<double>>) const;

// ---- Lattice Jacobian --------------------------------------------------------------------------

namespace {

// det of J(r, c) = sum_a B_a[r] dN_a[c] and, optionally, its cofactors d det / dJ(r, c).
template <class T>
T jacobianDeterminant(const T* B, const std::vector<int>& controls, const std::vector<std::array<double, 3>>& dN,
                      std::array<std::array<T, 3>, 3>* cofactor = nullptr) {
    std::array<std::array<T, 3>, 3> J{};
    for (auto& row : J) row.fill(T(0));
    for (std::size_t q = 0; q < controls.size(); ++q) {
        const T* b = B + 3 * controls[q];
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) J[r][c] += b[r] * dN[q][c];
        }
    }
    auto C = [&](int r, int c) {
        const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
        return J[r1][c1] * J[r2][c2] - J[r1][c2] * J[r2][c1];
    };
    if (cofactor) {
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) (*cofactor)[r][c] = C(r, c);
        }
    }
    return J[0][0] * C(0, 0) + J[0][1] * C(0, 1) + J[0][2] * C(0, 2);
}

}  // namespace

LatticeJacobianBound::LatticeJacobianBound(const FfdModel& model, int samplesPerSpan, double rho) : model_(model), rho_(rho) {
    if (samplesPerSpan < 1) throw GeometryError("lattice Jacobian bound: samples per span must be >= 1");
    const DesignSpace& ds = model.design();
    for (int l = 0; l < static_cast<int>(ds.baseline().size()); ++l) {
        const Lattice& L = ds.baseline()[l];
        const std::string name = model.lattices()[l].name.empty() ? "#" + std::to_string(l) : "'" + model.lattices()[l].name + "'";
        if (L.rational()) {
            throw GeometryError("lattice " + name + " is rational: the lattice Jacobian constraint is built for B-spline lattices");
        }
        dBdv_.push_back(ds.jacobian(l));
        std::array<std::vector<double>, 3> s;
        for (int d = 0; d < 3; ++d) {
            const auto& U = L.knots[d];
            for (std::size_t i = 0; i + 1 < U.size(); ++i) {
                if (!(U[i + 1] > U[i])) continue;
                for (int t = 0; t < samplesPerSpan; ++t) s[d].push_back(U[i] + (U[i + 1] - U[i]) * t / samplesPerSpan);
            }
            s[d].push_back(U.back());
        }
        std::vector<Sample> mine;
        double total = 0;
        for (double c : s[2]) {
            for (double b : s[1]) {
                for (double a : s[0]) {
                    Sample smp;
                    smp.lattice = l;
                    smp.xi = {a, b, c};
                    std::array<std::vector<double>, 3> ders;
                    std::array<int, 3> span{};
                    for (int d = 0; d < 3; ++d) {
                        span[d] = nurbs::findSpan(L.knots[d], L.degree[d], L.count[d], smp.xi[d]);
                        ders[d].resize(2 * (L.degree[d] + 1));
                        nurbs::basisDerivatives(L.knots[d], L.degree[d], span[d], smp.xi[d], 1, ders[d].data());
                    }
                    const int p0 = L.degree[0] + 1, p1 = L.degree[1] + 1;
                    for (int k = 0; k <= L.degree[2]; ++k) {
                        for (int j = 0; j <= L.degree[1]; ++j) {
                            for (int i = 0; i <= L.degree[0]; ++i) {
                                const double N0 = ders[0][i], N1 = ders[1][j], N2 = ders[2][k];
                                const double D0 = ders[0][p0 + i], D1 = ders[1][p1 + j], D2 = ders[2][L.degree[2] + 1 + k];
                                smp.controls.push_back(L.index(span[0] - L.degree[0] + i, span[1] - L.degree[1] + j, span[2] - L.degree[2] + k));
                                smp.dN.push_back({D0 * N1 * N2, N0 * D1 * N2, N0 * N1 * D2});
                            }
                        }
                    }
                    smp.baseline = jacobianDeterminant<double>(L.points.data(), smp.controls, smp.dN);
                    total += smp.baseline;
                    mine.push_back(std::move(smp));
                }
            }
        }
        const double sign = total < 0 ? -1.0 : 1.0;
        const double mean = std::abs(total) / static_cast<double>(mine.size());
        for (Sample& smp : mine) {
            smp.sign = sign;
            smp.baseline *= sign;
            if (!(smp.baseline > 1e-9 * mean)) {
                throw GeometryError("lattice " + name + ": the baseline's det J is " + formatNumber(smp.baseline) + " (mean " +
                                    formatNumber(mean) + ") at parameters (" + formatNumber(smp.xi[0]) + ", " +
                                    formatNumber(smp.xi[1]) + ", " + formatNumber(smp.xi[2]) +
                                    "): the lattice is degenerate or folded before any design change");
            }
            samples_.push_back(std::move(smp));
        }
    }
}

template <class T>
std::vector<T> LatticeJacobianBound::ratiosOf(std::span<const T> v) const {
    std::vector<std::vector<T>> B;
    for (int l = 0; l < static_cast<int>(dBdv_.size()); ++l) B.push_back(model_.design().latticePoints<T>(l, v));
    std::vector<T> r;
    r.reserve(samples_.size());
    for (const Sample& s : samples_) r.push_back(s.sign * jacobianDeterminant<T>(B[s.lattice].data(), s.controls, s.dN) / s.baseline);
    return r;
}

template <class T>
T LatticeJacobianBound::value(std::span<const double> vReal, std::span<const T> v) const {
    const std::vector<T> r = ratiosOf<T>(v);
    // The shift m only keeps exp() in range (g does not depend on it): the real ratios' minimum.
    double m = 0;
    if constexpr (std::is_same_v<T, double>) {
        m = *std::min_element(r.begin(), r.end());
    } else {
        const std::vector<double> rr = ratiosOf<double>(vReal);
        m = *std::min_element(rr.begin(), rr.end());
    }
    T sum(0);
    for (const T& x : r) sum += std::exp(-rho_ * (x - m));
    return m - std::log(sum) / rho_;
}

LatticeJacobianBound::Minimum LatticeJacobianBound::minimum(std::span<const double> v) const {
    const std::vector<double> r = ratiosOf<double>(v);
    const auto it = std::min_element(r.begin(), r.end());
    const Sample& s = samples_[static_cast<std::size_t>(it - r.begin())];
    return {*it, s.lattice, s.xi};
}

std::vector<double> LatticeJacobianBound::gradient(std::span<const double> v) const {
    std::vector<std::vector<double>> B;
    for (int l = 0; l < static_cast<int>(dBdv_.size()); ++l) B.push_back(model_.design().latticePoints<double>(l, v));
    std::vector<double> r(samples_.size());
    std::vector<std::array<std::array<double, 3>, 3>> cof(samples_.size());
    for (std::size_t q = 0; q < samples_.size(); ++q) {
        const Sample& s = samples_[q];
        r[q] = s.sign * jacobianDeterminant<double>(B[s.lattice].data(), s.controls, s.dN, &cof[q]) / s.baseline;
    }
    const double m = *std::min_element(r.begin(), r.end());
    double sum = 0;
    std::vector<double> w(r.size());
    for (std::size_t q = 0; q < r.size(); ++q) sum += (w[q] = std::exp(-rho_ * (r[q] - m)));
    // dg/dr_q = w_q / sum; dr_q/dB_a[row] = sign / baseline * sum_c cof(row, c) dN_a[c].
    std::vector<Eigen::VectorXd> gB;
    for (const auto& Bl : B) gB.push_back(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(Bl.size())));
    for (std::size_t q = 0; q < samples_.size(); ++q) {
        const Sample& s = samples_[q];
        const double f = w[q] / sum * s.sign / s.baseline;
        for (std::size_t a = 0; a < s.controls.size(); ++a) {
            for (int row = 0; row < 3; ++row) {
                double d = 0;
                for (int c = 0; c < 3; ++c) d += cof[q][row][c] * s.dN[a][c];
                gB[s.lattice][3 * s.controls[a] + row] += f * d;
            }
        }
    }
    Eigen::VectorXd dv = Eigen::VectorXd::Zero(model_.design().size());
    for (std::size_t l = 0; l < gB.size(); ++l) dv += dBdv_[l].transpose() * gB[l];
    return std::vector<double>(dv.data(), dv.data() + dv.size());
}

template double LatticeJacobianBound::value(std::span<const double>, std::span<const double>) const;
template std::complex<double> LatticeJacobianBound::value(std::span<const double>, std::span<const std::complex<double>>) const;

}  // namespace aero::ffd
