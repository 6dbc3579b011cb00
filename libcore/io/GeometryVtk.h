#pragma once
// Geometry for ParaView: sampled patches, their control nets and FFD lattices as structured
// blocks of a VTK multiblock file, with displacement fields against a baseline.
#include <vector>

#include "ffd/Lattice.h"
#include "geometry/PatchSet.h"
#include "io/VtkXml.h"

namespace aero::io {

/// Groups "patches" (each patch sampled samples x samples, point field "displacement" when a
/// baseline is given), "control_nets" and "lattices" (point field "displacement" when baseline
/// lattices are given). Baselines may be null; if given they must match in sizes.
std::vector<MultiBlockGroup> geometryBlocks(const geometry::PatchSet& set, const geometry::PatchSet* baseline,
                                            const std::vector<ffd::Lattice>& lattices,
                                            const std::vector<ffd::Lattice>* baselineLattices, int samples = 33);

}  // namespace aero::io
