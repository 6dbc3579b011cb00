#include <complex>

#include "flow/bc/BoundaryFlux.h"

namespace aero::flow {

// The symmetry plane is a slip wall for the Euler equations: the mirrored state has the same
// pressure and the opposite normal velocity, so only pressure crosses the plane.
template <class T>
void symmetryFlux(const T* q, const T* qOther, const T* n, const T* nhat, const FreeStream& fs,
                  T* flux) {
    slipWallFlux(q, qOther, n, nhat, fs, flux);
}

#define AERO_INSTANTIATE(T) \
    template void symmetryFlux<T>(const T*, const T*, const T*, const T*, const FreeStream&, T*);
AERO_FLOW_SCALARS(AERO_INSTANTIATE)
#undef AERO_INSTANTIATE

}  // namespace aero::flow
