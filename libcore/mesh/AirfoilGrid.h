#pragma once
// A two-block O-grid around a NACA 4-digit airfoil for quasi-2D flow validation: the airfoil
// lies in the X-Z plane (X chordwise downstream, leading edge at the origin, chord 1, Z up) and
// the grid is extruded a short span along +Y, so the flow solver sees a 3D grid a few nodes
// thick with symmetry planes on both Y faces.
//
// Surface nodes are uniform in the angle sigma of x = (1 + cos sigma) / 2 (sigma = 0 trailing
// edge, pi leading edge, 2 pi trailing edge again), which clusters them at both edges. Away from
// the wall the grid lines leave the surface along its normal and bend over to straight rays
// ending on the farfield circle (centre (0.5, 0), radius R) at the same angle sigma; the
// distance from the wall grows geometrically from the wall spacing. Block "upper" runs i from
// the trailing edge over the upper surface to the leading edge, block "lower" from the leading
// edge under the lower surface back to the trailing edge; j runs from the wall to the farfield,
// k along +Y (right-handed). The blocks meet on the cuts from the leading and trailing edges to
// the farfield, whose nodes coincide bit for bit.
#include <array>
#include <string>
#include <vector>

#include "mesh/MultiBlock.h"
#include "mesh/StructuredGrid.h"

namespace aero::mesh {

struct AirfoilGridOptions {
    std::string naca = "0012";   // 4 digits MPTT: max camber M %, its position P/10, thickness TT %
    int aroundNodes = 65;        // nodes around the airfoil, the trailing edge counted at both
                                 // ends (odd, >= 9): each block has (aroundNodes + 1) / 2 along i
    int normalNodes = 33;        // nodes from the wall to the farfield (>= 3)
    int spanNodes = 2;           // node layers along Y (>= 2)
    double span = 1.0;           // extent along Y, chords (> 0). The flow is 2D whatever the
                                 // span, but the solver's convergence is not: on 65 x 33 nodes,
                                 // span 1 converges in 30 iterations, 0.1 and 10 need 50-80
    double farfieldRadius = 50;  // farfield circle radius about mid-chord, chords (> 2)
    double wallSpacing = 4e-3;   // first grid spacing off the wall, chords (> 0, < radius / normalNodes);
                                 // scaled per grid line by its length / radius (within 1 %)
    double blendLength = 0.5;    // distance, chords, over which grid lines turn from the wall
                                 // normal to the straight ray to the farfield (> 0)
};

struct AirfoilGrid {
    std::vector<StructuredGrid> blocks;              // "upper", "lower"
    std::vector<std::array<FaceBoundary, 6>> faces;  // per block: j = 0 Wall, j = max Farfield,
                                                     // k faces Symmetry, i faces Interface
    std::vector<NodePair> interfaceNodes;            // coincident nodes of the two cuts
};

/// NACA 4-digit surface point at sigma in [0, 2 pi] (see the header comment), chord 1:
/// out = (x, z). Thickness with the closed trailing edge (-0.1036 x^4). Throws CaseError naming
/// `naca` if it is not 4 digits or the thickness is 0.
std::array<double, 2> nacaPoint(const std::string& naca, double sigma);

/// The grid of `o`. Throws CaseError naming the option on an invalid value.
AirfoilGrid makeAirfoilGrid(const AirfoilGridOptions& o = {});

}  // namespace aero::mesh
