#include "study/CaseGrid.h"

#include <chrono>
#include <cstdio>

#include "common/Error.h"
#include "mesh/Extrusion.h"

namespace aero::study {

namespace {
double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

CaseGrid buildCaseGrid(const io::CaseFile& c, const geometry::PatchSet& baseline, const CaseShape& shape,
                       const Log& log) {
    auto say = [&](const char* s) {
        if (log) log(s);
    };
    char buf[256];
    CaseGrid g;
    auto t = std::chrono::steady_clock::now();
    g.mesh = mesh::extrudeToFarfield(baseline, c.mesh.extrusion);
    g.secondsGenerate = since(t);
    std::snprintf(buf, sizeof buf, "level '%s': %zu blocks, %d control nodes, %ld grid nodes (%.3f s)",
                  c.mesh.level.c_str(), g.mesh.blocks.size(), g.mesh.controlCount(), g.mesh.gridNodeCount(),
                  g.secondsGenerate);
    say(buf);

    g.moved = shape.model != nullptr;
    if (g.moved) {
        t = std::chrono::steady_clock::now();
        g.move = mesh::moveControlGrid(g.mesh, shape.uniqueSurface, c.mesh.elasticity, [&](int i, int n) {
            std::snprintf(buf, sizeof buf, "elasticity increment %d/%d", i, n);
            say(buf);
        });
        g.secondsMove = since(t);
        std::snprintf(buf, sizeof buf, "moved the control grid: %d increments, %d PCG iterations, %d free DOFs, %.3f s",
                      static_cast<int>(g.move.cgIterations.size()), g.move.totalIterations, g.move.freeDofs,
                      g.secondsMove);
        say(buf);
        if (g.move.status != mesh::SolveStatus::Converged) {
            throw GeometryError("'" + c.path + "': mesh movement did not converge: " + g.move.message);
        }
    }

    t = std::chrono::steady_clock::now();
    g.grids = mesh::regenerateAll(g.mesh);
    g.secondsRegenerate = since(t);
    std::snprintf(buf, sizeof buf, "regenerated %ld grid nodes in %.3f s", g.mesh.gridNodeCount(), g.secondsRegenerate);
    say(buf);
    return g;
}

}  // namespace aero::study
