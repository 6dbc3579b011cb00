#pragma once
// Internal to aeroform_mesh: the trilinear hexahedral element of the elasticity move - what the
// move's assembly and the mesh adjoint (Elasticity.cpp) take from HexElement.cpp besides the
// public part in Elasticity.h (cellMetrics, cellModulus, hexStiffness, hexBilinear, ...).
#include "mesh/Elasticity.h"

namespace aero::mesh {

// Corner coordinates of control cell (i, j, k) of a block, VTK order.
inline void cellCorners(const MultiBlockMesh& m, const ControlBlock& b, int i, int j, int k, double* x, int* nodes) {
    const int off[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int a = 0; a < 8; ++a) {
        const int g = b.nodes[b.local(i + off[a][0], j + off[a][1], k + off[a][2])];
        nodes[a] = g;
        for (int c = 0; c < 3; ++c) x[3 * a + c] = m.control[3 * static_cast<std::size_t>(g) + c];
    }
}

// Calls fn(x, nodes) for every control cell of block b in cell order (i fastest), with the
// cell's corner coordinates x (8 x 3, VTK order) and global node numbers.
template <class Fn>
void forEachCell(const MultiBlockMesh& m, const ControlBlock& b, Fn&& fn) {
    double x[24];
    int nodes[8];
    for (int k = 0; k + 1 < b.count[2]; ++k) {
        for (int j = 0; j + 1 < b.count[1]; ++j) {
            for (int i = 0; i + 1 < b.count[0]; ++i) {
                cellCorners(m, b, i, j, k, x, nodes);
                fn(x, nodes);
            }
        }
    }
}

/// The cell's volume: the sum over the 2x2x2 Gauss points of det J.
template <class T>
T cellVolume(const T* x);

/// cellModulus for a cell whose volume is known (the assembly computes every volume first, for
/// their mean).
template <class T>
T modulusWithVolume(const T* x, T vol, T meanVolume, const ElasticityOptions& o);

/// The physical shape-function gradients and det J at the 8 Gauss points of one cell, computed
/// once for the modulus's derivative and every functional's bilinear-form derivative.
struct CellGauss {
    double G[8][8][3];  // per Gauss point: G(a, c) = dN_a / dx_c
    double det[8];
    explicit CellGauss(const double* x);
};

/// cellModulusGradient with the cell's Gauss data already computed.
double modulusGradient(const double* x, const CellGauss& gauss, double meanVolume, const ElasticityOptions& o,
                       double* dE, double* dVolume, double* volume);

/// hexBilinearGradient with the cell's Gauss data already computed.
double bilinearGradient(const CellGauss& gauss, double nu, const double* a, const double* b, double* grad);

}  // namespace aero::mesh
