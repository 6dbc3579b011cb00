#include "nurbs/Inversion.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "nurbs/Basis.h"

namespace aero::nurbs {

namespace {

double clampTo(double x, double lo, double hi) { return std::min(std::max(x, lo), hi); }

}  // namespace

CurveProjection project(const Curve<double>& c, const Vec3<double>& p, const InversionOptions& o) {
    const std::vector<double> us = spanSamples(c.knots, std::max(2, o.samplesPerSpan));
    CurveProjection r;
    double best = std::numeric_limits<double>::infinity();
    for (double u : us) {
        const double d = (evaluate(c, u) - p).squaredNorm();
        if (d < best) {
            best = d;
            r.u = u;
        }
    }
    const double lo = c.first(), hi = c.last();
    Vec3<double> D[3];
    for (r.iterations = 0; r.iterations < o.maxIterations; ++r.iterations) {
        evaluateDerivatives(c, r.u, 2, D);
        const Vec3<double> e = D[0] - p;
        r.distance = e.norm();
        const double f = D[1].dot(e);
        const double df = D[2].dot(e) + D[1].squaredNorm();
        if (r.distance <= o.tolerance || std::abs(f) <= 1e-14 * D[1].norm() * r.distance) {
            r.converged = true;
            break;
        }
        if (!(df > 0)) break;
        const double un = clampTo(r.u - f / df, lo, hi);
        const double step = std::abs(un - r.u) * D[1].norm();
        r.u = un;
        if (step <= o.tolerance * 1e-2) {
            r.converged = true;
            break;
        }
    }
    r.distance = (evaluate(c, r.u) - p).norm();
    return r;
}

SurfaceProjection project(const Surface<double>& s, const Vec3<double>& p, const InversionOptions& o) {
    const int per = std::max(2, o.samplesPerSpan);
    const std::vector<double> us = spanSamples(s.knotsU, per), vs = spanSamples(s.knotsV, per);
    std::vector<double> grid(3 * us.size() * vs.size());
    sampleGrid(s, us, vs, grid.data());
    SurfaceProjection r;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t b = 0; b < vs.size(); ++b) {
        for (std::size_t a = 0; a < us.size(); ++a) {
            const double* g = &grid[3 * (b * us.size() + a)];
            const double d = (Vec3<double>(g[0], g[1], g[2]) - p).squaredNorm();
            if (d < best) {
                best = d;
                r.u = us[a];
                r.v = vs[b];
            }
        }
    }
    const double ulo = s.knotsU.front(), uhi = s.knotsU.back();
    const double vlo = s.knotsV.front(), vhi = s.knotsV.back();
    for (r.iterations = 0; r.iterations < o.maxIterations; ++r.iterations) {
        const SurfaceDerivatives<double> d = evaluateDerivatives(s, r.u, r.v, 2);
        const Vec3<double> e = d.S - p;
        r.distance = e.norm();
        const double f = d.Su.dot(e), g = d.Sv.dot(e);
        if (r.distance <= o.tolerance ||
            (std::abs(f) <= 1e-14 * d.Su.norm() * r.distance && std::abs(g) <= 1e-14 * d.Sv.norm() * r.distance)) {
            r.converged = true;
            break;
        }
        Eigen::Matrix2d J;
        J << d.Su.squaredNorm() + e.dot(d.Suu), d.Su.dot(d.Sv) + e.dot(d.Suv), d.Su.dot(d.Sv) + e.dot(d.Suv),
            d.Sv.squaredNorm() + e.dot(d.Svv);
        Eigen::Vector2d step = J.ldlt().solve(Eigen::Vector2d(-f, -g));
        if (!step.allFinite()) break;
        const double un = clampTo(r.u + step[0], ulo, uhi), vn = clampTo(r.v + step[1], vlo, vhi);
        const double moved = ((un - r.u) * d.Su + (vn - r.v) * d.Sv).norm();
        r.u = un;
        r.v = vn;
        if (moved <= o.tolerance * 1e-2) {
            r.converged = true;
            break;
        }
    }
    r.distance = (evaluate(s, r.u, r.v) - p).norm();
    return r;
}

