// aeroform-cli fit GRID: the second route of the paper's second level for users who bring their
// own grid: read a multiblock Plot3D grid and fit one B-spline volume per block by least squares.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/CliSupport.h"
#include "io/VtkXml.h"
#include "mesh/Plot3d.h"
#include "mesh/VolumeFit.h"

namespace aero::app {

namespace {

const char* kFitHelp =
    "usage: aeroform-cli fit GRID.xyz [--counts I,J,K] [--degree P] [--uniform] [--control OUT.vtm]\n"
    "                        [--refit OUT.xyz] [--json]\n"
    "\n"
    "Reads a multiblock Plot3D grid (binary or ASCII, detected) and fits one B-spline volume per\n"
    "block by least squares (chord-length parameters, averaged knots; corners and faces are\n"
    "reproduced consistently between blocks), then reports the fit error per block.\n"
    "\n"
    "  --counts I,J,K   control points per direction (default: about one knot span per 4 grid\n"
    "                   intervals)\n"
    "  --degree P       degree in every direction (default 3)\n"
    "  --uniform        uniform parameters and knots (neighbouring blocks then share their faces\n"
    "                   exactly whenever their counts match)\n"
    "  --control F.vtm  write the fitted control grids for ParaView\n"
    "  --refit F.xyz    write the fitted volumes sampled at the grid's parameters (Plot3D binary)\n"
    "  --json           print one JSON summary on stdout\n"
    "  --help           this text\n";

bool parseCounts(const std::string& s, std::array<int, 3>& out) {
    int n = 0;
    std::size_t pos = 0;
    while (n < 3) {
        char* end = nullptr;
        const long v = std::strtol(s.c_str() + pos, &end, 10);
        if (end == s.c_str() + pos || v < 2 || v > 100000) return false;
        out[n++] = static_cast<int>(v);
        pos = static_cast<std::size_t>(end - s.c_str());
        if (n < 3) {
            if (s[pos] != ',') return false;
            ++pos;
        }
    }
    return pos == s.size();
}

}  // namespace

int cmdFit(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::printf("%s", kFitHelp);
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json", "--uniform"}, {"--counts", "--degree", "--control", "--refit"}, pos, val, err)) {
        return usageError("fit", err, kFitHelp);
    }
    if (pos.size() != 1) return usageError("fit", "expected exactly one GRID file", kFitHelp);
    mesh::FitOptions o;
    if (val.count("--counts") && !parseCounts(val["--counts"], o.count)) {
        return usageError("fit", "--counts expects three integers >= 2 like 8,8,12, got '" + val["--counts"] + "'", kFitHelp);
    }
    if (val.count("--degree")) {
        char* end = nullptr;
        const long p = std::strtol(val["--degree"].c_str(), &end, 10);
        if (*end != '\0' || p < 1 || p > 9) return usageError("fit", "--degree must be 1..9, got '" + val["--degree"] + "'", kFitHelp);
        o.degree = {static_cast<int>(p), static_cast<int>(p), static_cast<int>(p)};
    }
    if (val.count("--uniform")) {
        o.parameterization = mesh::Parameterization::Uniform;
        o.knots = mesh::KnotPlacement::Uniform;
    }
    return guarded("fit", [&] {
        const auto t0 = std::chrono::steady_clock::now();
        const std::vector<mesh::StructuredGrid> grids = mesh::readPlot3d(pos[0]);
        std::fprintf(stderr, "[fit] %s: %zu blocks\n", pos[0].c_str(), grids.size());
        nlohmann::ordered_json blocks = nlohmann::ordered_json::array();
        std::vector<io::StructuredBlock> control;
        std::vector<mesh::StructuredGrid> refit;
        double maxError = 0;
        long controlPoints = 0, nodes = 0;
        for (std::size_t b = 0; b < grids.size(); ++b) {
            const mesh::FitResult r = mesh::fitVolume(grids[b], o);
            maxError = std::max(maxError, r.maxError);
            controlPoints += r.volume.controlCount();
            nodes += grids[b].nodeCount();
            std::fprintf(stderr, "[fit] block %zu (%dx%dx%d nodes): %dx%dx%d control points, max error %.3e, rms %.3e\n", b + 1,
                         grids[b].dims[0], grids[b].dims[1], grids[b].dims[2], r.volume.count[0], r.volume.count[1],
                         r.volume.count[2], r.maxError, r.rmsError);
            blocks.push_back({{"name", grids[b].name},
                              {"dims", grids[b].dims},
                              {"control_counts", r.volume.count},
                              {"max_error", r.maxError},
                              {"rms_error", r.rmsError}});
            if (val.count("--control")) control.push_back({grids[b].name, r.volume.count, r.volume.points, {}, {}});
            if (val.count("--refit")) {
                mesh::StructuredGrid g = grids[b];
                nurbs::sampleGrid(r.volume, r.params[0], r.params[1], r.params[2], g.xyz.data());
                refit.push_back(std::move(g));
            }
        }
        if (val.count("--control")) io::writeVtm(val["--control"], {{"control_grid", std::move(control)}});
        if (val.count("--refit")) mesh::writePlot3d(val["--refit"], refit, true);
        if (val.count("--json")) {
            nlohmann::ordered_json j;
            j["grid"] = pos[0];
            j["blocks"] = blocks;
            j["grid_nodes"] = nodes;
            j["control_points"] = controlPoints;
            j["max_error"] = maxError;
            j["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            std::printf("%s\n", j.dump(2).c_str());
        }
        return kOk;
    });
}

}  // namespace aero::app
