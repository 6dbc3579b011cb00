#pragma once
// A case's second FFD level: the multiblock control grid generated around the baseline geometry,
// moved by linear elasticity to the deformed geometry's wall (when the case deforms it) and the
// grid regenerated from it. Shared by `aeroform-cli mesh`, `aeroform-cli flow` and batch runs.
#include <vector>

#include "mesh/Elasticity.h"
#include "mesh/MultiBlock.h"
#include "mesh/StructuredGrid.h"
#include "study/CaseShape.h"

namespace aero::study {

struct CaseGrid {
    mesh::MultiBlockMesh mesh;               // control grid (moved if the case deforms)
    std::vector<mesh::StructuredGrid> grids; // the regenerated grid, one per block
    bool moved = false;
    mesh::MoveReport move;                   // empty unless moved
    double secondsGenerate = 0, secondsMove = 0, secondsRegenerate = 0;
};

/// Generates, moves (if shape.model) and regenerates the case's grid, logging each stage.
/// Throws GeometryError naming the case when the elasticity solve does not converge.
CaseGrid buildCaseGrid(const io::CaseFile& c, const geometry::PatchSet& baseline, const CaseShape& shape,
                       const Log& log = {});

}  // namespace aero::study
