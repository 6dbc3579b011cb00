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

template void entropyFarfieldFlux<double>(const double*, const double*, const double*, const double*,
                                          const FreeStream&, double*);
template void entropyFarfieldFlux<std::complex<double>>(const std::complex<double>*,
                                                        const std::complex<double>*,
                                                        const std::complex<double>*,
                                                        const std::complex<double>*, const FreeStream&,
                                                        std::complex<double>*);
template void farfieldFlux<double>(const double*, const double*, const double*, const double*,
                                   const FreeStream&, double*);
template void farfieldFlux<std::complex<double>>(const std::complex<double>*,
                                                 const std::complex<double>*,
                                                 const std::complex<double>*,
                                                 const std::complex<double>*, const FreeStream&,
                                                 std::complex<double>*);
template void entropyFarfieldFlux<MetricDual>(const MetricDual*,
                                                        const MetricDual*,
                                                        const MetricDual*,
                                                        const MetricDual*, const FreeStream&,
                                                        MetricDual*);
template void farfieldFlux<MetricDual>(const MetricDual*,
                                                 const MetricDual*,
                                                 const MetricDual*,
                                                 const MetricDual*, const FreeStream&,
                                                 MetricDual*);
template void entropyFarfieldFlux<StateDual>(const StateDual*,
                                                        const StateDual*,
                                                        const StateDual*,
                                                        const StateDual*, const FreeStream&,
                                                        StateDual*);
template void farfieldFlux<StateDual>(const StateDual*,
                                                 const StateDual*,
                                                 const StateDual*,
                                                 const StateDual*, const FreeStream&,
                                                 StateDual*);

}  // namespace aero::flow
