#pragma once
// The embedding F^-1: parameters of every geometry control point in its lattice, and the
// deformation F~ that re-evaluates them on a moved lattice (Section III.A, Eq. 3-4).
#include <Eigen/SparseCore>
#include <vector>

#include "ffd/Lattice.h"
#include "geometry/Topology.h"
#include "nurbs/Inversion.h"

namespace aero::ffd {

struct EmbeddingOptions {
    double tolerance = 1e-12;  // world-space |V(xi) - t| for a point to count as embedded
    int maxIterations = 50;
};

/// A point that could not be embedded: outside the lattice, or Newton did not converge.
struct EmbeddingFailure {
    int point = -1;         // unique control-point index
    int patch = -1;         // first patch that holds it
    double distance = 0;    // world-space residual |V(xi) - t|
    bool outside = false;   // true: outside the lattice; false: not converged inside
};

/// Embedding of the unique control points of a patch set in one lattice.
struct Embedding {
    geometry::ControlPointIndex index;   // non-unique <-> unique control points
    std::vector<int> points;             // unique indices embedded in this lattice
    std::vector<double> params;          // 3 per embedded point: (xi, eta, zeta)
    std::vector<EmbeddingFailure> failures;
    double maxError = 0;                 // largest |V(xi) - t| over embedded points
    int iterationsMax = 0;
    double seconds = 0;
};

/// Embeds the unique control points of the patches in `patches` (all if empty). Points that fail
/// are listed in `failures` (never dropped silently) and not embedded.
Embedding embed(const geometry::PatchSet& set, const Lattice& lattice, const std::vector<int>& patches = {},
                const EmbeddingOptions& o = {});

/// F~: writes V(xi; B) of every embedded point into the unique points `unique` (3 per point),
/// leaving the others untouched. Batched, OpenMP.
void deformUnique(const Lattice& lattice, const Embedding& e, std::vector<double>& unique);

/// Scatters unique control points back into the patches (all copies of a point move alike,
/// so shared patch edges stay identical).
void scatter(const geometry::ControlPointIndex& index, const std::vector<double>& unique, geometry::PatchSet& set);

/// dA/dB of Eq. 3 as a scalar sparse matrix W (embedded points x lattice control points):
/// d A_p / d B_a = W(p, a) I_3. Row p follows e.points; rational lattices included.
Eigen::SparseMatrix<double, Eigen::RowMajor> sensitivity(const Lattice& lattice, const Embedding& e);

}  // namespace aero::ffd
