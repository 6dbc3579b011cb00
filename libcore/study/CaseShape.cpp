#include "study/CaseShape.h"

#include <cstdio>

#include "common/Error.h"

namespace aero::study {

namespace {

std::string format(const char* fmt, auto... args) {
    char buf[512];
    std::snprintf(buf, sizeof buf, fmt, args...);
    return buf;
}

}  // namespace

CaseShape deformCase(const io::CaseFile& c, const geometry::PatchSet& geometry, const Log& log) {
    auto say = [&](const std::string& s) {
        if (log) log(s);
    };
    CaseShape out;
    if (c.lattices.empty()) {
        out.deformed = geometry;
        out.uniqueSurface = geometry::buildControlPointIndex(geometry, 1e-10).points;
        return out;
    }
    out.model = std::make_unique<ffd::FfdModel>(io::buildModel(c, geometry));
    const ffd::FfdModel& model = *out.model;
    const ffd::EmbeddingSummary& emb = model.summary();
    say(format("embedded %d of %d unique control points in %zu lattice(s), max error %.2e, %.3f s", emb.embedded, emb.unique,
               model.lattices().size(), emb.maxError, emb.seconds));
    for (const auto& f : emb.failures) (f.outside ? out.pointsOutside : out.pointsNotConverged) += 1;
    if (!emb.failures.empty()) {
        say(format("%d control point(s) outside every lattice, %d not converged:", out.pointsOutside, out.pointsNotConverged));
        for (std::size_t i = 0; i < emb.failures.size() && i < 10; ++i) {
            const auto& f = emb.failures[i];
            const double* x = &model.index().points[3 * f.point];
            say(format("  control point (%.6g, %.6g, %.6g) of %s: %s, %.3e away", x[0], x[1], x[2],
                       geometry.describe(f.patch).c_str(), f.outside ? "outside" : "not converged", f.distance));
        }
        if (emb.failures.size() > 10) say(format("  ... and %zu more", emb.failures.size() - 10));
        if (!c.allowOutside) {
            throw GeometryError("'" + c.path + "': " + std::to_string(emb.failures.size()) +
                                " control point(s) could not be embedded (enlarge the lattice padding, or set "
                                "embedding.allow_outside to keep them fixed)");
        }
    }
    out.values = io::designValues(c, model);
    out.moved = io::movedLattices(c, model, out.values);
    std::string failure;
    for (std::size_t l = 0; l < out.moved.size(); ++l) {
        const ffd::InjectivityReport r = ffd::checkInjectivity(out.moved[l]);
        const auto& L = out.moved[l];
        const std::string& name = model.lattices()[l].name;
        say(format("lattice '%s' %dx%dx%d: %s, min det J / mean = %.3g", name.c_str(), L.count[0], L.count[1], L.count[2],
                   r.injective ? (r.certified ? "injective (certified)" : "injective (sampled)") : "NOT injective",
                   r.relativeMinJacobian));
        if (!r.injective && failure.empty()) {
            failure = format("lattice '%s' is not injective: det J changes sign near parameters (%.3f, %.3f, %.3f), world "
                             "point (%.4g, %.4g, %.4g); the embedded geometry could self-intersect",
                             name.c_str(), r.minAt[0], r.minAt[1], r.minAt[2], r.minPoint[0], r.minPoint[1], r.minPoint[2]);
        }
        out.injectivity.push_back(r);
    }
    if (!failure.empty()) throw GeometryError("'" + c.path + "': " + failure + " (nothing written)");
    out.uniqueSurface = model.uniqueWith(out.moved);
    out.deformed = model.deformWith(out.moved);
    return out;
}

}  // namespace aero::study
