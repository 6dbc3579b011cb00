#pragma once
// Length units of geometry files. A patch set keeps the unit its file states (PatchSet::unit) and
// its coordinates as written; converting is a separate, explicit step (convertUnits).
#include <cstdint>
#include <string>
#include <string_view>

namespace aero::geometry {

struct PatchSet;

struct LengthUnit {
    std::string_view
        name;  // canonical short name, as stored in PatchSet::unit: "mm", "m", "in", ...
    std::string_view longName;  // "millimetre"
    int igesFlag;               // IGES global section unit flag (1 inch, 2 mm, 4 ft, 6 m, ...)
    std::string_view igesName;  // IGES unit name written with the flag ("MM", "M", "INCH", ...)
    std::int64_t
        tenthNanometres;  // the unit's length in 1e-10 m, exactly (an integer for every unit)
};

/// The unit named `name` (canonical or common spellings, any case: "mm", "millimetre",
/// "millimeter", "in", "inch", "INCH", "m", "metre", "meter", ...), or nullptr.
const LengthUnit* findLengthUnit(std::string_view name);
/// The unit of an IGES unit flag (1, 2, 4..11), or nullptr (3 = "see the unit name" and others).
const LengthUnit* lengthUnitForIgesFlag(int flag);
/// "in, mm, ft, mi, m, km, mil, um, cm, uin": for messages and --help.
std::string knownLengthUnits();

/// The factor f with x[to] = f * x[from], as one correctly rounded division of exact integers
/// (in -> mm is the double nearest 25.4).
double lengthFactor(const LengthUnit& from, const LengthUnit& to);

/// Scales every control point of `set` from its unit to `to` and sets set.unit (trims are in
/// parameter space and do not change; weights and knots neither). A no-op when the units are
/// the same. Throws GeometryError when `to` is unknown or the set states no unit (naming the
/// source).
void convertUnits(PatchSet& set, std::string_view to);

}  // namespace aero::geometry
