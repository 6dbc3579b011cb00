#pragma once
// Cell quality of structured hexahedral blocks: the numbers that decide whether a generated,
// moved or imported grid may be handed to the flow solver.
//
// Each cell (i, j, k) .. (i+1, j+1, k+1) is read as a trilinear hex. Its 12 edges are taken in
// the +i, +j, +k directions: e_i = x(i+1, ., .) - x(i, ., .), and likewise for j and k. At each
// of the 8 corners, the three edges through that corner, in that orientation, are the columns
// of the trilinear map's Jacobian J (reference cell [0,1]^3) at the corner. Metrics per cell:
//   minJacobian     min over the 8 corners of det[e_i, e_j, e_k]. Units: length^3; equals the
//                   cell volume for a parallelepiped (h^3 for a uniform grid of spacing h).
//   scaledJacobian  min over the 8 corners of det[e_i/|e_i|, e_j/|e_j|, e_k/|e_k|], in [-1, 1],
//                   1 for a box; 0 where an edge at some corner has zero length.
//   orthogonality   1 - max |cos(angle)| over the 24 corner angles between edge pairs (each
//                   face's 4 interior angles, 6 faces), in [0, 1]: 1 when every edge meets
//                   its neighbours at right angles, 0 when two edges at a corner are parallel
//                   or one of them has zero length.
//   aspectRatio     max / min of the three mean edge lengths (mean of the 4 parallel edges of
//                   each direction), >= 1; +inf when a direction's edges all have zero length.
//   skewness        max |cos(angle)| between the cell's principal axes X_d = sum of its four
//                   d-direction edges, in [0, 1]: 0 when the axes are orthogonal (boxes, also
//                   symmetric trapezoids), 1 when two axes are parallel. Unlike orthogonality
//                   it ignores taper and sees only the shear of the cell as a whole.
// Orientation: a right-handed block (det > 0) is required. Some codes accept a left-handed
// block (all determinants negative) as valid; here it is reported as non-positive everywhere,
// because the grid generator produces right-handed blocks and the flow solver assumes them.
// A collapsed edge (e.g. on a polar axis) gives determinant 0 and counts as non-positive too.
#include <array>
#include <complex>
#include <string>
#include <vector>

#include "mesh/StructuredGrid.h"

