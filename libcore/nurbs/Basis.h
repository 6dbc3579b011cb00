#pragma once
// B-spline basis functions (Piegl & Tiller, The NURBS Book, A2.1-A2.3).
// A knot vector of a degree-p basis with n functions has n + p + 1 non-decreasing entries,
// clamped: the first and last p + 1 entries are equal. All routines are allocation-free;
// output arrays are owned by the caller.
#include <span>
#include <string_view>
#include <vector>

namespace aero::nurbs {

/// Largest degree the kernel supports (fixed-size stack workspaces).
inline constexpr int kMaxDegree = 9;

/// Throws GeometryError naming `what` unless `knots` is a valid clamped knot vector for
/// `count` basis functions of degree `degree` (finite, non-decreasing, clamped ends,
/// interior multiplicity <= degree, count >= degree + 1, 1 <= degree <= kMaxDegree).
void validateKnotVector(std::span<const double> knots, int degree, int count, std::string_view what);

/// Index s of the knot span with knots[s] <= u < knots[s+1], s in [degree, count-1];
/// u at or beyond the end maps to the last non-empty span, u below the start to the first.
int findSpan(std::span<const double> knots, int degree, int count, double u);

/// The degree+1 non-zero basis values N[s-p..s](u) at span s into N[0..p] (A2.2).
template <class T>
void basisFunctions(std::span<const double> knots, int degree, int span, const T& u, T* N);

/// Basis values and derivatives up to order nd (A2.3): ders[k*(p+1) + j] is the k-th
/// derivative of N[s-p+j]. ders has (nd+1)*(p+1) entries; derivatives above p are zero.
template <class T>
void basisDerivatives(std::span<const double> knots, int degree, int span, const T& u, int nd,
                      T* ders);

/// Uniform clamped knot vector on [0,1] for `count` functions of degree `degree`.
std::vector<double> uniformKnots(int degree, int count);

/// Parameter values sampling every non-empty knot span with `perSpan` intervals, from the first
/// knot to the last (a clamped vector's domain; a kink at a knot stays a sample).
std::vector<double> spanSamples(std::span<const double> knots, int perSpan);

/// The number of non-empty knot spans.
int nonEmptySpans(std::span<const double> knots);

}  // namespace aero::nurbs
