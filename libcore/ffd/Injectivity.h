#pragma once
// Injectivity of an FFD lattice (Section III.B.1): the Jacobian determinant of the lattice
// map must keep one sign everywhere, or embedded geometry may self-intersect.
#include <array>

#include "ffd/Lattice.h"

namespace aero::ffd {

struct InjectivityOptions {
    int samplesPerSpan = 4;   // density of the sampled minimum of det J
    int maxRefinements = 3;   // knot-insertion levels that sharpen the certificate
};

struct InjectivityReport {
    bool injective = false;   // the certificate holds (polynomial lattices) or, for rational
                              // lattices, the sampled det J keeps its sign
    bool certified = false;   // proven: every triple product of control-net differences that
                              // det J is a convex combination of has the right sign
    int refinements = 0;      // knot-insertion levels the certificate needed
    double minJacobian = 0;   // smallest sampled det J (sign-normalized: > 0 is good)
    double relativeMinJacobian = 0;  // minJacobian / mean |det J| over the samples
    std::array<double, 3> minAt{0, 0, 0};       // parameters of the sampled minimum
    std::array<double, 3> minPoint{0, 0, 0};    // its world position
    std::array<double, 3> failedCell{0, 0, 0};  // parameters (cell centre) where the certificate
                                                // failed at the finest level, if it failed
};

/// Sufficient test: det J(xi) = sum a_i b_j c_k det(D0_i, D1_j, D2_k) with non-negative
/// weights, where D0, D1, D2 are the control-point differences of the three derivative
/// volumes (trilinearity of the determinant). If all triple products active on a knot cell
/// have the orientation's sign (that of the image volume), det J cannot vanish there. Failing cells trigger
/// uniform knot refinement (exact, map unchanged), which converges the differences to the
/// derivatives. The sampled minimum is reported alongside.
InjectivityReport checkInjectivity(const Lattice& lattice, const InjectivityOptions& o = {});

}  // namespace aero::ffd