VolumeInverter::VolumeInverter(const Volume<double>& v, const InversionOptions& o) : volume_(v), options_(o) {
    const int per = std::max(1, o.samplesPerSpan);
    for (int d = 0; d < 3; ++d) samples_[d] = spanSamples(v.knots[d], per);
    grid_.resize(3 * samples_[0].size() * samples_[1].size() * samples_[2].size());
    sampleGrid(v, samples_[0], samples_[1], samples_[2], grid_.data());
    // Buckets: about 2 samples per bucket and direction.
    const std::size_t n = grid_.size() / 3;
    std::array<double, 3> hi{};
    for (int d = 0; d < 3; ++d) {
        lo_[d] = std::numeric_limits<double>::infinity();
        hi[d] = -lo_[d];
        buckets_[d] = std::max(1, static_cast<int>(samples_[d].size() / 2));
    }
    for (std::size_t a = 0; a < n; ++a) {
        for (int d = 0; d < 3; ++d) {
            lo_[d] = std::min(lo_[d], grid_[3 * a + d]);
            hi[d] = std::max(hi[d], grid_[3 * a + d]);
        }
    }
    for (int d = 0; d < 3; ++d) cell_[d] = std::max(hi[d] - lo_[d], 1e-300) / buckets_[d];
    auto bucketOf = [&](const double* x) {
        int b[3];
        for (int d = 0; d < 3; ++d) b[d] = std::clamp(static_cast<int>((x[d] - lo_[d]) / cell_[d]), 0, buckets_[d] - 1);
        return b[0] + buckets_[0] * (b[1] + buckets_[1] * b[2]);
    };
    const int nb = buckets_[0] * buckets_[1] * buckets_[2];
    bucketStart_.assign(nb + 1, 0);
    for (std::size_t a = 0; a < n; ++a) ++bucketStart_[bucketOf(&grid_[3 * a]) + 1];
    for (int b = 0; b < nb; ++b) bucketStart_[b + 1] += bucketStart_[b];
    bucketItems_.resize(n);
    std::vector<int> fill(bucketStart_.begin(), bucketStart_.end() - 1);
    for (std::size_t a = 0; a < n; ++a) bucketItems_[fill[bucketOf(&grid_[3 * a])]++] = static_cast<int>(a);
}

std::size_t VolumeInverter::nearestSample(const Vec3<double>& p) const {
    int c[3];
    for (int d = 0; d < 3; ++d) c[d] = std::clamp(static_cast<int>(std::floor((p[d] - lo_[d]) / cell_[d])), 0, buckets_[d] - 1);
    std::size_t best = 0;
    double bestD = std::numeric_limits<double>::infinity();
    // Rings of buckets around the point's bucket until a sample is found and the ring is farther
    // than the best distance (a sample-free neighbourhood is widened, never skipped).
    const int maxRing = std::max({buckets_[0], buckets_[1], buckets_[2]});
    for (int ring = 0; ring <= maxRing; ++ring) {
        for (int k = c[2] - ring; k <= c[2] + ring; ++k) {
            if (k < 0 || k >= buckets_[2]) continue;
            for (int j = c[1] - ring; j <= c[1] + ring; ++j) {
                if (j < 0 || j >= buckets_[1]) continue;
                for (int i = c[0] - ring; i <= c[0] + ring; ++i) {
                    if (i < 0 || i >= buckets_[0]) continue;
                    if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])}) != ring) continue;
                    const int b = i + buckets_[0] * (j + buckets_[1] * k);
                    for (int t = bucketStart_[b]; t < bucketStart_[b + 1]; ++t) {
                        const double* g = &grid_[3 * static_cast<std::size_t>(bucketItems_[t])];
                        const double dx = g[0] - p[0], dy = g[1] - p[1], dz = g[2] - p[2];
                        const double dd = dx * dx + dy * dy + dz * dz;
                        if (dd < bestD) {
                            bestD = dd;
                            best = static_cast<std::size_t>(bucketItems_[t]);
                        }
                    }
                }
            }
        }
        // Everything in rings > ring is at least ring * min(cell) away from the point's bucket.
        const double reach = ring * std::min({cell_[0], cell_[1], cell_[2]});
        if (bestD < std::numeric_limits<double>::infinity() && reach * reach >= bestD) break;
    }
    return best;
}

