#pragma once
// The flow solver's view of a multiblock structured mesh: block sizes, where each block's nodes
// start in the global node numbering, the boundary condition of every face, and the interface
// node pairs grouped by the pair of faces they join. Interface nodes are NOT merged: both blocks
// keep their coincident node and SATs couple them (the paper's SBP-SAT approach).
#include <array>
#include <string>
#include <vector>

#include "mesh/MultiBlock.h"
#include "mesh/StructuredGrid.h"

namespace aero::flow {

struct FlowBlock {
    std::string name;
    std::array<int, 3> dims{0, 0, 0};  // nodes along i, j, k (each >= 2)
    long offset = 0;                   // first global node of the block
    std::array<mesh::FaceBoundary, 6> faces;
    /// Per wall face: the wall junction (FlowMesh::wallJunctions) of every face node in
    /// faceNodes order, -1 for none; empty when the face has no junction node.
    std::array<std::vector<int>, 6> junction;

    long nodeCount() const { return static_cast<long>(dims[0]) * dims[1] * dims[2]; }
};

/// The coincident nodes of one interface: face `faceA` of block `blockA` against face `faceB` of
/// block `blockB`; `nodes` holds (local node in A, local node in B) pairs.
struct InterfacePatch {
    int blockA = 0, faceA = 0, blockB = 0, faceB = 0;
    std::vector<std::array<long, 2>> nodes;
};

/// Coincident wall nodes of several blocks (a wall node on an interface): (global node, wall
/// face) per member. Each block's metric normal there comes from one-sided tangential differences
/// at its edge and is tilted by O(h) from the wall's normal, in opposite senses on the two sides,
/// so the slip-wall SATs use a shared normal instead (wallJunctionNormals, Residual.h).
struct WallJunction {
    std::vector<std::array<long, 2>> members;
};

struct FlowMesh {
    std::vector<FlowBlock> blocks;
    std::vector<InterfacePatch> interfaces;
    std::vector<WallJunction> wallJunctions;
    long nodeCount = 0;
};

/// Face f (0 i=0, 1 i=max, 2 j=0, 3 j=max, 4 k=0, 5 k=max): its normal direction and side.
inline int faceDirection(int f) { return f / 2; }
inline bool faceIsMax(int f) { return f % 2 == 1; }
/// (i, j, k) of local node n of a block with `dims` (i fastest).
inline std::array<int, 3> nodeIndex(const std::array<int, 3>& dims, long n) {
    return {static_cast<int>(n % dims[0]), static_cast<int>((n / dims[0]) % dims[1]),
            static_cast<int>(n / (static_cast<long>(dims[0]) * dims[1]))};
}
/// Whether local node n of a block with `dims` lies on face f.
bool onFace(const std::array<int, 3>& dims, long n, int f);
/// Local nodes of face f, the lower tangential index fastest.
std::vector<long> faceNodes(const std::array<int, 3>& dims, int f);
/// Position of local node n (which lies on face f) in faceNodes(dims, f).
long faceNodeIndex(const std::array<int, 3>& dims, int f, long n);

/// Builds the layout from blocks (offsets are recomputed) and interface node pairs (block and
/// local node indices; any order of the two sides). Every pair is assigned to the face pair it
/// lies on, and wall nodes joined through pairs (directly or via other blocks) form the wall
/// junctions. Throws GeometryError naming the block and face if a pair fits no interface face or
/// several, or if an interface face's nodes are not all paired.
FlowMesh makeFlowMesh(std::vector<FlowBlock> blocks, const std::vector<mesh::NodePair>& pairs);

/// The layout of a mesh::MultiBlockMesh whose grids are `grids` (from regenerateAll): dims from
/// the grids, faces and interface pairs from the mesh.
FlowMesh makeFlowMesh(const mesh::MultiBlockMesh& m, const std::vector<mesh::StructuredGrid>& grids);

/// Grid coordinates in the global node order, 3 per node (x, y, z).
std::vector<double> gatherCoordinates(const FlowMesh& fm,
                                      const std::vector<mesh::StructuredGrid>& grids);

/// Each node's group when the blocks are split into `groups` runs of consecutive blocks of
/// about equal node count (a block joins the group holding its middle node); for the parallel
/// ILU ordering (BlockIlu.h).
std::vector<int> blockGroups(const FlowMesh& fm, int groups);

}  // namespace aero::flow
