#include "adjoint/GridSensitivity.h"

#include <cmath>
#include <complex>

#include "common/Dual.h"
#include "common/Error.h"
#include "flow/Jacobian.h"
#include "flow/Metrics.h"
#include "flow/bc/BoundaryFlux.h"

namespace aero::adjoint {

namespace {

using C = std::complex<double>;
using flow::kMetricWidth;
using flow::kVars;
constexpr double kStep = 1e-30;  // complex step: exact to round-off

// Calls fn(block, global node, (i, j, k)) for every node of every block: one parallel region
// over the blocks (with passive OpenMP waiting a region per block costs a wake-up each).
template <class Fn>
void forEachNode(const flow::FlowMesh& fm, Fn&& fn) {
    const long nb = static_cast<long>(fm.blocks.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (long b = 0; b < nb; ++b) {
        const flow::FlowBlock& blk = fm.blocks[b];
        const long count = blk.nodeCount();
        for (long n = 0; n < count; ++n) fn(blk, blk.offset + n, flow::nodeIndex(blk.dims, n));
    }
}

// Wall SAT rows that use a wall junction's normal: (global node, face, junction).
struct JunctionRow {
    long node;
    int face;
    int junction;
};

std::vector<JunctionRow> junctionRows(const flow::FlowMesh& fm) {
    std::vector<JunctionRow> rows;
    for (const flow::FlowBlock& blk : fm.blocks) {
        for (int f = 0; f < 6; ++f) {
            if (blk.faces[f].kind != mesh::BoundaryKind::Wall || blk.junction[f].empty()) continue;
            const std::vector<long> nodes = flow::faceNodes(blk.dims, f);
            for (std::size_t a = 0; a < nodes.size(); ++a) {
                if (blk.junction[f][a] >= 0) rows.push_back({blk.offset + nodes[a], f, blk.junction[f][a]});
            }
        }
    }
    return rows;
}

// The junction part of psi^T dR/dm: rows whose wall SAT uses a junction normal nhat = s / |s|
// (s the sum of the members' outward metric vectors), differentiated through nhat only (the
// coloured part held nhat fixed).
void addJunctionPart(const flow::FlowMesh& fm, const std::vector<double>& metrics, const std::vector<double>& q,
                     const std::vector<double>& psi, const flow::ResidualOptions& o, std::vector<double>& gm) {
    if (!(o.terms & flow::kBoundarySat) || fm.wallJunctions.empty()) return;
    const std::vector<double> normals = flow::wallJunctionNormals(fm, metrics.data());
    std::vector<double> gn(normals.size(), 0.0);  // dL/dnhat per junction
    const flow::BoundaryFluxFn<C> flux = flow::boundaryFlux<C>(mesh::BoundaryKind::Wall, o.scheme);
    for (const JunctionRow& row : junctionRows(fm)) {
        const double* nh = &normals[3 * static_cast<std::size_t>(row.junction)];
        if (nh[0] == 0 && nh[1] == 0 && nh[2] == 0) continue;  // a corner: the node's own normal
        double nOut[3];
        flow::outwardNormal(&metrics[kMetricWidth * row.node], row.face, nOut);
        const C n[3] = {nOut[0], nOut[1], nOut[2]};
        C qn[kVars];
        for (int v = 0; v < kVars; ++v) qn[v] = q[kVars * row.node + v];
        for (int c = 0; c < 3; ++c) {
            C nhat[3] = {nh[0], nh[1], nh[2]};
            nhat[c] += C(0.0, kStep);
            C fstar[kVars];
            flux(qn, nullptr, n, nhat, o.freeStream, fstar);
            double s = 0;  // the SAT is 2 (F* - F_n), and F_n does not see nhat
            for (int v = 0; v < kVars; ++v) s += psi[kVars * row.node + v] * 2.0 * fstar[v].imag() / kStep;
            gn[3 * row.junction + c] += s;
        }
    }
    for (std::size_t j = 0; j < fm.wallJunctions.size(); ++j) {
        const double* nh = &normals[3 * j];
        if (nh[0] == 0 && nh[1] == 0 && nh[2] == 0) continue;
        const auto& members = fm.wallJunctions[j].members;
        double sum[3] = {0, 0, 0};
        for (const auto& mem : members) {
            double n[3];
            flow::outwardNormal(&metrics[kMetricWidth * mem[0]], static_cast<int>(mem[1]), n);
            for (int c = 0; c < 3; ++c) sum[c] += n[c];
        }
        const double len = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        // dL/ds = (I - nhat nhat^T) dL/dnhat / |s|
        const double* g = &gn[3 * j];
        const double dot = g[0] * nh[0] + g[1] * nh[1] + g[2] * nh[2];
        double gs[3];
        for (int c = 0; c < 3; ++c) gs[c] = (g[c] - dot * nh[c]) / len;
        for (const auto& mem : members) {
            const int f = static_cast<int>(mem[1]);
            const int d = flow::faceDirection(f);
            const double sign = flow::faceIsMax(f) ? 1.0 : -1.0;
            for (int c = 0; c < 3; ++c) gm[kMetricWidth * mem[0] + 3 * d + c] += sign * gs[c];
        }
    }
}

}  // namespace

std::vector<double> residualMetricGradient(const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                           const std::vector<double>& q, const std::vector<double>& psi,
                                           const flow::ResidualOptions& o) {
    return residualMetricGradients(fm, metrics, q, {psi}, o).front();
}

std::vector<std::vector<double>> residualMetricGradients(const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                                         const std::vector<double>& q,
                                                         const std::vector<std::vector<double>>& psis,
                                                         const flow::ResidualOptions& o) {
    const long N = fm.nodeCount;
    bool sizes = metrics.size() == static_cast<std::size_t>(kMetricWidth * N) && q.size() == static_cast<std::size_t>(kVars * N);
    for (const auto& psi : psis) sizes = sizes && psi.size() == q.size();
    if (!sizes) {
        throw Error("grid sensitivity: metrics, state and adjoint do not match the grid's " + std::to_string(N) +
                    " nodes");
    }
    const int radius = 2;  // the exact residual's star (flow::stencilRadius without lumping)
    const flow::StencilColouring col = flow::stencilColouring(radius);
    using D = flow::MetricDual;  // direction k: metric value k of the colour's nodes
    const std::vector<double> normalsReal =
        (o.terms & flow::kBoundarySat) ? flow::wallJunctionNormals(fm, metrics.data()) : std::vector<double>();
    const std::vector<D> normals(normalsReal.begin(), normalsReal.end());
    std::vector<std::vector<double>> gms(psis.size(), std::vector<double>(metrics.size(), 0.0));
    std::vector<D> md(metrics.size()), qd(q.begin(), q.end()), rd(q.size());
    for (int colour = 0; colour < col.count; ++colour) {
        forEachNode(fm, [&](const flow::FlowBlock&, long g, const std::array<int, 3>& idx) {
            const bool seeded = col.colour(idx[0], idx[1], idx[2]) == colour;
            for (int k = 0; k < kMetricWidth; ++k) {
                const double m = metrics[kMetricWidth * g + k];
                md[kMetricWidth * g + k] = seeded ? D::variable(m, k) : D(m);
            }
        });
        flow::residual(fm, md.data(), qd.data(), o, rd.data(), &normals);
        // Column g of this colour: the rows of its star see only it among this colour's nodes.
        forEachNode(fm, [&](const flow::FlowBlock& blk, long g, const std::array<int, 3>& idx) {
            if (col.colour(idx[0], idx[1], idx[2]) != colour) return;
            const long stride[3] = {1, blk.dims[0], static_cast<long>(blk.dims[0]) * blk.dims[1]};
            for (std::size_t p = 0; p < psis.size(); ++p) {
                const std::vector<double>& psi = psis[p];
                std::array<double, kMetricWidth> s{};
                auto addRow = [&](long row) {
                    for (int v = 0; v < kVars; ++v) {
                        const double w = psi[kVars * row + v];
                        const D& r = rd[kVars * row + v];
                        for (int k = 0; k < kMetricWidth; ++k) s[k] += w * r.d[k];
                    }
                };
                addRow(g);
                for (int d = 0; d < 3; ++d) {
                    for (int t = -radius; t <= radius; ++t) {
                        if (t == 0 || idx[d] + t < 0 || idx[d] + t >= blk.dims[d]) continue;
                        addRow(g + t * stride[d]);
                    }
                }
                for (int k = 0; k < kMetricWidth; ++k) gms[p][kMetricWidth * g + k] = s[k];
            }
        });
    }
    for (std::size_t p = 0; p < psis.size(); ++p) addJunctionPart(fm, metrics, q, psis[p], o, gms[p]);
    return gms;
}

std::vector<double> metricTranspose(const flow::FlowMesh& fm, const std::vector<double>& x,
                                    const std::vector<double>& gm) {
    return metricTransposes(fm, x, {gm}).front();
}

std::vector<std::vector<double>> metricTransposes(const flow::FlowMesh& fm, const std::vector<double>& x,
                                                  const std::vector<std::vector<double>>& gms) {
    const long N = fm.nodeCount;
    bool sizes = x.size() == static_cast<std::size_t>(3 * N);
    for (const auto& gm : gms) sizes = sizes && gm.size() == static_cast<std::size_t>(kMetricWidth * N);
    if (!sizes) {
        throw Error("grid sensitivity: coordinates or metric gradient do not match the grid's " + std::to_string(N) +
                    " nodes");
    }
    std::vector<std::vector<double>> gxs(gms.size(), std::vector<double>(x.size(), 0.0));
    using D = Dual<3>;  // direction c: coordinate c of the colour's nodes
    std::vector<D> xd(x.size()), md(kMetricWidth * static_cast<std::size_t>(N));
    auto colourOf = [](const std::array<int, 3>& idx) { return idx[0] % 3 + 3 * (idx[1] % 3) + 9 * (idx[2] % 3); };
    for (int colour = 0; colour < 27; ++colour) {
        forEachNode(fm, [&](const flow::FlowBlock&, long g, const std::array<int, 3>& idx) {
            const bool seeded = colourOf(idx) == colour;
            for (int c = 0; c < 3; ++c) xd[3 * g + c] = seeded ? D::variable(x[3 * g + c], c) : D(x[3 * g + c]);
        });
        flow::computeMetrics(fm, xd.data(), md.data());
        forEachNode(fm, [&](const flow::FlowBlock& blk, long g, const std::array<int, 3>& idx) {
            if (colourOf(idx) != colour) return;
            for (std::size_t p = 0; p < gms.size(); ++p) {
                const std::vector<double>& gm = gms[p];
                std::array<double, 3> s{};
                for (int dk = -1; dk <= 1; ++dk) {
                    const int k = idx[2] + dk;
                    if (k < 0 || k >= blk.dims[2]) continue;
                    for (int dj = -1; dj <= 1; ++dj) {
                        const int j = idx[1] + dj;
                        if (j < 0 || j >= blk.dims[1]) continue;
                        for (int di = -1; di <= 1; ++di) {
                            const int i = idx[0] + di;
                            if (i < 0 || i >= blk.dims[0]) continue;
                            const long n = blk.offset + i +
                                           static_cast<long>(blk.dims[0]) * (j + static_cast<long>(blk.dims[1]) * k);
                            for (int w = 0; w < kMetricWidth; ++w) {
                                const D& m = md[kMetricWidth * n + w];
                                for (int c = 0; c < 3; ++c) s[c] += gm[kMetricWidth * n + w] * m.d[c];
                            }
                        }
                    }
                }
                for (int c = 0; c < 3; ++c) gxs[p][3 * g + c] = s[c];
            }
        });
    }
    return gxs;
}

void addFunctionalGridGradient(Functional f, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                               const std::vector<double>& x, const std::vector<double>& q,
                               const flow::FreeStream& fs, const flow::ForceReference& ref,
                               std::vector<double>& gm, std::vector<double>& gx) {
    const std::vector<flow::WallNode> wall = flow::wallNodes(fm);
    for (std::size_t k = 0; k < wall.size(); ++k) {
        const flow::WallNode& w = wall[k];
        C qn[kVars];
        for (int v = 0; v < kVars; ++v) qn[v] = q[kVars * w.node + v];
        // 10 metric values, then 3 coordinates.
        for (int p = 0; p < kMetricWidth + 3; ++p) {
            C m[kMetricWidth], xn[3];
            for (int i = 0; i < kMetricWidth; ++i) m[i] = metrics[kMetricWidth * w.node + i];
            for (int i = 0; i < 3; ++i) xn[i] = x[3 * w.node + i];
            (p < kMetricWidth ? m[p] : xn[p - kMetricWidth]) += C(0.0, kStep);
            const double s = wallNodeShare<C>(f, w, k, m, xn, qn, fs, ref).imag();
            if (p < kMetricWidth) {
                gm[kMetricWidth * w.node + p] += s / kStep;
            } else {
                gx[3 * w.node + p - kMetricWidth] += s / kStep;
            }
        }
    }
}

std::vector<double> coordinateGradient(Functional f, const std::vector<double>& psi, const flow::FlowMesh& fm,
                                       const std::vector<double>& x, const std::vector<double>& metrics,
                                       const std::vector<double>& q, const flow::ResidualOptions& o,
                                       const flow::ForceReference& ref) {
    return coordinateGradients({f}, {psi}, fm, x, metrics, q, o, ref).front();
}

std::vector<std::vector<double>> coordinateGradients(const std::vector<Functional>& fs,
                                                     const std::vector<std::vector<double>>& psis,
                                                     const flow::FlowMesh& fm, const std::vector<double>& x,
                                                     const std::vector<double>& metrics, const std::vector<double>& q,
                                                     const flow::ResidualOptions& o, const flow::ForceReference& ref) {
    if (fs.size() != psis.size()) throw Error("grid sensitivity: one adjoint per functional");
    std::vector<std::vector<double>> gms = residualMetricGradients(fm, metrics, q, psis, o);
    std::vector<std::vector<double>> direct(fs.size(), std::vector<double>(x.size(), 0.0));
    for (std::size_t p = 0; p < fs.size(); ++p) {
        addFunctionalGridGradient(fs[p], fm, metrics, x, q, o.freeStream, ref, gms[p], direct[p]);
    }
    std::vector<std::vector<double>> gxs = metricTransposes(fm, x, gms);
    for (std::size_t p = 0; p < fs.size(); ++p) {
        for (std::size_t i = 0; i < x.size(); ++i) gxs[p][i] += direct[p][i];
    }
    return gxs;
}

}  // namespace aero::adjoint
