#include "io/CaseFile.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "common/Error.h"
#include "io/InputFile.h"
#include "io/Options.h"
#include "nurbs/Basis.h"
#include "nurbs/KnotInsertion.h"

namespace aero::io {

using nlohmann::json;

namespace {

constexpr const char* kFormat = "aeroform.case";
constexpr int kVersion = 1;

// Validation context: every error names the case file and the JSON path of the key.
struct Ctx {
    const std::string& file;
    [[noreturn]] void fail(const std::string& key, const std::string& why) const {
        throw CaseError("'" + file + "': " + key + ": " + why);
    }
    void keys(const json& obj, const std::string& key, std::initializer_list<const char*> allowed) const {
        keys(obj, key, std::vector<std::string>(allowed.begin(), allowed.end()));
    }
    void keys(const json& obj, const std::string& key, const std::vector<std::string>& allowed) const {
        if (!obj.is_object()) fail(key, "expected an object");
        for (auto it = obj.begin(); it != obj.end(); ++it) {
            bool ok = false;
            for (const auto& a : allowed) ok = ok || it.key() == a;
            if (!ok) {
                std::string list;
                for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
                fail(key.empty() ? it.key() : key + "." + it.key(), "unknown key (allowed: " + list + ")");
            }
        }
    }
    double number(const json& v, const std::string& key) const {
        if (!v.is_number()) fail(key, std::string("expected a number, found ") + v.type_name());
        const double x = v.get<double>();
        if (!std::isfinite(x)) fail(key, "must be finite");
        return x;
    }
    int integer(const json& v, const std::string& key, int lo, int hi) const {
        if (!v.is_number_integer()) fail(key, std::string("expected an integer, found ") + v.type_name());
        const long long x = v.get<long long>();
        if (x < lo || x > hi) fail(key, std::to_string(x) + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return static_cast<int>(x);
    }
    bool boolean(const json& v, const std::string& key) const {
        if (!v.is_boolean()) fail(key, std::string("expected true or false, found ") + v.type_name());
        return v.get<bool>();
    }
    std::string string(const json& v, const std::string& key) const {
        if (!v.is_string()) fail(key, std::string("expected a string, found ") + v.type_name());
        return v.get<std::string>();
    }
    template <std::size_t N>
    std::array<double, N> numbers(const json& v, const std::string& key) const {
        if (!v.is_array() || v.size() != N) fail(key, "expected " + std::to_string(N) + " numbers");
        std::array<double, N> a{};
        for (std::size_t i = 0; i < N; ++i) a[i] = number(v[i], key + "[" + std::to_string(i) + "]");
        return a;
    }
    template <std::size_t N>
    std::array<int, N> integers(const json& v, const std::string& key, int lo, int hi) const {
        if (!v.is_array() || v.size() != N) fail(key, "expected " + std::to_string(N) + " integers");
        std::array<int, N> a{};
        for (std::size_t i = 0; i < N; ++i) a[i] = integer(v[i], key + "[" + std::to_string(i) + "]", lo, hi);
        return a;
    }
    std::vector<double> numberList(const json& v, const std::string& key) const {
        if (!v.is_array()) fail(key, "expected an array of numbers");
        std::vector<double> out;
        for (std::size_t i = 0; i < v.size(); ++i) out.push_back(number(v[i], key + "[" + std::to_string(i) + "]"));
        return out;
    }
    int axis(const json& v, const std::string& key) const {
        const std::string s = string(v, key);
        if (s == "x") return 0;
        if (s == "y") return 1;
        if (s == "z") return 2;
        fail(key, "expected \"x\", \"y\" or \"z\", got \"" + s + "\"");
    }
};

std::string resolve(const std::string& caseFile, const std::string& p) {
    const std::filesystem::path path(p);
    if (path.is_absolute()) return p;
    return (std::filesystem::path(caseFile).parent_path() / path).lexically_normal().string();
}

}  // namespace

// Control points per direction after the case's refinements and creases (what indices refer to).
std::array<int, 3> refinedCounts(const LatticeCase& lc) {
    std::array<int, 3> n{};
    for (int d = 0; d < 3; ++d) {
        std::vector<double> U = nurbs::uniformKnots(lc.degrees[d], lc.counts[d]);
        auto insert = [&](double u) { U.insert(std::upper_bound(U.begin(), U.end(), u), u); };
        for (const auto& [dir, knots] : lc.refine) {
            if (dir == d) {
                for (double u : knots) insert(u);
            }
        }
        for (const auto& [dir, u] : lc.crease) {
            if (dir != d) continue;
            for (int m = nurbs::multiplicity(U, u); m < lc.degrees[d]; ++m) insert(u);
        }
        n[d] = static_cast<int>(U.size()) - lc.degrees[d] - 1;
    }
    return n;
}

namespace {

int latticeRef(const Ctx& ctx, const json& v, const std::string& key, const std::vector<LatticeCase>& lattices) {
    if (v.is_number_integer()) return ctx.integer(v, key, 0, static_cast<int>(lattices.size()) - 1);
    const std::string name = ctx.string(v, key);
    for (std::size_t l = 0; l < lattices.size(); ++l) {
        if (lattices[l].name == name) return static_cast<int>(l);
    }
    ctx.fail(key, "no lattice named '" + name + "'");
}

// The keys of one section that an option table describes: type, range (the table's message) and
// the setter, in the table's order.
template <class S>
void readOptions(const Ctx& ctx, const json& j, const std::string& section, const std::vector<Option<S>>& options, S& out) {
    for (const auto& o : options) {
        if (!j.contains(o.spec.key)) continue;
        const std::string key = section + "." + o.spec.key;
        const json& v = j[o.spec.key];
        OptionValue value;
        switch (o.spec.kind) {
            case OptionKind::Number:
                value = ctx.number(v, key);
                break;
            case OptionKind::Integer:
                if (!v.is_number_integer()) ctx.fail(key, std::string("expected an integer, found ") + v.type_name());
                value = static_cast<long>(std::clamp<long long>(v.get<long long>(), -(1LL << 53), 1LL << 53));
                break;
            case OptionKind::Boolean:
                value = ctx.boolean(v, key);
                break;
            case OptionKind::Choice:
                value = ctx.string(v, key);
                break;
            case OptionKind::Point:
                value = ctx.numbers<3>(v, key);
                break;
        }
        const std::string why = o.spec.check(value);
        if (!why.empty()) ctx.fail(key, why);
        o.set(out, value);
    }
}

}  // namespace

CaseFile parseCase(const std::string& text, const std::string& path) {
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::exception& e) {  // parse_error, and out_of_range for a number like 1E400
        throw InputError("'" + path + "': not valid JSON: " + e.what());
    }
    const Ctx ctx{path};
    ctx.keys(doc, "", {"format", "version", "description", "geometry", "lattices", "design_variables", "values",
                       "displacements", "embedding", "constraints", "mesh", "flow", "optimization", "output"});
    if (!doc.contains("format") || !doc["format"].is_string() || doc["format"] != kFormat) {
        ctx.fail("format", std::string("expected \"") + kFormat + "\"");
    }
    if (!doc.contains("version") || !doc["version"].is_number_integer() || doc["version"] != kVersion) {
        ctx.fail("version", "unsupported version (this build reads version " + std::to_string(kVersion) + ")");
    }
    CaseFile c;
    c.path = path;
    if (!doc.contains("geometry")) ctx.fail("geometry", "missing (the geometry file, .igs or .json)");
    c.geometry = resolve(path, ctx.string(doc["geometry"], "geometry"));
    if (doc.contains("description")) c.description = ctx.string(doc["description"], "description");

