#include "mesh/MultiBlock.h"

#include <cmath>
#include <unordered_map>

#include "common/Error.h"
#include "nurbs/Basis.h"

namespace aero::mesh {

const char* boundaryName(BoundaryKind k) {
    switch (k) {
        case BoundaryKind::Wall:
            return "wall";
        case BoundaryKind::Farfield:
            return "farfield";
        case BoundaryKind::Symmetry:
            return "symmetry";
        case BoundaryKind::Interface:
            return "interface";
    }
    return "?";
}

BoundaryKind boundaryFromName(const std::string& name, const std::string& key) {
    for (BoundaryKind k : {BoundaryKind::Wall, BoundaryKind::Farfield, BoundaryKind::Symmetry,
                           BoundaryKind::Interface}) {
        if (name == boundaryName(k)) return k;
    }
    throw CaseError(key + ": unknown boundary condition '" + name +
                    "' (expected wall, farfield, symmetry or interface)");
}

std::vector<std::array<bool, 6>> wallFaces(const MultiBlockMesh& m) {
    std::vector<std::array<bool, 6>> w(m.blocks.size());
    for (std::size_t b = 0; b < w.size(); ++b) {
        for (int f = 0; f < 6; ++f) w[b][f] = m.blocks[b].faces[f].kind == BoundaryKind::Wall;
    }
    return w;
}

long MultiBlockMesh::gridNodeCount() const {
    long n = 0;
    for (const auto& b : blocks) {
        const auto d = b.gridDims();
        n += static_cast<long>(d[0]) * d[1] * d[2];
    }
    return n;
}

nurbs::Volume<double> blockVolume(const MultiBlockMesh& m, int block) {
    const ControlBlock& b = m.blocks[block];
    nurbs::Volume<double> v;
    v.degree = b.degree;
    v.count = b.count;
    v.knots = b.knots;
    v.points.resize(3 * b.nodes.size());
    for (std::size_t a = 0; a < b.nodes.size(); ++a) {
        for (int c = 0; c < 3; ++c)
            v.points[3 * a + c] = m.control[3 * static_cast<std::size_t>(b.nodes[a]) + c];
    }
    return v;
}

void regenerate(const MultiBlockMesh& m, int block, StructuredGrid& out) {
    const ControlBlock& b = m.blocks[block];
    out.name = b.name;
    out.dims = b.gridDims();
    out.xyz.resize(3 * static_cast<std::size_t>(out.nodeCount()));
    nurbs::sampleGrid(blockVolume(m, block), b.samples[0], b.samples[1], b.samples[2],
                      out.xyz.data());
}

void regenerateAll(const MultiBlockMesh& m, std::vector<StructuredGrid>& grids) {
    grids.resize(m.blocks.size());
    for (std::size_t b = 0; b < m.blocks.size(); ++b) regenerate(m, static_cast<int>(b), grids[b]);
    for (const NodePair& p : m.interfaceNodes) {
        const double* src = &grids[p.blockA].xyz[3 * p.nodeA];
        double* dst = &grids[p.blockB].xyz[3 * p.nodeB];
        dst[0] = src[0];
        dst[1] = src[1];
        dst[2] = src[2];
    }
}

void regenerateTranspose(const MultiBlockMesh& m, int block, const double* gridGradient,
                         std::vector<double>& controlGradient) {
    const ControlBlock& b = m.blocks[block];
    const std::array<int, 3> dims = b.gridDims();
    // Basis rows per direction: first control index and p+1 values of every sample.
    std::array<std::vector<int>, 3> first;
    std::array<std::vector<double>, 3> values;
    for (int d = 0; d < 3; ++d) {
        const int p = b.degree[d];
        first[d].resize(dims[d]);
        values[d].resize(static_cast<std::size_t>(dims[d]) * (p + 1));
        for (int s = 0; s < dims[d]; ++s) {
            const double u = b.samples[d][s];
            const int span = nurbs::findSpan(b.knots[d], p, b.count[d], u);
            nurbs::basisFunctions(b.knots[d], p, span, u, &values[d][static_cast<std::size_t>(s) * (p + 1)]);
            first[d][s] = span - p;
        }
    }
    const int n0 = b.count[0], n1 = b.count[1], n2 = b.count[2];
    // g1[k][j][a] = sum_i N_a(xi_i) g[k][j][i]
    std::vector<double> g1(3 * static_cast<std::size_t>(n0) * dims[1] * dims[2], 0.0);
    const int p0 = b.degree[0], p1 = b.degree[1], p2 = b.degree[2];
#pragma omp parallel for schedule(static)
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            double* out = &g1[3 * (static_cast<std::size_t>(k) * dims[1] + j) * n0];
            for (int i = 0; i < dims[0]; ++i) {
                const double* g = gridGradient + 3 * (i + static_cast<long>(dims[0]) * (j + static_cast<long>(dims[1]) * k));
                for (int t = 0; t <= p0; ++t) {
                    const double w = values[0][static_cast<std::size_t>(i) * (p0 + 1) + t];
                    const int a = first[0][i] + t;
                    for (int c = 0; c < 3; ++c) out[3 * a + c] += w * g[c];
                }
            }
        }
    }
    // g2[k][bj][a] = sum_j N_bj(eta_j) g1[k][j][a]
    std::vector<double> g2(3 * static_cast<std::size_t>(n0) * n1 * dims[2], 0.0);
