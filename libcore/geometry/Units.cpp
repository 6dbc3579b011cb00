#include "geometry/Units.h"

#include <algorithm>
#include <array>
#include <cctype>

#include "common/Error.h"
#include "geometry/PatchSet.h"

namespace aero::geometry {

namespace {

// In IGES flag order. Lengths in 1e-10 m are exact integers (the inch is 0.0254 m by definition).
constexpr std::array<LengthUnit, 10> kUnits{{
    {"in", "inch", 1, "INCH", 254000000},
    {"mm", "millimetre", 2, "MM", 10000000},
    {"ft", "foot", 4, "FT", 3048000000},
    {"mi", "mile", 5, "MI", 16093440000000},
    {"m", "metre", 6, "M", 10000000000},
    {"km", "kilometre", 7, "KM", 10000000000000},
    {"mil", "mil (0.001 in)", 8, "MIL", 254000},
    {"um", "micrometre", 9, "UM", 10000},
    {"cm", "centimetre", 10, "CM", 100000000},
    {"uin", "microinch", 11, "UIN", 254},
}};

struct Alias {
    std::string_view alias, unit;
};
constexpr Alias kAliases[] = {
    {"inch", "in"},        {"inches", "in"},      {"millimetre", "mm"}, {"millimeter", "mm"},
    {"millimetres", "mm"}, {"millimeters", "mm"}, {"foot", "ft"},       {"feet", "ft"},
    {"mile", "mi"},        {"miles", "mi"},       {"metre", "m"},       {"meter", "m"},
    {"metres", "m"},       {"meters", "m"},       {"kilometre", "km"},  {"kilometer", "km"},
    {"thou", "mil"},       {"mils", "mil"},       {"micron", "um"},     {"microns", "um"},
    {"micrometre", "um"},  {"micrometer", "um"},  {"centimetre", "cm"}, {"centimeter", "cm"},
    {"microinch", "uin"},  {"microinches", "uin"}};

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

}  // namespace

const LengthUnit* findLengthUnit(std::string_view name) {
    const std::string key = lower(name);
    std::string_view canonical = key;
    for (const Alias& a : kAliases)
        if (a.alias == key) canonical = a.unit;
    for (const LengthUnit& u : kUnits)
        if (u.name == canonical) return &u;
    return nullptr;
}

const LengthUnit* lengthUnitForIgesFlag(int flag) {
    for (const LengthUnit& u : kUnits)
        if (u.igesFlag == flag) return &u;
    return nullptr;
}

std::string knownLengthUnits() {
    std::string s;
    for (const LengthUnit& u : kUnits) s += (s.empty() ? "" : ", ") + std::string(u.name);
    return s;
}

double lengthFactor(const LengthUnit& from, const LengthUnit& to) {
    return static_cast<double>(from.tenthNanometres) / static_cast<double>(to.tenthNanometres);
}

void convertUnits(PatchSet& set, std::string_view to) {
    const LengthUnit* target = findLengthUnit(to);
    const std::string what =
        set.source.empty() ? std::string("the geometry") : "'" + set.source + "'";
    if (!target)
        throw GeometryError("unknown length unit '" + std::string(to) +
                            "' (known: " + knownLengthUnits() + ")");
    if (set.unit.empty())
        throw GeometryError(what + " states no length unit, so it cannot be converted to " +
                            std::string(target->name));
    const LengthUnit* source = findLengthUnit(set.unit);
    if (!source) throw GeometryError(what + ": unknown length unit '" + set.unit + "'");
    if (source != target) {
        const double f = lengthFactor(*source, *target);
        for (Patch& p : set.patches)
            for (double& x : p.points) x *= f;
    }
    set.unit = std::string(target->name);
}

}  // namespace aero::geometry
