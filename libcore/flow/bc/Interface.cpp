#include <complex>

#include "flow/bc/BoundaryFlux.h"

namespace aero::flow {

template <class T>
void interfaceFlux(const T* q, const T* qOther, const T* n, const T*, const FreeStream& fs,
                   T* flux) {
    upwindFlux(q, qOther, n, fs.gamma, flux);
}

template <class T>
void entropyInterfaceFlux(const T* q, const T* qOther, const T* n, const T*, const FreeStream& fs,
                          T* flux) {
    entropyUpwindFlux(q, qOther, n, fs.gamma, flux);
}

#define AERO_INSTANTIATE(T)                                                                        \
    template void interfaceFlux<T>(const T*, const T*, const T*, const T*, const FreeStream&, T*);  \
    template void entropyInterfaceFlux<T>(const T*, const T*, const T*, const T*, const FreeStream&, T*);
AERO_FLOW_SCALARS(AERO_INSTANTIATE)
#undef AERO_INSTANTIATE

}  // namespace aero::flow
