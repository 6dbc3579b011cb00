#include "cli/Commands.h"

#include <chrono>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "cad/Step.h"
#include "cli/CliSupport.h"
#include "geometry/Units.h"
#include "study/GeometryFiles.h"
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

const char* surfaceKey(cad::SurfaceOutcome s) {
    switch (s) {
        case cad::SurfaceOutcome::Kept: return "kept";
        case cad::SurfaceOutcome::Converted: return "converted";
        case cad::SurfaceOutcome::Ignored: return "ignored";
    }
    return "";
}

const char* trimKey(cad::TrimOutcome t) {
    switch (t) {
        case cad::TrimOutcome::None: return "none";
        case cad::TrimOutcome::Kept: return "kept";
        case cad::TrimOutcome::Converted: return "converted";
        case cad::TrimOutcome::Computed: return "computed";
        case cad::TrimOutcome::Dropped: return "dropped";
    }
    return "";
}

/// "128 rational B-spline surface" (IGES) or the kind alone.
std::string rowName(int type, const std::string& kind) { return type ? std::to_string(type) + " " + kind : kind; }

/// What was read and how (the report's rows), in text and JSON.
void describeRead(const cad::ReadReport& report, GeometryInfo& info) {
    auto& j = info.json;
    std::string& t = info.text;
    // IGES entities by their directory entry (the DE pointer other entities use), STEP faces by #id.
    const bool step = report.format == "STEP";
    const std::string entityWord = report.format == "IGES" ? "DE " : (step ? "" : "patches ");
    const auto list = [&](const std::vector<int>& e) { return entityWord + cad::listEntities(e, 8, step ? "#" : ""); };
    nlohmann::ordered_json read = nlohmann::ordered_json::array(), ignored = nlohmann::ordered_json::array();
    std::string readText, ignoredText;
    for (const cad::ReportRow& r : cad::summarize(report)) {
        const std::string outcome = cad::outcomeText(r.surface, r.trim);
        if (r.surface == cad::SurfaceOutcome::Ignored) {
            ignoredText += (ignoredText.empty() ? "ignored          " : "                 ") + rowName(r.type, r.kind) + ": " +
                           std::to_string(r.entities.size()) + " (" + list(r.entities) + ")" +
                           (r.reason.empty() ? std::string() : ": " + r.reason) + "\n";
            continue;
        }
        nlohmann::ordered_json row;
        row["type"] = r.type;
        row["kind"] = r.kind;
        row["surface"] = surfaceKey(r.surface);
        row["trim"] = trimKey(r.trim);
        row["outcome"] = outcome;
        row["count"] = r.entities.size();
        row["entities"] = r.entities;
        if (!r.reason.empty()) row["note"] = r.reason;
        read.push_back(std::move(row));
        readText += (readText.empty() ? "read             " : "                 ") + rowName(r.type, r.kind) + ": " +
                    std::to_string(r.entities.size()) + " " + outcome + " (" + list(r.entities) + ")" +
                    (r.reason.empty() ? std::string() : ": " + r.reason) + "\n";
    }
    nlohmann::ordered_json items = nlohmann::ordered_json::array();
    for (const cad::ReadItem& item : report.items) {
        nlohmann::ordered_json ji;
        ji[report.format == "IGES" ? "de" : (report.format == "STEP" ? "step_id" : "patch")] = item.entity;
        ji["type"] = item.type;
        ji["kind"] = item.kind;
        ji["surface"] = surfaceKey(item.surface);
        ji["trim"] = trimKey(item.trim);
        ji["patches"] = item.patches;
        if (!item.note.empty()) ji["note"] = item.note;
        if (item.surface == cad::SurfaceOutcome::Ignored)
            ignored.push_back({{"de", item.entity}, {"type", item.type}, {"kind", item.kind}, {"reason", item.note}});
        items.push_back(std::move(ji));
    }
    j["read"] = std::move(read);
    j["ignored"] = std::move(ignored);
    j["items"] = std::move(items);
    j["warnings"] = report.warnings;
    j["notes"] = report.notes;
    t += readText + ignoredText;
    for (const std::string& n : report.notes) t += "note             " + n + "\n";
}

