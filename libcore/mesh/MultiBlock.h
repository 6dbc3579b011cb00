#pragma once
// The second FFD level (Section III.B.2): every block of a structured multiblock grid is a
// B-spline volume whose control net is part of one global control grid b. The wall face of a
// block's control net IS the geometry's control net: b holds the unique geometry control points
// among its nodes (A = [0 I] b, one storage), and blocks that meet share their interface control
// nodes, so the regenerated grid nodes on interfaces coincide.
#include <array>
#include <string>
#include <vector>

#include "mesh/StructuredGrid.h"
#include "nurbs/Volume.h"

namespace aero::mesh {

enum class BoundaryKind { Wall, Farfield, Symmetry, Interface };

/// "wall", "farfield", "symmetry", "interface".
const char* boundaryName(BoundaryKind k);
/// Inverse of boundaryName; throws CaseError naming `key` for an unknown name.
BoundaryKind boundaryFromName(const std::string& name, const std::string& key);

struct FaceBoundary {
    BoundaryKind kind = BoundaryKind::Farfield;
    int neighbour = -1;      // Interface: the neighbour block
    int neighbourFace = -1;  // Interface: its face (0..5, see Face)
};

/// One block: a B-spline volume over global control nodes, and the parameters of its grid nodes.
struct ControlBlock {
    std::string name;
    std::array<int, 3> degree{3, 3, 3};
    std::array<int, 3> count{0, 0, 0};
    std::array<std::vector<double>, 3> knots;
    std::vector<int> nodes;  // global control node of local (i, j, k), [k][j][i]
    std::array<FaceBoundary, 6> faces;
    std::array<std::vector<double>, 3> samples;  // grid-node parameters per direction

    int local(int i, int j, int k) const { return i + count[0] * (j + count[1] * k); }
    std::array<int, 3> gridDims() const {
        return {static_cast<int>(samples[0].size()), static_cast<int>(samples[1].size()),
                static_cast<int>(samples[2].size())};
    }
};

/// Grid nodes that are the same point in two blocks (interfaces): block a's node == block b's node.
struct NodePair {
    int blockA = 0;
    long nodeA = 0;
    int blockB = 0;
    long nodeB = 0;
};

struct MultiBlockMesh {
    std::vector<double> control;   // b: 3 per global control node
    std::vector<int> surfaceNode;  // unique geometry control point -> its global control node
    std::vector<ControlBlock> blocks;
    std::vector<NodePair> interfaceNodes;  // coincident grid nodes, owner (a) first

    int controlCount() const { return static_cast<int>(control.size() / 3); }
    long gridNodeCount() const;
};

/// Per block, which of its 6 faces (Face order) are walls.
std::vector<std::array<bool, 6>> wallFaces(const MultiBlockMesh& m);

/// The block's B-spline volume with its control points gathered from b.
nurbs::Volume<double> blockVolume(const MultiBlockMesh& m, int block);

/// x = N b for one block (separable tensor-product evaluation).
void regenerate(const MultiBlockMesh& m, int block, StructuredGrid& out);
/// The transpose of regenerate: controlGradient (3 per global control node) += N^T gridGradient
/// (3 per grid node of the block, its node order). Sum factorization in the reverse order of
/// the evaluation (i, then j, then k contracted).
void regenerateTranspose(const MultiBlockMesh& m, int block, const double* gridGradient,
                         std::vector<double>& controlGradient);
/// All blocks (OpenMP over planes inside each), then interface nodes copied from their owner so
/// they coincide bit for bit.
std::vector<StructuredGrid> regenerateAll(const MultiBlockMesh& m);
void regenerateAll(const MultiBlockMesh& m, std::vector<StructuredGrid>& grids);

/// Finds coincident grid nodes on interface faces (within `tolerance`) and stores them in
/// m.interfaceNodes; throws GeometryError naming the blocks and faces if an interface face has
/// nodes without a partner (mismatched interfaces).
void matchInterfaces(MultiBlockMesh& m, const std::vector<StructuredGrid>& grids,
                     double tolerance = 1e-9);

/// Throws GeometryError naming block and face on inconsistent data (sizes, node indices,
/// interface references that are not mutual).
void validate(const MultiBlockMesh& m);

}  // namespace aero::mesh
