#pragma once
// What a CAD reader did with each item of a file (IGES entities, STEP faces): kept exactly,
// converted exactly, kept with its trimming, or ignored and why. `aeroform-cli info` and the GUI
// show it; every change to the geometry is also a warning (`--strict` fails on warnings).
#include <string>
#include <vector>

namespace aero::cad {

/// The surface of an item.
enum class SurfaceOutcome {
    Kept,       // a NURBS surface taken as written, bit for bit
    Converted,  // another surface type (plane, revolution, ruled, ...) made an exact NURBS, or a
                // NURBS moved by a transformation / re-knotted (same surface, computed control
                // points)
    Ignored,    // not read (see the note)
};

/// The trimming of an item.
enum class TrimOutcome {
    None,       // untrimmed
    Kept,       // parameter-space loops taken as written, bit for bit
    Converted,  // the same parameter-space curves, control points computed (circular arcs made
                // rational B-splines, transformation matrices applied)
    Computed,   // parameter-space loops computed by OpenCASCADE (model-space trims, converted
                // surfaces, STEP faces): the note gives the largest distance to the model-space
                // edges
    Dropped,    // the trimming could not be kept: the whole base surface is used (a warning)
};

struct ReadItem {
    int entity =
        0;  // IGES: the directory entry (DE pointer, odd); STEP: the face's #id (0 if unknown)
    int type = 0;      // IGES entity type (128, 144, ...); 0 for STEP
    std::string kind;  // "rational B-spline surface", "trimmed surface", "ADVANCED_FACE", ...
    SurfaceOutcome surface = SurfaceOutcome::Ignored;
    TrimOutcome trim = TrimOutcome::None;
    std::vector<int> patches;  // the patches (0-based) it became
    std::string note;          // how it was converted, or why it was ignored
};

struct ReadReport {
    std::string format;  // "IGES", "STEP" or "JSON"
    std::string unit;  // unit of the coordinates ("mm", "m", "in", ...; "" if the file states none)
    std::string unitSource;  // how the file states it, e.g. "IGES unit flag 6 ('M')"
    std::vector<ReadItem> items;
    std::vector<std::string> warnings;  // each a change to the geometry or information lost
    std::vector<std::string> notes;     // informational

    int count(SurfaceOutcome s) const;
    int count(TrimOutcome t) const;
};

/// "kept as NURBS exactly", "converted to NURBS exactly", "kept with trimming, exactly", ...,
/// "ignored".
std::string outcomeText(SurfaceOutcome s, TrimOutcome t);

/// The report grouped by (entity type, outcome), in order of first appearance.
struct ReportRow {
    int type = 0;
    std::string kind;
    SurfaceOutcome surface = SurfaceOutcome::Ignored;
    TrimOutcome trim = TrimOutcome::None;
    std::vector<int> entities;  // the items' entity numbers
    std::string reason;         // for ignored rows: the items' note when they all share it
};
std::vector<ReportRow> summarize(const ReadReport& report);

/// "1, 3, 5 and 12 more" (at most `shown` numbers, each after `prefix`, e.g. "#").
std::string listEntities(const std::vector<int>& entities, std::size_t shown = 8,
                         const std::string& prefix = "");

}  // namespace aero::cad
