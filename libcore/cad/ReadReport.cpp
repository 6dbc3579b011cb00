#include "cad/ReadReport.h"

#include <algorithm>

namespace aero::cad {

int ReadReport::count(SurfaceOutcome s) const {
    return static_cast<int>(std::count_if(items.begin(), items.end(),
                                          [&](const ReadItem& i) { return i.surface == s; }));
}

int ReadReport::count(TrimOutcome t) const {
    return static_cast<int>(std::count_if(items.begin(), items.end(), [&](const ReadItem& i) {
        return i.surface != SurfaceOutcome::Ignored && i.trim == t;
    }));
}

std::string outcomeText(SurfaceOutcome s, TrimOutcome t) {
    if (s == SurfaceOutcome::Ignored) return "ignored";
    const std::string surface = s == SurfaceOutcome::Kept ? "kept" : "converted to NURBS exactly";
    switch (t) {
        case TrimOutcome::None:
            return s == SurfaceOutcome::Kept ? "kept as NURBS exactly" : surface;
        case TrimOutcome::Kept:
            return surface + (s == SurfaceOutcome::Kept ? " with trimming, exactly"
                                                        : ", trimming kept exactly");
        case TrimOutcome::Converted:
            return surface + (s == SurfaceOutcome::Kept ? " exactly" : "") +
                   ", trimming converted exactly";
        case TrimOutcome::Computed:
            return surface + (s == SurfaceOutcome::Kept ? " exactly" : "") +
                   ", trim curves computed by OpenCASCADE";
        case TrimOutcome::Dropped:
            return surface + (s == SurfaceOutcome::Kept ? " exactly" : "") +
                   ", TRIMMING DROPPED (whole base surface used)";
    }
    return surface;
}

std::vector<ReportRow> summarize(const ReadReport& report) {
    std::vector<ReportRow> rows;
    for (const ReadItem& item : report.items) {
        auto it = std::find_if(rows.begin(), rows.end(), [&](const ReportRow& r) {
            return r.type == item.type && r.kind == item.kind && r.surface == item.surface &&
                   r.trim == item.trim;
        });
        if (it == rows.end()) {
            ReportRow r;
            r.type = item.type;
            r.kind = item.kind;
            r.surface = item.surface;
            r.trim = item.trim;
            r.reason = item.note;
            rows.push_back(r);
            it = rows.end() - 1;
        } else if (it->reason != item.note) {
            it->reason.clear();  // the items differ: each note is in the item list
        }
        it->entities.push_back(item.entity);
    }
    return rows;
}

std::string listEntities(const std::vector<int>& entities, std::size_t shown,
                         const std::string& prefix) {
    std::string s;
    const std::size_t n = std::min(shown, entities.size());
    for (std::size_t k = 0; k < n; ++k) s += (k ? ", " : "") + prefix + std::to_string(entities[k]);
    if (entities.size() > n) s += " and " + std::to_string(entities.size() - n) + " more";
    return s;
}

}  // namespace aero::cad