#pragma omp parallel for schedule(static)
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            const double* in = &g1[3 * (static_cast<std::size_t>(k) * dims[1] + j) * n0];
            for (int t = 0; t <= p1; ++t) {
                const double w = values[1][static_cast<std::size_t>(j) * (p1 + 1) + t];
                double* out = &g2[3 * (static_cast<std::size_t>(k) * n1 + first[1][j] + t) * n0];
                for (int e = 0; e < 3 * n0; ++e) out[e] += w * in[e];
            }
        }
    }
    // control[c][bj][a] += sum_k N_c(zeta_k) g2[k][bj][a]
    const std::size_t plane = 3 * static_cast<std::size_t>(n0) * n1;
    std::vector<double> g3(plane * n2, 0.0);
    for (int k = 0; k < dims[2]; ++k) {
        const double* in = &g2[plane * k];
        for (int t = 0; t <= p2; ++t) {
            const double w = values[2][static_cast<std::size_t>(k) * (p2 + 1) + t];
            double* out = &g3[plane * (first[2][k] + t)];
            for (std::size_t e = 0; e < plane; ++e) out[e] += w * in[e];
        }
    }
    for (std::size_t a = 0; a < b.nodes.size(); ++a) {
        for (int c = 0; c < 3; ++c) controlGradient[3 * static_cast<std::size_t>(b.nodes[a]) + c] += g3[3 * a + c];
    }
}

std::vector<StructuredGrid> regenerateAll(const MultiBlockMesh& m) {
    std::vector<StructuredGrid> g;
    regenerateAll(m, g);
    return g;
}

namespace {

// Node indices of one face of a grid, in face order.
std::vector<long> faceNodes(const StructuredGrid& g, int face) {
    std::vector<long> out;
    const int d = face / 2;
    const int fixed = (face % 2 == 0) ? 0 : g.dims[d] - 1;
    const int a = (d + 1) % 3, b = (d + 2) % 3;
    for (int t = 0; t < g.dims[b]; ++t) {
        for (int s = 0; s < g.dims[a]; ++s) {
            int ijk[3];
            ijk[d] = fixed;
            ijk[a] = s;
            ijk[b] = t;
            out.push_back(g.node(ijk[0], ijk[1], ijk[2]));
        }
    }
    return out;
}

}  // namespace