GeometryInfo describeGeometry(const std::string& path, const geometry::PatchSet& set, const cad::ReadReport* report) {
    const geometry::ControlPointIndex idx = geometry::buildControlPointIndex(set, 1e-10);
    const geometry::BoundingBox box = geometry::surfaceBoundingBox(set);
    const geometry::BoundingBox net = geometry::controlBoundingBox(set);
    std::set<std::pair<int, int>> degrees;
    int rational = 0;
    for (const auto& p : set.patches) {
        degrees.insert({p.degreeU, p.degreeV});
        rational += p.rational() ? 1 : 0;
    }
    const int trimmed = set.trimmedCount();

    GeometryInfo info;
    auto& j = info.json;
    char buf[512];
    std::string& t = info.text;
    j["file"] = path;
    t += "geometry         " + path + "\n";
    if (report) {
        j["format"] = report->format;
        std::snprintf(buf, sizeof buf, "format           %s, %zu top-level item%s\n", report->format.c_str(), report->items.size(),
                      report->items.size() == 1 ? "" : "s");
        t += buf;
    }
    j["unit"] = set.unit.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(set.unit);
    if (report) j["unit_source"] = report->unitSource;
    if (set.unit.empty()) {
        t += "unit             not stated" + (report ? " (" + report->unitSource + ")" : std::string()) + "\n";
    } else {
        const geometry::LengthUnit* u = geometry::findLengthUnit(set.unit);
        t += "unit             " + set.unit + " (" + std::string(u ? u->longName : "") + (report ? ", " + report->unitSource : "") +
             "); coordinates as written in the file\n";
    }
    if (report) describeRead(*report, info);
    j["patches"] = set.size();
    j["rational_patches"] = rational;
    j["trimmed_patches"] = trimmed;
    nlohmann::ordered_json deg = nlohmann::ordered_json::array();
    for (const auto& d : degrees) deg.push_back({d.first, d.second});
    j["degrees"] = deg;
    j["control_points"] = set.controlPointCount();
    j["unique_control_points"] = idx.uniqueCount();
    j["bbox"] = {{"min", box.min}, {"max", box.max}};
    j["control_bbox"] = {{"min", net.min}, {"max", net.max}};

    std::snprintf(buf, sizeof buf, "patches          %d (%d rational, %d trimmed)\n", set.size(), rational, trimmed);
    t += buf;
    t += "degrees         ";
    for (const auto& d : degrees) t += " " + std::to_string(d.first) + "x" + std::to_string(d.second);
    t += "\n";
    std::snprintf(buf, sizeof buf, "control points   %d (%d unique, merged within 1e-10)\n", set.controlPointCount(),
                  idx.uniqueCount());
    t += buf;
    std::snprintf(buf, sizeof buf, "bounding box     [%.6g, %.6g] x [%.6g, %.6g] x [%.6g, %.6g]%s\n", box.min[0], box.max[0], box.min[1],
                  box.max[1], box.min[2], box.max[2], trimmed ? " (trimmed surfaces)" : "");
    t += buf;
    // Where the largest boundary gap is: the patch (counted from 0 in the JSON, as items' patches
    // are) and the point.
    auto gapLocation = [&](const geometry::BoundaryGaps& g) {
        return nlohmann::ordered_json{{"patch", g.worstPatch},
                                      {"name", set.names[static_cast<std::size_t>(g.worstPatch)]},
                                      {"point", g.worstPoint}};
    };
    auto gapPlace = [&](const geometry::BoundaryGaps& g) {
        char at[96];
        std::snprintf(at, sizeof at, " (%.6g, %.6g, %.6g)", g.worstPoint[0], g.worstPoint[1], g.worstPoint[2]);
        return set.describe(g.worstPatch) + at;
    };
    if (trimmed == 0) {
        const geometry::Adjacency adj = geometry::buildAdjacency(set, 1e-6);
        int identical = 0;
        for (const auto& s : adj.shared) identical += s.identicalNets ? 1 : 0;
        j["shared_edges"] = adj.shared.size();
        j["shared_edges_identical"] = identical;
        j["free_edges"] = adj.free.size();
        j["max_edge_gap"] = adj.maxGap;
        std::snprintf(buf, sizeof buf, "edges            %zu shared (%d with identical control points), %zu free\n",
                      adj.shared.size(), identical, adj.free.size());
        t += buf;
        std::snprintf(buf, sizeof buf, "largest edge gap %.3e\n", adj.maxGap);
        t += buf;
        if (!adj.free.empty()) {
            // Edges pair only when their end points coincide: an edge split differently on the two
            // sides (a T-junction, as ship-hull files have) counts as free there. Measured along the
            // other patches' whole boundaries instead, as for trimmed sets.
            const geometry::BoundaryGaps gaps = geometry::boundaryGaps(set, 1e-6);
            j["boundary_pieces"] = gaps.pieces;
            j["matched_pieces"] = gaps.matched;
            j["free_pieces"] = gaps.free;
            j["partly_free_pieces"] = gaps.partlyFree;
            j["max_boundary_gap"] = gaps.maxGap;
            std::snprintf(buf, sizeof buf,
                          "boundary         %d patch edges (poles left out): %d along another patch's boundary (also where "
                          "the two sides are split differently; %d of them partly free), %d free\n",
                          gaps.pieces, gaps.matched, gaps.partlyFree, gaps.free);
            t += buf;
            if (gaps.worstPatch >= 0) {
                j["max_boundary_gap_at"] = gapLocation(gaps);
                std::snprintf(buf, sizeof buf, "largest gap      %.3e along the boundaries, at %s\n", gaps.maxGap,
                              gapPlace(gaps).c_str());
                t += buf;
            }
        }
    } else {
        // Patch edges are not the body's edges: measure along the trim loops.
        const geometry::BoundaryGaps gaps = geometry::boundaryGaps(set, 1e-6);
        j["boundary_pieces"] = gaps.pieces;
        j["matched_pieces"] = gaps.matched;
        j["free_pieces"] = gaps.free;
        j["max_edge_gap"] = gaps.maxGap;
        std::snprintf(buf, sizeof buf,
                      "edges            %d boundary pieces (trim curves and untrimmed patch edges): %d along another patch, %d free\n",
                      gaps.pieces, gaps.matched, gaps.free);
        t += buf;
        std::snprintf(buf, sizeof buf, "largest edge gap %.3e (along the trimmed boundaries)", gaps.maxGap);
        t += buf;
        if (gaps.worstPatch >= 0 && gaps.maxGap > 0) {
            j["max_edge_gap_at"] = gapLocation(gaps);
            t += " at " + gapPlace(gaps);
        }
        t += "\n";
    }
    return info;
}

