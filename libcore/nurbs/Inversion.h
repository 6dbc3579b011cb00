#pragma once
// Point inversion: parameters of a given point (closest point on curves and surfaces, the
// preimage for volumes: the FFD embedding F^-1 of the paper). Newton iterations with a robust
// start from a coarse structured search and a backtracking line search; parameters stay in
// the domain (clamped). Non-convergence is reported, never thrown.
#include <array>

#include "nurbs/Surface.h"
#include "nurbs/Volume.h"

namespace aero::nurbs {

struct InversionOptions {
    double tolerance = 1e-12;  // world-space tolerance on |F(x) - p| (volumes) or the step
    int maxIterations = 50;
    int samplesPerSpan = 4;    // coarse search density for the starting guess
};

struct CurveProjection {
    double u = 0;
    double distance = 0;  // |C(u) - p|
    int iterations = 0;
    bool converged = false;
};

struct SurfaceProjection {
    double u = 0, v = 0;
    double distance = 0;
    int iterations = 0;
    bool converged = false;
};

struct VolumeInversion {
    std::array<double, 3> xi{0, 0, 0};
    double residual = 0;  // |V(xi) - p| in world units
    int iterations = 0;
    bool converged = false;  // residual <= tolerance
    bool inside = true;      // false if the closest parameters lie on the domain boundary
                             // with residual > tolerance (the point is outside the volume)
};

CurveProjection project(const Curve<double>& c, const Vec3<double>& p, const InversionOptions& o = {});
SurfaceProjection project(const Surface<double>& s, const Vec3<double>& p,
                          const InversionOptions& o = {});
VolumeInversion invert(const Volume<double>& v, const Vec3<double>& p, const InversionOptions& o = {});

/// Inverts many points against one volume: the coarse search grid is sampled once.
/// Holds a reference to the volume, which must outlive it. Thread-safe calls.
class VolumeInverter {
public:
    explicit VolumeInverter(const Volume<double>& v, const InversionOptions& o = {});
    VolumeInversion operator()(const Vec3<double>& p) const;
    /// Inverts n points (3 x n) into out[0..n) with OpenMP.
    void invertAll(std::span<const double> points, VolumeInversion* out) const;

private:
    const Volume<double>& volume_;
    InversionOptions options_;
    std::array<std::vector<double>, 3> samples_;  // parameter values of the coarse grid
    std::vector<double> grid_;                    // 3 per coarse sample, [k][j][i]
    // Uniform buckets over the samples' bounding box: the start search looks at the point's
    // bucket and its neighbours instead of every sample.
    std::array<double, 3> lo_{}, cell_{};
    std::array<int, 3> buckets_{1, 1, 1};
    std::vector<int> bucketStart_, bucketItems_;  // CSR: samples of bucket b
    std::size_t nearestSample(const Vec3<double>& p) const;
};

}  // namespace aero::nurbs