void matchInterfaces(MultiBlockMesh& m, const std::vector<StructuredGrid>& grids,
                     double tolerance) {
    m.interfaceNodes.clear();
    const double h = 4 * tolerance;
    auto key = [h](const double* x) {
        const long long i = static_cast<long long>(std::floor(x[0] / h)),
                        j = static_cast<long long>(std::floor(x[1] / h)),
                        k = static_cast<long long>(std::floor(x[2] / h));
        return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
    };
    for (std::size_t b = 0; b < m.blocks.size(); ++b) {
        for (int f = 0; f < 6; ++f) {
            const FaceBoundary& fb = m.blocks[b].faces[f];
            if (fb.kind != BoundaryKind::Interface || fb.neighbour < static_cast<int>(b))
                continue;  // each pair once
            if (fb.neighbour == static_cast<int>(b) && fb.neighbourFace < f) continue;
            const StructuredGrid& ga = grids[b];
            const StructuredGrid& gb = grids[fb.neighbour];
            const std::vector<long> na = faceNodes(ga, f), nb = faceNodes(gb, fb.neighbourFace);
            std::unordered_multimap<long long, long> hash;
            for (long n : nb) hash.emplace(key(&gb.xyz[3 * n]), n);
            long missing = 0;
            for (long n : na) {
                const double* x = &ga.xyz[3 * n];
                long found = -1;
                const long long ci = static_cast<long long>(std::floor(x[0] / h)),
                                cj = static_cast<long long>(std::floor(x[1] / h)),
                                ck = static_cast<long long>(std::floor(x[2] / h));
                for (int di = -1; di <= 1 && found < 0; ++di) {
                    for (int dj = -1; dj <= 1 && found < 0; ++dj) {
                        for (int dk = -1; dk <= 1 && found < 0; ++dk) {
                            const double y[3] = {(ci + di + 0.5) * h, (cj + dj + 0.5) * h,
                                                 (ck + dk + 0.5) * h};
                            auto range = hash.equal_range(key(y));
                            for (auto it = range.first; it != range.second; ++it) {
                                const double* z = &gb.xyz[3 * it->second];
                                if (std::abs(z[0] - x[0]) <= tolerance &&
                                    std::abs(z[1] - x[1]) <= tolerance &&
                                    std::abs(z[2] - x[2]) <= tolerance) {
                                    found = it->second;
                                    break;
                                }
                            }
                        }
                    }
                }
                if (found < 0) {
                    ++missing;
                } else {
                    m.interfaceNodes.push_back({static_cast<int>(b), n, fb.neighbour, found});
                }
            }
            if (missing > 0 || na.size() != nb.size()) {
                throw GeometryError(
                    "mismatched interface between block " + std::to_string(b + 1) + " ('" +
                    m.blocks[b].name + "') face " + std::to_string(f) + " and block " +
                    std::to_string(fb.neighbour + 1) + " ('" + m.blocks[fb.neighbour].name +
                    "') face " + std::to_string(fb.neighbourFace) + ": " + std::to_string(missing) +
                    " of " + std::to_string(na.size()) + " nodes have no coincident partner (" +
                    std::to_string(nb.size()) + " on the other side)");
            }
        }
    }
}

void validate(const MultiBlockMesh& m) {
    const int n = m.controlCount();
    for (std::size_t b = 0; b < m.blocks.size(); ++b) {
        const ControlBlock& cb = m.blocks[b];
        const std::string where = "block " + std::to_string(b + 1) + " ('" + cb.name + "')";
        if (cb.nodes.size() != static_cast<std::size_t>(cb.count[0]) * cb.count[1] * cb.count[2]) {
            throw GeometryError(where + ": " + std::to_string(cb.nodes.size()) +
                                " control nodes for a " + std::to_string(cb.count[0]) + "x" +
                                std::to_string(cb.count[1]) + "x" + std::to_string(cb.count[2]) +
                                " net");
        }
        for (int node : cb.nodes) {
            if (node < 0 || node >= n)
                throw GeometryError(where + ": control node " + std::to_string(node) +
                                    " does not exist");
        }
        nurbs::validate(blockVolume(m, static_cast<int>(b)), where);
        for (int f = 0; f < 6; ++f) {
            const FaceBoundary& fb = cb.faces[f];
            if (fb.kind != BoundaryKind::Interface) continue;
            if (fb.neighbour < 0 || fb.neighbour >= static_cast<int>(m.blocks.size()) ||
                fb.neighbourFace < 0 || fb.neighbourFace > 5) {
                throw GeometryError(where + " face " + std::to_string(f) +
                                    ": interface to a block or face that does not exist");
            }
            const FaceBoundary& back = m.blocks[fb.neighbour].faces[fb.neighbourFace];
            if (back.kind != BoundaryKind::Interface || back.neighbour != static_cast<int>(b) ||
                back.neighbourFace != f) {
                throw GeometryError(where + " face " + std::to_string(f) +
                                    ": interface is not mutual (block " +
                                    std::to_string(fb.neighbour + 1) + " face " +
                                    std::to_string(fb.neighbourFace) + " does not point back)");
            }
        }
        for (int d = 0; d < 3; ++d) {
            if (cb.samples[d].size() < 2)
                throw GeometryError(where + ": fewer than 2 grid nodes in direction " +
                                    std::to_string(d));
        }
    }
}

}  // namespace aero::mesh
