#pragma once
// VTK XML output for ParaView, written without VTK: structured grids (.vts, "StructuredGrid"
// version 1.0) and multiblock files (.vtm, "vtkMultiBlockDataSet" version 1.0) that point to them.
// Arrays are Float64, appended raw binary, little endian, header_type UInt64 (exact, compact).
#include <array>
#include <string>
#include <vector>

namespace aero::io {

/// A named array with `components` values per point or cell, tuples contiguous:
/// values.size() == components * count.
struct VtkField {
    std::string name;
    int components = 1;
    std::vector<double> values;
};

/// One structured grid piece. Points per direction in `dims` (use 1 for surfaces and curves);
/// `points` is 3 * dims[0]*dims[1]*dims[2] doubles [k][j][i][xyz] (i fastest). A cell field has
/// one tuple per cell, prod(max(dims[d] - 1, 1)) tuples, in the same order.
struct StructuredBlock {
    std::string name;  // shown in ParaView's block tree
    std::array<int, 3> dims{1, 1, 1};
    std::vector<double> points;
    std::vector<VtkField> pointData;
    std::vector<VtkField> cellData;
};

struct MultiBlockGroup {
    std::string name;
    std::vector<StructuredBlock> blocks;
};

/// Writes `path` (must end in .vtm; its folder must exist) and one .vts per block in a folder
/// next to it named after the file stem: out/deformed.vtm + out/deformed/<group>_<index>.vts,
/// with <group> the group name restricted to [A-Za-z0-9._-] (other characters become '_';
/// groups that would share a file name get "-2", "-3", ...). Every block is checked before
/// anything is written. Each file is replaced whole (temporary file + rename); stale pieces of an
/// earlier, larger output are left in the folder.
/// Throws Error naming the group, block and field if sizes are inconsistent (dims < 1, points or
/// values of the wrong length, components < 1, empty or repeated field names), and InputError
/// naming the path if the extension is wrong or a file or folder cannot be written.
void writeVtm(const std::string& path, const std::vector<MultiBlockGroup>& groups);

/// Writes one structured grid file; `path` must end in .vts. Throws as writeVtm.
void writeVts(const std::string& path, const StructuredBlock& block);

}  // namespace aero::io
