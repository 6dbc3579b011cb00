#pragma once
// Geometry for ParaView: sampled patches, their control nets and FFD lattices as structured
// blocks of a VTK multiblock file, with displacement fields against a baseline.
#include <vector>

#include "ffd/Lattice.h"
#include "geometry/PatchSet.h"
#include "io/VtkXml.h"

namespace aero::io {

/// Groups "patches" (each patch sampled samples x samples over its whole parameter rectangle,
/// point field "displacement" when a baseline is given and, when any patch is trimmed,
/// "inside_trim": 1 inside the patch's trim, 0 outside), "control_nets" and "lattices" (point
/// field "displacement" when baseline lattices are given). Baselines may be null; if given they
/// must match in sizes.
std::vector<MultiBlockGroup> geometryBlocks(const geometry::PatchSet& set, const geometry::PatchSet* baseline,
                                            const std::vector<ffd::Lattice>& lattices,
                                            const std::vector<ffd::Lattice>* baselineLattices, int samples = 33);

}  // namespace aero::io
