#include "io/GeometryVtk.h"

namespace aero::io {

namespace {

std::vector<double> parameters(const std::vector<double>& knots, int samples) {
    std::vector<double> s(samples);
    for (int i = 0; i < samples; ++i) s[i] = knots.front() + (knots.back() - knots.front()) * i / (samples - 1);
    return s;
}

VtkField difference(const char* name, const std::vector<double>& a, const std::vector<double>& b) {
    VtkField f{name, 3, a};
    for (std::size_t i = 0; i < a.size(); ++i) f.values[i] -= b[i];
    return f;
}

std::vector<double> sampled(const geometry::Patch& p, int samples) {
    const std::vector<double> us = parameters(p.knotsU, samples), vs = parameters(p.knotsV, samples);
    std::vector<double> out(3 * static_cast<std::size_t>(samples) * samples);
    nurbs::sampleGrid(p, us, vs, out.data());
    return out;
}

}  // namespace

std::vector<MultiBlockGroup> geometryBlocks(const geometry::PatchSet& set, const geometry::PatchSet* baseline,
                                            const std::vector<ffd::Lattice>& lattices,
                                            const std::vector<ffd::Lattice>* baselineLattices, int samples) {
    MultiBlockGroup patches{"patches", {}}, nets{"control_nets", {}}, boxes{"lattices", {}};
    for (int p = 0; p < set.size(); ++p) {
        const geometry::Patch& s = set.patches[p];
        const std::string name = p < static_cast<int>(set.names.size()) && !set.names[p].empty()
                                     ? set.names[p]
                                     : "patch " + std::to_string(p + 1);
        StructuredBlock b{name, {samples, samples, 1}, sampled(s, samples), {}, {}};
        if (baseline) b.pointData.push_back(difference("displacement", b.points, sampled(baseline->patches[p], samples)));
        if (set.trimmedCount() > 0) {
            // Trimmed sets: 1 where the sample is inside the patch's trim, 0 outside (threshold
            // on it in ParaView to see the trimmed surfaces).
            VtkField inside{"inside_trim", 1, std::vector<double>(static_cast<std::size_t>(samples) * samples, 1.0)};
            if (set.trimmed(p)) {
                const geometry::TrimPolygons poly = geometry::polygonize(set.trims[p], s);
                const std::vector<double> us = parameters(s.knotsU, samples), vs = parameters(s.knotsV, samples);
                for (int j = 0; j < samples; ++j)
                    for (int i = 0; i < samples; ++i)
                        inside.values[static_cast<std::size_t>(i + samples * j)] = geometry::contains(poly, us[i], vs[j]) ? 1.0 : 0.0;
            }
            b.pointData.push_back(std::move(inside));
        }
        patches.blocks.push_back(std::move(b));
        StructuredBlock n{name, {s.countU, s.countV, 1}, s.points, {}, {}};
        if (baseline) n.pointData.push_back(difference("displacement", s.points, baseline->patches[p].points));
        nets.blocks.push_back(std::move(n));
    }
    for (std::size_t l = 0; l < lattices.size(); ++l) {
        const ffd::Lattice& L = lattices[l];
        StructuredBlock b{"lattice " + std::to_string(l + 1), {L.count[0], L.count[1], L.count[2]}, L.points, {}, {}};
        if (baselineLattices) b.pointData.push_back(difference("displacement", L.points, (*baselineLattices)[l].points));
        boxes.blocks.push_back(std::move(b));
    }
    std::vector<MultiBlockGroup> groups{std::move(patches), std::move(nets)};
    if (!boxes.blocks.empty()) groups.push_back(std::move(boxes));
    return groups;
}

}  // namespace aero::io
