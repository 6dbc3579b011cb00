#pragma once
// Geometric constraints of an optimization that the FFD model answers exactly, with gradients
// with respect to the design variables. Both are functions of the model alone (no grid, no flow),
// so they cost microseconds and their gradients need no adjoint.
//
// Thickness: at a planform point (x, y), the surface points straight above and below it on the
// baseline are found once and kept at their surface parameters (patch, u, v), so they move with
// the control points: S(u, v) = sum_i R_i(u, v) A_i is linear in the unique control points A(v),
// and t(v) = |S_top(A(v)) - S_bottom(A(v))| (the distance, as the points may also slide in x
// and y). The constraint is t / t_baseline >= a minimum ratio.
//
// Lattice Jacobian: det J(xi_s; B(v)) / det J(xi_s; B_baseline) at samples xi_s of every lattice,
// reduced to one smooth lower bound by the Kreisselmeier-Steinhauser function
//     g = m - (1 / rho) ln sum_s exp(-rho (r_s - m)),  m = min_s r_s,  so g <= min_s r_s.
// A lattice folds where det J changes sign; the injectivity certificate (ffd/Injectivity.h)
// decides each evaluation, and this bound, kept above a positive ratio, keeps the optimizer's
// iterates away from the fold instead of failing evaluations on it. At the baseline every ratio
// is 1 and g = 1 - ln(N) / rho for N samples.
#include <array>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Sparse>

#include "ffd/FfdModel.h"

namespace aero::ffd {

/// Where thickness is measured: stations (y) times chord fractions of each station's section,
/// and/or explicit planform points (x, y). Thickness is measured along z.
struct ThicknessSpec {
    std::vector<double> stations;
    std::vector<double> chordFractions;         // in (0, 1): from the section's smallest x (0) to its largest (1)
    std::vector<std::array<double, 2>> points;  // (x, y)
};

struct ThicknessPoint {
    std::string name;            // e.g. "thickness y=0.5 x/c=0.3" or "thickness (0.2, 0.5)"
    double x = 0, y = 0;         // the planform point
    std::vector<std::pair<int, double>> weights;  // unique control point -> R_top - R_bottom
    int topPatch = -1, bottomPatch = -1;
    std::array<double, 2> topUv{0, 0}, bottomUv{0, 0};
    double baseline = 0;         // thickness of the baseline geometry
};

/// The thickness constraints of a model: located on construction (throws GeometryError naming the
/// station or point when the surface is not found both above and below it, or when a section has
/// no extent), then evaluated for any design.
class ThicknessConstraints {
public:
    ThicknessConstraints(const FfdModel& model, const ThicknessSpec& spec);

    const std::vector<ThicknessPoint>& points() const { return points_; }
    int size() const { return static_cast<int>(points_.size()); }

    /// Thickness of point k at design v; templated for complex step.
    template <class T>
    T thickness(int k, std::span<const T> v) const;
    /// t_k(v) / t_k(baseline) for every point.
    std::vector<double> ratios(std::span<const double> v) const;
    /// d(t_k / t_k baseline)/dv, one row per point (each of design size), exact.
    std::vector<std::vector<double>> ratioGradients(std::span<const double> v) const;

private:
    template <class T>
    std::array<T, 3> difference(const ThicknessPoint& p, std::span<const T> unique) const;

    const FfdModel& model_;
    Eigen::SparseMatrix<double> dAdv_;
    std::vector<ThicknessPoint> points_;
};

/// The smooth lower bound of every lattice's Jacobian ratio (the KS function above). Throws
/// GeometryError naming the lattice for a rational lattice (the bound is built for polynomial
/// maps) or a baseline lattice whose det J vanishes at a sample.
class LatticeJacobianBound {
public:
    explicit LatticeJacobianBound(const FfdModel& model, int samplesPerSpan = 2, double rho = 100);

    int sampleCount() const { return static_cast<int>(samples_.size()); }
    double rho() const { return rho_; }
    /// g(v); templated for complex step.
    template <class T>
    T value(std::span<const double> vReal, std::span<const T> v) const;
    double value(std::span<const double> v) const { return value<double>(v, v); }
    /// The smallest ratio r_s at v, and where (lattice and world point of the baseline sample).
    struct Minimum {
        double ratio = 0;
        int lattice = -1;
        std::array<double, 3> xi{0, 0, 0};
    };
    Minimum minimum(std::span<const double> v) const;
    /// dg/dv, exact.
    std::vector<double> gradient(std::span<const double> v) const;

private:
    struct Sample {
        int lattice = 0;
        std::array<double, 3> xi{0, 0, 0};
        std::vector<int> controls;             // lattice control indices with non-zero basis
        std::vector<std::array<double, 3>> dN;  // their basis gradients
        double baseline = 0;                   // sign-normalized det J of the baseline lattice
        double sign = 1;                       // the lattice's orientation
    };
    template <class T>
    std::vector<T> ratiosOf(std::span<const T> v) const;

    const FfdModel& model_;
    double rho_;
    std::vector<Sample> samples_;
    std::vector<Eigen::SparseMatrix<double>> dBdv_;  // per lattice
};

}  // namespace aero::ffd
