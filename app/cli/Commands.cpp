#include "cli/Commands.h"

#include <chrono>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "cli/CliSupport.h"
#include "geometry/HalfSphere.h"
#include "geometry/Topology.h"
#include "io/CaseFile.h"
#include "study/Optimization.h"

namespace aero::app {

namespace {


struct GeometryInfo {
    nlohmann::ordered_json json;
    std::string text;
};

GeometryInfo describeGeometry(const std::string& path, const geometry::PatchSet& set) {
    const geometry::ControlPointIndex idx = geometry::buildControlPointIndex(set, 1e-10);
    const geometry::Adjacency adj = geometry::buildAdjacency(set, 1e-6);
    const geometry::BoundingBox box = geometry::surfaceBoundingBox(set);
    const geometry::BoundingBox net = geometry::controlBoundingBox(set);
    std::set<std::pair<int, int>> degrees;
    int rational = 0;
    for (const auto& p : set.patches) {
        degrees.insert({p.degreeU, p.degreeV});
        rational += p.rational() ? 1 : 0;
    }
    int identical = 0;
    for (const auto& s : adj.shared) identical += s.identicalNets ? 1 : 0;

    GeometryInfo info;
    auto& j = info.json;
    j["file"] = path;
    j["patches"] = set.size();
    j["rational_patches"] = rational;
    nlohmann::ordered_json deg = nlohmann::ordered_json::array();
    for (const auto& d : degrees) deg.push_back({d.first, d.second});
    j["degrees"] = deg;
    j["control_points"] = set.controlPointCount();
    j["unique_control_points"] = idx.uniqueCount();
    j["bbox"] = {{"min", box.min}, {"max", box.max}};
    j["control_bbox"] = {{"min", net.min}, {"max", net.max}};
    j["shared_edges"] = adj.shared.size();
    j["shared_edges_identical"] = identical;
    j["free_edges"] = adj.free.size();
    j["max_edge_gap"] = adj.maxGap;

    char buf[512];
    std::string& t = info.text;
    t += "geometry         " + path + "\n";
    std::snprintf(buf, sizeof buf, "patches          %d (%d rational)\n", set.size(), rational);
    t += buf;
    t += "degrees         ";
    for (const auto& d : degrees) t += " " + std::to_string(d.first) + "x" + std::to_string(d.second);
    t += "\n";
    std::snprintf(buf, sizeof buf, "control points   %d (%d unique, merged within 1e-10)\n", set.controlPointCount(),
                  idx.uniqueCount());
    t += buf;
    std::snprintf(buf, sizeof buf, "bounding box     [%.6g, %.6g] x [%.6g, %.6g] x [%.6g, %.6g]\n", box.min[0],
                  box.max[0], box.min[1], box.max[1], box.min[2], box.max[2]);
    t += buf;
    std::snprintf(buf, sizeof buf, "edges            %zu shared (%d with identical control points), %zu free\n",
                  adj.shared.size(), identical, adj.free.size());
    t += buf;
    std::snprintf(buf, sizeof buf, "largest edge gap %.3e\n", adj.maxGap);
    t += buf;
    return info;
}

const char* kInfoHelp =
    "usage: aeroform-cli info FILE [--json]\n"
    "\n"
    "Reads a patch set (.igs/.iges or native .json) and reports its patches, degrees,\n"
    "control points (non-unique and unique), bounding box and watertightness (largest gap\n"
    "along shared patch edges).\n"
    "\n"
    "  --json    print one JSON object on stdout (keys: patches, control_points,\n"
    "            unique_control_points, max_edge_gap, bbox, ...) and nothing else\n"
    "  --help    this text\n";

int cmdInfo(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::cout << kInfoHelp;
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json"}, {}, pos, val, err)) return usageError("info", err, kInfoHelp);
    if (pos.size() != 1) return usageError("info", "expected exactly one FILE", kInfoHelp);
    return guarded("info", [&] {
        const geometry::PatchSet set = loadPatchSet(pos[0]);
        const GeometryInfo info = describeGeometry(pos[0], set);
        if (val.count("--json")) {
            std::cout << info.json.dump(2) << std::endl;
        } else {
            std::cout << info.text;
        }
        return kOk;
    });
}

const char* kSampleHelp =
    "usage: aeroform-cli sample half-sphere -o FILE [--radius R] [--json]\n"
    "\n"
    "Generates the paper's half-sphere: the half y >= 0 of a sphere (symmetry plane Y=0,\n"
    "X streamwise, Z up) as 20 bicubic B-spline patches with 6x6 control nets, watertight.\n"
    "FILE ends in .json (native) or .igs/.iges (IGES 128, 17 significant digits).\n"
    "\n"
    "  -o FILE      output file (required)\n"
    "  --radius R   sphere radius (default 1)\n"
    "  --json       print a JSON summary on stdout\n"
    "  --help       this text\n";

int cmdSample(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::cout << kSampleHelp;
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json"}, {"-o", "--radius"}, pos, val, err)) return usageError("sample", err, kSampleHelp);
    if (pos.size() != 1 || pos[0] != "half-sphere") {
        return usageError("sample", "expected the sample name 'half-sphere'", kSampleHelp);
    }
    if (!val.count("-o")) return usageError("sample", "missing -o FILE", kSampleHelp);
    geometry::HalfSphereOptions o;
    if (val.count("--radius")) {
        char* end = nullptr;
        o.radius = std::strtod(val["--radius"].c_str(), &end);
        if (*end != '\0' || !(o.radius > 0) || !std::isfinite(o.radius)) {
            return usageError("sample", "--radius must be a positive number, got '" + val["--radius"] + "'",
                              kSampleHelp);
        }
    }
    return guarded("sample", [&] {
        const geometry::PatchSet set = geometry::makeHalfSphere(o);
        savePatchSet(set, val["-o"]);
        const double dev = geometry::maxRadialDeviation(set, o.radius, 81);
        if (val.count("--json")) {
            nlohmann::ordered_json j;
            j["file"] = val["-o"];
            j["patches"] = set.size();
            j["control_points"] = set.controlPointCount();
            j["radius"] = o.radius;
            j["max_radial_deviation"] = dev;
            std::cout << j.dump(2) << std::endl;
        } else {
            std::fprintf(stderr, "wrote %s: %d patches, %d control points, max radial deviation %.3e\n",
                         val["-o"].c_str(), set.size(), set.controlPointCount(), dev);
        }
        return kOk;
    });
}

const char* kConvertHelp =
    "usage: aeroform-cli convert IN -o OUT\n"
    "\n"
    "Converts a patch set between IGES (.igs/.iges) and the native JSON format (.json).\n"
    "Both directions are exact (17 significant digits).\n"
    "\n"
    "  -o OUT   output file (required)\n"
    "  --help   this text\n";

int cmdConvert(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::cout << kConvertHelp;
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {}, {"-o"}, pos, val, err)) return usageError("convert", err, kConvertHelp);
    if (pos.size() != 1) return usageError("convert", "expected exactly one input file", kConvertHelp);
    if (!val.count("-o")) return usageError("convert", "missing -o OUT", kConvertHelp);
    return guarded("convert", [&] {
        const geometry::PatchSet set = loadPatchSet(pos[0]);
        savePatchSet(set, val["-o"]);
        std::fprintf(stderr, "wrote %s: %d patches\n", val["-o"].c_str(), set.size());
        return kOk;
    });
}

