// IGES import and export (see Iges.h). Our own text parser reads B-spline surfaces and trimmed
// surfaces over them exactly; OpenCASCADE (cad/Occt.h) converts the other surface types in the
// file's own unit. The writer is ours too: 17 significant digits, the set's unit, 144/142/126 for
// trimmed patches.
#include "cad/Iges.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <set>
#include <sstream>

#include "cad/IgesText.h"
#include "cad/Occt.h"
#include "common/AtomicFile.h"
#include "common/Error.h"
#include "geometry/Trim.h"
#include "geometry/Units.h"
#include "nurbs/Basis.h"

namespace aero::cad {

namespace {

using geometry::Patch;
using geometry::PatchSet;
using geometry::PatchTrim;
using geometry::TrimCurve;
using geometry::TrimLoop;
using iges::Entity;
using iges::File;

std::string quoted(const std::string& path) {
    return "'" + path + "'";
}

std::string readText(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw InputError("cannot open IGES file " + quoted(path) + ": is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw InputError("cannot open IGES file " + quoted(path) + ": " + std::strerror(errno));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad())
        throw InputError("cannot read IGES file " + quoted(path) + ": " + std::strerror(errno));
    return std::move(text).str();
}

std::string number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

// ------------------------------------------------------------------------------------------
// Reading entities exactly

/// Why an entity cannot be taken directly: empty = it can; `unsupported` = valid IGES that
/// Aeroform's NURBS cannot hold (OpenCASCADE would not help), so it is ignored with a warning.
struct Refusal {
    std::string why;
    bool unsupported = false;
    bool modelSpaceTrim = false;
    explicit operator bool() const { return !why.empty(); }
};

bool clampedKnots(const std::vector<double>& k, int p) {
    for (int i = 1; i <= p; ++i)
        if (k[static_cast<std::size_t>(i)] != k[0] ||
            k[k.size() - 1 - static_cast<std::size_t>(i)] != k.back())
            return false;
    return true;
}

/// Largest interior knot multiplicity.
int interiorMultiplicity(const std::vector<double>& k, int p) {
    int best = 0, run = 0;
    for (std::size_t i = static_cast<std::size_t>(p) + 1;
         i + static_cast<std::size_t>(p) + 1 < k.size(); ++i) {
        run = (i > static_cast<std::size_t>(p) + 1 && k[i] == k[i - 1]) ? run + 1 : 1;
        best = std::max(best, run);
    }
    return best;
}

/// The name an entity gives its patch: its name property (406 form 15) among the pointers after
/// its own `defined` parameters, else its label, else "" (the caller names it by number).
std::string entityName(const File& f, const Entity& e, std::size_t defined) {
    std::string name;
    if (e.params.size() > defined) {
        const int na = iges::integer(f, e, defined);
        const std::size_t npAt = defined + 1 + static_cast<std::size_t>(std::max(na, 0));
        if (na >= 0 && npAt < e.params.size()) {
            const int np = iges::integer(f, e, npAt);
            for (int k = 0; k < np && npAt + 1 + static_cast<std::size_t>(k) < e.params.size();
                 ++k) {
                const Entity* prop =
                    f.at(iges::integer(f, e, npAt + 1 + static_cast<std::size_t>(k)));
                if (prop && prop->type == 406 && prop->form == 15 && prop->params.size() >= 2)
                    name = prop->params[1];
            }
        }
    }
    if (name.empty()) name = e.label;
    if (!name.empty() && e.subscript != 0) name += "(" + std::to_string(e.subscript) + ")";
    return name;
}

std::string generatedName(const Entity& e) {
    return "entity " + std::to_string(e.number());
}

/// Entity 128 as written. Throws GeometryError naming the entity for invalid knots; returns a
/// refusal for what only OpenCASCADE can take (a transformation, unclamped knots) or what Aeroform
/// cannot hold (degree > 9, a discontinuity).
Refusal surface128(const File& f, const Entity& e, Patch& p, PatchTrim& range, std::string& name) {
    using iges::integer;
    using iges::real;
    const int K1 = integer(f, e, 0), K2 = integer(f, e, 1), M1 = integer(f, e, 2),
              M2 = integer(f, e, 3);
    const bool polynomial = integer(f, e, 6) == 1;
    p.degreeU = M1;
    p.degreeV = M2;
    p.countU = K1 + 1;
    p.countV = K2 + 1;
    std::size_t at = 9;
    const std::size_t nku = static_cast<std::size_t>(K1 + M1 + 2),
                      nkv = static_cast<std::size_t>(K2 + M2 + 2);
    const std::size_t n = static_cast<std::size_t>(p.countU) * static_cast<std::size_t>(p.countV);
    p.knotsU.resize(nku);
    p.knotsV.resize(nkv);
    for (double& k : p.knotsU) k = real(f, e, at++);
    for (double& k : p.knotsV) k = real(f, e, at++);
    std::vector<double> w(n);
    for (double& x : w) x = real(f, e, at++);
    p.points.resize(3 * n);
    for (double& x : p.points) x = real(f, e, at++);
    const double u0 = real(f, e, at), u1 = real(f, e, at + 1), v0 = real(f, e, at + 2),
                 v1 = real(f, e, at + 3);
    name = entityName(f, e, at + 4);
    const bool equal = std::all_of(w.begin(), w.end(), [&](double x) { return x == w[0]; });
    if (!(polynomial && equal)) p.weights = std::move(w);

    if (e.transform)
        return {"it has a transformation matrix (" + iges::describe(e.transform, 124) + ")"};
    // Knots that go down or are not finite are bad data: an error naming the entity.
    for (const auto* knots : {&p.knotsU, &p.knotsV})
        for (std::size_t i = 1; i < knots->size(); ++i)
            if ((*knots)[i] < (*knots)[i - 1] || !((*knots).back() > (*knots).front()))
                throw GeometryError("IGES file " + quoted(f.path) + ": " + iges::describe(e) +
                                    " is not a valid B-spline surface: its " +
                                    (knots == &p.knotsU ? "u" : "v") +
                                    " knot vector decreases at index " + std::to_string(i) +
                                    " or has an empty range");
    if (M1 > nurbs::kMaxDegree || M2 > nurbs::kMaxDegree)
        return {"degrees " + std::to_string(M1) + " x " + std::to_string(M2) +
                    ": Aeroform's NURBS go up to degree " + std::to_string(nurbs::kMaxDegree),
                true};
    if (!clampedKnots(p.knotsU, M1) || !clampedKnots(p.knotsV, M2))
        return {"its knot vectors are not clamped"};
    if (interiorMultiplicity(p.knotsU, M1) > M1 || interiorMultiplicity(p.knotsV, M2) > M2)
        return {"an interior knot of multiplicity degree + 1 splits it into pieces", true};
    try {
        nurbs::validate(p, "it");
    } catch (const GeometryError& err) {
        throw GeometryError("IGES file " + quoted(f.path) + ": " + iges::describe(e) +
                            " is not a valid B-spline surface: " + err.what());
    }
    // The entity's parameter range restricts the surface: narrower than the knots, it is a
    // rectangular trim (kept exactly; the control points stay as written).
    const double a0 = p.knotsU.front(), a1 = p.knotsU.back(), b0 = p.knotsV.front(),
                 b1 = p.knotsV.back();
    const double tol = 1e-12 * std::max(a1 - a0, b1 - b0);
    const double r0 = std::max(u0, a0), r1 = std::min(u1, a1), s0 = std::max(v0, b0),
                 s1 = std::min(v1, b1);
    if (r0 < r1 && s0 < s1 && (r0 > a0 + tol || r1 < a1 - tol || s0 > b0 + tol || s1 < b1 - tol))
        range.outer = geometry::rectangleLoop(r0, r1, s0, s1);
    return {};
}

/// A 126 as a trim curve: (x, y) of its control points in parameter space.
Refusal curve126(const File& f, const Entity& e, TrimCurve& c) {
    using iges::integer;
    using iges::real;
    const int K = integer(f, e, 0), M = integer(f, e, 1);
    const bool polynomial = integer(f, e, 4) == 1;
    c.curve.degree = M;
    std::size_t at = 6;
    c.curve.knots.resize(static_cast<std::size_t>(K + M + 2));
    for (double& k : c.curve.knots) k = real(f, e, at++);
    std::vector<double> w(static_cast<std::size_t>(K + 1));
    for (double& x : w) x = real(f, e, at++);
    c.curve.points.resize(3 * static_cast<std::size_t>(K + 1));
    for (int i = 0; i <= K; ++i) {
        for (std::size_t d = 0; d < 3; ++d)
            c.curve.points[3 * static_cast<std::size_t>(i) + d] = real(f, e, at + d);
        at += 3;  // z is dropped once any transformation is applied: parameter space is (x, y)
    }
    c.first = real(f, e, at);
    c.last = real(f, e, at + 1);
    const bool equal = std::all_of(w.begin(), w.end(), [&](double x) { return x == w[0]; });
    if (!(polynomial && equal)) c.curve.weights = std::move(w);
    if (M > nurbs::kMaxDegree)
        return {"its curve " + iges::describe(e) + " has degree " + std::to_string(M)};
    if (!clampedKnots(c.curve.knots, M))
        return {"its curve " + iges::describe(e) + " has unclamped knots"};
    // A range a hair outside the knots (rounding in the writer) is the whole curve.
    const double span = c.curve.knots.back() - c.curve.knots.front();
    if (c.first < c.curve.knots.front() && c.first > c.curve.knots.front() - 1e-9 * span)
        c.first = c.curve.knots.front();
    if (c.last > c.curve.knots.back() && c.last < c.curve.knots.back() + 1e-9 * span)
        c.last = c.curve.knots.back();
    return {};
}

/// Applies the entity's transformation matrices (a 124, itself possibly transformed) to a curve's
/// control points, in 3D: x' = R x + T. Affine maps keep a NURBS curve's shape and parametrization
/// exactly (the control points are computed).
void transformCurve(const File& f, const Entity& e, TrimCurve& c) {
    for (int de = e.transform, depth = 0; de != 0; ++depth) {
        if (depth == 64)
            throw InputError("IGES file '" + f.path + "': " + iges::describe(e) +
                             ": its transformation matrices form a cycle");
        const Entity& m = *f.at(de);
        if (m.type != 124)
            throw InputError("IGES file '" + f.path + "': " + iges::describe(e) +
                             ": its transformation matrix pointer refers to " + iges::describe(m) +
                             ", not a transformation matrix (124)");
        double r[12];
        for (std::size_t k = 0; k < 12; ++k) r[k] = iges::real(f, m, k);
        for (std::size_t a = 0; a < c.curve.points.size(); a += 3) {
            const double x = c.curve.points[a], y = c.curve.points[a + 1],
                         z = c.curve.points[a + 2];
            c.curve.points[a] = r[0] * x + r[1] * y + r[2] * z + r[3];
            c.curve.points[a + 1] = r[4] * x + r[5] * y + r[6] * z + r[7];
            c.curve.points[a + 2] = r[8] * x + r[9] * y + r[10] * z + r[11];
        }
        de = m.transform;
    }
}

/// A circular arc (100) as a rational quadratic B-spline, exactly the same curve: at most a
/// quarter circle per segment, the file's start and end points kept as the end control points.
TrimCurve arc100(const File& f, const Entity& e) {
    using iges::real;
    const double cx = real(f, e, 1), cy = real(f, e, 2), sx = real(f, e, 3), sy = real(f, e, 4),
                 ex = real(f, e, 5), ey = real(f, e, 6);
    const double r = std::hypot(sx - cx, sy - cy);
    if (!(r > 0))
        throw InputError("IGES file '" + f.path + "': " + iges::describe(e) +
                         ": a circular arc of radius 0");
    const double a0 = std::atan2(sy - cy, sx - cx);
    double sweep = std::atan2(ey - cy, ex - cx) - a0;
    const double pi = 3.14159265358979323846;
    if (sweep <= 0 || (sx == ex && sy == ey)) sweep += 2 * pi;
    const int n = std::max(1, static_cast<int>(std::ceil(sweep / (0.5 * pi) - 1e-12)));
    const double d = sweep / n, w = std::cos(0.5 * d);
    TrimCurve c;
    c.curve.degree = 2;
    c.curve.knots = {0, 0, 0};
    c.curve.points = {sx, sy, 0};
    c.curve.weights = {1};
    for (int i = 0; i < n; ++i) {
        const double am = a0 + (i + 0.5) * d, a1 = a0 + (i + 1) * d;
        c.curve.points.insert(c.curve.points.end(),
                              {cx + r / w * std::cos(am), cy + r / w * std::sin(am), 0});
        if (i + 1 < n)
            c.curve.points.insert(c.curve.points.end(),
                                  {cx + r * std::cos(a1), cy + r * std::sin(a1), 0});
        else
            c.curve.points.insert(c.curve.points.end(), {ex, ey, 0});
        c.curve.weights.insert(c.curve.weights.end(), {w, 1});
        c.curve.knots.insert(c.curve.knots.end(),
                             i + 1 < n
                                 ? std::initializer_list<double>{double(i + 1), double(i + 1)}
                                 : std::initializer_list<double>{double(n), double(n), double(n)});
    }
    c.first = 0;
    c.last = n;
    return c;
}

/// The parameter-space curves of a 142: 126, 110, 100 and composites (102) of them, each mapped
/// by its transformation matrix. `converted` collects what was computed rather than copied.
Refusal curvesOf(const File& f, const Entity& b, std::vector<TrimCurve>& out,
                 std::set<std::string>& converted, int depth = 0) {
    if (b.type == 102 && depth == 0) {
        if (b.transform)
            return {"its parameter-space composite curve " + iges::describe(b) +
                    " has a transformation matrix"};
        const int n = iges::integer(f, b, 0);
        for (int k = 0; k < n; ++k)
            if (Refusal r = curvesOf(f, *f.at(iges::integer(f, b, 1 + static_cast<std::size_t>(k))),
                                     out, converted, depth + 1))
                return r;
        return {};
    }
    TrimCurve c;
    if (b.type == 126) {
        if (Refusal r = curve126(f, b, c)) return r;
    } else if (b.type == 110) {
        using iges::real;
        c = geometry::lineCurve({real(f, b, 0), real(f, b, 1)}, {real(f, b, 3), real(f, b, 4)});
        c.curve.points[2] = real(f, b, 2);
        c.curve.points[5] = real(f, b, 5);
    } else if (b.type == 100) {
        c = arc100(f, b);
        for (std::size_t a = 2; a < c.curve.points.size(); a += 3)
            c.curve.points[a] = iges::real(f, b, 0);  // ZT
        converted.insert("circular arcs made rational B-splines");
    } else {
        return {"its parameter-space curve " + iges::describe(b) + " is a " +
                iges::typeName(b.type) + " (read exactly: 126, 110, 100 and composites of them)"};
    }
    if (b.transform) {
        transformCurve(f, b, c);
        converted.insert("transformation matrices applied");
    }
    for (std::size_t a = 2; a < c.curve.points.size(); a += 3) c.curve.points[a] = 0.0;
    out.push_back(std::move(c));
    return {};
}

/// A 142's loop from its parameter-space curve.
Refusal loopOf(const File& f, int de, TrimLoop& loop, std::set<std::string>& converted) {
    const Entity& c = *f.at(de);
    if (c.type != 142)
        return {"its boundary " + iges::describe(c) + " is a " + iges::typeName(c.type) +
                ", not a curve on a surface (142)"};
    if (c.transform) return {"its boundary " + iges::describe(c) + " has a transformation matrix"};
    const int b = iges::integer(f, c, 2);
    if (b == 0) {
        Refusal r{"its trim loops are defined in model space only (" + iges::describe(c) +
                  " has no parameter-space curve)"};
        r.modelSpaceTrim = true;
        return r;
    }
    return curvesOf(f, *f.at(b), loop.curves, converted);
}

/// Entity 144 over a 128 with parameter-space loops, exactly.
Refusal trimmed144(const File& f, const Entity& e, Patch& p, PatchTrim& trim, std::string& name,
                   std::set<std::string>& converted, bool& wholeRectangle) {
    const Entity& s = *f.at(iges::integer(f, e, 0));
    if (e.transform) return {"it has a transformation matrix"};
    if (s.type != 128)
        return {"its base surface " + iges::describe(s) + " is a " + iges::typeName(s.type)};
    PatchTrim ignoredRange;
    std::string baseName;
    if (Refusal r = surface128(f, s, p, ignoredRange, baseName)) {
        r.why = "its base surface " + iges::describe(s) + ": " + r.why;
        return r;
    }
    const int n2 = iges::integer(f, e, 2);
    name = entityName(f, e, 4 + static_cast<std::size_t>(n2));
    if (name.empty()) name = baseName;
    if (iges::integer(f, e, 1) == 1) {
        if (Refusal r = loopOf(f, iges::integer(f, e, 3), trim.outer, converted)) return r;
        // An outer loop around the whole parameter rectangle trims nothing (Parasolid, for one,
        // writes one around every surface): the patch is untrimmed, as the STEP reader makes it,
        // and can go where trimmed patches cannot (the enclosed volume, the mesh).
        wholeRectangle = geometry::onParameterBoundary(trim.outer, p);
        if (wholeRectangle) trim.outer = {};
    }
    for (int k = 0; k < n2; ++k) {
        TrimLoop hole;
        if (Refusal r =
                loopOf(f, iges::integer(f, e, 4 + static_cast<std::size_t>(k)), hole, converted))
            return r;
        trim.holes.push_back(std::move(hole));
    }
    try {
        geometry::validate(trim, p, "its trim");
    } catch (const GeometryError& err) {
        return {std::string("its loops as written are not usable (") + err.what() + ")"};
    }
    return {};
}

// ------------------------------------------------------------------------------------------
// What to do with each top-level entity

bool occtSurface(int type) {
    switch (type) {
        case 108:
        case 114:
        case 118:
        case 120:
        case 122:
        case 128:
        case 140:
        case 143:
        case 144:
        case 186:
        case 190:
        case 192:
        case 194:
        case 196:
        case 198:
        case 408:
        case 510:
        case 514:
            return true;
        default:
            return false;
    }
}

/// Why a top-level entity that is not a surface is not read.
std::string ignoredReason(const Entity& e, bool& warn) {
    warn = false;
    const int t = e.type;
    if (t == 116) return "a point, not a surface";
    if ((t >= 100 && t <= 106) || t == 110 || t == 112 || t == 126 || t == 130)
        return "a curve, not a surface (nothing trims with it)";
    if (t == 142 || t == 141) return "a curve on a surface that no trimmed surface uses";
    if (t == 123 || t == 124 || t == 125) return "not a surface";
    if ((t >= 150 && t <= 184) || t == 430) {
        warn = true;
        return "a CSG solid: not supported";
    }
    if (t >= 200 && t < 300) return "an annotation";
    if (t == 402) return "an associativity (a group): its members are read on their own";
    if (t >= 300 && t < 500) return "structure or attributes, not geometry";
    if (t >= 502 && t <= 508) return "B-rep topology that no face uses";
    warn = t < 600;  // an unknown geometric entity
    return "an entity type Aeroform does not read";
}

/// The types of the surfaces an entity is built on (itself included), through its parts.
std::set<int> surfaceTypesUnder(const File& f, const Entity& root) {
    static const std::set<int> surfaces{108, 114, 118, 120, 122, 128, 140, 190, 192, 194, 196, 198};
    std::set<int> types;
    std::vector<char> seen(f.entities.size(), 0);
    std::vector<const Entity*> stack{&root};
    while (!stack.empty()) {
        const Entity* e = stack.back();
        stack.pop_back();
        if (seen[static_cast<std::size_t>(e->de / 2)]) continue;
        seen[static_cast<std::size_t>(e->de / 2)] = 1;
        if (surfaces.count(e->type)) types.insert(e->type);
        for (int c : iges::geometryChildren(f, *e)) stack.push_back(f.at(c));
    }
    return types;
}

struct Plan {
    const Entity* entity = nullptr;
    enum { Direct, Occt, Ignore } how = Ignore;
    Patch patch;
    PatchTrim trim;
    std::string name;
    Refusal refusal;                        // why not direct (for Occt) or why ignored
    std::set<std::string> trimConversions;  // direct trims computed exactly (arcs, transformations)
    bool warnIgnored = false;
    bool wholeRectangle = false;            // a 144 whose outer loop was its rectangle (dropped)
    int occtIndex = -1;
};

const geometry::LengthUnit& fileUnit(const iges::Global& g, ReadReport& rep,
                                     const std::string& path) {
    const geometry::LengthUnit* byFlag = geometry::lengthUnitForIgesFlag(g.unitFlag);
    const geometry::LengthUnit* byName =
        g.unitName.empty() ? nullptr : geometry::findLengthUnit(g.unitName);
    if (!byName && g.unitName == "IN") byName = geometry::findLengthUnit("in");
    const std::string source = "IGES unit flag " + std::to_string(g.unitFlag) +
                               (g.unitName.empty() ? "" : " ('" + g.unitName + "')");
    if (g.unitFlag == 3) {
        if (!byName)
            throw InputError(
                "IGES file " + quoted(path) +
                ": unit flag 3 (the unit name says which) with unit name '" + g.unitName +
                "', which Aeroform does not know (known: " + geometry::knownLengthUnits() + ")");
        rep.unitSource = source;
        return *byName;
    }
    rep.unitSource = source;
    if (byName && byName != byFlag)
        rep.notes.push_back("the unit name '" + g.unitName + "' disagrees with unit flag " +
                            std::to_string(g.unitFlag) + ": the flag is used (" +
                            std::string(byFlag->longName) + ")");
    return *byFlag;
}

}  // namespace

PatchSet readIges(const std::string& path, ReadReport* report) {
    ReadReport local;
    ReadReport& rep = report ? *report : local;
    rep = {};
    rep.format = "IGES";

    const File file = iges::parse(readText(path), path);
    for (const Entity& e : file.entities) iges::check(file, e);
    iges::checkCycles(file);
    const geometry::LengthUnit& unit = fileUnit(file.global, rep, path);
    rep.unit = std::string(unit.name);
    if (file.column65Line)
        rep.notes.push_back("parameter data runs into column 65 (first on line " +
                            std::to_string(file.column65Line) +
                            "), which the IGES standard keeps blank: read as data, the directory "
                            "entry pointer from columns 66-72 (pyGeo, for one, writes so)");
    if (file.global.modelScale != 1.0)
        rep.notes.push_back("the global section's model space scale is " +
                            number(file.global.modelScale) +
                            ": coordinates are kept in model space, as written");

    // Entities that are parts of others are read with their parent. Non-surfaces the file flags
    // as dependent (properties, points of analytic surfaces, ...) are parts too.
    std::vector<char> part(file.entities.size(), 0);
    for (const Entity& e : file.entities) {
        for (int c : iges::geometryChildren(file, e))
            if (c != e.de) part[static_cast<std::size_t>(c / 2)] = 1;
        if (e.transform) part[static_cast<std::size_t>(e.transform / 2)] = 1;
        if (e.subordinate() != 0 && !occtSurface(e.type))
            part[static_cast<std::size_t>(e.de / 2)] = 1;
    }

    std::vector<Plan> plans;
    std::vector<int> occtEntities;
    std::vector<char> modelSpaceTrims;
    for (const Entity& e : file.entities) {
        if (part[static_cast<std::size_t>(e.de / 2)]) continue;
        Plan plan;
        plan.entity = &e;
        if (e.type == 128 || e.type == 144) {
            plan.refusal = e.type == 128 ? surface128(file, e, plan.patch, plan.trim, plan.name)
                                         : trimmed144(file, e, plan.patch, plan.trim, plan.name,
                                                      plan.trimConversions, plan.wholeRectangle);
            plan.how = !plan.refusal ? Plan::Direct
                                     : (plan.refusal.unsupported ? Plan::Ignore : Plan::Occt);
            plan.warnIgnored = plan.refusal.unsupported;
        } else if (e.type == 108 && e.form == 0) {
            plan.refusal = {"an unbounded plane (form 0): not a surface patch"};
        } else if (occtSurface(e.type)) {
            plan.how = Plan::Occt;
        } else {
            plan.refusal = {ignoredReason(e, plan.warnIgnored)};
        }
        if (plan.how == Plan::Occt && file.column65Line) {
            // OpenCASCADE reads columns 1-64 of a parameter line: the delimiter in column 65
            // would be lost and the parameters after it shift.
            plan.how = Plan::Ignore;
            plan.warnIgnored = true;
            plan.refusal = {"OpenCASCADE would convert it, but it reads only columns 1-64 of the parameter "
                            "lines and this file has data in column 65 (from line " +
                            std::to_string(file.column65Line) + " on), so its parameters would shift"};
        }
        if (plan.how == Plan::Occt) {
            plan.occtIndex = static_cast<int>(occtEntities.size());
            occtEntities.push_back(e.de);
            modelSpaceTrims.push_back(plan.refusal.modelSpaceTrim ? 1 : 0);
        }
        plans.push_back(std::move(plan));
    }

    std::vector<occt::EntityFaces> converted;
    if (!occtEntities.empty())
        converted = occt::transferIgesEntitiesIsolated(path, std::string(unit.igesName), occtEntities,
                                                       modelSpaceTrims);

    PatchSet set;
    set.source = path;
    set.unit = std::string(unit.name);
    auto addPatch = [&](Patch p, PatchTrim t, std::string name) {
        set.patches.push_back(std::move(p));
        set.trims.push_back(std::move(t));
        set.names.push_back(std::move(name));
        return set.size() - 1;
    };
    for (Plan& plan : plans) {
        const Entity& e = *plan.entity;
        ReadItem item;
        item.entity = e.de;
        item.type = e.type;
        item.kind = iges::typeName(e.type);
        if (e.type == 144)
            item.kind += " over a " + iges::typeName(file.at(iges::integer(file, e, 0))->type);
        const std::string what = iges::describe(e);
        if (e.status / 1000000 == 1)
            rep.notes.push_back(what + " is blanked (hidden) in the file; it is read");
        if (plan.how == Plan::Direct) {
            item.surface = SurfaceOutcome::Kept;
            item.trim =
                plan.trim.trimmed()
                    ? (plan.trimConversions.empty() ? TrimOutcome::Kept : TrimOutcome::Converted)
                    : TrimOutcome::None;
            if (e.type == 128 && plan.trim.trimmed())
                item.note =
                    "its parameter range is narrower than its knots: kept as a rectangular trim";
            if (plan.wholeRectangle)
                item.note = std::string("its outer loop is the whole parameter rectangle: ") +
                            (plan.trim.trimmed() ? "only its holes trim it" : "read as untrimmed");
            std::string conversions;
            for (const std::string& c : plan.trimConversions)
                conversions += (conversions.empty() ? "trim curves: " : ", ") + c;
            if (!conversions.empty()) item.note += (item.note.empty() ? "" : "; ") + conversions;
            item.patches.push_back(addPatch(std::move(plan.patch), std::move(plan.trim),
                                            plan.name.empty() ? generatedName(e) : plan.name));
        } else if (plan.how == Plan::Ignore) {
            item.surface = SurfaceOutcome::Ignored;
            item.note = plan.refusal.why;
            if (plan.warnIgnored)
                rep.warnings.push_back(what + " (" + item.kind + ") ignored: " + item.note);
        } else {
            const occt::EntityFaces& r = converted[static_cast<std::size_t>(plan.occtIndex)];
            if (r.faces.empty()) {
                item.surface = SurfaceOutcome::Ignored;
                item.note = "OpenCASCADE could not convert it: " + r.failure;
                rep.warnings.push_back(what + " (" + item.kind + ") ignored: " + item.note);
            }
            std::string base =
                plan.name.empty() ? (e.label.empty() ? generatedName(e) : e.label) : plan.name;
            std::vector<std::string> notes;
            if (plan.refusal) notes.push_back("read by OpenCASCADE because " + plan.refusal.why);
            bool anyConverted = false, anyComputed = false, anyDropped = false;
            double deviation = 0;
            // OpenCASCADE's B-spline faces are the file's own values when every surface under the
            // entity is a 128 (with our cascade unit nothing is scaled); other types are computed.
            const std::set<int> types = surfaceTypesUnder(file, e);
            const bool onlyBSplines = types.size() == 1 && *types.begin() == 128;
            for (std::size_t k = 0; k < r.faces.size(); ++k) {
                const occt::Face& face = r.faces[k];
                const bool exactSurface =
                    !face.converted && face.surfaceType == "Geom_BSplineSurface" && onlyBSplines;
                anyConverted = anyConverted || !exactSurface;
                if (face.converted && !face.conversion.empty() &&
                    std::find(notes.begin(), notes.end(), face.conversion) == notes.end())
                    notes.push_back(face.conversion);
                if (face.surfaceType == "Geom_OffsetSurface")
                    rep.warnings.push_back(what +
                                           ": an offset surface, approximated by a NURBS surface");
                if (!face.trimProblem.empty()) {
                    anyDropped = true;
                    rep.warnings.push_back(
                        what +
                        ": trimming dropped, the whole base surface is used: " + face.trimProblem);
                } else if (face.trim.trimmed()) {
                    anyComputed = true;
                    deviation = std::max(deviation, face.trimDeviation);
                }
                const std::string name =
                    r.faces.size() == 1 ? base : base + " face " + std::to_string(k + 1);
                item.patches.push_back(addPatch(face.patch, face.trim, name));
            }
            if (!r.faces.empty()) {
                item.surface = anyConverted ? SurfaceOutcome::Converted : SurfaceOutcome::Kept;
                item.trim = anyDropped ? TrimOutcome::Dropped
                                       : (anyComputed ? TrimOutcome::Computed : TrimOutcome::None);
                if (anyComputed) {
                    notes.push_back(
                        "parameter-space trim curves computed by OpenCASCADE: largest distance " +
                        number(deviation) + " from the model-space edges");
                    const geometry::BoundingBox box = geometry::controlBoundingBox(set);
                    const double size = std::hypot(box.max[0] - box.min[0], box.max[1] - box.min[1],
                                                   box.max[2] - box.min[2]);
                    if (plan.refusal.modelSpaceTrim || deviation > 1e-9 * size)
                        rep.warnings.push_back(what + ": " +
                                               (plan.refusal.modelSpaceTrim
                                                    ? "trim loops defined in model space only; "
                                                    : "") +
                                               "parameter-space trim curves computed by "
                                               "OpenCASCADE, largest distance " +
                                               number(deviation) + " from the model-space edges");
                }
                if (!r.failure.empty())
                    rep.warnings.push_back(what + ": some faces were not converted: " + r.failure);
            }
            for (const std::string& n : notes) item.note += (item.note.empty() ? "" : "; ") + n;
        }
        rep.items.push_back(std::move(item));
    }
    if (set.patches.empty()) {
        // Say what the file has instead (a curves-only airfoil file, say), and why any surface in
        // it was not read.
        std::string found;
        for (const ReportRow& row : summarize(rep)) {
            found += (found.empty() ? "" : "; ") + std::to_string(row.entities.size()) + " " + row.kind + " (" +
                     std::to_string(row.type) + ", DE " + listEntities(row.entities, 4) + ")";
            if (!row.reason.empty()) found += ": " + row.reason;
        }
        throw InputError("IGES file " + quoted(path) + " has no surfaces" +
                         (found.empty() ? std::string() : ": its top-level entities are " + found));
    }
    if (set.trimmedCount() == 0) set.trims.clear();
    geometry::validate(set);
    return set;
}

// ------------------------------------------------------------------------------------------
// Writing

namespace {

std::string realText(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.16E", x);  // 17 significant digits: read back exactly
    return buf;
}

std::string hollerith(const std::string& s) {
    return std::to_string(s.size()) + "H" + s;
}

/// Free-format data packed into lines of `width` columns, parameters never split (a string
/// longer than a line continues on the next ones, as IGES allows).
std::vector<std::string> pack(const std::vector<std::string>& tokens, std::size_t width) {
    std::vector<std::string> lines(1);
    for (std::size_t k = 0; k < tokens.size(); ++k) {
        std::string t = tokens[k] + (k + 1 < tokens.size() ? "," : ";");
        if (!lines.back().empty() && lines.back().size() + t.size() > width) lines.emplace_back();
        while (lines.back().size() + t.size() > width) {
            const std::size_t room = width - lines.back().size();
            lines.back() += t.substr(0, room);
            t.erase(0, room);
            lines.emplace_back();
        }
        lines.back() += t;
    }
    return lines;
}

class IgesOut {
  public:
    /// Adds an entity and returns its directory entry (DE pointer).
    int add(int type, int form, const char* status, std::vector<std::string> params,
            const std::string& label = "") {
        Item item;
        item.type = type;
        item.form = form;
        item.status = status;
        item.label = label.substr(0, 8);
        item.params.push_back(std::to_string(type));
        for (auto& p : params) item.params.push_back(std::move(p));
        items_.push_back(std::move(item));
        return 2 * static_cast<int>(items_.size()) - 1;
    }
    /// Appends "0, 1, DE" (no associativities, one property) to the entity's parameters.
    void addProperty(int de, int property) {
        auto& p = items_[static_cast<std::size_t>(de / 2)].params;
        p.insert(p.end(), {"0", "1", std::to_string(property)});
    }