    if (doc.contains("lattices")) {
        const json& ls = doc["lattices"];
        if (!ls.is_array()) ctx.fail("lattices", "expected an array");
        std::set<std::string> names;
        for (std::size_t l = 0; l < ls.size(); ++l) {
            const std::string key = "lattices[" + std::to_string(l) + "]";
            const json& j = ls[l];
            ctx.keys(j, key, {"name", "counts", "degrees", "padding", "axes", "box", "patches", "refine", "crease"});
            LatticeCase lc;
            lc.name = j.contains("name") ? ctx.string(j["name"], key + ".name") : "L" + std::to_string(l);
            if (!names.insert(lc.name).second) ctx.fail(key + ".name", "duplicate lattice name '" + lc.name + "'");
            if (j.contains("counts")) lc.counts = ctx.integers<3>(j["counts"], key + ".counts", 2, 1000);
            if (j.contains("degrees")) lc.degrees = ctx.integers<3>(j["degrees"], key + ".degrees", 1, 9);
            for (int d = 0; d < 3; ++d) {
                if (lc.counts[d] < lc.degrees[d] + 1) {
                    ctx.fail(key + ".counts[" + std::to_string(d) + "]", std::to_string(lc.counts[d]) +
                             " control points are too few for degree " + std::to_string(lc.degrees[d]));
                }
            }
            if (j.contains("padding")) {
                lc.padding = ctx.numbers<3>(j["padding"], key + ".padding");
                for (int d = 0; d < 3; ++d) {
                    if (lc.padding[d] < 0) ctx.fail(key + ".padding[" + std::to_string(d) + "]", "must be >= 0");
                }
            }
            if (j.contains("axes")) {
                const json& a = j["axes"];
                if (!a.is_array() || a.size() != 3) ctx.fail(key + ".axes", "expected three [x, y, z] axes");
                for (int d = 0; d < 3; ++d) lc.axes[d] = ctx.numbers<3>(a[d], key + ".axes[" + std::to_string(d) + "]");
                // Must be orthonormal.
                for (int d = 0; d < 3; ++d) {
                    for (int e = 0; e < 3; ++e) {
                        double dot = 0;
                        for (int k = 0; k < 3; ++k) dot += lc.axes[d][k] * lc.axes[e][k];
                        if (std::abs(dot - (d == e ? 1.0 : 0.0)) > 1e-9) ctx.fail(key + ".axes", "must be orthonormal");
                    }
                }
            }
            if (j.contains("box")) {
                ctx.keys(j["box"], key + ".box", {"origin", "size"});
                ffd::LatticeBox b;
                b.axes = lc.axes;
                if (!j["box"].contains("origin") || !j["box"].contains("size")) ctx.fail(key + ".box", "needs origin and size");
                b.origin = ctx.numbers<3>(j["box"]["origin"], key + ".box.origin");
                b.size = ctx.numbers<3>(j["box"]["size"], key + ".box.size");
                for (int d = 0; d < 3; ++d) {
                    if (!(b.size[d] > 0)) ctx.fail(key + ".box.size[" + std::to_string(d) + "]", "must be positive");
                }
                lc.box = b;
            }
            if (j.contains("patches")) {
                const json& p = j["patches"];
                if (!p.is_array()) ctx.fail(key + ".patches", "expected an array of patch numbers (1-based)");
                for (std::size_t i = 0; i < p.size(); ++i) {
                    lc.patches.push_back(ctx.integer(p[i], key + ".patches[" + std::to_string(i) + "]", 1, 1000000) - 1);
                }
            }
            if (j.contains("refine")) {
                const json& r = j["refine"];
                if (!r.is_array()) ctx.fail(key + ".refine", "expected an array");
                for (std::size_t i = 0; i < r.size(); ++i) {
                    const std::string k = key + ".refine[" + std::to_string(i) + "]";
                    ctx.keys(r[i], k, {"direction", "knots"});
                    if (!r[i].contains("direction") || !r[i].contains("knots")) ctx.fail(k, "needs direction and knots");
                    lc.refine.push_back({ctx.integer(r[i]["direction"], k + ".direction", 0, 2), ctx.numberList(r[i]["knots"], k + ".knots")});
                    for (double u : lc.refine.back().second) {
                        if (!(u > 0 && u < 1)) ctx.fail(k + ".knots", "knots must lie in (0, 1)");
                    }
                }
            }
            if (j.contains("crease")) {
                const json& r = j["crease"];
                if (!r.is_array()) ctx.fail(key + ".crease", "expected an array");
                for (std::size_t i = 0; i < r.size(); ++i) {
                    const std::string k = key + ".crease[" + std::to_string(i) + "]";
                    ctx.keys(r[i], k, {"direction", "at"});
                    if (!r[i].contains("direction") || !r[i].contains("at")) ctx.fail(k, "needs direction and at");
                    const double u = ctx.number(r[i]["at"], k + ".at");
                    if (!(u > 0 && u < 1)) ctx.fail(k + ".at", "must lie in (0, 1)");
                    lc.crease.push_back({ctx.integer(r[i]["direction"], k + ".direction", 0, 2), u});
                }
            }
            // Hostile sizes refused before anything is built (issue #20: a 200^3 lattice took
            // 13.8 GB; 100,000 inserted knots ran for minutes).
            {
                std::size_t inserted = 0;
                for (const auto& [dir, knots] : lc.refine) inserted += knots.size();
                if (inserted > 3000) {
                    ctx.fail(key + ".refine", std::to_string(inserted) + " knots to insert, more than the 3000 accepted");
                }
                const std::array<int, 3> n = refinedCounts(lc);
                const double total = static_cast<double>(n[0]) * n[1] * n[2];
                for (int d = 0; d < 3; ++d) {
                    if (n[d] > 1000) {
                        ctx.fail(key, std::to_string(n[d]) + " control points in direction " + std::to_string(d) +
                                          " after refinement, more than the 1000 accepted");
                    }
                }
                if (total > 1e6) {
                    ctx.fail(key, std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " + std::to_string(n[2]) +
                                      " control points after refinement, more than the 10^6 accepted");
                }
            }
            c.lattices.push_back(std::move(lc));
        }
    }
    if (c.lattices.empty() && (doc.contains("design_variables") || doc.contains("displacements"))) {
        ctx.fail("lattices", "design variables and displacements need at least one lattice");
    }

