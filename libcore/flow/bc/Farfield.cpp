#include <complex>

#include "flow/bc/BoundaryFlux.h"

namespace aero::flow {

template <class T>
void farfieldFlux(const T* q, const T*, const T* n, const T*, const FreeStream& fs, T* flux) {
    const auto s = fs.state();
    const T qinf[kVars] = {s[0], s[1], s[2], s[3], s[4]};
    upwindFlux(q, qinf, n, fs.gamma, flux);
}

template <class T>
void entropyFarfieldFlux(const T* q, const T*, const T* n, const T*, const FreeStream& fs, T* flux) {
    const auto s = fs.state();
    const T qinf[kVars] = {s[0], s[1], s[2], s[3], s[4]};
    entropyUpwindFlux(q, qinf, n, fs.gamma, flux);
}

#define AERO_INSTANTIATE(T)                                                                        \
    template void farfieldFlux<T>(const T*, const T*, const T*, const T*, const FreeStream&, T*);   \
    template void entropyFarfieldFlux<T>(const T*, const T*, const T*, const T*, const FreeStream&, T*);
AERO_FLOW_SCALARS(AERO_INSTANTIATE)
#undef AERO_INSTANTIATE

}  // namespace aero::flow
