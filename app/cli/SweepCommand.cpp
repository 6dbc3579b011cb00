// aeroform-cli sweep CASE: the case's flow evaluated over its design space, the robustness suite of
// docs/validation.md: the case's design scaled towards the baseline (--fractions) and random designs
// (--random, a fixed seed; a draw whose lattice is not injective or whose grid folds is redrawn and
// counted). One row per design: status, forces, the largest Mach number and where, iterations,
// GMRES iterations, time, peak memory; exit 1 unless every design converged.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "cli/CliSupport.h"
#include "common/AtomicFile.h"
#include "common/Memory.h"
#include "io/CaseWriter.h"
#include "study/CaseEvaluator.h"
#include "study/DesignSweep.h"
#include "study/GeometryFiles.h"

namespace aero::app {

namespace {

const char* kSweepHelp =
    "usage: aeroform-cli sweep CASE.json [--fractions LIST] [--random N] [--seed S] [--spread X]\n"
    "                                     [--feasible] [--warm] [--csv FILE] [--json]\n"
    "\n"
    "Solves the case's flow at many designs of its design space and reports each: the case's own\n"
    "design scaled towards the baseline (v0 + f (v - v0) for every f of --fractions; default\n"
    "0,0.25,0.5,0.75,1) and --random N designs whose every variable lies anywhere up to X times its\n"
    "range from its baseline value (--spread, default 0.5), drawn with --seed (default 1). A random\n"
    "design whose lattice is not injective or whose moved grid folds is redrawn; the redraws are\n"
    "counted and their last reason reported. With --feasible only draws that satisfy the case's\n"
    "linear constraints (stations in order with constraints.station_gap, symmetry) are kept, as\n"
    "every optimizer iterate does; those redraws cost no lattice check and are counted apart. Each\n"
    "design starts from the free stream (--warm: from the previous converged design, as an\n"
    "optimizer would).\n"
    "\n"
    "  --fractions LIST  comma-separated fractions (empty: none)\n"
    "  --random N        random designs (default 0)\n"
    "  --seed S          random seed (default 1)\n"
    "  --spread X        fraction of each variable's range (default 0.5)\n"
    "  --max-draws N     random draws tried per design before giving up (default 20000)\n"
    "  --feasible        random draws within the case's linear constraints\n"
    "  --cases DIR       write each design as a case file DIR/<design>.json (its values), to\n"
    "                    look at or re-run one with aeroform-cli flow/mesh/deform\n"
    "  --no-flow         shapes and grids only: how many draws are valid, without solving\n"
    "  --warm            warm-start every design from the last converged one\n"
    "  --csv FILE        one row per design (with growing_mode_rate for a flow that did not converge)\n"
    "  --json            one JSON summary on stdout\n"
    "  --help            this text\n"
    "Exit 0 when every design converged, 1 otherwise (each failure says why), 2 usage error.\n";

void say(const std::string& s) { std::fprintf(stderr, "[sweep] %s\n", s.c_str()); }

std::vector<double> parseList(const std::string& s, const std::string& what) {
    std::vector<double> out;
    for (const std::string& item : splitList(s)) {
        try {
            std::size_t used = 0;
            out.push_back(std::stod(item, &used));
            if (used != item.size()) throw std::invalid_argument(item);
        } catch (const std::exception&) {
            throw CaseError(what + ": '" + item + "' is not a number");
        }
    }
    return out;
}

struct Row {
    std::string label;
    std::string status;
    std::string message;
    int redraws = 0;
    double CL = 0, CD = 0, maxMach = 0, orders = 0, seconds = 0, peakMb = 0;
    double wallBend = 0;  // degrees, the wall's sharpest node-to-node turn (0: no grid)
    std::string maxMachAt;
    // A flow that did not converge (flow.stall_modes): the fastest growing mode's rate, 0 when
    // none grows; NaN when not looked for.
    double growingMode = std::numeric_limits<double>::quiet_NaN();
    int iterations = 0, gmres = 0;
    long nodes = 0;
    bool converged = false;
    bool warm = false;
};

}  // namespace

int runSweep(const std::string& casePath, const std::vector<double>& fractions, int random, std::uint64_t seed,
             double spread, int maxDraws, bool feasible, bool noFlow, bool warm, const std::string& csvPath,
             const std::string& casesDir, bool json) {
    return guarded("sweep", [&] {
        const io::CaseFile c = io::readCase(casePath);
        if (!c.flow.present) throw CaseError("'" + casePath + "': the case has no \"flow\" section to sweep");
        study::CaseEvaluator ev(c, loadPatchSet(c.geometry), say);
        say(std::to_string(ev.variableCount()) + " design variables; " + std::to_string(fractions.size()) +
            " scaled designs, " + std::to_string(random) + " random (seed " + std::to_string(seed) + ", spread " +
            std::to_string(spread) + (feasible ? ", within the linear constraints" : "") + ")");
        std::optional<CancelOnSignal> signals(std::in_place);
        std::atomic<bool>& cancel = *CancelOnSignal::flag();
        std::vector<Row> rows;
        study::RandomDesigns designs(ev, seed, spread, feasible);
        int redrawsShape = 0, redrawsMesh = 0;
        const int total = static_cast<int>(fractions.size()) + random;
        for (int d = 0; d < total && !cancel.load(); ++d) {
            Row row;
            std::vector<double> v;
            if (d < static_cast<int>(fractions.size())) {
                char b[64];
                std::snprintf(b, sizeof b, "fraction %g", fractions[d]);
                row.label = b;
                v = study::scaledDesign(ev, fractions[d]);
            } else {
                row.label = "random " + std::to_string(d - static_cast<int>(fractions.size()) + 1);
                const study::ValidDraw draw = study::drawValidDesign(ev, designs, maxDraws, &cancel);
                row.redraws = draw.rejected;
                redrawsShape += draw.rejectedShape;
                redrawsMesh += draw.rejectedMesh;
                if (!draw.accepted) {
                    row.status = cancel.load() ? "cancelled" : "no-valid-draw";
                    row.message = "no valid design in " + std::to_string(maxDraws) + " draws; the last: " + draw.lastReason;
                    rows.push_back(row);
                    continue;
                }
                if (draw.rejected > 0) say(row.label + ": " + std::to_string(draw.rejected) + " draw(s) redrawn; the last: " + draw.lastReason);
                v = draw.values;
            }
            if (!casesDir.empty() && ev.model()) {
                // The design as a case of its own (values by name; outputs dropped).
                const io::CaseFile one = ev.designCase(v, std::nullopt, "design '" + row.label + "' of aeroform-cli sweep " + casePath);
                std::string file = row.label;
                std::replace(file.begin(), file.end(), ' ', '_');
                std::filesystem::create_directories(casesDir);
                io::writeCase(one, (std::filesystem::path(casesDir) / (file + ".json")).string());
            }
            study::EvaluationRequest rq;
            rq.warmStart = warm;
            rq.flow = !noFlow;
            const auto t0 = std::chrono::steady_clock::now();
            int lastIteration = 0;
            const study::Evaluation e = ev.evaluate(v, rq, [&](const study::Progress& p) {
                if (p.iteration && p.iteration->rejected.empty() && !p.coarse) lastIteration = p.iteration->iteration;
            }, &cancel);
            row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            row.status = study::evaluationStatusName(e.status);
            row.message = e.message;
            (void)lastIteration;
            if (e.mesh && !e.mesh->grids.empty()) row.wallBend = e.mesh->wallBend.degrees;
            if (noFlow) row.converged = e.ok();
            if (e.flow) {
                const flow::FlowReport& r = e.flow->report;
                row.converged = r.converged();
                row.iterations = r.iterations;
                row.gmres = r.linearIterations;
                row.orders = r.finalResidual > 0 ? std::log10(r.initialResidual / r.finalResidual) : 16.0;
                row.CL = e.flow->forces.CL;
                row.CD = e.flow->forces.CD;
                row.maxMach = e.flow->maxMach.value;
                char w[160];
                std::snprintf(w, sizeof w, "block %d '%s' (%.2f, %.2f, %.2f)", e.flow->maxMach.block,
                              e.flow->maxMach.blockName.c_str(), e.flow->maxMach.x[0], e.flow->maxMach.x[1],
                              e.flow->maxMach.x[2]);
                row.maxMachAt = w;
                row.nodes = e.flow->mesh.nodeCount;
                row.warm = e.flow->warmStarted;
                if (e.flow->modesChecked) row.growingMode = e.flow->modes.growthRate();
            }
            row.peakMb = peakMemoryMb();
            char line[512];
            std::snprintf(line, sizeof line,
                          "%-14s %-18s CL %8.4f  CD %8.4f  max Mach %.3f  bend %4.1f deg  %5.1f orders  %3d it  %5d GMRES  %6.1f s%s",
                          row.label.c_str(), row.status.c_str(), row.CL, row.CD, row.maxMach, row.wallBend, row.orders,
                          row.iterations, row.gmres, row.seconds, row.warm ? "  (warm)" : "");
            say(line);
            if (!e.ok()) say("  why: " + e.message);
            rows.push_back(row);
        }
        signals.reset();

        int converged = 0;
        for (const Row& r : rows) converged += r.converged ? 1 : 0;
        say(std::to_string(converged) + " of " + std::to_string(rows.size()) + (noFlow ? " designs valid; " : " designs converged; ") +
            std::to_string(redrawsShape) + " random draws redrawn for a non-injective lattice, " +
            std::to_string(redrawsMesh) + " for an invalid grid" +
            (feasible ? ", " + std::to_string(designs.linearRejections()) + " for a linear constraint" : std::string()));
        if (!csvPath.empty()) {
            std::ostringstream out;
            out << "design,status,converged,orders,iterations,gmres,seconds,peak_memory_mb,CL,CD,max_mach,max_mach_at,"
                   "sharpest_wall_bend,growing_mode_rate,redraws,nodes\n";
            for (const Row& r : rows) {
                out << r.label << ',' << r.status << ',' << (r.converged ? 1 : 0) << ',' << r.orders << ',' << r.iterations << ','
                    << r.gmres << ',' << r.seconds << ',' << r.peakMb << ',' << r.CL << ',' << r.CD << ',' << r.maxMach << ",\""
                    << r.maxMachAt << "\"," << r.wallBend << ',';
                if (!std::isnan(r.growingMode)) out << r.growingMode;  // empty: not looked for
                out << ',' << r.redraws << ',' << r.nodes << '\n';
            }
            writeTextAtomically(csvPath, out.str(), "sweep CSV");
            say("wrote " + csvPath);
        }
        if (json) {
            nlohmann::ordered_json j;
            j["case"] = casePath;
            j["designs"] = rows.size();
            j["converged"] = converged;
            j["redrawn_not_injective"] = redrawsShape;
            j["redrawn_invalid_mesh"] = redrawsMesh;
            j["redrawn_linear_constraint"] = designs.linearRejections();
            nlohmann::ordered_json arr = nlohmann::ordered_json::array();
            for (const Row& r : rows) {
                arr.push_back({{"design", r.label},      {"status", r.status},   {"converged", r.converged},
                               {"message", r.message},   {"orders", r.orders},   {"iterations", r.iterations},
                               {"gmres", r.gmres},       {"seconds", r.seconds}, {"peak_memory_mb", r.peakMb},
                               {"CL", r.CL},             {"CD", r.CD},           {"max_mach", r.maxMach},
                               {"max_mach_at", r.maxMachAt}, {"sharpest_wall_bend", r.wallBend},
                               {"growing_mode_rate", std::isnan(r.growingMode) ? nlohmann::ordered_json()
                                                                               : nlohmann::ordered_json(r.growingMode)},
                               {"redraws", r.redraws}, {"grid_nodes", r.nodes},
                               {"warm_start", r.warm}});
            }
            j["rows"] = arr;
            std::printf("%s\n", j.dump(2).c_str());
        }
        return converged == static_cast<int>(rows.size()) && !rows.empty() ? kOk : kFailed;
    });
}

int cmdSweep(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::printf("%s", kSweepHelp);
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json", "--warm", "--feasible", "--no-flow"}, {"--fractions", "--random", "--seed", "--spread", "--csv", "--max-draws", "--cases"}, pos, val, err)) {
        return usageError("sweep", err, kSweepHelp);
    }
    if (pos.size() != 1) return usageError("sweep", "expected exactly one CASE file", kSweepHelp);
    std::vector<double> fractions{0, 0.25, 0.5, 0.75, 1.0};
    int random = 0;
    std::uint64_t seed = 1;
    double spread = 0.5;
    int maxDraws = 20000;
    try {
        if (val.count("--max-draws")) maxDraws = std::stoi(val["--max-draws"]);
        if (val.count("--fractions")) fractions = parseList(val["--fractions"], "--fractions");
        if (val.count("--random")) random = std::stoi(val["--random"]);
        if (val.count("--seed")) seed = std::stoull(val["--seed"]);
        if (val.count("--spread")) spread = std::stod(val["--spread"]);
    } catch (const std::exception& e) {
        return usageError("sweep", std::string("bad option value: ") + e.what(), kSweepHelp);
    }
    if (random < 0 || !(spread >= 0) || maxDraws < 1) return usageError("sweep", "--random and --spread must not be negative", kSweepHelp);
    return runSweep(pos[0], fractions, random, seed, spread, maxDraws, val.count("--feasible") > 0, val.count("--no-flow") > 0, val.count("--warm") > 0, val.count("--csv") ? val["--csv"] : "", val.count("--cases") ? val["--cases"] : "",
                    val.count("--json") > 0);
}

}  // namespace aero::app
