// aeroform-cli mesh CASE: the second FFD level. Generates the multiblock B-spline volume grid
// around the case's baseline geometry, moves its control grid by linear elasticity to the
// deformed geometry (when the case deforms it), regenerates the grid, checks its quality and
// writes VTK (grid with quality fields, control grid) and Plot3D.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/CliSupport.h"
#include "io/VtkXml.h"
#include "mesh/Plot3d.h"
#include "mesh/Quality.h"
#include "study/CaseEvaluator.h"

namespace aero::app {

namespace {

const char* kMeshHelp =
    "usage: aeroform-cli mesh CASE.json [--json]\n"
    "\n"
    "Builds the case's multiblock grid: one B-spline volume block per surface patch, extruded to\n"
    "a farfield sphere (case key \"mesh\": level coarse | medium | paper, refine, increments,\n"
    "poisson, ...; docs/case-file.md). If the case deforms the geometry (lattices, values,\n"
    "displacements), the control grid follows by linear elasticity in m increments, then the grid\n"
    "is regenerated from it. Cell quality is checked: a non-positive Jacobian fails the command\n"
    "(exit 1) with the block and cell named; requested outputs are still written for inspection.\n"
    "Outputs (case key \"output\"): mesh_vtk (grid + quality), control_vtk (control grid), plot3d.\n"
    "\n"
    "  --json    print one JSON summary on stdout (blocks, control_nodes, grid_nodes, increments,\n"
    "            cg_iterations, min_jacobian, min_scaled_jacobian, max_aspect_ratio,\n"
    "            sharpest_wall_bend (degrees the wall turns from one grid node to the next, and where),\n"
    "            seconds_generate, seconds_move, seconds_mesh, ...)\n"
    "  --help    this text\n";

double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void say(const std::string& s) { std::fprintf(stderr, "[mesh] %s\n", s.c_str()); }

nlohmann::ordered_json metricJson(const mesh::MetricSummary& m) {
    return {{"min", m.min}, {"max", m.max}, {"mean", m.mean}, {"histogram_range", {m.lo, m.hi}}, {"histogram", m.histogram}};
}

void ensureFolder(const std::string& file) {
    const auto parent = std::filesystem::path(file).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
}

}  // namespace

int runMesh(const std::string& casePath, bool json) {
    return guarded("mesh", [&] {
        const auto t0 = std::chrono::steady_clock::now();
        const io::CaseFile c = io::readCase(casePath);
        geometry::PatchSet set = loadPatchSet(c.geometry);
        say("geometry " + c.geometry + ": " + std::to_string(set.size()) + " patches");

        // The one pipeline (study::CaseEvaluator): shape and mesh stages at the case's design.
        study::CaseEvaluator ev(c, std::move(set), say);
        study::EvaluationRequest request;
        request.flow = false;
        const auto tGenerate = std::chrono::steady_clock::now();
        (void)ev.baselineMesh();
        const double secondsGenerate = since(tGenerate);
        const study::Evaluation e = ev.evaluate(ev.caseValues(), request, [](const study::Progress& p) {
            if (!p.message.empty()) say(p.message);
        });
        if (e.status == study::EvaluationStatus::InvalidShape || !e.mesh) {
            throw GeometryError("'" + casePath + "': " + e.message);
        }
        if (e.mesh->grids.empty()) throw GeometryError("'" + casePath + "': " + e.message);  // cancelled
        const mesh::MultiBlockMesh& m = e.mesh->control;
        const std::vector<mesh::StructuredGrid>& grids = e.mesh->grids;
        const mesh::MoveReport& move = e.mesh->move;
        const bool moving = e.mesh->moved;
        char buf[256];

        const std::vector<mesh::CellQuality>& q = e.mesh->cellQuality;
        const mesh::QualitySummary& qs = e.mesh->quality;
        std::snprintf(buf, sizeof buf, "quality: min Jacobian %.3e, min scaled Jacobian %.3f, max aspect ratio %.1f, %ld bad cells",
                      qs.minJacobian.min, qs.scaledJacobian.min, qs.aspectRatio.max, qs.nonPositiveJacobian);
        say(buf);
        const mesh::WallBend& bend = e.mesh->wallBend;
        if (bend.degrees > study::kWallBendWarning) {
            say("warning: " + study::describeWallBend(bend));
        } else if (bend.block >= 0) {
            std::snprintf(buf, sizeof buf, "the wall turns by at most %.1f degrees from one grid node to the next", bend.degrees);
            say(buf);
        }

        // Outputs (also when the grid is bad or the move failed: the user needs to see it).
        nlohmann::ordered_json outputs = nlohmann::ordered_json::object();
        if (!c.outputMeshVtk.empty()) {
            std::vector<io::StructuredBlock> blocks;
            for (std::size_t b = 0; b < grids.size(); ++b) {
                io::StructuredBlock sb{grids[b].name, grids[b].dims, grids[b].xyz, {}, {}};
                sb.cellData = {{"min_jacobian", 1, q[b].minJacobian},     {"scaled_jacobian", 1, q[b].scaledJacobian},
                               {"orthogonality", 1, q[b].orthogonality},  {"aspect_ratio", 1, q[b].aspectRatio},
                               {"skewness", 1, q[b].skewness}};
                blocks.push_back(std::move(sb));
            }
            ensureFolder(c.outputMeshVtk);
            io::writeVtm(c.outputMeshVtk, {{"grid", std::move(blocks)}});
            outputs["mesh_vtk"] = c.outputMeshVtk;
        }
        if (!c.outputControlVtk.empty()) {
            std::vector<io::StructuredBlock> blocks;
            for (std::size_t b = 0; b < m.blocks.size(); ++b) {
                const nurbs::Volume<double> v = mesh::blockVolume(m, static_cast<int>(b));
                blocks.push_back({m.blocks[b].name, v.count, v.points, {}, {}});
            }
            ensureFolder(c.outputControlVtk);
            io::writeVtm(c.outputControlVtk, {{"control_grid", std::move(blocks)}});
            outputs["control_vtk"] = c.outputControlVtk;
        }
        if (!c.outputPlot3d.empty()) {
            ensureFolder(c.outputPlot3d);
            const std::string ext = extension(c.outputPlot3d);
            mesh::writePlot3d(c.outputPlot3d, grids, ext != "p3d" && ext != "fmt");
            outputs["plot3d"] = c.outputPlot3d;
        }
        for (const auto& [key, file] : outputs.items()) say("wrote " + file.get<std::string>());

        if (json) {
            nlohmann::ordered_json j;
            j["case"] = casePath;
            j["level"] = c.mesh.level;
            j["blocks"] = m.blocks.size();
            j["control_nodes"] = m.controlCount();
            j["grid_nodes"] = m.gridNodeCount();
            j["interface_node_pairs"] = m.interfaceNodes.size();
            j["deformed"] = moving;
            j["increments"] = moving ? static_cast<int>(move.cgIterations.size()) : 0;
            j["cg_iterations"] = move.totalIterations;
            j["cg_iterations_per_increment"] = move.cgIterations;
            j["free_dofs"] = move.freeDofs;
            j["min_jacobian"] = qs.minJacobian.min;
            j["min_scaled_jacobian"] = qs.scaledJacobian.min;
            j["max_aspect_ratio"] = qs.aspectRatio.max;
            j["non_positive_cells"] = qs.nonPositiveJacobian;
            j["sharpest_wall_bend"] = wallBendJson(bend);
            j["quality"] = {{"min_jacobian", metricJson(qs.minJacobian)},   {"scaled_jacobian", metricJson(qs.scaledJacobian)},
                            {"orthogonality", metricJson(qs.orthogonality)}, {"aspect_ratio", metricJson(qs.aspectRatio)},
                            {"skewness", metricJson(qs.skewness)}};
            nlohmann::ordered_json worst = nlohmann::ordered_json::array();
            for (const auto& w : qs.worst) {
                worst.push_back({{"block", w.block}, {"name", w.blockName}, {"cell", w.cell}, {"centroid", w.centroid}, {"scaled_jacobian", w.value}});
            }
            j["worst_cells"] = worst;
            j["seconds_generate"] = secondsGenerate;
            j["seconds_move"] = move.seconds;
            j["seconds_mesh"] = e.secondsMesh;  // move + regeneration + quality
            j["outputs"] = outputs;
            j["seconds"] = since(t0);
            std::printf("%s\n", j.dump(2).c_str());
        }
        if (!e.ok()) throw GeometryError("'" + casePath + "': " + e.message);  // names the block and cell
        std::snprintf(buf, sizeof buf, "done in %.3f s", since(t0));
        say(buf);
        return kOk;
    });
}

int cmdMesh(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::printf("%s", kMeshHelp);
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json"}, {}, pos, val, err)) return usageError("mesh", err, kMeshHelp);
    if (pos.size() != 1) return usageError("mesh", "expected exactly one CASE file", kMeshHelp);
    return runMesh(pos[0], val.count("--json") > 0);
}

}  // namespace aero::app