    std::string text(const std::vector<std::string>& global, const std::string& start) const {
        std::string out;
        char buf[96];
        auto line = [&](const std::string& data, char section, int seq) {
            std::snprintf(buf, sizeof buf, "%-72s%c%07d\n", data.c_str(), section, seq);
            out += buf;
        };
        int s = 0, g = 0, d = 0, p = 0;
        line(start, 'S', ++s);
        for (const std::string& l : pack(global, 72)) line(l, 'G', ++g);
        std::vector<std::vector<std::string>> data;
        for (const Item& item : items_) data.push_back(pack(item.params, 64));
        int pointer = 1;
        for (std::size_t k = 0; k < items_.size(); ++k) {
            const Item& item = items_[k];
            const int lines = static_cast<int>(data[k].size());
            std::snprintf(buf, sizeof buf, "%8d%8d%8d%8d%8d%8d%8d%8d%8s", item.type, pointer, 0, 0,
                          0, 0, 0, 0, item.status);
            line(buf, 'D', ++d);
            std::snprintf(buf, sizeof buf, "%8d%8d%8d%8d%8d%8s%8s%8s%8d", item.type, 0, 0, lines,
                          item.form, "", "", item.label.c_str(), 0);
            line(buf, 'D', ++d);
            pointer += lines;
        }
        for (std::size_t k = 0; k < items_.size(); ++k)
            for (const std::string& l : data[k]) {
                std::snprintf(buf, sizeof buf, "%-64s%8d", l.c_str(), static_cast<int>(2 * k + 1));
                line(buf, 'P', ++p);
            }
        std::snprintf(buf, sizeof buf, "S%07dG%07dD%07dP%07d", s, g, d, p);
        line(buf, 'T', 1);
        return out;
    }