    if (doc.contains("design_variables")) {
        const json& dv = doc["design_variables"];
        ctx.keys(dv, "design_variables", {"stations", "points"});
        if (dv.contains("stations")) {
            const json& ss = dv["stations"];
            if (!ss.is_array()) ctx.fail("design_variables.stations", "expected an array");
            for (std::size_t i = 0; i < ss.size(); ++i) {
                const std::string key = "design_variables.stations[" + std::to_string(i) + "]";
                const json& j = ss[i];
                ctx.keys(j, key, {"lattice", "direction", "bits", "section_scaling", "taper", "vertical", "streamwise",
                                  "translation_bound", "scaling_bounds", "taper_bounds"});
                ffd::StationSpec s;
                s.lattice = j.contains("lattice") ? latticeRef(ctx, j["lattice"], key + ".lattice", c.lattices) : 0;
                s.prefix = c.lattices[s.lattice].name;
                if (j.contains("direction")) s.direction = ctx.integer(j["direction"], key + ".direction", 0, 2);
                if (j.contains("bits")) {
                    const json& b = j["bits"];
                    if (!b.is_array()) ctx.fail(key + ".bits", "expected one \"zyx\" bit string per station");
                    for (std::size_t t = 0; t < b.size(); ++t) {
                        const std::string bits = ctx.string(b[t], key + ".bits[" + std::to_string(t) + "]");
                        if (bits.size() != 3 || bits.find_first_not_of("01") != std::string::npos) {
                            ctx.fail(key + ".bits[" + std::to_string(t) + "]", "expected three 0/1 digits (zyx), got \"" + bits + "\"");
                        }
                        s.bits.push_back(bits);
                    }
                    const int n = c.lattices[s.lattice].counts[s.direction];
                    if (static_cast<int>(s.bits.size()) != n) {
                        ctx.fail(key + ".bits", std::to_string(s.bits.size()) + " bit strings for " + std::to_string(n) + " stations");
                    }
                }
                if (j.contains("section_scaling")) s.sectionScaling = ctx.boolean(j["section_scaling"], key + ".section_scaling");
                if (j.contains("taper")) s.taper = ctx.boolean(j["taper"], key + ".taper");
                if (j.contains("vertical")) s.vertical = ctx.axis(j["vertical"], key + ".vertical");
                if (j.contains("streamwise")) s.streamwise = ctx.axis(j["streamwise"], key + ".streamwise");
                if (j.contains("translation_bound")) {
                    s.translationBound = ctx.number(j["translation_bound"], key + ".translation_bound");
                    if (!(s.translationBound > 0)) ctx.fail(key + ".translation_bound", "must be positive");
                }
                for (const char* bk : {"scaling_bounds", "taper_bounds"}) {
                    if (!j.contains(bk)) continue;
                    const auto b = ctx.numbers<2>(j[bk], key + "." + bk);
                    if (!(b[0] > 0 && b[0] <= 1 && b[1] >= 1)) ctx.fail(key + "." + bk, "expected [lower <= 1, upper >= 1] with lower > 0");
                    (std::string(bk) == "scaling_bounds" ? s.scalingBounds : s.taperBounds) = b;
                }
                c.stations.push_back(std::move(s));
            }
        }
        if (dv.contains("points")) {
            const json& ps = dv["points"];
            if (!ps.is_array()) ctx.fail("design_variables.points", "expected an array");
            for (std::size_t i = 0; i < ps.size(); ++i) {
                const std::string key = "design_variables.points[" + std::to_string(i) + "]";
                const json& j = ps[i];
                ctx.keys(j, key, {"lattice", "index", "axes", "bounds"});
                PointVariableCase p;
                p.lattice = j.contains("lattice") ? latticeRef(ctx, j["lattice"], key + ".lattice", c.lattices) : 0;
                if (!j.contains("index")) ctx.fail(key + ".index", "missing ([i, j, k] of the lattice point)");
                p.index = ctx.integers<3>(j["index"], key + ".index", 0, 99999);
                const std::array<int, 3> n = refinedCounts(c.lattices[p.lattice]);
                for (int d = 0; d < 3; ++d) {
                    if (p.index[d] >= n[d]) {
                        ctx.fail(key + ".index[" + std::to_string(d) + "]", std::to_string(p.index[d]) + " is beyond the lattice's " +
                                 std::to_string(n[d]) + " points (after refinement)");
                    }
                }
                if (j.contains("axes")) {
                    p.axes = ctx.string(j["axes"], key + ".axes");
                    if (p.axes.empty() || p.axes.find_first_not_of("xyz") != std::string::npos) ctx.fail(key + ".axes", "expected letters from \"xyz\"");
                }
                if (j.contains("bounds")) {
                    p.bounds = ctx.numbers<2>(j["bounds"], key + ".bounds");
                    if (!(p.bounds[0] <= 0 && p.bounds[1] >= 0)) ctx.fail(key + ".bounds", "must contain 0 (the baseline)");
                }
                c.pointVariables.push_back(p);
            }
        }
    }

