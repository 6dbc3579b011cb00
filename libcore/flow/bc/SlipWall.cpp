#include <complex>

#include "flow/bc/BoundaryFlux.h"

namespace aero::flow {

// The upwind flux against the mirror state (normal velocity reversed) in closed form. With the
// wall's unit normal nhat, u_n = u . nhat and the tangential velocity u_t = u - u_n nhat, the
// wall state has density rho, velocity u_t and the linearized Riemann pressure
//   p* = p + rho u_n (u_n + c)
// of flow running into (u_n > 0) or away from the wall, and F* is its flux through the face n.
// Where nhat is parallel to n (everywhere but at wall junctions) u_t . n = 0 and only pressure
// crosses: F* = (0, p* n, 0).
template <class T>
void slipWallFlux(const T* q, const T*, const T* n, const T* nhat, const FreeStream& fs, T* flux) {
    using std::sqrt;
    const T p = pressure(q, fs.gamma);
    const T c = sqrt(fs.gamma * p / q[0]);
    const T u[3] = {q[1] / q[0], q[2] / q[0], q[3] / q[0]};
    const T un = u[0] * nhat[0] + u[1] * nhat[1] + u[2] * nhat[2];
    const T ut[3] = {u[0] - un * nhat[0], u[1] - un * nhat[1], u[2] - un * nhat[2]};
    const T pw = p + q[0] * un * (un + c);
    const T U = ut[0] * n[0] + ut[1] * n[1] + ut[2] * n[2];
    const T rhoH = fs.gamma / (fs.gamma - 1.0) * pw + 0.5 * q[0] * (ut[0] * ut[0] + ut[1] * ut[1] + ut[2] * ut[2]);
    flux[0] = q[0] * U;
    for (int c3 = 0; c3 < 3; ++c3) flux[1 + c3] = q[0] * ut[c3] * U + pw * n[c3];
    flux[4] = rhoH * U;
}

#define AERO_INSTANTIATE(T) \
    template void slipWallFlux<T>(const T*, const T*, const T*, const T*, const FreeStream&, T*);
AERO_FLOW_SCALARS(AERO_INSTANTIATE)
#undef AERO_INSTANTIATE

}  // namespace aero::flow
