#include "flow/Jacobian.h"

#include <algorithm>
#include <cmath>

#include "common/Error.h"
#include "flow/BlockView.h"
#include "flow/Dissipation.h"
#include "flow/Metrics.h"
#include "flow/Sbp.h"
#include "flow/bc/BoundaryFlux.h"

namespace aero::flow {

using cplx = std::complex<double>;

namespace {

constexpr double kStep = 1e-30;  // complex step

// Whether two star offsets of `radius` can reach one row: differences t e_d (|t| <= 2 radius) and
// s e_d - t e_e (d != e, 1 <= |s|, |t| <= radius).
bool colouringWorks(int P, int a, int b, int radius) {
    const int w[3] = {1, a, b};
    auto bad = [&](long value) { return ((value % P) + P) % P == 0; };
    for (int d = 0; d < 3; ++d) {
        for (int t = 1; t <= 2 * radius; ++t) {
            if (bad(static_cast<long>(t) * w[d])) return false;
        }
        for (int e = 0; e < 3; ++e) {
            if (e == d) continue;
            for (int s = -radius; s <= radius; ++s) {
                for (int t = -radius; t <= radius; ++t) {
                    if (s == 0 || t == 0) continue;
                    if (bad(static_cast<long>(s) * w[d] - static_cast<long>(t) * w[e])) return false;
                }
            }
        }
    }
    return true;
}

// d/dq and d/dqOther of the SAT 2 (F*(q, qOther, n, nhat) - F_n(q)) (5x5 row-major each).
void satJacobian(BoundaryFluxFn<cplx> flux, const double* q, const double* qOther, const double* n,
                 const double* nhat, const FreeStream& fs, double* dq, double* dOther) {
    const cplx nc[3] = {n[0], n[1], n[2]};
    const cplx nh[3] = {nhat[0], nhat[1], nhat[2]};
    for (int side = 0; side < (qOther ? 2 : 1); ++side) {
        double* out = side == 0 ? dq : dOther;
        for (int w = 0; w < kVars; ++w) {
            cplx a[kVars], b[kVars], fstar[kVars], fn[kVars];
            for (int v = 0; v < kVars; ++v) {
                a[v] = q[v];
                b[v] = qOther ? qOther[v] : 0.0;
            }
            (side == 0 ? a : b)[w] += cplx(0.0, kStep);
            flux(a, qOther ? b : nullptr, nc, nh, fs, fstar);
            normalFlux(a, nc, fs.gamma, fn);
            for (int v = 0; v < kVars; ++v) out[kBlock * v + w] = 2.0 * (fstar[v] - fn[v]).imag() / kStep;
        }
    }
}

void addBlock(BlockSparseMatrix& J, long row, long col, const double* b, double scale = 1.0) {
    const long idx = J.find(row, col);
    AERO_ASSERT(idx >= 0);  // checkPattern ran before
    double* a = J.block(idx);
    for (int e = 0; e < kBlockSize; ++e) a[e] += scale * b[e];
}

void addInterfaceBlocks(const FlowMesh& fm, const std::vector<double>& metrics, const double* q,
                        const FreeStream& fs, InviscidScheme scheme, BlockSparseMatrix& J) {
    const BoundaryFluxFn<cplx> flux = boundaryFlux<cplx>(mesh::BoundaryKind::Interface, scheme);
    for (const InterfacePatch& ip : fm.interfaces) {
        const long offA = fm.blocks[ip.blockA].offset, offB = fm.blocks[ip.blockB].offset;
        const long count = static_cast<long>(ip.nodes.size());
#pragma omp parallel for schedule(static) if (ip.blockA != ip.blockB)
        for (long p = 0; p < count; ++p) {
            const long na = offA + ip.nodes[p][0], nb = offB + ip.nodes[p][1];
            double n[3], dSelf[kBlockSize], dOther[kBlockSize];
            outwardNormal(&metrics[kMetricWidth * na], ip.faceA, n);
            satJacobian(flux, q + kVars * na, q + kVars * nb, n, n, fs, dSelf, dOther);
            addBlock(J, na, na, dSelf);
            addBlock(J, na, nb, dOther);
            outwardNormal(&metrics[kMetricWidth * nb], ip.faceB, n);
            satJacobian(flux, q + kVars * nb, q + kVars * na, n, n, fs, dSelf, dOther);
            addBlock(J, nb, nb, dSelf);
            addBlock(J, nb, na, dOther);
        }
    }
}

void checkPattern(const FlowMesh& fm, const BlockSparseMatrix& J, int radius) {
    // Rows must match, and the pattern must hold the widest row of the stencil (spot check on
    // the first interior node of every block plus every interface pair).
    if (J.rows != fm.nodeCount) {
        throw Error("flow: Jacobian pattern has " + std::to_string(J.rows) + " block rows for " +
                    std::to_string(fm.nodeCount) + " nodes");
    }
    for (const FlowBlock& blk : fm.blocks) {
        const long s[3] = {1, blk.dims[0], static_cast<long>(blk.dims[0]) * blk.dims[1]};
        for (int d = 0; d < 3; ++d) {
            if (blk.dims[d] > radius && J.find(blk.offset, blk.offset + radius * s[d]) < 0) {
                throw Error("flow: Jacobian pattern narrower than the stencil (radius " + std::to_string(radius) + ")");
            }
        }
    }
    for (const InterfacePatch& ip : fm.interfaces) {
        for (const auto& pr : ip.nodes) {
            if (J.find(fm.blocks[ip.blockA].offset + pr[0], fm.blocks[ip.blockB].offset + pr[1]) < 0) {
                throw Error("flow: Jacobian pattern lacks interface couplings");
            }
        }
    }
}

}  // namespace

StencilColouring stencilColouring(int radius) {
    for (int P = 1; P < 200; ++P) {
        for (int a = 0; a < P; ++a) {
            for (int b = 0; b < P; ++b) {
                if (colouringWorks(P, a, b, radius)) return {P, a, b};
            }
        }
    }
    throw Error("flow: no stencil colouring found");
}

int stencilRadius(const ResidualOptions& o) {
    return (o.lumpedDissipation && o.freezeCoefficients) || !(o.terms & kDissipation) ? 1 : 2;
}

BlockSparseMatrix jacobianPattern(const FlowMesh& fm, int radius) {
    std::vector<std::vector<long>> cols(fm.nodeCount);
    for (const FlowBlock& blk : fm.blocks) {
#pragma omp parallel for schedule(static)
        for (long n = 0; n < blk.nodeCount(); ++n) {
            const auto idx = nodeIndex(blk.dims, n);
            const BlockView<const double> view{nullptr, blk.dims, 1};
            std::vector<long>& row = cols[blk.offset + n];
            row.push_back(blk.offset + n);
            for (int d = 0; d < 3; ++d) {
                for (int t = -radius; t <= radius; ++t) {
                    if (t == 0 || idx[d] + t < 0 || idx[d] + t >= blk.dims[d]) continue;
                    row.push_back(blk.offset + n + t * view.stride(d));
                }
            }
        }
    }
    for (const InterfacePatch& ip : fm.interfaces) {
        const long offA = fm.blocks[ip.blockA].offset, offB = fm.blocks[ip.blockB].offset;
        for (const auto& pr : ip.nodes) {
            cols[offA + pr[0]].push_back(offB + pr[1]);
            cols[offB + pr[1]].push_back(offA + pr[0]);
        }
    }
    return makeBlockSparse(cols);
}

void assembleJacobian(const FlowMesh& fm, const std::vector<double>& metrics, const double* q,
                      const ResidualOptions& o, BlockSparseMatrix& J) {
    const int radius = stencilRadius(o);
    const StencilColouring col = stencilColouring(radius);
    checkPattern(fm, J, radius);
    J.setZero();
    const long N = fm.nodeCount;
    // Forward mode: the 5 state values of every node of colour c seeded as 5 directions (one
    // residual per colour instead of 5 complex ones).
    using D = StateDual;
    const std::vector<D> md(metrics.begin(), metrics.end());
    std::vector<D> qd(kVars * N), rd(kVars * N);
    ResidualOptions local = o;
    local.terms = o.terms & ~kInterfaceSat;
    for (int c = 0; c < col.count; ++c) {
        for (const FlowBlock& blk : fm.blocks) {
#pragma omp parallel for schedule(static)
            for (long n = 0; n < blk.nodeCount(); ++n) {
                const auto idx = nodeIndex(blk.dims, n);
                const bool seeded = col.colour(idx[0], idx[1], idx[2]) == c;
                const long g = kVars * (blk.offset + n);
                for (int w = 0; w < kVars; ++w) qd[g + w] = seeded ? D::variable(q[g + w], w) : D(q[g + w]);
            }
        }
        residual(fm, md.data(), qd.data(), local, rd.data());
        // Row r's entry of colour c is the one column of that colour in its stencil.
        for (const FlowBlock& blk : fm.blocks) {
            const BlockView<const double> view{nullptr, blk.dims, 1};
#pragma omp parallel for schedule(static)
            for (long n = 0; n < blk.nodeCount(); ++n) {
                const auto idx = nodeIndex(blk.dims, n);
                long column = -1;
                for (int d = 0; d < 3 && column < 0; ++d) {
                    for (int t = -radius; t <= radius; ++t) {
                        int j[3] = {idx[0], idx[1], idx[2]};
                        j[d] += t;
                        if (j[d] < 0 || j[d] >= blk.dims[d]) continue;
                        if (col.colour(j[0], j[1], j[2]) == c) {
                            column = n + t * view.stride(d);
                            break;
                        }
                    }
                }
                if (column < 0) continue;
                const long b = J.find(blk.offset + n, blk.offset + column);
                AERO_ASSERT(b >= 0);
                double* a = J.block(b);
                const D* r = &rd[kVars * (blk.offset + n)];
                for (int v = 0; v < kVars; ++v) {
                    for (int w = 0; w < kVars; ++w) a[kBlock * v + w] = r[v].d[w];
                }
            }
        }
    }
    if (o.terms & kInterfaceSat) addInterfaceBlocks(fm, metrics, q, o.freeStream, o.scheme, J);
}

void assembleApproximateJacobian(const FlowMesh& fm, const std::vector<double>& metrics,
                                 const double* q, const ResidualOptions& o, BlockSparseMatrix& J) {
    checkPattern(fm, J, 1);
    J.setZero();
    const FreeStream& fs = o.freeStream;
    const double gamma = fs.gamma;
    const std::vector<double> junctionNormals = wallJunctionNormals(fm, metrics.data());
    for (const FlowBlock& blk : fm.blocks) {
        const long N = blk.nodeCount();
        const BlockView<const double> qb{q + kVars * blk.offset, blk.dims, kVars};
        const BlockView<const double> mb{metrics.data() + kMetricWidth * blk.offset, blk.dims, kMetricWidth};
        // Cartesian flux Jacobians dF_c/dq (c = x, y, z) at every node (complex step of the
        // pointwise flux through the unit vectors): the Jacobian through any n is sum_c n_c A_c.
        std::vector<double> A;
        if (o.terms & kInviscid) {
            A.resize(3 * kBlockSize * static_cast<std::size_t>(N));
#pragma omp parallel for schedule(static)
            for (long n = 0; n < N; ++n) {
                for (int c = 0; c < 3; ++c) {
                    const cplx nc[3] = {c == 0 ? 1.0 : 0.0, c == 1 ? 1.0 : 0.0, c == 2 ? 1.0 : 0.0};
                    for (int w = 0; w < kVars; ++w) {
                        cplx qc[kVars], f[kVars];
                        for (int v = 0; v < kVars; ++v) qc[v] = qb.at(n)[v];
                        qc[w] += cplx(0.0, kStep);
                        normalFlux(qc, nc, gamma, f);
                        for (int v = 0; v < kVars; ++v) A[kBlockSize * (3 * n + c) + kBlock * v + w] = f[v].imag() / kStep;
                    }
                }
            }
        }
        DissipationFields<double> df;
        if (o.terms & kDissipation) dissipationFields(qb, mb, gamma, true, df, false);
#pragma omp parallel for schedule(static)
        for (long n = 0; n < N; ++n) {
            const auto idx = nodeIndex(blk.dims, n);
            const long row = blk.offset + n;
            for (int d = 0; d < 3; ++d) {
                const int len = blk.dims[d], a = idx[d];
                const long s = qb.stride(d);
                if (o.terms & kInviscid) {
                    // coef * dF_nv/dq at node col, nv = sum of the weights times metric vectors.
                    auto add = [&](long col, double coef, const double* nv) {
                        double blockJ[kBlockSize];
                        const double* Ac = &A[kBlockSize * 3 * col];
                        for (int e = 0; e < kBlockSize; ++e) {
                            blockJ[e] = coef * (nv[0] * Ac[e] + nv[1] * Ac[kBlockSize + e] + nv[2] * Ac[2 * kBlockSize + e]);
                        }
                        addBlock(J, row, blk.offset + col, blockJ);
                    };
                    const double* mn = mb.at(n) + 3 * d;
                    if (o.scheme == InviscidScheme::Central) {
                        if (a == 0) {
                            add(n, -1.0, mn);
                            add(n + s, 1.0, mb.at(n + s) + 3 * d);
                        } else if (a == len - 1) {
                            add(n, 1.0, mn);
                            add(n - s, -1.0, mb.at(n - s) + 3 * d);
                        } else {
                            add(n - s, -0.5, mb.at(n - s) + 3 * d);
                            add(n + s, 0.5, mb.at(n + s) + 3 * d);
                        }
                    } else {
                        // The flux-difference form linearized with F_ec ~ (F(q_i) + F(q_j))/2 through
                        // the averaged metric (exact at a uniform state, where dF_ec/dq_j = A_j / 2).
                        double diag[3] = {0, 0, 0};
                        if (a < len - 1) {
                            const double* mp = mb.at(n + s) + 3 * d;
                            const double w = a == 0 ? 2.0 : 1.0;
                            const double nav[3] = {0.5 * (mn[0] + mp[0]), 0.5 * (mn[1] + mp[1]), 0.5 * (mn[2] + mp[2])};
                            add(n + s, 0.5 * w, nav);
                            for (int c = 0; c < 3; ++c) diag[c] += 0.5 * w * nav[c];
                        } else {
                            for (int c = 0; c < 3; ++c) diag[c] += 2.0 * mn[c];
                        }
                        if (a > 0) {
                            const double* mm = mb.at(n - s) + 3 * d;
                            const double w = a == len - 1 ? 2.0 : 1.0;
                            const double nav[3] = {0.5 * (mn[0] + mm[0]), 0.5 * (mn[1] + mm[1]), 0.5 * (mn[2] + mm[2])};
                            add(n - s, -0.5 * w, nav);
                            for (int c = 0; c < 3; ++c) diag[c] -= 0.5 * w * nav[c];
                        } else {
                            for (int c = 0; c < 3; ++c) diag[c] -= 2.0 * mn[c];
                        }
                        add(n, 1.0, diag);
                    }
                }
                if (o.terms & kDissipation) {
                    const double hinv = 1.0 / sbpWeight(a, len);
                    const auto& lam = df.lambda[d];
                    const auto& nu = df.nu[d];
                    double I[kBlockSize] = {};
                    for (int v = 0; v < kVars; ++v) I[kBlock * v + v] = 1.0;
                    if (a > 0) {
                        const double e = hinv * eps2Lumped(lam[n - s], lam[n], nu[n - s], nu[n], o.dissipation);
                        addBlock(J, row, row, I, e);
                        addBlock(J, row, row - s, I, -e);
                    }
                    if (a < len - 1) {
                        const double e = hinv * eps2Lumped(lam[n], lam[n + s], nu[n], nu[n + s], o.dissipation);
                        addBlock(J, row, row, I, e);
                        addBlock(J, row, row + s, I, -e);
                    }
                }
            }
            if (o.terms & kBoundarySat) {
                for (int f = 0; f < 6; ++f) {
                    const mesh::BoundaryKind kind = blk.faces[f].kind;
                    if (kind == mesh::BoundaryKind::Interface || !onFace(blk.dims, n, f)) continue;
                    double nrm[3], nhat[3], dSelf[kBlockSize];
                    outwardNormal(mb.at(n), f, nrm);
                    surfaceNormal(blk, f, faceNodeIndex(blk.dims, f, n), nrm, junctionNormals, nhat);
                    satJacobian(boundaryFlux<cplx>(kind, o.scheme), qb.at(n), nullptr, nrm, nhat, fs, dSelf,
                                nullptr);
                    addBlock(J, row, row, dSelf);
                }
            }
        }
    }
    if (o.terms & kInterfaceSat) addInterfaceBlocks(fm, metrics, q, fs, o.scheme, J);
}

JacobianProduct::JacobianProduct(const FlowMesh& fm, const std::vector<double>& metrics,
                                 const ResidualOptions& o, ProductMode mode)
    : fm_(&fm), o_(o), mode_(mode), realMetrics_(&metrics), q_(kVars * fm.nodeCount) {
    const std::size_t n = q_.size();
    if (mode_ == ProductMode::ComplexStep) {
        metrics_.assign(metrics.begin(), metrics.end());
        qc_.resize(n);
        rc_.resize(n);
    } else {
        r_.resize(n);
        qp_.resize(n);
        rp_.resize(n);
    }
}

void JacobianProduct::setState(const double* q, const double* r) {
    std::copy(q, q + q_.size(), q_.begin());
    if (mode_ != ProductMode::Difference) return;
    if (r) {
        std::copy(r, r + r_.size(), r_.begin());
    } else {
        residual(*fm_, realMetrics_->data(), q_.data(), o_, r_.data());
    }
    double s = 0;
    for (double x : q_) s += x * x;
    qNorm_ = std::sqrt(s);
}

void JacobianProduct::mult(const double* v, double* out) const {
    const long n = static_cast<long>(q_.size());
    if (mode_ == ProductMode::Difference) {
        double s = 0;
        for (long i = 0; i < n; ++i) s += v[i] * v[i];
        if (s == 0) {
            std::fill(out, out + n, 0.0);
            return;
        }
        // h = sqrt(eps) sqrt(1 + ||q||) / ||v|| (the Walker-Pernice choice): on 98k nodes a
        // spread-out v moves each value by ~1e-9 of its size, a v on one node by ~5e-7, both
        // far from where truncation or round-off would matter at a GMRES tolerance of 0.05.
        const double h = 1.4901161193847656e-08 * std::sqrt(1.0 + qNorm_) / std::sqrt(s);
#pragma omp parallel for schedule(static)
        for (long i = 0; i < n; ++i) qp_[i] = q_[i] + h * v[i];
        residual(*fm_, realMetrics_->data(), qp_.data(), o_, rp_.data());
        const double inv = 1.0 / h;
#pragma omp parallel for schedule(static)
        for (long i = 0; i < n; ++i) out[i] = (rp_[i] - r_[i]) * inv;
        return;
    }
    double vmax = 0;
    for (long i = 0; i < n; ++i) vmax = std::max(vmax, std::abs(v[i]));
    if (vmax == 0) {
        std::fill(out, out + n, 0.0);
        return;
    }
    const double h = kStep / vmax;
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) qc_[i] = cplx(q_[i], h * v[i]);
    residual(*fm_, metrics_.data(), qc_.data(), o_, rc_.data());
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) out[i] = rc_[i].imag() / h;
}

void coordinateProduct(const FlowMesh& fm, const std::vector<double>& x, const double* q,
                       const double* v, const ResidualOptions& o, double* out) {
    const long N = fm.nodeCount;
    double vmax = 0;
    for (long i = 0; i < 3 * N; ++i) vmax = std::max(vmax, std::abs(v[i]));
    if (vmax == 0) {
        std::fill(out, out + kVars * N, 0.0);
        return;
    }
    const double h = kStep / vmax;
    std::vector<cplx> xc(3 * N), mc(kMetricWidth * N), qc(q, q + kVars * N), rc(kVars * N);
    for (long i = 0; i < 3 * N; ++i) xc[i] = cplx(x[i], h * v[i]);
    computeMetrics(fm, xc.data(), mc.data());
    residual(fm, mc.data(), qc.data(), o, rc.data());
    for (long i = 0; i < kVars * N; ++i) out[i] = rc[i].imag() / h;
}

}  // namespace aero::flow
