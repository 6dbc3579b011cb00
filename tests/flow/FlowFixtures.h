#pragma once
// Shared grids of the flow tests: the paper's half-sphere (coarse level, scaled by `refine`) and
// a small synthetic two-block box with a curved interior, flat outer faces and a rotated second
// block.
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "flow/FlowMesh.h"
#include "flow/Metrics.h"
#include "geometry/HalfSphere.h"
#include "mesh/Extrusion.h"

namespace aero::flow::testing {

struct FlowCase {
    mesh::MultiBlockMesh mesh;  // empty for synthetic cases
    FlowMesh fm;
    std::vector<double> x;        // 3 per node
    std::vector<double> metrics;  // kMetricWidth per node
};

/// The half-sphere grid of the "coarse" level with ExtrusionOptions::refine = refine (cached).
/// wallSpacing > 0 replaces the level's gridWallSpacing (the coarse level's 1e-3 leaves one
/// radial cell spanning r = 1.3 .. 20 at refine 0.5, which the flow solver handles badly).
inline const FlowCase& halfSphere(double refine, double wallSpacing = 0, double farfield = 0) {
    static std::map<std::array<double, 3>, std::unique_ptr<FlowCase>> cache;
    auto& slot = cache[{refine, wallSpacing, farfield}];
    if (!slot) {
        slot = std::make_unique<FlowCase>();
        mesh::ExtrusionOptions o = mesh::extrusionLevel("coarse");
        o.refine = refine;
        if (wallSpacing > 0) o.gridWallSpacing = wallSpacing;
        if (farfield > 0) o.farfieldRadius = farfield;
        slot->mesh = mesh::extrudeToFarfield(geometry::makeHalfSphere(), o);
        const auto grids = mesh::regenerateAll(slot->mesh);
        slot->fm = makeFlowMesh(slot->mesh, grids);
        slot->x = gatherCoordinates(slot->fm, grids);
        slot->metrics = computeMetrics(slot->fm, slot->x);
    }
    return *slot;
}

/// Two blocks filling [0,2] x [0,1] x [0,1], joined at x = 1. Nodes are displaced smoothly inside
/// (each coordinate by a bump that vanishes on the faces normal to it), so the outer faces stay
/// planar while the grid lines curve. Block B runs (x, z, -y) along its (i, j, k): its interface
/// face is seen with swapped and reversed tangential directions. Faces: y = 0 / y = 1 are
/// `yFaces` (wall or symmetry), the others farfield.
inline FlowCase wavyBox(int n, mesh::BoundaryKind yFaces, double amplitude = 0.08) {
    const int nx = n, ny = n - 1, nz = n + 1;  // nodes per block along x, y, z
    const int NX = 2 * (nx - 1);
    auto place = [&](int I, int J, int K, double* out) {
        const double X = static_cast<double>(I) / NX, Y = static_cast<double>(J) / (ny - 1),
                     Z = static_cast<double>(K) / (nz - 1);
        const double pi = 3.14159265358979323846;
        out[0] = 2.0 * X + amplitude * 4 * X * (1 - X) * std::sin(2 * pi * Y + 1.0) * std::cos(pi * Z);
        out[1] = Y + amplitude * 4 * Y * (1 - Y) * std::sin(pi * X + 0.3) * std::cos(2 * pi * Z);
        out[2] = Z + amplitude * 4 * Z * (1 - Z) * std::cos(3 * pi * X) * std::sin(pi * Y + 0.5);
    };
    FlowCase c;
    std::vector<FlowBlock> blocks(2);
    blocks[0].name = "A";
    blocks[0].dims = {nx, ny, nz};
    blocks[1].name = "B";
    blocks[1].dims = {nx, nz, ny};
    for (auto& b : blocks) {
        for (auto& f : b.faces) f.kind = mesh::BoundaryKind::Farfield;
    }
    blocks[0].faces[2].kind = blocks[0].faces[3].kind = yFaces;  // A: j is y
    blocks[1].faces[4].kind = blocks[1].faces[5].kind = yFaces;  // B: k is -y
    blocks[0].faces[1] = {mesh::BoundaryKind::Interface, 1, 0};
    blocks[1].faces[0] = {mesh::BoundaryKind::Interface, 0, 1};
    std::vector<mesh::NodePair> pairs;
    for (int k = 0; k < nz; ++k) {
        for (int j = 0; j < ny; ++j) {
            const long na = (nx - 1) + static_cast<long>(nx) * (j + static_cast<long>(ny) * k);
            const long nb = 0 + static_cast<long>(nx) * (k + static_cast<long>(nz) * (ny - 1 - j));
            pairs.push_back({0, na, 1, nb});
        }
    }
    c.fm = makeFlowMesh(blocks, pairs);
    c.x.resize(3 * static_cast<std::size_t>(c.fm.nodeCount));
    for (int b = 0; b < 2; ++b) {
        const FlowBlock& blk = c.fm.blocks[b];
        for (int k = 0; k < blk.dims[2]; ++k) {
            for (int j = 0; j < blk.dims[1]; ++j) {
                for (int i = 0; i < blk.dims[0]; ++i) {
                    const long node = blk.offset + i + static_cast<long>(blk.dims[0]) * (j + static_cast<long>(blk.dims[1]) * k);
                    if (b == 0) {
                        place(i, j, k, &c.x[3 * node]);
                    } else {
                        place(nx - 1 + i, ny - 1 - k, j, &c.x[3 * node]);
                    }
                }
            }
        }
    }
    c.metrics = computeMetrics(c.fm, c.x);
    return c;
}

/// A free vortex between two concentric circular walls (radii 1 and 2 about the Y axis, in the
/// X-Z plane): two blocks (theta in [0, pi] and [pi, 2 pi]; i around, j from the inner to the
/// outer wall, k along Y with 2 layers and symmetry faces) joined at both cuts, so each wall has
/// two junctions. `exact` gets the steady homentropic solution u_theta = 0.5 / r (Mach 0.51 on
/// the inner wall), which is tangent to both walls.
inline FlowCase vortexAnnulus(int around, int radial, std::vector<double>& exact) {
    const double pi = 3.14159265358979323846, gamma = 1.4;
    std::vector<FlowBlock> blocks(2);
    for (int b = 0; b < 2; ++b) {
        blocks[b].name = b == 0 ? "upper" : "lower";
        blocks[b].dims = {around, radial, 2};
        for (auto& f : blocks[b].faces) f.kind = mesh::BoundaryKind::Symmetry;
        blocks[b].faces[2].kind = blocks[b].faces[3].kind = mesh::BoundaryKind::Wall;
        blocks[b].faces[0] = {mesh::BoundaryKind::Interface, 1 - b, 1};
        blocks[b].faces[1] = {mesh::BoundaryKind::Interface, 1 - b, 0};
    }
    auto local = [&](int i, int j, int k) { return i + static_cast<long>(around) * (j + static_cast<long>(radial) * k); };
    std::vector<mesh::NodePair> pairs;
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < radial; ++j) {
            pairs.push_back({0, local(around - 1, j, k), 1, local(0, j, k)});
            pairs.push_back({1, local(around - 1, j, k), 0, local(0, j, k)});
        }
    }
    FlowCase c;
    c.fm = makeFlowMesh(blocks, pairs);
    c.x.resize(3 * static_cast<std::size_t>(c.fm.nodeCount));
    exact.resize(5 * static_cast<std::size_t>(c.fm.nodeCount));
    for (int b = 0; b < 2; ++b) {
        for (int k = 0; k < 2; ++k) {
            for (int j = 0; j < radial; ++j) {
                for (int i = 0; i < around; ++i) {
                    const long n = c.fm.blocks[b].offset + local(i, j, k);
                    const double r = 1.0 + static_cast<double>(j) / (radial - 1);
                    const double th = pi * (b + static_cast<double>(i) / (around - 1));
                    c.x[3 * n] = r * std::cos(th);
                    c.x[3 * n + 1] = k;
                    c.x[3 * n + 2] = r * std::sin(th);
                    const double ut = 0.5 / r;
                    const double rho = std::pow(1.0 - 0.5 * (gamma - 1.0) * ut * ut, 1.0 / (gamma - 1.0));
                    const double p = std::pow(rho, gamma) / gamma;
                    const double u = -ut * std::sin(th), w = ut * std::cos(th);
                    double* q = &exact[5 * n];
                    q[0] = rho;
                    q[1] = rho * u;
                    q[2] = 0.0;
                    q[3] = rho * w;
                    q[4] = p / (gamma - 1.0) + 0.5 * rho * (u * u + w * w);
                }
            }
        }
    }
    c.metrics = computeMetrics(c.fm, c.x);
    return c;
}

/// A smooth, clearly non-uniform flow state (density, velocity and pressure vary in space).
inline std::vector<double> smoothState(const FlowCase& c, double mach, double amplitude = 0.05) {
    std::vector<double> q(5 * static_cast<std::size_t>(c.fm.nodeCount));
    for (long n = 0; n < c.fm.nodeCount; ++n) {
        const double* x = &c.x[3 * n];
        const double s = std::sin(0.7 * x[0] + 0.3) * std::cos(0.5 * x[1] - 0.2) * std::sin(0.4 * x[2] + 1.1);
        const double t = std::cos(0.9 * x[0] - 0.4 * x[2]) * std::sin(0.6 * x[1] + 0.7);
        const double rho = 1.0 + amplitude * s;
        const double u = mach * (1.0 + amplitude * t), v = mach * amplitude * s, w = mach * amplitude * (s - t);
        const double p = (1.0 + amplitude * t * s) / 1.4;
        q[5 * n + 0] = rho;
        q[5 * n + 1] = rho * u;
        q[5 * n + 2] = rho * v;
        q[5 * n + 3] = rho * w;
        q[5 * n + 4] = p / 0.4 + 0.5 * rho * (u * u + v * v + w * w);
    }
    return q;
}

}  // namespace aero::flow::testing
