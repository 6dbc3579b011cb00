#pragma once
// One structured block of grid nodes: the layout every mesh and flow routine shares.
// Node (i, j, k) of a dims[0] x dims[1] x dims[2] block is at xyz[3 * (i + dims[0] * (j + dims[1] * k))],
// i fastest ([k][j][i][xyz], contiguous). Cells are (i, j, k) .. (i+1, j+1, k+1), numbered alike
// over (dims[0]-1) x (dims[1]-1) x (dims[2]-1).
#include <array>
#include <string>
#include <vector>

namespace aero::mesh {

struct StructuredGrid {
    std::string name;
    std::array<int, 3> dims{0, 0, 0};
    std::vector<double> xyz;

    long nodeCount() const { return static_cast<long>(dims[0]) * dims[1] * dims[2]; }
    long cellCount() const {
        return static_cast<long>(dims[0] - 1) * (dims[1] - 1) * (dims[2] - 1);
    }
    long node(int i, int j, int k) const { return i + static_cast<long>(dims[0]) * (j + static_cast<long>(dims[1]) * k); }
    long cell(int i, int j, int k) const {
        return i + static_cast<long>(dims[0] - 1) * (j + static_cast<long>(dims[1] - 1) * k);
    }
    const double* at(int i, int j, int k) const { return &xyz[3 * node(i, j, k)]; }
    double* at(int i, int j, int k) { return &xyz[3 * node(i, j, k)]; }
};

/// Faces of a block: 0 i = 0, 1 i = max, 2 j = 0, 3 j = max, 4 k = 0, 5 k = max.
enum class Face { IMin = 0, IMax = 1, JMin = 2, JMax = 3, KMin = 4, KMax = 5 };

}  // namespace aero::mesh