VolumeInversion VolumeInverter::operator()(const Vec3<double>& p) const {
    const Volume<double>& v = volume_;
    VolumeInversion r;
    // Robust start: the nearest coarse sample.
    const std::size_t n0 = samples_[0].size(), n1 = samples_[1].size();
    const std::size_t bestIdx = nearestSample(p);
    r.xi = {samples_[0][bestIdx % n0], samples_[1][(bestIdx / n0) % n1], samples_[2][bestIdx / (n0 * n1)]};
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
        lo[d] = v.knots[d].front();
        hi[d] = v.knots[d].back();
    }
    Vec3<double> P;
    Eigen::Matrix3d J;
    evaluateJacobian(v, r.xi[0], r.xi[1], r.xi[2], P, J);
    Vec3<double> res = p - P;
    r.residual = res.norm();
    for (r.iterations = 0; r.iterations < options_.maxIterations && r.residual > options_.tolerance;
         ++r.iterations) {
        // Newton step; coordinates pinned at a bound with the step pointing outwards are held
        // fixed and the rest solve the least-squares problem (closest point on that face).
        Vec3<double> step = J.partialPivLu().solve(res);
        bool fixed[3] = {false, false, false};
        bool anyFixed = false;
        for (int d = 0; d < 3; ++d) {
            fixed[d] = (r.xi[d] <= lo[d] && step[d] < 0) || (r.xi[d] >= hi[d] && step[d] > 0) || !std::isfinite(step[d]);
            anyFixed = anyFixed || fixed[d];
        }
        if (anyFixed) {
            int freeIdx[3], nf = 0;
            for (int d = 0; d < 3; ++d) {
                if (!fixed[d]) freeIdx[nf++] = d;
            }
            if (nf == 0) break;
            Eigen::MatrixXd Jf(3, nf);
            for (int t = 0; t < nf; ++t) Jf.col(t) = J.col(freeIdx[t]);
            const Eigen::VectorXd sf = Jf.colPivHouseholderQr().solve(res);
            step.setZero();
            for (int t = 0; t < nf; ++t) step[freeIdx[t]] = sf[t];
        }
        // Backtracking line search (Armijo on the Gauss-Newton model): the decrease is measured
        // against what the linear model predicts, not against the whole residual, so a point
        // outside the volume still converges to its closest point on the boundary.
        const double predicted = res.squaredNorm() - (res - J * step).squaredNorm();
        if (!(predicted > 1e-32 * std::max(1.0, res.squaredNorm()))) break;  // nothing left to gain
        double alpha = 1.0;
        std::array<double, 3> trial{};
        double trialRes = 0;
        Vec3<double> trialP;
        Eigen::Matrix3d trialJ;
        bool accepted = false;
        for (int ls = 0; ls < 30; ++ls) {
            for (int d = 0; d < 3; ++d) trial[d] = clampTo(r.xi[d] + alpha * step[d], lo[d], hi[d]);
            evaluateJacobian(v, trial[0], trial[1], trial[2], trialP, trialJ);
            trialRes = (p - trialP).norm();
            if (trialRes * trialRes <= r.residual * r.residual - 1e-4 * alpha * predicted ||
                trialRes <= options_.tolerance) {
                accepted = true;
                break;
            }
            alpha *= 0.5;
        }
        if (!accepted) break;  // stalled: at the closest reachable point
        r.xi = trial;
        P = trialP;
        J = trialJ;
        res = p - P;
        r.residual = trialRes;
    }
    r.converged = r.residual <= options_.tolerance;
    bool onBoundary = false;
    for (int d = 0; d < 3; ++d) onBoundary = onBoundary || r.xi[d] <= lo[d] || r.xi[d] >= hi[d];
    r.inside = r.converged || !onBoundary;
    return r;
}

void VolumeInverter::invertAll(std::span<const double> points, VolumeInversion* out) const {
    const long n = static_cast<long>(points.size() / 3);
#pragma omp parallel for schedule(dynamic, 64)
    for (long i = 0; i < n; ++i) {
        out[i] = (*this)(Vec3<double>(points[3 * i], points[3 * i + 1], points[3 * i + 2]));
    }
}

VolumeInversion invert(const Volume<double>& v, const Vec3<double>& p, const InversionOptions& o) {
    return VolumeInverter(v, o)(p);
}

}  // namespace aero::nurbs
