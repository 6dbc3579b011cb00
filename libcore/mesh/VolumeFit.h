#pragma once
// "Bring your own grid" (Section III.B.2, Eq. 5, after Hicken and Zingg): one B-spline volume
// per block fitted by least squares to the block's nodes, so that the grid can afterwards be
// regenerated from the volume's control net (nurbs::sampleGrid at the returned parameters).
//
// The fit is separable. Each direction d gets one parameter per grid index (shared by all grid
// lines of the block), a clamped knot vector and the 1D operator A_d that maps the dims[d]
// data of a grid line to count[d] control points: the least-squares fit of the line with its
// two end points interpolated (end control points = end nodes). The control net is
// (A_2 (x) A_1 (x) A_0) applied to the nodes, one direction after the other: the exact
// minimizer for tensor-product data, and cheap (three small dense products).
// Consequences of the end-point constraint, which keep neighbouring blocks consistent:
//   - the 8 corner nodes become the corner control points exactly (bitwise), so the volume
//     passes through them (up to the round-off of the basis evaluation);
//   - the control points of a boundary face depend only on that face's nodes (and those of an
//     edge only on that edge's nodes), through A of the two in-face directions. Two blocks that
//     share a face with matching nodes therefore get the same face surface (to round-off) if
//     they use the same degree, count, parameters and knots in the shared directions: always
//     true with Parameterization::Uniform and equal counts; with chord length (averaged over
//     the whole block) pass common FitOptions::params when the blocks' averages could differ.
#include <array>
#include <vector>

#include "mesh/StructuredGrid.h"
#include "nurbs/Volume.h"

namespace aero::mesh {

enum class Parameterization {
    ChordLength,  // per direction, normalized cumulative chord length averaged over all grid
                  // lines of the block (Piegl & Tiller 9.2.1, 9.4.1); degenerate lines skipped
    Uniform,      // index / (dims[d] - 1)
};

enum class KnotPlacement {
    Averaging,  // Piegl & Tiller: Eq. 9.8 when count == dims (interpolation), Eq. 9.69 otherwise;
                // every knot span then holds parameters (the least-squares matrix has full rank)
    Uniform,    // nurbs::uniformKnots
};

struct FitOptions {
    std::array<int, 3> degree{3, 3, 3};  // 1 .. nurbs::kMaxDegree
    std::array<int, 3> count{0, 0, 0};   // control points per direction, degree+1 .. dims; 0 means
                                         // automatic: about one knot span per 4 grid intervals
    Parameterization parameterization = Parameterization::ChordLength;
    KnotPlacement knots = KnotPlacement::Averaging;
    // Optional: explicit parameters per direction (dims[d] non-decreasing values from 0 to 1),
    // overriding `parameterization` for that direction when non-empty.
    std::array<std::vector<double>, 3> params;
};

struct FitResult {
    nurbs::Volume<double> volume;               // polynomial (no weights), knots on [0, 1]
    std::array<std::vector<double>, 3> params;  // params[d][i]: parameter of grid index i along d
    double maxError = 0;                        // max |grid node - volume(params)|, grid units
    double rmsError = 0;                        // root mean square of the same distances
};

/// Fits one B-spline volume to block `g` (see the header comment). Throws GeometryError naming
/// the block for dims < 2, xyz of the wrong size, non-finite nodes, a degree outside
/// 1..kMaxDegree, a count outside degree+1..dims, bad explicit params, or a singular fit.
FitResult fitVolume(const StructuredGrid& g, const FitOptions& o = {});

/// Averaged normalized chord-length parameters of `g` along direction dir (0, 1, 2): dims[dir]
/// values, first 0, last 1; uniform if every line of that direction has zero length.
/// Precondition: g is valid (dims >= 2, xyz sized 3 * nodeCount).
std::vector<double> chordLengthParameters(const StructuredGrid& g, int dir);

/// Clamped knot vector on [0, 1] for `count` functions of degree `degree` fitted to the
/// non-decreasing `params` (params.size() >= count >= degree + 1), placed as `placement` says.
std::vector<double> fitKnots(const std::vector<double>& params, int degree, int count,
                             KnotPlacement placement);

}  // namespace aero::mesh
