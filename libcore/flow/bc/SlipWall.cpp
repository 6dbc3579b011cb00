#include <complex>

#include "flow/bc/BoundaryFlux.h"

namespace aero::flow {

// The upwind flux against the mirror state (normal velocity reversed), in closed form: with the
// mean state's normal velocity zero, only pressure crosses the wall,
//   F* = (0, p* n, 0),  p* = p + rho u_n (u_n + c),  u_n = u . n / |n|  (n outward, into the wall),
// the linearized Riemann pressure of flow running into (u_n > 0) or away from the wall.
template <class T>
void slipWallFlux(const T* q, const T*, const T* n, const FreeStream& fs, T* flux) {
    using std::sqrt;
    const T p = pressure(q, fs.gamma);
    const T c = sqrt(fs.gamma * p / q[0]);
    const T un = (q[1] * n[0] + q[2] * n[1] + q[3] * n[2]) / (q[0] * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]));
    const T pw = p + q[0] * un * (un + c);
    flux[0] = 0.0;
    flux[1] = pw * n[0];
    flux[2] = pw * n[1];
    flux[3] = pw * n[2];
    flux[4] = 0.0;
}

template void slipWallFlux<double>(const double*, const double*, const double*, const FreeStream&,
                                   double*);
template void slipWallFlux<std::complex<double>>(const std::complex<double>*,
                                                 const std::complex<double>*,
                                                 const std::complex<double>*, const FreeStream&,
                                                 std::complex<double>*);

}  // namespace aero::flow