const char* kMainHelp =
    "usage: aeroform-cli COMMAND [ARGS] (COMMAND --help for details)\n"
    "\n"
    "Aeroform: two-level free-form deformation for aerodynamic shape design.\n"
    "\n"
    "commands:\n"
    "  info FILE [--json]             patches, control points, bounding box, edge gaps\n"
    "  sample half-sphere -o FILE     generate the paper's half-sphere sample\n"
    "  convert IN -o OUT              IGES <-> native JSON, exact\n"
    "  deform CASE [--json]           embed in FFD lattices, deform, check, write IGES + VTK\n"
    "  mesh CASE [--json]             B-spline volume grid, elasticity move, quality, VTK/Plot3D\n"
    "  flow CASE [--json]             deform, grid, Euler solution: forces, Cp/Mach/entropy VTK\n"
    "  sweep CASE [--random N]        the flow over the design space: scaled and random designs\n"
    "  gradient CASE [--json]         dJ/dv of CL, CD, CL/CD by the discrete adjoint, all variables\n"
    "  gradient-check CASE [--groups] the adjoint's directional derivative vs centred differences\n"
    "  optimize CASE [--resume]       the case's optimization (Ipopt/SLSQP, adjoint gradients), resumable\n"
    "  fit GRID.xyz [--json]          fit B-spline volumes to your own Plot3D grid, report errors\n"
    "\n"
    "exit codes: 0 success, 1 the work failed (bad input, invalid geometry), 2 usage error\n";

}  // namespace