    if (doc.contains("values")) {
        const json& v = doc["values"];
        if (!v.is_object()) ctx.fail("values", "expected an object {\"variable name\": value}");
        for (auto it = v.begin(); it != v.end(); ++it) c.values[it.key()] = ctx.number(it.value(), "values." + it.key());
    }
    if (doc.contains("displacements")) {
        const json& ds = doc["displacements"];
        if (!ds.is_array()) ctx.fail("displacements", "expected an array");
        for (std::size_t i = 0; i < ds.size(); ++i) {
            const std::string key = "displacements[" + std::to_string(i) + "]";
            ctx.keys(ds[i], key, {"lattice", "index", "delta"});
            DisplacementCase d;
            d.lattice = ds[i].contains("lattice") ? latticeRef(ctx, ds[i]["lattice"], key + ".lattice", c.lattices) : 0;
            if (!ds[i].contains("index") || !ds[i].contains("delta")) ctx.fail(key, "needs index and delta");
            d.index = ctx.integers<3>(ds[i]["index"], key + ".index", 0, 99999);
            const std::array<int, 3> n = refinedCounts(c.lattices[d.lattice]);
            for (int dd = 0; dd < 3; ++dd) {
                if (d.index[dd] >= n[dd]) {
                    ctx.fail(key + ".index[" + std::to_string(dd) + "]", "beyond the lattice's " + std::to_string(n[dd]) +
                             " points (after refinement)");
                }
            }
            d.delta = ctx.numbers<3>(ds[i]["delta"], key + ".delta");
            c.displacements.push_back(d);
        }
    }
    if (doc.contains("embedding")) {
        const json& e = doc["embedding"];
        ctx.keys(e, "embedding", {"tolerance", "max_iterations", "allow_outside"});
        if (e.contains("tolerance")) {
            c.embedding.tolerance = ctx.number(e["tolerance"], "embedding.tolerance");
            if (!(c.embedding.tolerance > 0 && c.embedding.tolerance < 1)) ctx.fail("embedding.tolerance", "must lie in (0, 1)");
        }
        if (e.contains("max_iterations")) c.embedding.maxIterations = ctx.integer(e["max_iterations"], "embedding.max_iterations", 1, 10000);
        if (e.contains("allow_outside")) c.allowOutside = ctx.boolean(e["allow_outside"], "embedding.allow_outside");
    }
    if (doc.contains("constraints")) {
        const json& k = doc["constraints"];
        ctx.keys(k, "constraints", {"symmetry", "station_gap", "station_second_difference", "min_volume", "thickness",
                                        "min_lattice_jacobian"});
        if (k.contains("symmetry")) c.symmetry = ctx.boolean(k["symmetry"], "constraints.symmetry");
        if (k.contains("station_gap")) {
            c.stationGap = ctx.number(k["station_gap"], "constraints.station_gap");
            if (*c.stationGap < 0) ctx.fail("constraints.station_gap", "must be >= 0");
        }
        if (k.contains("station_second_difference")) {
            const std::string key = "constraints.station_second_difference";
            c.stationSecondDifference = ctx.number(k["station_second_difference"], key);
            if (!(*c.stationSecondDifference > 0)) ctx.fail(key, "must be > 0 (a length in the case's units)");
        }
        if (k.contains("min_volume")) {
            const json& mv = k["min_volume"];
            if (mv.is_string()) {
                if (mv != "initial") ctx.fail("constraints.min_volume", "expected a number or \"initial\"");
                c.minVolume = std::numeric_limits<double>::quiet_NaN();
            } else {
                c.minVolume = ctx.number(mv, "constraints.min_volume");
            }
        }
        if (k.contains("thickness")) {
            const json& t = k["thickness"];
            const std::string key = "constraints.thickness";
            ctx.keys(t, key, {"stations", "chord_fractions", "points", "min_ratio"});
            ThicknessCase& tc = c.thickness;
            if (t.contains("stations")) tc.stations = ctx.numberList(t["stations"], key + ".stations");
            if (t.contains("chord_fractions")) {
                tc.chordFractions = ctx.numberList(t["chord_fractions"], key + ".chord_fractions");
                for (std::size_t i = 0; i < tc.chordFractions.size(); ++i) {
                    const double f = tc.chordFractions[i];
                    if (!(f > 0 && f < 1)) ctx.fail(key + ".chord_fractions[" + std::to_string(i) + "]", "must lie in (0, 1), got " + std::to_string(f));
                }
            }
            if (tc.stations.empty() != tc.chordFractions.empty()) {
                ctx.fail(key, "stations and chord_fractions go together (each station is measured at every chord fraction)");
            }
            if (t.contains("points")) {
                const json& ps = t["points"];
                if (!ps.is_array()) ctx.fail(key + ".points", "expected an array of [x, y] pairs");
                for (std::size_t i = 0; i < ps.size(); ++i) tc.points.push_back(ctx.numbers<2>(ps[i], key + ".points[" + std::to_string(i) + "]"));
            }
            if (!tc.present()) ctx.fail(key, "expected stations with chord_fractions, or points");
            if (t.contains("min_ratio")) tc.minRatio = ctx.number(t["min_ratio"], key + ".min_ratio");
            if (!(tc.minRatio > 0 && tc.minRatio <= 10)) ctx.fail(key + ".min_ratio", "must lie in (0, 10] (a fraction of the baseline thickness)");
        }
        if (k.contains("min_lattice_jacobian")) {
            c.minLatticeJacobian = ctx.number(k["min_lattice_jacobian"], "constraints.min_lattice_jacobian");
            if (!(c.minLatticeJacobian >= 0 && c.minLatticeJacobian < 1)) {
                ctx.fail("constraints.min_lattice_jacobian", "must lie in [0, 1) (a fraction of the baseline lattice's det J; 0: none)");
            }
        }
    }
    if (doc.contains("mesh")) {
        const json& j = doc["mesh"];
        std::vector<std::string> allowed;
        for (const auto& o : meshOptions()) allowed.push_back(o.spec.key);
        ctx.keys(j, "mesh", allowed);
        MeshCase& mc = c.mesh;
        mc.present = true;
        readOptions(ctx, j, "mesh", meshOptions(), mc);
    }
    if (doc.contains("flow")) {
        const json& j = doc["flow"];
        // Every key but "restart" (a path) comes from the option table (io/Options.h).
        std::vector<std::string> allowed{"restart"};
        for (const auto& o : flowOptions()) allowed.push_back(o.spec.key);
        ctx.keys(j, "flow", allowed);
        FlowCase& fc = c.flow;
        fc.present = true;
        readOptions(ctx, j, "flow", flowOptions(), fc);
        if (j.contains("restart")) fc.restart = resolve(path, ctx.string(j["restart"], "flow.restart"));
        if (fc.newton.gmresDeflation > 0 && fc.newton.gmresDeflation >= fc.newton.gmresRestart - 1) {
            ctx.fail("flow.gmres_deflation", "must be below gmres_restart - 1 (" +
                                                 std::to_string(fc.newton.gmresRestart - 1) +
                                                 "): the cycle needs room for new vectors");
        }
    }
    if (doc.contains("optimization")) {
        const json& j = doc["optimization"];
        std::vector<std::string> allowed{"history", "iterations", "target_pressure", "start_design"};
        for (const auto& o : optimizationOptions()) allowed.push_back(o.spec.key);
        ctx.keys(j, "optimization", allowed);
        OptimizationCase& oc = c.optimization;
        oc.present = true;
        readOptions(ctx, j, "optimization", optimizationOptions(), oc);
        if (!c.flow.present) ctx.fail("optimization", "needs a \"flow\" section (the objective is a flow functional)");
        if (oc.alphaLower >= oc.alphaUpper) ctx.fail("optimization.alpha_upper", "must be above alpha_lower");
        if (oc.alphaVariable && !(c.flow.freeStream.alphaDeg >= oc.alphaLower && c.flow.freeStream.alphaDeg <= oc.alphaUpper)) {
            ctx.fail("optimization.alpha_lower", "flow.alpha (the start) lies outside [alpha_lower, alpha_upper]");
        }
        if (j.contains("history")) {
            oc.history = resolve(path, ctx.string(j["history"], "optimization.history"));
            if (std::filesystem::path(oc.history).extension() != ".csv") ctx.fail("optimization.history", "must end in .csv");
        } else {
            const std::filesystem::path p(path);
            oc.history = (p.parent_path() / (p.stem().string() + ".history.csv")).string();
        }
        if (j.contains("iterations")) oc.iterations = resolve(path, ctx.string(j["iterations"], "optimization.iterations"));
        if (j.contains("target_pressure")) {
            oc.targetPressure = resolve(path, ctx.string(j["target_pressure"], "optimization.target_pressure"));
        }
        if (j.contains("start_design")) {
            oc.startDesign = resolve(path, ctx.string(j["start_design"], "optimization.start_design"));
            if (const std::string why = startDesignPathProblem(oc.startDesign); !why.empty()) {
                ctx.fail("optimization.start_design", why);
            }
        }
        if (oc.objective == "pressure" && oc.targetPressure.empty()) {
            ctx.fail("optimization.target_pressure", "missing: the objective 'pressure' needs the target's wall pressures (a CSV "
                                                     "written by output.wall_pressure)");
        }
        if (oc.objective == "pressure" && oc.maximize) ctx.fail("optimization.sense", "the pressure mismatch is minimized");
    }
    if (doc.contains("output")) {
        const json& o = doc["output"];
        ctx.keys(o, "output", {"geometry", "vtk", "mesh_vtk", "control_vtk", "plot3d", "flow_vtk", "residual_csv", "restart",
                               "wall_pressure"});
        if (o.contains("geometry")) c.outputGeometry = resolve(path, ctx.string(o["geometry"], "output.geometry"));
        auto vtm = [&](const char* key, std::string& out) {
            if (!o.contains(key)) return;
            out = resolve(path, ctx.string(o[key], std::string("output.") + key));
            if (std::filesystem::path(out).extension() != ".vtm") ctx.fail(std::string("output.") + key, "must end in .vtm");
        };
        vtm("vtk", c.outputVtk);
        vtm("mesh_vtk", c.outputMeshVtk);
        vtm("control_vtk", c.outputControlVtk);
        if (o.contains("plot3d")) c.outputPlot3d = resolve(path, ctx.string(o["plot3d"], "output.plot3d"));
        vtm("flow_vtk", c.outputFlowVtk);
        if (o.contains("residual_csv")) c.outputResidualCsv = resolve(path, ctx.string(o["residual_csv"], "output.residual_csv"));
        if (o.contains("restart")) c.outputRestart = resolve(path, ctx.string(o["restart"], "output.restart"));
        if (o.contains("wall_pressure")) c.outputWallPressure = resolve(path, ctx.string(o["wall_pressure"], "output.wall_pressure"));
        // An output never overwrites an input (issue #20: output.geometry equal to the geometry
        // replaced the user's file with exit 0). A restart read and written in place is allowed:
        // the run continues it.
        const auto same = [](const std::string& a, const std::string& b) {
            if (a.empty() || b.empty()) return false;
            std::error_code e1, e2;
            const auto ca = std::filesystem::weakly_canonical(a, e1), cb = std::filesystem::weakly_canonical(b, e2);
            return !e1 && !e2 && ca == cb;
        };
        const std::pair<const char*, const std::string*> outputs[] = {
            {"geometry", &c.outputGeometry},   {"vtk", &c.outputVtk},           {"mesh_vtk", &c.outputMeshVtk},
            {"control_vtk", &c.outputControlVtk}, {"plot3d", &c.outputPlot3d}, {"flow_vtk", &c.outputFlowVtk},
            {"residual_csv", &c.outputResidualCsv}, {"restart", &c.outputRestart}, {"wall_pressure", &c.outputWallPressure}};
        for (const auto& [key, file] : outputs) {
            if (same(*file, c.geometry)) ctx.fail(std::string("output.") + key, "is the case's geometry file '" + c.geometry + "' (an output never overwrites an input)");
            if (same(*file, path)) ctx.fail(std::string("output.") + key, "is the case file itself (an output never overwrites an input)");
            if (std::string(key) != "restart" && same(*file, c.flow.restart)) {
                ctx.fail(std::string("output.") + key, "is the restart file the flow starts from (an output never overwrites an input)");
            }
        }
        for (std::size_t a = 0; a < std::size(outputs); ++a) {
            for (std::size_t b = a + 1; b < std::size(outputs); ++b) {
                if (same(*outputs[a].second, *outputs[b].second)) {
                    ctx.fail(std::string("output.") + outputs[b].first, std::string("is the same file as output.") + outputs[a].first);
                }
            }
        }
    }
    return c;
}

CaseFile readCase(const std::string& path) {
    checkInputFile(path, "case file", 64u << 20);  // cases are a few KB
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot open case file '" + path + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    return parseCase(ss.str(), path);
}

bool looksLikeCase(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::ostringstream ss;
    ss << in.rdbuf();
    const json doc = json::parse(ss.str(), nullptr, false);
    return doc.is_object() && doc.contains("format") && doc["format"] == kFormat;
}

ffd::FfdModel buildModel(const CaseFile& c, const geometry::PatchSet& geometry) {
    std::vector<ffd::LatticeSpec> specs;
    for (std::size_t l = 0; l < c.lattices.size(); ++l) {
        const LatticeCase& lc = c.lattices[l];
        for (std::size_t i = 0; i < lc.patches.size(); ++i) {
            if (lc.patches[i] >= geometry.size()) {
                throw CaseError("'" + c.path + "': lattices[" + std::to_string(l) + "].patches[" + std::to_string(i) + "]: patch " +
                                std::to_string(lc.patches[i] + 1) + " does not exist ('" + geometry.source + "' has " +
                                std::to_string(geometry.size()) + " patches)");
            }
        }
        ffd::LatticeSpec spec;
        spec.name = lc.name;
        spec.patches = lc.patches;
        const ffd::LatticeBox box = lc.box ? *lc.box : ffd::boxAround(geometry, lc.patches, lc.padding, lc.axes);
        spec.lattice = ffd::makeLattice(box, lc.counts, lc.degrees);
        for (const auto& [dir, knots] : lc.refine) ffd::refineLattice(spec.lattice, dir, knots);
        for (const auto& [dir, u] : lc.crease) ffd::creaseLattice(spec.lattice, dir, u);
        specs.push_back(std::move(spec));
    }
    ffd::FfdModel model(geometry, std::move(specs), c.embedding);
    for (const auto& s : c.stations) model.design().addStations(s);
    for (const auto& p : c.pointVariables) {
        const ffd::Lattice& L = model.lattices()[p.lattice].lattice;
        // Indices refer to the lattice as refined by the case.
        for (int d = 0; d < 3; ++d) {
            if (p.index[d] >= L.count[d]) {
                throw CaseError("'" + c.path + "': design_variables.points: index beyond the refined lattice '" +
                                model.lattices()[p.lattice].name + "'");
            }
        }
        for (char a : p.axes) {
            model.design().addPointCoordinate(p.lattice, L.index(p.index[0], p.index[1], p.index[2]), a - 'x',
                                              p.bounds[0], p.bounds[1], model.lattices()[p.lattice].name);
        }
    }
    return model;
}

std::string startDesignPathProblem(const std::string& path) {
    if (std::filesystem::path(path).extension() == ".json") return "";
    return "must be a case file (.json), e.g. one aeroform-cli optimize --design N writes";
}

std::vector<double> designValues(const CaseFile& c, const ffd::FfdModel& model) {
    std::vector<double> v = model.design().baselineValues();
    for (const auto& [name, value] : c.values) {
        const int i = model.design().find(name);
        if (i < 0) {
            throw CaseError("'" + c.path + "': values." + name + ": no design variable of that name (the case defines " +
                            std::to_string(model.design().size()) + "; `aeroform-cli deform CASE --list` prints them)");
        }
        const auto& d = model.design().variables()[i];
        if (value < d.lower || value > d.upper) {
            std::ostringstream m;
            m << "'" << c.path << "': values." << name << ": " << value << " is outside the bounds [" << d.lower << ", "
              << d.upper << "]";
            throw CaseError(m.str());
        }
        v[i] = value;
    }
    return v;
}

std::vector<ffd::Lattice> movedLattices(const CaseFile& c, const ffd::FfdModel& model, const std::vector<double>& v) {
    std::vector<ffd::Lattice> moved;
    for (std::size_t l = 0; l < model.lattices().size(); ++l) moved.push_back(model.design().lattice(static_cast<int>(l), v));
    for (const auto& d : c.displacements) {
        ffd::Lattice& L = moved[d.lattice];
        for (int k = 0; k < 3; ++k) {
            if (d.index[k] >= L.count[k]) {
                throw CaseError("'" + c.path + "': displacements: index beyond the refined lattice '" + model.lattices()[d.lattice].name + "'");
            }
        }
        const int a = L.index(d.index[0], d.index[1], d.index[2]);
        for (int k = 0; k < 3; ++k) L.points[3 * a + k] += d.delta[k];
    }
    return moved;
}

}  // namespace aero::io
