#include "io/PatchSetJson.h"

#include <algorithm>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/AtomicFile.h"
#include "common/Error.h"
#include "geometry/Units.h"

namespace aero::io {

using nlohmann::json;

namespace {

constexpr const char* kFormat = "aeroform.patchset";
constexpr int kVersion = 1;

[[noreturn]] void fail(const std::string& origin, const std::string& where, const std::string& why) {
    throw InputError("'" + origin + "': " + where + ": " + why);
}

const json& require(const json& obj, const char* key, const std::string& origin, const std::string& where) {
    auto it = obj.find(key);
    if (it == obj.end()) fail(origin, where, std::string("missing key '") + key + "'");
    return *it;
}

std::vector<double> numbers(const json& arr, const std::string& origin, const std::string& where) {
    if (!arr.is_array()) fail(origin, where, "expected an array of numbers");
    std::vector<double> out;
    out.reserve(arr.size());
    for (std::size_t i = 0; i < arr.size(); ++i) {
        if (!arr[i].is_number()) {
            fail(origin, where + "[" + std::to_string(i) + "]", "expected a number, found " + std::string(arr[i].type_name()));
        }
        out.push_back(arr[i].get<double>());
    }
    return out;
}

std::array<int, 2> intPair(const json& v, const std::string& origin, const std::string& where) {
    if (!v.is_array() || v.size() != 2 || !v[0].is_number_integer() || !v[1].is_number_integer()) {
        fail(origin, where, "expected two integers");
    }
    // Read wide and check, so 2^32 + k is refused, not taken as k.
    const long long a = v[0].get<long long>(), b = v[1].get<long long>();
    for (long long x : {a, b}) {
        if (x < -1000000000LL || x > 1000000000LL) fail(origin, where, "value " + std::to_string(x) + " out of range");
    }
    return {static_cast<int>(a), static_cast<int>(b)};
}

void checkKeys(const json& obj, std::initializer_list<const char*> keys, const std::string& origin, const std::string& where) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
        if (std::none_of(keys.begin(), keys.end(), [&](const char* k) { return it.key() == k; })) {
            fail(origin, where, "unknown key '" + it.key() + "'");
        }
    }
}

// {"degree": p, "knots": [...], "points": [[u, v], ...], "weights": [...], "range": [first, last]}
geometry::TrimCurve trimCurve(const json& jc, const std::string& origin, const std::string& where) {
    if (!jc.is_object()) fail(origin, where, "expected an object");
    checkKeys(jc, {"degree", "knots", "points", "weights", "range"}, origin, where);
    geometry::TrimCurve c;
    const json& degree = require(jc, "degree", origin, where);
    if (!degree.is_number_integer() || degree.get<long long>() < 1 || degree.get<long long>() > 100)
        fail(origin, where + ".degree", "expected an integer in [1, 100]");
    c.curve.degree = degree.get<int>();
    c.curve.knots = numbers(require(jc, "knots", origin, where), origin, where + ".knots");
    const json& pts = require(jc, "points", origin, where);
    if (!pts.is_array()) fail(origin, where + ".points", "expected an array of [u, v]");
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const std::vector<double> uv = numbers(pts[i], origin, where + ".points[" + std::to_string(i) + "]");
        if (uv.size() != 2) fail(origin, where + ".points[" + std::to_string(i) + "]", "expected [u, v]");
        c.curve.points.insert(c.curve.points.end(), {uv[0], uv[1], 0.0});
    }
    if (auto w = jc.find("weights"); w != jc.end()) c.curve.weights = numbers(*w, origin, where + ".weights");
    const std::vector<double> range = numbers(require(jc, "range", origin, where), origin, where + ".range");
    if (range.size() != 2) fail(origin, where + ".range", "expected [first, last]");
    c.first = range[0];
    c.last = range[1];
    return c;
}

geometry::TrimLoop trimLoop(const json& jl, const std::string& origin, const std::string& where) {
    if (!jl.is_array() || jl.empty()) fail(origin, where, "expected a non-empty array of curves");
    geometry::TrimLoop loop;
    for (std::size_t k = 0; k < jl.size(); ++k) loop.curves.push_back(trimCurve(jl[k], origin, where + "[" + std::to_string(k) + "]"));
    return loop;
}