void ensurePassiveOpenMpWaiting(char** argv) {
    if (std::getenv("OMP_WAIT_POLICY")) return;
    setenv("OMP_WAIT_POLICY", "passive", 1);
    execv("/proc/self/exe", argv);  // returns only on failure: then run as we are
}

int runCli(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << kMainHelp;
        return kUsage;
    }
    const std::string cmd = argv[1];
    const Args args(argv + 2, argv + argc);
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
        std::cout << kMainHelp;
        return kOk;
    }
    if (cmd == "--version") {
        std::cout << "aeroform-cli 0.1.0\n";
        return kOk;
    }
    if (cmd == "info") return cmdInfo(args);
    if (cmd == "sample") return cmdSample(args);
    if (cmd == "convert") return cmdConvert(args);
    if (cmd == "deform") return cmdDeform(args);
    if (cmd == "mesh") return cmdMesh(args);
    if (cmd == "fit") return cmdFit(args);
    if (cmd == "flow") return cmdFlow(args);
    if (cmd == "sweep") return cmdSweep(args);
    if (cmd == "gradient") return cmdGradient(args);
    if (cmd == "gradient-check") return cmdGradientCheck(args);
    if (cmd == "optimize") return cmdOptimize(args);
    std::cerr << "aeroform-cli: unknown command '" << cmd << "'\n\n" << kMainHelp;
    return kUsage;
}

int runBatch(const std::string& path) {
    // A case file runs the whole case as deep as it goes; a geometry file is reported.
    if (io::looksLikeCase(path)) {
        std::fprintf(stderr, "[batch] case %s\n", path.c_str());
        // The deepest stage the case asks for: a flow section runs the flow solver (on the mesh
        // section's grid), a mesh section the mesh level. A bad case is an error like in the CLI
        // (exit 1 with the message), not an uncaught exception.
        int stage = 0;
        bool resumable = false;
        const int code = guarded("batch", [&] {
            const io::CaseFile c = io::readCase(path);
            stage = c.optimization.present ? 3 : (c.flow.present ? 2 : (c.mesh.present ? 1 : 0));
            if (stage == 3) resumable = std::filesystem::exists(study::historyJsonlPath(c.optimization.history));
            return kOk;
        });
        if (code != kOk) return code;
        if (stage == 3) return runOptimize(path, resumable, false, false, true);
        if (stage == 2) return runFlow(path, "", false);
        return stage == 1 ? runMesh(path, false) : runDeform(path, false, false);
    }
    return guarded("batch", [&] {
        const auto t0 = std::chrono::steady_clock::now();
        std::fprintf(stderr, "[batch] reading %s\n", path.c_str());
        const geometry::PatchSet set = loadPatchSet(path);
        const GeometryInfo info = describeGeometry(path, set);
        std::cout << info.text;
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::fprintf(stderr, "[batch] done in %.3f s\n", s);
        return kOk;
    });
}

}  // namespace aero::app
