#pragma once
// The paper's sample FFD model, shared by the FFD tests: a 6x6x2 lattice (cubic X, Y; linear Z)
// around the half-sphere, 6 spanwise stations; the root translates in X, the others in X and Y
// (11 translations), every lattice point scales vertically in its section (72), one taper per
// station (6): 89 variables.
#include "ffd/FfdModel.h"
#include "geometry/HalfSphere.h"

namespace aero::test {

inline ffd::FfdModel paperModel() {
    const auto set = geometry::makeHalfSphere();
    ffd::LatticeSpec spec;
    spec.name = "body";
    spec.lattice = ffd::makeLattice(ffd::boxAround(set, {}, {0.05, 0.0, 0.05}), {6, 6, 2}, {3, 3, 1});
    ffd::FfdModel m(set, {spec});
    ffd::StationSpec st;
    st.direction = 1;
    st.bits = {"001", "011", "011", "011", "011", "011"};
    m.design().addStations(st);
    return m;
}

}  // namespace aero::test
