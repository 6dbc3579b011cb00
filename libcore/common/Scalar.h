#pragma once
// Helpers that let numerics templated on the scalar type (double, std::complex<double>,
// later a forward-mode dual) branch on the real part, e.g. for knot-span search.
#include <complex>

namespace aero {

inline double realPart(double x) { return x; }
inline double realPart(const std::complex<double>& z) { return z.real(); }

}  // namespace aero