/// The reader's warnings on stderr; with --strict they fail the command.
int reportWarnings(const char* command, const cad::ReadReport& report, bool strict) {
    for (const std::string& w : report.warnings) std::cerr << "aeroform-cli " << command << ": warning: " << w << "\n";
    if (strict && !report.warnings.empty()) {
        std::cerr << "aeroform-cli " << command << ": error: " << report.warnings.size()
                  << " warning(s) and --strict: the geometry read is not exactly the file's\n";
        return kFailed;
    }
    return kOk;
}

const char* kInfoHelp =
    "usage: aeroform-cli info FILE [--json] [--strict]\n"
    "\n"
    "Reads a patch set (.igs/.iges, .stp/.step or native .json) and reports its unit, what was\n"
    "read per entity type (kept as NURBS exactly, converted exactly, kept with trimming, ignored\n"
    "and why), its patches, degrees, control points (non-unique and unique), bounding box and\n"
    "watertightness (largest gap along shared patch edges, or along the trim loops when patches\n"
    "are trimmed). Coordinates stay in the file's unit. Anything that changes the geometry\n"
    "(dropped or approximated trims, surfaces that could not be read) is a warning on stderr.\n"
    "\n"
    "  --json    print one JSON object on stdout (keys: unit, read, ignored, items, warnings,\n"
    "            patches, trimmed_patches, control_points, unique_control_points, max_edge_gap,\n"
    "            bbox, ...) and nothing else\n"
    "  --strict  exit with code 1 when there are warnings (the output is still printed)\n"
    "  --help    this text\n";

