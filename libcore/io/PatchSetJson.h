#pragma once
// The native JSON format of a patch set (schema in docs/file-formats.md):
// {"format": "aeroform.patchset", "version": 1, "patches": [ {"name", "degree": [pu, pv],
//  "count": [nu, nv], "knots_u", "knots_v", "points": [[x,y,z], ...] (u fastest),
//  "weights" (optional), "trim" (optional: {"outer": [curve...], "holes": [[curve...]...]},
//  curve = {"degree", "knots", "points": [[u, v], ...], "weights" (optional), "range": [first, last]})} ],
//  "unit" (optional: "mm", "m", "in", ...)}. Doubles are written in shortest round-trip form (exact).
#include <string>

#include "geometry/PatchSet.h"

namespace aero::io {

/// Reads and validates a patch set; throws InputError naming the file (and the JSON key or
/// patch) on any problem.
geometry::PatchSet readPatchSetJson(const std::string& path);
void writePatchSetJson(const geometry::PatchSet& set, const std::string& path);

/// In-memory variants (text is a JSON document); `origin` names the source in messages.
geometry::PatchSet parsePatchSetJson(const std::string& text, const std::string& origin);
std::string formatPatchSetJson(const geometry::PatchSet& set);

}  // namespace aero::io