json formatLoop(const geometry::TrimLoop& loop) {
    json out = json::array();
    for (const geometry::TrimCurve& c : loop.curves) {
        json jc;
        jc["degree"] = c.curve.degree;
        jc["knots"] = c.curve.knots;
        json pts = json::array();
        for (std::size_t a = 0; a < c.curve.points.size(); a += 3) pts.push_back({c.curve.points[a], c.curve.points[a + 1]});
        jc["points"] = std::move(pts);
        if (c.curve.rational()) jc["weights"] = c.curve.weights;
        jc["range"] = {c.first, c.last};
        out.push_back(std::move(jc));
    }
    return out;
}

}  // namespace

geometry::PatchSet parsePatchSetJson(const std::string& text, const std::string& origin) {
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::exception& e) {  // parse_error, and out_of_range for a number like 1E400
        throw InputError("'" + origin + "': not valid JSON: " + e.what());
    }
    if (!doc.is_object()) fail(origin, "document", "expected a JSON object");
    for (auto it = doc.begin(); it != doc.end(); ++it) {
        if (it.key() != "format" && it.key() != "version" && it.key() != "unit" && it.key() != "patches") {
            fail(origin, "document", "unknown key '" + it.key() + "'");
        }
    }
    const json& format = require(doc, "format", origin, "document");
    if (!format.is_string() || format.get<std::string>() != kFormat) {
        fail(origin, "format", std::string("expected \"") + kFormat + "\"");
    }
    const json& version = require(doc, "version", origin, "document");
    if (!version.is_number_integer() || version.get<int>() != kVersion) {
        fail(origin, "version", "unsupported version (this build reads version " + std::to_string(kVersion) + ")");
    }
    const json& patches = require(doc, "patches", origin, "document");
    if (!patches.is_array()) fail(origin, "patches", "expected an array");

    geometry::PatchSet set;
    set.source = origin;
    if (auto u = doc.find("unit"); u != doc.end()) {
        if (!u->is_string()) fail(origin, "unit", "expected a string");
        const geometry::LengthUnit* unit = geometry::findLengthUnit(u->get<std::string>());
        if (!unit) fail(origin, "unit", "unknown length unit '" + u->get<std::string>() + "' (known: " + geometry::knownLengthUnits() + ")");
        set.unit = std::string(unit->name);
    }
    bool anyTrim = false;
    for (std::size_t p = 0; p < patches.size(); ++p) {
        const std::string where = "patches[" + std::to_string(p) + "]";
        const json& jp = patches[p];
        if (!jp.is_object()) fail(origin, where, "expected an object");
        static const char* kKeys[] = {"name", "degree", "count", "knots_u", "knots_v", "points", "weights", "trim"};
        for (auto it = jp.begin(); it != jp.end(); ++it) {
            if (std::find(std::begin(kKeys), std::end(kKeys), it.key()) == std::end(kKeys)) {
                fail(origin, where, "unknown key '" + it.key() + "'");
            }
        }
        geometry::Patch patch;
        const auto degree = intPair(require(jp, "degree", origin, where), origin, where + ".degree");
        const auto count = intPair(require(jp, "count", origin, where), origin, where + ".count");
        patch.degreeU = degree[0];
        patch.degreeV = degree[1];
        patch.countU = count[0];
        patch.countV = count[1];
        if (count[0] < 1 || count[1] < 1 || count[0] > 100000 || count[1] > 100000) {
            fail(origin, where + ".count", "counts " + std::to_string(count[0]) + " x " + std::to_string(count[1]) +
                                               " outside [1, 100000]");
        }
        if (static_cast<long long>(count[0]) * count[1] > 10000000LL) {
            fail(origin, where + ".count", std::to_string(count[0]) + " x " + std::to_string(count[1]) +
                                               " control points: more than the 10 million a patch may have");
        }
        patch.knotsU = numbers(require(jp, "knots_u", origin, where), origin, where + ".knots_u");
        patch.knotsV = numbers(require(jp, "knots_v", origin, where), origin, where + ".knots_v");
        const json& pts = require(jp, "points", origin, where);
        if (!pts.is_array()) fail(origin, where + ".points", "expected an array of [x, y, z]");
        patch.points.reserve(3 * pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) {
            const std::vector<double> xyz = numbers(pts[i], origin, where + ".points[" + std::to_string(i) + "]");
            if (xyz.size() != 3) fail(origin, where + ".points[" + std::to_string(i) + "]", "expected [x, y, z]");
            patch.points.insert(patch.points.end(), xyz.begin(), xyz.end());
        }
        if (auto w = jp.find("weights"); w != jp.end()) patch.weights = numbers(*w, origin, where + ".weights");
        std::string name;
        if (auto n = jp.find("name"); n != jp.end()) {
            if (!n->is_string()) fail(origin, where + ".name", "expected a string");
            name = n->get<std::string>();
        }
        geometry::PatchTrim trim;
        if (auto t = jp.find("trim"); t != jp.end()) {
            if (!t->is_object()) fail(origin, where + ".trim", "expected an object with \"outer\" and/or \"holes\"");
            checkKeys(*t, {"outer", "holes"}, origin, where + ".trim");
            if (auto o = t->find("outer"); o != t->end()) trim.outer = trimLoop(*o, origin, where + ".trim.outer");
            if (auto h = t->find("holes"); h != t->end()) {
                if (!h->is_array()) fail(origin, where + ".trim.holes", "expected an array of loops");
                for (std::size_t k = 0; k < h->size(); ++k)
                    trim.holes.push_back(trimLoop((*h)[k], origin, where + ".trim.holes[" + std::to_string(k) + "]"));
            }
            anyTrim = anyTrim || trim.trimmed();
        }
        set.patches.push_back(std::move(patch));
        set.names.push_back(name);
        set.trims.push_back(std::move(trim));
    }
    if (!anyTrim) set.trims.clear();
    try {
        geometry::validate(set);
    } catch (const GeometryError& e) {
        throw InputError(e.what());
    }
    return set;
}

