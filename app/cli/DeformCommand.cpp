// aeroform-cli deform CASE: geometry -> lattices -> embedding -> design variables -> deformed
// geometry, with injectivity, constraints and outputs (IGES/JSON and VTK for ParaView).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/CliSupport.h"
#include "geometry/EnclosedVolume.h"
#include "geometry/Planform.h"
#include "io/CaseFile.h"
#include "io/GeometryVtk.h"
#include "study/CaseEvaluator.h"

namespace aero::app {

namespace {

const char* kDeformHelp =
    "usage: aeroform-cli deform CASE.json [--json] [--list]\n"
    "\n"
    "Reads a case (docs/case-file.md): loads its geometry, places the FFD lattices, embeds the\n"
    "geometry's control points, applies the design-variable values and lattice displacements,\n"
    "checks the lattices' injectivity and the geometric constraints, and writes the deformed\n"
    "geometry (IGES or JSON, exact NURBS) and a VTK multiblock for ParaView (sampled patches,\n"
    "control nets, lattices, with displacement fields).\n"
    "Fails (exit 1, nothing written) if control points lie outside every lattice (unless the\n"
    "case sets embedding.allow_outside) or a deformed lattice is not injective.\n"
    "\n"
    "  --json    print one JSON summary on stdout (embedded_points, max_embedding_error,\n"
    "            points_outside, injective, min_jacobian, volume, planform (half_span,\n"
    "            projected_area, aspect_ratio), design_variables, ...)\n"
    "  --list    list the design variables (name, baseline, bounds, value) and exit\n"
    "  --help    this text\n";

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void progress(bool quiet, const char* fmt, auto... args) {
    if (quiet) return;
    std::fprintf(stderr, "[deform] ");
    std::fprintf(stderr, fmt, args...);
    std::fprintf(stderr, "\n");
}

}  // namespace

int runDeform(const std::string& casePath, bool json, bool list) {
    return guarded("deform", [&] {
        const auto t0 = std::chrono::steady_clock::now();
        const io::CaseFile c = io::readCase(casePath);
        if (c.lattices.empty()) throw CaseError("'" + casePath + "': lattices: the case defines no FFD lattice");
        const geometry::PatchSet set = loadPatchSet(c.geometry);
        progress(list, "geometry %s: %d patches, %d control points", c.geometry.c_str(), set.size(), set.controlPointCount());
        if (list) {
            // Variables only: no deformation checks needed.
            const ffd::FfdModel model = io::buildModel(c, set);
            const std::vector<double> v = io::designValues(c, model);
            const auto& vars = model.design().variables();
            std::printf("%-28s %10s %10s %10s %10s\n", "name", "baseline", "lower", "upper", "value");
            for (std::size_t i = 0; i < vars.size(); ++i) {
                std::printf("%-28s %10.4g %10.4g %10.4g %10.4g\n", vars[i].name.c_str(), vars[i].baseline, vars[i].lower,
                            vars[i].upper, v[i]);
            }
            return kOk;
        }
        // The one pipeline (study::CaseEvaluator): its shape stage at the case's design.
        study::CaseEvaluator ev(c, set, [](const std::string& s) { std::fprintf(stderr, "[deform] %s\n", s.c_str()); });
        study::EvaluationRequest shapeOnly;
        shapeOnly.mesh = false;
        shapeOnly.flow = false;
        const study::Evaluation e = ev.evaluate(ev.caseValues(), shapeOnly);
        if (!e.ok()) throw GeometryError("'" + casePath + "': " + e.message);
        const ffd::FfdModel& model = *ev.model();
        const ffd::EmbeddingSummary& emb = model.summary();
        const std::vector<double>& v = e.values;
        const std::vector<ffd::Lattice>& moved = e.lattices;
        double minJacobian = std::numeric_limits<double>::infinity();
        nlohmann::ordered_json lattices = nlohmann::ordered_json::array();
        for (std::size_t l = 0; l < moved.size(); ++l) {
            const ffd::InjectivityReport& r = e.injectivity[l];
            minJacobian = std::min(minJacobian, r.relativeMinJacobian);
            lattices.push_back({{"name", model.lattices()[l].name},
                                {"counts", moved[l].count},
                                {"degrees", moved[l].degree},
                                {"injective", r.injective},
                                {"certified", r.certified},
                                {"refinements", r.refinements},
                                {"min_jacobian", r.relativeMinJacobian}});
        }
        int outside = 0;
        for (const auto& f : emb.failures) outside += f.outside ? 1 : 0;
        const int notConverged = static_cast<int>(emb.failures.size()) - outside;
        const geometry::PatchSet& deformed = e.shape;
        // The enclosed volume integrates over whole patches: not computed for trimmed ones (a
        // min_volume constraint then fails in enclosedVolume with the patch named).
        const bool trimmed = set.trimmedCount() > 0 && !c.minVolume;
        const double nan = std::numeric_limits<double>::quiet_NaN();
        const double volume0 = trimmed ? nan : geometry::enclosedVolume(set);
        const double volume = trimmed ? nan : geometry::enclosedVolume(deformed);
        if (trimmed)
            progress(false, "enclosed volume not computed (%d trimmed patches)", set.trimmedCount());
        else
            progress(false, "enclosed volume %.10g (baseline %.10g)", volume, volume0);
        if (volume0 < 0)
            std::fprintf(stderr,
                         "aeroform-cli deform: warning: the enclosed volume is negative: the patches' normals point "
                         "into the body, or the shape is not a half-body closed by the symmetry plane Y = 0 (the "
                         "volume, and min_volume, assume both)\n");
        // The planform (Section V of the paper): half-span, shadow on Z = 0, aspect ratio.
        geometry::Planform planform0, planform;
        if (!trimmed) {
            planform0 = geometry::planform(set);
            planform = geometry::planform(deformed);
            progress(false, "planform: half-span %.6g, projected area %.6g, aspect ratio %.4g (baseline %.6g, %.6g, %.4g)",
                     planform.halfSpan, planform.projectedArea, planform.aspectRatio, planform0.halfSpan,
                     planform0.projectedArea, planform0.aspectRatio);
        }

        // Constraints, reported (deform does not enforce them; the optimizer will).
        nlohmann::ordered_json constraints;
        if (c.symmetry) {
            // Measured on the deformed patches (explicit displacements are included there).
            double off = 0;
            for (int p = 0; p < set.size(); ++p) {
                for (std::size_t a = 1; a < set.patches[p].points.size(); a += 3) {
                    if (set.patches[p].points[a] == 0.0) off = std::max(off, std::abs(deformed.patches[p].points[a]));
                }
            }
            constraints["symmetry_max_offset"] = off;
        }
        if (c.stationGap) {
            const auto gaps = model.stationGapConstraints(*c.stationGap);
            int violated = 0;
            for (const auto& g : gaps) {
                double value = 0;
                for (std::size_t i = 0; i < v.size(); ++i) value += g.row[i] * v[i];
                violated += value < g.lower - 1e-12 ? 1 : 0;
            }
            constraints["station_gap"] = *c.stationGap;
            constraints["station_gap_violations"] = violated;
        }
        {
            // Reported always: how far the design bends the lattice across adjacent stations.
            const auto [largest, where] = model.largestStationSecondDifference(v);
            if (!where.empty()) {
                progress(false, "largest second difference of the lattice across stations %.4g at %s", largest,
                         where.c_str());
                constraints["largest_station_second_difference"] = largest;
                constraints["largest_station_second_difference_at"] = where;
            }
            if (c.stationSecondDifference) {
                constraints["station_second_difference"] = *c.stationSecondDifference;
                constraints["station_second_difference_ok"] = largest <= *c.stationSecondDifference * (1 + 1e-12);
            }
        }
        if (c.minVolume) {
            const double minV = std::isnan(*c.minVolume) ? volume0 : *c.minVolume;
            constraints["min_volume"] = minV;
            constraints["volume_ok"] = volume >= minV * (1 - 1e-12);
        }

        nlohmann::ordered_json outputs = nlohmann::ordered_json::object();
        if (!c.outputGeometry.empty()) {
            std::filesystem::create_directories(std::filesystem::path(c.outputGeometry).parent_path());
            savePatchSet(deformed, c.outputGeometry);
            outputs["geometry"] = c.outputGeometry;
            progress(false, "wrote %s", c.outputGeometry.c_str());
        }
        if (!c.outputVtk.empty()) {
            std::filesystem::create_directories(std::filesystem::path(c.outputVtk).parent_path());
            std::vector<ffd::Lattice> baseLattices;
            for (const auto& s : model.lattices()) baseLattices.push_back(s.lattice);
            io::writeVtm(c.outputVtk, io::geometryBlocks(deformed, &set, moved, &baseLattices));
            outputs["vtk"] = c.outputVtk;
            progress(false, "wrote %s", c.outputVtk.c_str());
        }

        if (json) {
            nlohmann::ordered_json j;
            j["case"] = casePath;
            j["geometry"] = c.geometry;
            j["patches"] = set.size();
            j["unique_control_points"] = emb.unique;
            j["embedded_points"] = emb.embedded;
            j["fixed_points"] = emb.fixed;
            j["max_embedding_error"] = emb.maxError;
            j["points_outside"] = outside;
            j["points_not_converged"] = notConverged;
            j["design_variables"] = model.design().size();
            j["injective"] = true;  // a non-injective lattice is an InvalidShape status: refused above
            j["min_jacobian"] = minJacobian;
            j["lattices"] = lattices;
            j["volume"] = trimmed ? nlohmann::ordered_json() : nlohmann::ordered_json(volume);
            j["initial_volume"] = trimmed ? nlohmann::ordered_json() : nlohmann::ordered_json(volume0);
            auto planformJson = [&](const geometry::Planform& f) {
                if (trimmed) return nlohmann::ordered_json();
                nlohmann::ordered_json p;
                p["half_span"] = f.halfSpan;
                p["projected_area"] = f.projectedArea;
                p["aspect_ratio"] = f.aspectRatio;
                p["half_body"] = f.halfBody;
                return p;
            };
            j["planform"] = planformJson(planform);
            j["initial_planform"] = planformJson(planform0);
            j["constraints"] = constraints;
            j["outputs"] = outputs;
            j["seconds"] = seconds(t0);
            std::printf("%s\n", j.dump(2).c_str());
        }
        progress(false, "done in %.3f s", seconds(t0));
        return kOk;
    });
}

int cmdDeform(const Args& args) {
    if (hasFlag(args, "--help") || hasFlag(args, "-h")) {
        std::printf("%s", kDeformHelp);
        return kOk;
    }
    std::vector<std::string> pos;
    std::map<std::string, std::string> val;
    std::string err;
    if (!parse(args, {"--json", "--list"}, {}, pos, val, err)) return usageError("deform", err, kDeformHelp);
    if (pos.size() != 1) return usageError("deform", "expected exactly one CASE file", kDeformHelp);
    return runDeform(pos[0], val.count("--json") > 0, val.count("--list") > 0);
}

}  // namespace aero::app
