#pragma once
// Files of a flow solution: the restart file (the state q with the layout it belongs to and the
// free stream it was computed for), the residual history as CSV and the solution fields as VTK
// XML multiblock for ParaView (volume fields per block plus the wall faces with Cp).
#include <array>
#include <string>
#include <vector>

#include "flow/Euler.h"
#include "flow/FlowMesh.h"
#include "flow/FlowSolver.h"

namespace aero::io {

/// What a restart file holds besides q.
struct RestartInfo {
    flow::FreeStream freeStream;
    int iterations = 0;       // nonlinear iterations that produced it (cumulative over restarts)
    double residual = 0;      // ||R|| of the state when it was written
    double initialResidual = 0;  // ||R0|| of the first run (so orders stay comparable on resume)
    double cflBase = 0;          // the CFL law's base when it was written
    double lumping = 0;          // the preconditioner's lumping factor then (0: not recorded)
    /// Per block, the parameters of its grid nodes along i, j, k in the analytic grid the state
    /// was solved on (mesh::GridBlock::samples): what lets a state be carried to another sampling
    /// of that grid (a finer mesh.refine). Empty when not recorded (files of version 1).
    std::vector<std::array<std::vector<double>, 3>> samples;
    /// Per block, the coordinates of its 8 corner nodes (i fastest, then j, k; blockCorners),
    /// recorded with `samples`: samplings of the same analytic grid share them (any mesh.refine
    /// or grid_wall_spacing), another level, farfield or shape does not.
    std::vector<std::array<double, 24>> corners;
};

/// The corners of every block of fm at the node coordinates x (3 per node): RestartInfo::corners.
std::vector<std::array<double, 24>> blockCorners(const flow::FlowMesh& fm, const std::vector<double>& x);

/// A restart file whatever grid it was written for: its header, the dims of its blocks and q.
struct RestartContents {
    RestartInfo info;
    std::vector<std::array<int, 3>> dims;  // per block, nodes along i, j, k
    std::vector<double> q;                 // 5 per node, blocks one after the other
};

/// Writes q (5 per node, fm's order) to `path`, replacing it atomically (temporary file +
/// rename: an interrupted write never leaves a truncated restart behind). Binary, little endian:
/// magic, version, block count, dims of every block, the blocks' grid parameters when
/// info.samples has them (a flag, then dims[d] doubles per block and direction, then the 24
/// corner coordinates per block), free stream, iteration data, node count, q, and a checksum of
/// everything before it. Throws InputError naming the path, Error when info.samples or
/// info.corners do not match fm's blocks.
void writeRestart(const std::string& path, const flow::FlowMesh& fm, const std::vector<double>& q,
                  const RestartInfo& info);

/// Reads a restart file for the layout fm. Throws InputError naming the file when it cannot be
/// read, is not a restart file, is truncated or corrupt (checksum), or was written for another
/// grid (block count, or the block and its dims that differ).
std::vector<double> readRestart(const std::string& path, const flow::FlowMesh& fm, RestartInfo* info = nullptr);

/// Reads a restart file of any grid (this version's and version 1). Throws InputError naming the
/// file when it cannot be read, is not a restart file, is truncated or corrupt, or is not
/// consistent in itself (node count against the blocks' dims, grid parameters that do not
/// increase); nothing is allocated from a count the file's size does not back.
RestartContents readRestartContents(const std::string& path);

/// Throws the InputError readRestart gives when `file` (read from `path`) was written for
/// another grid than fm (block count, a block's dims).
void checkRestartLayout(const std::string& path, const RestartContents& file, const flow::FlowMesh& fm);

/// A bare flow state (an optimization's warm starts: the node count, then q; native byte order,
/// no layout), written atomically.
void writeWarmState(const std::string& path, const std::vector<double>& q);
/// Such a state, or empty when the file is missing, unreadable or damaged (its count must match
/// the file's size: nothing is allocated from a count the data does not back).
std::vector<double> readWarmState(const std::string& path);

/// The residual history: one row per nonlinear iteration (iteration, residual,
/// relative_residual, cfl, linear_iterations, linear_residual, step_scale, seconds). `first`
/// numbers the rows from there (a resumed run continues the count).
void writeResidualCsv(const std::string& path, const std::vector<flow::FlowIteration>& history, int first = 0);

/// The static pressure at every wall node, in flow::wallNodes order, as CSV (block, i, j, k, x, y,
/// z, p, cp; p with 17 significant digits): the target of an inverse design
/// (optimization.target_pressure). x: 3 per node. Replaces the file atomically.
void writeWallPressureCsv(const std::string& path, const flow::FlowMesh& fm, const std::vector<double>& x,
                          const std::vector<double>& q, const flow::FreeStream& fs);
/// The pressures of such a file for grid fm (one per wall node, flow::wallNodes order). Throws
/// InputError naming the file and line when it cannot be read, a row is malformed, or its block
/// and node are not the grid's wall node of that row (a file written for another grid).
std::vector<double> readWallPressureCsv(const std::string& path, const flow::FlowMesh& fm);

/// The solution as VTK XML multiblock (`path` ends in .vtm): group "flow" with every block's
/// grid and the point fields density, velocity, pressure, Cp, Mach, entropy; group "wall" with
/// every wall face (a surface piece per block face) and Cp, Mach, entropy. x: 3 per node.
void writeFlowVtm(const std::string& path, const flow::FlowMesh& fm, const std::vector<double>& x,
                  const std::vector<double>& q, const flow::FreeStream& fs);

}  // namespace aero::io