std::string formatPatchSetJson(const geometry::PatchSet& set) {
    json doc;
    doc["format"] = kFormat;
    doc["version"] = kVersion;
    if (!set.unit.empty()) doc["unit"] = set.unit;
    json patches = json::array();
    for (int p = 0; p < set.size(); ++p) {
        const geometry::Patch& s = set.patches[p];
        json jp;
        jp["name"] = p < static_cast<int>(set.names.size()) ? set.names[p] : "";
        jp["degree"] = {s.degreeU, s.degreeV};
        jp["count"] = {s.countU, s.countV};
        jp["knots_u"] = s.knotsU;
        jp["knots_v"] = s.knotsV;
        json pts = json::array();
        for (std::size_t a = 0; a < s.points.size(); a += 3) pts.push_back({s.points[a], s.points[a + 1], s.points[a + 2]});
        jp["points"] = std::move(pts);
        if (s.rational()) jp["weights"] = s.weights;
        if (set.trimmed(p)) {
            const geometry::PatchTrim& t = set.trims[p];
            json jt = json::object();
            if (!t.outer.curves.empty()) jt["outer"] = formatLoop(t.outer);
            if (!t.holes.empty()) {
                json holes = json::array();
                for (const geometry::TrimLoop& h : t.holes) holes.push_back(formatLoop(h));
                jt["holes"] = std::move(holes);
            }
            jp["trim"] = std::move(jt);
        }
        patches.push_back(std::move(jp));
    }
    doc["patches"] = std::move(patches);
    return doc.dump(1) + "\n";
}

geometry::PatchSet readPatchSetJson(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError("cannot open patch-set file '" + path + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    return parsePatchSetJson(ss.str(), path);
}

void writePatchSetJson(const geometry::PatchSet& set, const std::string& path) {
    const std::string text = formatPatchSetJson(set);
    // Write to a temporary file and rename: an existing file is never left half-written, and no
    // temporary file stays behind after a failure.
    writeTextAtomically(path, text, "patch-set file");
}

}  // namespace aero::io