namespace aero::mesh {

/// Per-cell metrics of one block, each indexed like StructuredGrid::cell(i, j, k).
struct CellQuality {
    std::vector<double> minJacobian;
    std::vector<double> scaledJacobian;
    std::vector<double> orthogonality;
    std::vector<double> aspectRatio;
    std::vector<double> skewness;
};

/// Quality of every cell of `g` (see the header comment for the definitions). OpenMP over k.
/// Throws GeometryError naming the block if a dimension is below 2 or xyz has the wrong size.
CellQuality cellQuality(const StructuredGrid& g);

/// Number of histogram bins per metric.
inline constexpr int kQualityBins = 10;

/// Statistics of one metric over all cells of all blocks. Non-finite values (NaN from NaN
/// coordinates, +inf aspect ratios) count in nonFinite; min and max see +-inf but not NaN,
/// mean and histogram see finite values only.
struct MetricSummary {
    double min = 0, max = 0, mean = 0;
    long nonFinite = 0;
    // Histogram over [lo, hi]: bin b holds [lo + b w, lo + (b+1) w), w = (hi - lo) / bins;
    // values outside the range (and hi itself) go to the end bins.
    double lo = 0, hi = 0;
    std::array<long, kQualityBins> histogram{};
};

/// One cell, located for a human: block index and name, cell (i, j, k), centroid (mean of the
/// 8 corners, grid units) and the value of the metric it was selected by.
struct CellLocation {
    int block = 0;
    std::string blockName;
    std::array<int, 3> cell{0, 0, 0};
    std::array<double, 3> centroid{0, 0, 0};
    double value = 0;
};

/// Histogram ranges: scaledJacobian [-1, 1]; orthogonality and skewness [0, 1]; minJacobian
/// [min, max] of the data; aspectRatio [1, largest finite value]. A zero-width range puts
/// everything in bin 0.
struct QualitySummary {
    long cellCount = 0;
    MetricSummary minJacobian, scaledJacobian, orthogonality, aspectRatio, skewness;
    std::vector<CellLocation> worst;  // lowest scaled Jacobian first (NaN counts as lowest)
    long nonPositiveJacobian = 0;     // cells whose minJacobian is <= 0 or NaN
};

/// Summary of blocks[b] with metrics q[b] (q from cellQuality, same order and sizes); keeps the
/// `worst` cells by scaled Jacobian. Throws Error if q does not match blocks.
QualitySummary summarize(const std::vector<StructuredGrid>& blocks,
                         const std::vector<CellQuality>& q, int worst = 10);

/// Throws GeometryError unless every cell's minJacobian is > 0: the message names the first
/// offending cell in (block, k, j, i) order by block index and name, cell (i, j, k), centroid
/// and value, and gives the total count of such cells. q as for summarize.
void requirePositiveJacobians(const std::vector<StructuredGrid>& blocks,
                              const std::vector<CellQuality>& q);

/// A smooth lower bound of how much any cell corner shrank: over every corner of every cell, g =
/// log(det J / det J_baseline) (the corner Jacobians of cellQuality; `baseline` the same blocks
/// before the move), aggregated by the Kreisselmeier-Steinhauser function
///   KS = m - log(sum exp(-rho (g - m))) / rho,  m = min g,
/// which lies in [m - log(corners) / rho, m]. The design constraint KS >= log(tau) keeps every
/// corner's volume above tau times its baseline's, a margin before the grid folds. -inf when a
/// corner is not positive (then no gradient). With `gradient`: dKS/dx per block (3 per node, the
/// xyz layout of each grid), accumulated in a fixed order (reproducible bit for bit). Throws
/// Error when the blocks do not match the baseline's.
double cornerRatioSmoothMin(const std::vector<StructuredGrid>& grids, const std::vector<StructuredGrid>& baseline,
                            double rho, std::vector<std::vector<double>>* gradient = nullptr);

/// The largest jump of the spacing along a grid line, and where: over every block, direction d
/// and node n with neighbours on both sides along d, the ratio of the longer to the shorter of
/// the two edges a = |x(n) - x(n - e_d)| and b = |x(n + e_d) - x(n)| (+inf when exactly one is
/// zero; two zero edges, a collapsed line, are skipped). A second-order central difference of a
/// smooth field loses its accuracy across such a node: its leading error is (ratio - 1) h f''/2
/// where the uniform grid has none (the coarse half-sphere level with wall spacing 1e-3 has a
/// last radial cell 18.5 times its neighbour, and its flow stalls there).
struct SpacingJump {
    double ratio = 1;                   // >= 1; 1 when no block has a node inside a grid line
    int block = -1;                     // index into the blocks
    std::string blockName;
    int direction = 0;                  // 0 i, 1 j, 2 k
    std::array<int, 3> node{0, 0, 0};   // the node between the two edges
    std::array<double, 3> x{0, 0, 0};   // its coordinates
};
SpacingJump largestSpacingJump(const std::vector<StructuredGrid>& blocks);

/// The sharpest bend of the wall from one grid node to the next, and where: on every wall face
/// (wallFaces[b][f], faces numbered 0 i=0, 1 i=max, 2 j=0, 3 j=max, 4 k=0, 5 k=max), each node's
/// unit normal from the cross product of the two tangential differences (central inside the face,
/// one-sided at its edges), and the angle between the normals of neighbouring face nodes. A wall
/// resolved by the grid turns by a few degrees per node (the half-sphere's coarse level: 3); a
/// fold or a bend tighter than the spacing turns by tens of degrees, and the flow there is not
/// resolved (the optimizer's stalled blended-wing designs: 33-44 degrees). Nodes whose normal is
/// undefined (a collapsed edge) are skipped. Throws Error when wallFaces does not match blocks.
struct WallBend {
    double degrees = 0;                     // 0 when no wall face has two nodes
    int block = -1;                         // index into the blocks
    std::string blockName;
    std::array<int, 3> node{0, 0, 0};       // the first node of the pair
    std::array<int, 3> neighbour{0, 0, 0};  // the second
    std::array<double, 3> x{0, 0, 0};       // the first node's coordinates
};
WallBend sharpestWallBend(const std::vector<StructuredGrid>& blocks, const std::vector<std::array<bool, 6>>& wallFaces);

/// A smooth upper bound of the sharpest wall bend, in degrees, for the optimizer's constraint:
/// the Kreisselmeier-Steinhauser maximum over the node pairs of sharpestWallBend of
/// s = 1 - cos(angle) (smooth where the angle is 0, unlike the angle itself),
///   S = max s + log(sum exp(rho (s - max s))) / rho,   degrees = acos(1 - S),
/// which lies within log(pairs) / rho of the largest s (rho 1000 and 12,000 pairs: within 1.2
/// degrees at 25). With `gradient`: d degrees / dx per block (the xyz layout of each grid),
/// exact. 0 (and a zero gradient) when no wall pair has normals.
double wallBendSmoothMax(const std::vector<StructuredGrid>& blocks, const std::vector<std::array<bool, 6>>& wallFaces,
                         double rho, std::vector<std::vector<double>>* gradient = nullptr);
/// The same on complex coordinates xyz[b] (the layout of blocks[b].xyz): complex-step checks.
std::complex<double> wallBendSmoothMax(const std::vector<StructuredGrid>& blocks,
                                       const std::vector<std::vector<std::complex<double>>>& xyz,
                                       const std::vector<std::array<bool, 6>>& wallFaces, double rho);

}  // namespace aero::mesh