  private:
    struct Item {
        int type = 0, form = 0;
        const char* status = "00000000";
        std::string label;
        std::vector<std::string> params;
    };
    std::vector<Item> items_;
};

constexpr const char* kIndependent = "00000000";
constexpr const char* kDependent = "00010000";  // physically dependent geometry (part of a 144)
constexpr const char* kParametric =
    "00010500";  // physically dependent, 2D parametric (trim curves)

int addSurface(IgesOut& out, const Patch& p, const char* status, const std::string& label) {
    std::vector<std::string> t;
    for (int v :
         {p.countU - 1, p.countV - 1, p.degreeU, p.degreeV, 0, 0, p.rational() ? 0 : 1, 0, 0})
        t.push_back(std::to_string(v));
    for (double k : p.knotsU) t.push_back(realText(k));
    for (double k : p.knotsV) t.push_back(realText(k));
    for (int k = 0; k < p.controlCount(); ++k)
        t.push_back(realText(p.rational() ? p.weights[static_cast<std::size_t>(k)] : 1.0));
    for (double x : p.points) t.push_back(realText(x));
    for (double r : {p.knotsU[static_cast<std::size_t>(p.degreeU)],
                     p.knotsU[static_cast<std::size_t>(p.countU)],
                     p.knotsV[static_cast<std::size_t>(p.degreeV)],
                     p.knotsV[static_cast<std::size_t>(p.countV)]})
        t.push_back(realText(r));
    return out.add(128, 0, status, std::move(t), label);
}

int addTrimCurve(IgesOut& out, const TrimCurve& c) {
    const int n = c.curve.count();
    std::vector<std::string> t;
    for (int v : {n - 1, c.curve.degree, 1, 0, c.curve.rational() ? 0 : 1, 0})
        t.push_back(std::to_string(v));
    for (double k : c.curve.knots) t.push_back(realText(k));
    for (int k = 0; k < n; ++k)
        t.push_back(
            realText(c.curve.rational() ? c.curve.weights[static_cast<std::size_t>(k)] : 1.0));
    for (int k = 0; k < n; ++k)
        for (int d = 0; d < 3; ++d)
            t.push_back(realText(
                d < 2
                    ? c.curve.points[3 * static_cast<std::size_t>(k) + static_cast<std::size_t>(d)]
                    : 0.0));
    for (double x : {c.first, c.last, 0.0, 0.0, 1.0}) t.push_back(realText(x));
    return out.add(126, 0, kParametric, std::move(t));
}

/// A loop as a 142 on `surface` (parameter-space curve only).
int addLoop(IgesOut& out, const TrimLoop& loop, int surface) {
    int curve;
    if (loop.curves.size() == 1) {
        curve = addTrimCurve(out, loop.curves[0]);
    } else {
        std::vector<std::string> t{std::to_string(loop.curves.size())};
        for (const TrimCurve& c : loop.curves) t.push_back(std::to_string(addTrimCurve(out, c)));
        curve = out.add(102, 0, kParametric, std::move(t));
    }
    return out.add(142, 0, kDependent,
                   {"0", std::to_string(surface), std::to_string(curve), "0", "1"});
}

/// Names the reader made up ("entity 12", "entity 12 face 3") are not written: the numbers would
/// be wrong in the new file.
bool generated(const std::string& name) {
    std::istringstream in(name);
    std::string word, rest;
    int n = 0;
    if (!(in >> word >> n) || word != "entity") return false;
    if (!(in >> rest)) return true;
    return rest == "face" && (in >> n) && !(in >> rest);
}

std::string timestamp() {
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y%m%d.%H%M%S", &utc);
    return buf;
}

}  // namespace

void writeIges(const PatchSet& set, const std::string& path) {
    geometry::validate(set);
    const geometry::LengthUnit* unit = geometry::findLengthUnit(set.unit.empty() ? "mm" : set.unit);

    IgesOut out;
    double largest = 0;
    for (int k = 0; k < set.size(); ++k) {
        const Patch& p = set.patches[static_cast<std::size_t>(k)];
        for (double x : p.points) largest = std::max(largest, std::abs(x));
        const std::string name = k < static_cast<int>(set.names.size()) &&
                                         !generated(set.names[static_cast<std::size_t>(k)])
                                     ? set.names[static_cast<std::size_t>(k)]
                                     : std::string();
        int top;
        if (!set.trimmed(k)) {
            top = addSurface(out, p, kIndependent, name);
        } else {
            const PatchTrim& trim = set.trims[static_cast<std::size_t>(k)];
            const int surface = addSurface(out, p, kDependent, "");
            const int outer = trim.outer.curves.empty() ? 0 : addLoop(out, trim.outer, surface);
            std::vector<std::string> t{std::to_string(surface), outer ? "1" : "0",
                                       std::to_string(trim.holes.size()), std::to_string(outer)};
            for (const TrimLoop& h : trim.holes)
                t.push_back(std::to_string(addLoop(out, h, surface)));
            top = out.add(144, 0, kIndependent, std::move(t), name);
        }
        if (name.size() > 8 || name.find_first_of(",;") != std::string::npos)
            out.addProperty(top, out.add(406, 15, kDependent, {"1", hollerith(name)}));
    }

    const std::string file = std::filesystem::path(path).filename().string();
    const std::string now = timestamp();
    const std::vector<std::string> global = {"1H,",
                                             "1H;",
                                             hollerith("Aeroform"),
                                             hollerith(file),
                                             hollerith("Aeroform"),
                                             hollerith("Aeroform IGES writer"),
                                             "32",
                                             "38",
                                             "6",
                                             "308",
                                             "15",
                                             hollerith("Aeroform"),
                                             realText(1.0),
                                             std::to_string(unit->igesFlag),
                                             hollerith(std::string(unit->igesName)),
                                             "1",
                                             realText(1.0),
                                             hollerith(now),
                                             realText(1e-10),
                                             realText(largest > 0 ? largest : 1.0),
                                             "",
                                             "",
                                             "11",
                                             "0",
                                             hollerith(now)};
    writeTextAtomically(
        path,
        out.text(global, "Aeroform: NURBS patches, trimmed ones as 144/142/126 in parameter space"),
        "IGES file");
}

}  // namespace aero::cad
