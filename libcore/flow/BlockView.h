#pragma once
// The one layout of structured-block node data in libcore/flow: a block of dims[0] x dims[1] x
// dims[2] nodes stores `width` values per node, [k][j][i][width] contiguous, i fastest (the same
// node order as mesh::StructuredGrid). A multiblock field is the blocks one after the other
// (FlowMesh::blocks[b].offset gives the first node of block b).
#include <array>

namespace aero::flow {

template <class T>
struct BlockView {
    T* data = nullptr;
    std::array<int, 3> dims{0, 0, 0};
    int width = 1;

    long node(int i, int j, int k) const {
        return i + static_cast<long>(dims[0]) * (j + static_cast<long>(dims[1]) * k);
    }
    T* at(int i, int j, int k) const { return data + width * node(i, j, k); }
    T* at(long n) const { return data + width * n; }
    long nodeCount() const { return static_cast<long>(dims[0]) * dims[1] * dims[2]; }
    /// Node stride along direction d (0 i, 1 j, 2 k).
    long stride(int d) const {
        return d == 0 ? 1 : (d == 1 ? dims[0] : static_cast<long>(dims[0]) * dims[1]);
    }
};

}  // namespace aero::flow
