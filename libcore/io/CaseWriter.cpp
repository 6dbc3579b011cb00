#include "io/CaseWriter.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <variant>

#include "common/Error.h"
#include "io/Options.h"

namespace aero::io {

using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

namespace {

const char* axisName(int axis) {
    static const char* const kNames[] = {"x", "y", "z"};
    return axis >= 0 && axis < 3 ? kNames[axis] : "?";
}

// `p` as the case file will store it: relative to the case's folder when that survives moving
// the project tree (both in the same top-level folder), else unchanged.
std::string storedPath(const std::string& p, const std::string& casePath) {
    if (p.empty() || casePath.empty()) return p;
    fs::path target = fs::path(p).lexically_normal();
    fs::path base = fs::path(casePath).parent_path().lexically_normal();
    if (!target.is_absolute() && !base.is_absolute()) {
        // Both relative to the working directory: relative to each other works as well.
        const fs::path rel = target.lexically_relative(base.empty() ? fs::path(".") : base);
        return rel.empty() ? p : rel.generic_string();
    }
    std::error_code ec;
    if (!target.is_absolute()) target = fs::absolute(target, ec).lexically_normal();
    if (!base.is_absolute()) base = fs::absolute(base, ec).lexically_normal();
    if (ec) return p;
    auto t = target.begin(), b = base.begin();
    // Skip the root, then require the same first folder.
    if (t == target.end() || b == base.end()) return target.generic_string();
    ++t;
    ++b;
    if (t == target.end() || b == base.end() || *t != *b) return target.generic_string();
    const fs::path rel = target.lexically_relative(base);
    return rel.empty() ? target.generic_string() : rel.generic_string();
}

const std::string& latticeName(const CaseFile& c, int lattice, const std::string& key) {
    if (lattice < 0 || lattice >= static_cast<int>(c.lattices.size())) {
        throw CaseError("'" + c.path + "': " + key + ": lattice " + std::to_string(lattice) + " does not exist (the case has " +
                        std::to_string(c.lattices.size()) + ")");
    }
    return c.lattices[static_cast<std::size_t>(lattice)].name;
}

bool identityAxes(const std::array<std::array<double, 3>, 3>& a) {
    for (int d = 0; d < 3; ++d)
        for (int k = 0; k < 3; ++k)
            if (a[d][k] != (d == k ? 1.0 : 0.0)) return false;
    return true;
}

Json latticeJson(const LatticeCase& l) {
    Json j;
    j["name"] = l.name;
    j["counts"] = l.counts;
    j["degrees"] = l.degrees;
    j["padding"] = l.padding;
    if (!identityAxes(l.axes)) j["axes"] = l.axes;
    if (l.box) j["box"] = {{"origin", l.box->origin}, {"size", l.box->size}};
    if (!l.patches.empty()) {
        Json p = Json::array();
        for (int patch : l.patches) p.push_back(patch + 1);  // 1-based in the file
        j["patches"] = std::move(p);
    }
    if (!l.refine.empty()) {
        Json r = Json::array();
        for (const auto& [dir, knots] : l.refine) r.push_back({{"direction", dir}, {"knots", knots}});
        j["refine"] = std::move(r);
    }
    if (!l.crease.empty()) {
        Json r = Json::array();
        for (const auto& [dir, at] : l.crease) r.push_back({{"direction", dir}, {"at", at}});
        j["crease"] = std::move(r);
    }
    return j;
}

Json caseJson(const CaseFile& c) {
    Json doc;
    doc["format"] = "aeroform.case";
    doc["version"] = 1;
    if (!c.description.empty()) doc["description"] = c.description;
    doc["geometry"] = storedPath(c.geometry, c.path);
    if (!c.lattices.empty()) {
        Json ls = Json::array();
        for (const LatticeCase& l : c.lattices) ls.push_back(latticeJson(l));
        doc["lattices"] = std::move(ls);
    }
    if (!c.stations.empty() || !c.pointVariables.empty()) {
        Json dv;
        if (!c.stations.empty()) {
            Json ss = Json::array();
            for (std::size_t i = 0; i < c.stations.size(); ++i) {
                const ffd::StationSpec& s = c.stations[i];
                Json j;
                j["lattice"] = latticeName(c, s.lattice, "design_variables.stations[" + std::to_string(i) + "].lattice");
                j["direction"] = s.direction;
                if (!s.bits.empty()) j["bits"] = s.bits;
                j["section_scaling"] = s.sectionScaling;
                j["taper"] = s.taper;
                j["vertical"] = axisName(s.vertical);
                j["streamwise"] = axisName(s.streamwise);
                j["translation_bound"] = s.translationBound;
                j["scaling_bounds"] = s.scalingBounds;
                j["taper_bounds"] = s.taperBounds;
                ss.push_back(std::move(j));
            }
            dv["stations"] = std::move(ss);
        }
        if (!c.pointVariables.empty()) {
            Json ps = Json::array();
            for (std::size_t i = 0; i < c.pointVariables.size(); ++i) {
                const PointVariableCase& p = c.pointVariables[i];
                ps.push_back({{"lattice", latticeName(c, p.lattice, "design_variables.points[" + std::to_string(i) + "].lattice")},
                              {"index", p.index},
                              {"axes", p.axes},
                              {"bounds", p.bounds}});
            }
            dv["points"] = std::move(ps);
        }
        doc["design_variables"] = std::move(dv);
    }
    if (!c.values.empty()) {
        Json v = Json::object();
        for (const auto& [name, value] : c.values) v[name] = value;
        doc["values"] = std::move(v);
    }
    if (!c.displacements.empty()) {
        Json ds = Json::array();
        for (std::size_t i = 0; i < c.displacements.size(); ++i) {
            const DisplacementCase& d = c.displacements[i];
            ds.push_back({{"lattice", latticeName(c, d.lattice, "displacements[" + std::to_string(i) + "].lattice")},
                          {"index", d.index},
                          {"delta", d.delta}});
        }
        doc["displacements"] = std::move(ds);
    }
    doc["embedding"] = {{"tolerance", c.embedding.tolerance},
                        {"max_iterations", c.embedding.maxIterations},
                        {"allow_outside", c.allowOutside}};
    Json k;
    k["symmetry"] = c.symmetry;
    if (c.stationGap) k["station_gap"] = *c.stationGap;
    if (c.stationSecondDifference) k["station_second_difference"] = *c.stationSecondDifference;
    if (c.minVolume) {
        if (std::isnan(*c.minVolume))
            k["min_volume"] = "initial";
        else
            k["min_volume"] = *c.minVolume;
    }
    if (c.thickness.present()) {
        Json t;
        if (!c.thickness.stations.empty()) {
            t["stations"] = c.thickness.stations;
            t["chord_fractions"] = c.thickness.chordFractions;
        }
        if (!c.thickness.points.empty()) {
            Json ps = Json::array();
            for (const auto& p : c.thickness.points) ps.push_back({p[0], p[1]});
            t["points"] = std::move(ps);
        }
        t["min_ratio"] = c.thickness.minRatio;
        k["thickness"] = std::move(t);
    }
    if (c.minLatticeJacobian > 0) k["min_lattice_jacobian"] = c.minLatticeJacobian;
    doc["constraints"] = std::move(k);
    if (c.mesh.present) {
        // The level names the defaults; every option of the table is written explicitly (the
        // level first, so reading it back applies the level before the overrides).
        Json j = Json::object();
        for (const auto& opt : meshOptions()) std::visit([&](const auto& v) { j[opt.spec.key] = v; }, opt.get(c.mesh));
        doc["mesh"] = std::move(j);
    }
    if (c.flow.present) {
        const FlowCase& f = c.flow;
        Json j = Json::object();
        for (const auto& opt : flowOptions()) {  // every option of the table (io/Options.h)
            std::visit([&](const auto& v) { j[opt.spec.key] = v; }, opt.get(f));
        }
        if (!f.restart.empty()) j["restart"] = storedPath(f.restart, c.path);
        doc["flow"] = std::move(j);
    }
    if (c.optimization.present) {
        Json j = Json::object();
        for (const auto& opt : optimizationOptions()) {
            std::visit([&](const auto& v) { j[opt.spec.key] = v; }, opt.get(c.optimization));
        }
        if (!c.optimization.history.empty()) j["history"] = storedPath(c.optimization.history, c.path);
        if (!c.optimization.iterations.empty()) j["iterations"] = storedPath(c.optimization.iterations, c.path);
        if (!c.optimization.targetPressure.empty()) j["target_pressure"] = storedPath(c.optimization.targetPressure, c.path);
        if (!c.optimization.startDesign.empty()) j["start_design"] = storedPath(c.optimization.startDesign, c.path);
        doc["optimization"] = std::move(j);
    }
    Json o = Json::object();
    if (!c.outputGeometry.empty()) o["geometry"] = storedPath(c.outputGeometry, c.path);
    if (!c.outputVtk.empty()) o["vtk"] = storedPath(c.outputVtk, c.path);
    if (!c.outputMeshVtk.empty()) o["mesh_vtk"] = storedPath(c.outputMeshVtk, c.path);
    if (!c.outputControlVtk.empty()) o["control_vtk"] = storedPath(c.outputControlVtk, c.path);
    if (!c.outputPlot3d.empty()) o["plot3d"] = storedPath(c.outputPlot3d, c.path);
    if (!c.outputFlowVtk.empty()) o["flow_vtk"] = storedPath(c.outputFlowVtk, c.path);
    if (!c.outputResidualCsv.empty()) o["residual_csv"] = storedPath(c.outputResidualCsv, c.path);
    if (!c.outputRestart.empty()) o["restart"] = storedPath(c.outputRestart, c.path);
    if (!c.outputWallPressure.empty()) o["wall_pressure"] = storedPath(c.outputWallPressure, c.path);
    if (!o.empty()) doc["output"] = std::move(o);
    return doc;
}

// Compact rendering of a scalar-only array, or "" if it holds objects or is too long for a line.
std::string inlineArray(const Json& a) {
    std::string s = "[";
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (i) s += ", ";
        const Json& e = a[i];
        if (e.is_object()) return {};
        if (e.is_array()) {
            const std::string inner = inlineArray(e);
            if (inner.empty()) return {};
            s += inner;
        } else {
            s += e.dump();
        }
        if (s.size() > 96) return {};
    }
    return s + "]";
}

// Two-space indentation like dump(2), but short arrays of numbers stay on one line.
void render(const Json& j, int indent, std::string& out) {
    const std::string pad(static_cast<std::size_t>(indent) + 2, ' ');
    if (j.is_object()) {
        if (j.empty()) {
            out += "{}";
            return;
        }
        out += "{\n";
        bool first = true;
        for (auto it = j.begin(); it != j.end(); ++it) {
            if (!first) out += ",\n";
            first = false;
            out += pad + Json(it.key()).dump() + ": ";
            render(it.value(), indent + 2, out);
        }
        out += "\n" + std::string(static_cast<std::size_t>(indent), ' ') + "}";
    } else if (j.is_array()) {
        const std::string line = inlineArray(j);
        if (!line.empty() || j.empty()) {
            out += j.empty() ? "[]" : line;
            return;
        }
        out += "[\n";
        for (std::size_t i = 0; i < j.size(); ++i) {
            if (i) out += ",\n";
            out += pad;
            render(j[i], indent + 2, out);
        }
        out += "\n" + std::string(static_cast<std::size_t>(indent), ' ') + "]";
    } else {
        out += j.dump();
    }
}

}  // namespace

std::string formatCase(const CaseFile& c) {
    std::string out;
    render(caseJson(c), 0, out);
    return out + "\n";
}

void writeCase(const CaseFile& c, const std::string& path) {
    CaseFile located = c;
    located.path = path;
    const std::string text = formatCase(located);
    // Temporary file + rename: an existing project is never left half-written.
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw InputError("cannot write case file '" + path + "'");
        out << text;
        if (!out.flush()) {
            out.close();
            std::remove(tmp.c_str());
            throw InputError("cannot write case file '" + path + "'");
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw InputError("cannot replace case file '" + path + "'");
    }
}

}  // namespace aero::io
