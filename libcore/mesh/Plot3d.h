#pragma once
// Multi-block 3D Plot3D grid files ("whole" layout: all x of a block, then all y, then all z,
// i fastest; no iblank written).
//   formatted (ASCII): nblocks, then idim jdim kdim per block, then the coordinates, all
//     whitespace-separated (commas also accepted on reading; Fortran 'D' exponents too).
//     Written with 17 significant digits, locale-independent: the round trip is exact.
//   unformatted (binary): Fortran sequential records, little-endian, 4-byte record markers
//     (byte count before and after each record): [int32 nblocks] [int32 dims x 3 nblocks]
//     [float64 x, y, z] per block. The round trip is bitwise.
// Reading also accepts binary files with float32 coordinates and/or an int32 iblank array
// after z (iblank is discarded). Not supported: single-block files without the block count,
// 2D files, big-endian files, records over 2 GiB (gfortran subrecords); these are reported.
#include <string>
#include <vector>

#include "mesh/StructuredGrid.h"

namespace aero::mesh {

/// Writes blocks to `path` (via path + ".tmp", then renamed), binary or formatted. Each block
/// needs dims >= 1 and xyz of 3 * nodeCount values. Throws GeometryError for a bad block
/// (naming it), InputError if the file cannot be written.
void writePlot3d(const std::string& path, const std::vector<StructuredGrid>& blocks, bool binary);

/// Reads a multi-block 3D Plot3D file, binary or formatted (detected from the first record
/// marker). Blocks are named "block0", "block1", ... Throws InputError naming the file and the
/// place (block, coordinate, value index, line or byte offset) for a missing or truncated
/// file, bad dims, non-numeric or non-finite data, mismatched record markers or trailing data.
std::vector<StructuredGrid> readPlot3d(const std::string& path);

}  // namespace aero::mesh