int cmdInfo(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::cout << kInfoHelp;
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json", "--strict"}, {}, pos, val, err)) return usageError("info", err, kInfoHelp);
    if (pos.size() != 1) return usageError("info", "expected exactly one FILE", kInfoHelp);
    return guarded("info", [&] {
        cad::ReadReport report;
        const geometry::PatchSet set = study::loadGeometry(pos[0], &report);
        const GeometryInfo info = describeGeometry(pos[0], set, &report);
        if (val.count("--json")) {
            std::cout << info.json.dump(2) << std::endl;
        } else {
            std::cout << info.text;
        }
        return reportWarnings("info", report, val.count("--strict") > 0);
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
    "usage: aeroform-cli convert IN OUT [--units U] [--schema AP214|AP242] [--strict]\n"
    "       aeroform-cli convert IN -o OUT ...\n"
    "\n"
    "Converts a patch set between IGES (.igs/.iges), STEP (.stp/.step) and the native JSON\n"
    "format (.json). Coordinates stay in the input's unit, which the output records, unless\n"
    "--units asks for another. Trimmed patches keep their loops in parameter space (IGES\n"
    "144/142, STEP face bounds, JSON \"trim\"). IGES and JSON are exact both ways (17 significant\n"
    "digits); STEP keeps poles, weights and knots exactly.\n"
    "\n"
    "  -o OUT          output file (or give it as the second argument)\n"
    "  --units U       convert the coordinates to U (in, mm, ft, mi, m, km, mil, um, cm, uin)\n"
    "  --schema S      STEP output schema: AP214 (default) or AP242\n"
    "  --strict        refuse (exit 1, nothing written) when reading gave warnings\n"
    "  --help          this text\n";

int cmdConvert(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::cout << kConvertHelp;
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--strict"}, {"-o", "--units", "--schema"}, pos, val, err)) return usageError("convert", err, kConvertHelp);
    if (val.count("-o")) pos.push_back(val["-o"]);
    if (pos.size() != 2) return usageError("convert", "expected an input and an output file (IN OUT or IN -o OUT)", kConvertHelp);
    const std::string out = pos[1];
    if (val.count("--units") && !geometry::findLengthUnit(val["--units"]))
        return usageError("convert", "unknown unit '" + val["--units"] + "' (known: " + geometry::knownLengthUnits() + ")", kConvertHelp);
    const std::string schema = val.count("--schema") ? val["--schema"] : "AP214";
    if (schema != "AP214" && schema != "AP242") return usageError("convert", "--schema must be AP214 or AP242", kConvertHelp);
    return guarded("convert", [&] {
        cad::ReadReport report;
        geometry::PatchSet set = study::loadGeometry(pos[0], &report);
        if (const int code = reportWarnings("convert", report, val.count("--strict") > 0); code != kOk) return code;
        if (val.count("--units")) {
            const std::string from = set.unit;
            geometry::convertUnits(set, val["--units"]);
            if (from != set.unit)
                std::fprintf(stderr, "converted coordinates from %s to %s (factor %.17g)\n", from.c_str(), set.unit.c_str(),
                             geometry::lengthFactor(*geometry::findLengthUnit(from), *geometry::findLengthUnit(set.unit)));
        }
        const std::string ext = study::fileExtension(out);
        if (ext == "stp" || ext == "step")
            cad::writeStep(set, out, schema);
        else
            savePatchSet(set, out);
        std::fprintf(stderr, "wrote %s: %d patches (%d trimmed), unit %s\n", out.c_str(), set.size(), set.trimmedCount(),
                     set.unit.empty() ? "not stated" : set.unit.c_str());
        return kOk;
    });
}

const char* kMainHelp =
    "usage: aeroform-cli COMMAND [ARGS] (COMMAND --help for details)\n"
    "\n"
    "Aeroform: two-level free-form deformation for aerodynamic shape design.\n"
    "\n"
    "commands:\n"
    "  info FILE [--json] [--strict]  unit, what was read, patches, trims, bounding box, edge gaps\n"
    "  sample half-sphere -o FILE     generate the paper's half-sphere sample\n"
    "  convert IN OUT [--units U]     IGES / STEP / native JSON, in the file's unit, trims kept\n"
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
    // A short spin before a thread sleeps (libgomp's count of pause instructions; passive alone
    // is 0): a flow solve's threads meet 30-40 times per GMRES iteration, and on this VM each
    // sleep and wake-up costs tens of microseconds. 3000 took 0.81-0.96x the time of 0 on the
    // idle machine and the same with a busy process beside it; 30000 took 1.46x there
    // (docs/performance.md).
    setenv("GOMP_SPINCOUNT", "3000", 0);
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
        cad::ReadReport report;
        const geometry::PatchSet set = study::loadGeometry(path, &report);
        const GeometryInfo info = describeGeometry(path, set, &report);
        for (const std::string& w : report.warnings) std::fprintf(stderr, "[batch] warning: %s\n", w.c_str());
        std::cout << info.text;
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::fprintf(stderr, "[batch] done in %.3f s\n", s);
        return kOk;
    });
}

}  // namespace aero::app
