#include "flow/Residual.h"

#include <array>
#include <complex>

#include "flow/BlockView.h"
#include "flow/Metrics.h"
#include "flow/Sbp.h"
#include "flow/bc/BoundaryFlux.h"

namespace aero::flow {

namespace {

template <class T>
void inviscidTerm(const BlockView<const T>& q, const BlockView<const T>& m, double gamma,
                  const BlockView<T>& r) {
    const long N = q.nodeCount();
    std::vector<T> F(3 * kVars * static_cast<std::size_t>(N));
#pragma omp parallel for schedule(static)
    for (long n = 0; n < N; ++n) {
        for (int d = 0; d < 3; ++d) normalFlux(q.at(n), m.at(n) + 3 * d, gamma, &F[kVars * (d * N + n)]);
    }
    const std::array<int, 3> dims = q.dims;
#pragma omp parallel for schedule(static)
    for (int k = 0; k < dims[2]; ++k) {
        for (int j = 0; j < dims[1]; ++j) {
            for (int i = 0; i < dims[0]; ++i) {
                const int idx[3] = {i, j, k};
                const long n = q.node(i, j, k);
                T* rn = r.at(n);
                for (int d = 0; d < 3; ++d) {
                    const T* f = &F[kVars * (d * N + n)];
                    const long s = kVars * q.stride(d);
                    for (int v = 0; v < kVars; ++v) rn[v] += sbpDiff(f + v, s, idx[d], dims[d]);
                }
            }
        }
    }
}

// The entropy-conservative flux-difference form of the same SBP operator: per direction, the
// flux between neighbours i and i+1 is f = F_ec(q_i, q_i+1, (m_i + m_i+1)/2); node i gets
// (f_i+1/2 - f_i-1/2) / H_ii, with the SBP boundary flux F_n(q) at the ends (the SATs replace it).
// With F_ec(q, q, n) = F_n(q) and metrics that satisfy sum_d D_d m_d = 0 a uniform flow stays
// a steady state. Each face's flux is evaluated once (a first pass stores it at the face's lower
// node) and then added to one side and subtracted from the other: the two-point flux with its
// two logarithmic means is the residual's largest cost, and evaluating it from both sides did it
// twice. The values and the order of the sums per node are those of the two-sided form.
template <class T>
void entropyConservativeTerm(const BlockView<const T>& q, const BlockView<const T>& m, double gamma,
                             const BlockView<T>& r) {
    const std::array<int, 3> dims = q.dims;
    std::vector<T> faces(kVars * static_cast<std::size_t>(q.nodeCount()));
    for (int d = 0; d < 3; ++d) {
        const int len = dims[d];
        if (len < 2) continue;
        const long s = q.stride(d);
        // The flux through the face between node n and n + s, at faces[n].
#pragma omp parallel for schedule(static)
        for (int k = 0; k < dims[2]; ++k) {
            for (int j = 0; j < dims[1]; ++j) {
                for (int i = 0; i < dims[0]; ++i) {
                    const int idx[3] = {i, j, k};
                    if (idx[d] == len - 1) continue;
                    const long n = q.node(i, j, k);
                    const T* mn = m.at(n) + 3 * d;
                    const T* mp = m.at(n + s) + 3 * d;
                    const T nav[3] = {0.5 * (mn[0] + mp[0]), 0.5 * (mn[1] + mp[1]), 0.5 * (mn[2] + mp[2])};
                    entropyConservativeFlux(q.at(n), q.at(n + s), nav, gamma, &faces[kVars * n]);
                }
            }
        }
#pragma omp parallel for schedule(static)
        for (int k = 0; k < dims[2]; ++k) {
            for (int j = 0; j < dims[1]; ++j) {
                for (int i = 0; i < dims[0]; ++i) {
                    const int idx[3] = {i, j, k};
                    const int a = idx[d];
                    const long n = q.node(i, j, k);
                    T* rn = r.at(n);
                    T f[kVars];
                    const T* mn = m.at(n) + 3 * d;
                    if (a < len - 1) {
                        const T* fp = &faces[kVars * n];
                        const double w = a == 0 ? 2.0 : 1.0;
                        for (int v = 0; v < kVars; ++v) rn[v] += w * fp[v];
                    } else {
                        normalFlux(q.at(n), mn, gamma, f);
                        for (int v = 0; v < kVars; ++v) rn[v] += 2.0 * f[v];
                    }
                    if (a > 0) {
                        const T* fm = &faces[kVars * (n - s)];
                        const double w = a == len - 1 ? 2.0 : 1.0;
                        for (int v = 0; v < kVars; ++v) rn[v] -= w * fm[v];
                    } else {
                        normalFlux(q.at(n), mn, gamma, f);
                        for (int v = 0; v < kVars; ++v) rn[v] -= 2.0 * f[v];
                    }
                }
            }
        }
    }
}

// The SAT (F*(q, qOther, n, nhat) - F_n(q)) / H_n into inc; H_n = 1/2 at every face node.
template <class T>
void satIncrement(BoundaryFluxFn<T> flux, const T* q, const T* qOther, const T* n, const T* nhat,
                  const FreeStream& fs, T* inc) {
    T fstar[kVars], fn[kVars];
    flux(q, qOther, n, nhat, fs, fstar);
    normalFlux(q, n, fs.gamma, fn);
    for (int v = 0; v < kVars; ++v) inc[v] = 2.0 * (fstar[v] - fn[v]);
}

// The SAT added to rn.
template <class T>
void addSat(BoundaryFluxFn<T> flux, const T* q, const T* qOther, const T* n, const T* nhat,
            const FreeStream& fs, T* rn) {
    T inc[kVars];
    satIncrement(flux, q, qOther, n, nhat, fs, inc);
    for (int v = 0; v < kVars; ++v) rn[v] += inc[v];
}

template <class T>
void boundaryTerm(const FlowBlock& blk, const BlockView<const T>& q, const BlockView<const T>& m,
                  const FreeStream& fs, InviscidScheme scheme, const std::vector<T>& junctionNormals,
                  const BlockView<T>& r) {
    for (int f = 0; f < 6; ++f) {
        const mesh::BoundaryKind kind = blk.faces[f].kind;
        if (kind == mesh::BoundaryKind::Interface) continue;
        const BoundaryFluxFn<T> flux = boundaryFlux<T>(kind, scheme);
        const std::vector<long> nodes = faceNodes(blk.dims, f);
        const long count = static_cast<long>(nodes.size());
#pragma omp parallel for schedule(static)
        for (long a = 0; a < count; ++a) {
            const long node = nodes[a];
            T n[3], nhat[3];
            outwardNormal(m.at(node), f, n);
            surfaceNormal(blk, f, a, n, junctionNormals, nhat);
            addSat(flux, q.at(node), static_cast<const T*>(nullptr), n, nhat, fs, r.at(node));
        }
    }
}

// Every interface node pair's two SATs in one parallel loop over all patches, then added to r in
// patch order on one thread. A node on a block edge or corner lies in several patches, so the
// patches cannot be summed in parallel; a parallel loop per patch instead woke the thread team
// once per patch (36 times per residual on the 20-block half-sphere: with passive OpenMP waiting
// three quarters of the flow solve's context switches). The increments and the order of the sums
// are those of adding each SAT where it is computed.
template <class T>
void interfaceTerm(const FlowMesh& fm, const T* metrics, const T* q, const FreeStream& fs,
                   InviscidScheme scheme, T* r) {
    const BoundaryFluxFn<T> flux = boundaryFlux<T>(mesh::BoundaryKind::Interface, scheme);
    const long patches = static_cast<long>(fm.interfaces.size());
    std::vector<long> first(patches + 1, 0);
    for (long p = 0; p < patches; ++p) first[p + 1] = first[p] + static_cast<long>(fm.interfaces[p].nodes.size());
    const long pairs = first[patches];
    thread_local std::vector<T> increments;
    increments.resize(2 * kVars * static_cast<std::size_t>(pairs));
    T* inc = increments.data();
#pragma omp parallel for schedule(static)
    for (long p = 0; p < patches; ++p) {
        const InterfacePatch& ip = fm.interfaces[p];
        const long offA = fm.blocks[ip.blockA].offset, offB = fm.blocks[ip.blockB].offset;
        for (long a = first[p]; a < first[p + 1]; ++a) {
            const auto& pair = ip.nodes[a - first[p]];
            const long na = offA + pair[0], nb = offB + pair[1];
            T n[3];
            outwardNormal(metrics + kMetricWidth * na, ip.faceA, n);
            satIncrement(flux, q + kVars * na, q + kVars * nb, n, n, fs, inc + 2 * kVars * a);
            outwardNormal(metrics + kMetricWidth * nb, ip.faceB, n);
            satIncrement(flux, q + kVars * nb, q + kVars * na, n, n, fs, inc + 2 * kVars * a + kVars);
        }
    }
    for (long p = 0; p < patches; ++p) {
        const InterfacePatch& ip = fm.interfaces[p];
        const long offA = fm.blocks[ip.blockA].offset, offB = fm.blocks[ip.blockB].offset;
        for (long a = first[p]; a < first[p + 1]; ++a) {
            const auto& pair = ip.nodes[a - first[p]];
            T* ra = r + kVars * (offA + pair[0]);
            T* rb = r + kVars * (offB + pair[1]);
            const T* ia = inc + 2 * kVars * a;
            for (int v = 0; v < kVars; ++v) ra[v] += ia[v];
            for (int v = 0; v < kVars; ++v) rb[v] += ia[kVars + v];
        }
    }
}

}  // namespace

template <class T>
std::vector<T> wallJunctionNormals(const FlowMesh& fm, const T* metrics) {
    using std::real;
    using std::sqrt;
    const double cos45 = 0.70710678118654752;
    std::vector<T> out(3 * fm.wallJunctions.size(), T(0.0));
    std::vector<std::array<T, 3>> normals;
    for (std::size_t j = 0; j < fm.wallJunctions.size(); ++j) {
        const auto& members = fm.wallJunctions[j].members;
        normals.resize(members.size());
        T sum[3] = {T(0.0), T(0.0), T(0.0)};
        for (std::size_t k = 0; k < members.size(); ++k) {
            outwardNormal(metrics + kMetricWidth * members[k][0], static_cast<int>(members[k][1]),
                          normals[k].data());
            for (int c = 0; c < 3; ++c) sum[c] += normals[k][c];
        }
        const T len = sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
        if (real(len) == 0.0) continue;
        bool corner = false;
        for (const auto& n : normals) {
            const double dot = real(n[0] * sum[0] + n[1] * sum[1] + n[2] * sum[2]);
            const double nl = std::sqrt(real(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]));
            corner = corner || dot < cos45 * nl * real(len);
        }
        if (corner) continue;
        for (int c = 0; c < 3; ++c) out[3 * j + c] = sum[c] / len;
    }
    return out;
}

template <class T>
void residual(const FlowMesh& fm, const T* metrics, const T* q, const ResidualOptions& o, T* r,
              const std::vector<T>* fixedJunctionNormals) {
    const double gamma = o.freeStream.gamma;
    std::fill(r, r + kVars * fm.nodeCount, T(0.0));
    // Blocks in parallel (each writes only its own nodes); the per-plane loops inside then run
    // on one thread. One parallel region per residual instead of several per block: with
    // passive OpenMP waiting every region costs a wake-up of the team.
    const std::vector<T> junctionNormals = !(o.terms & kBoundarySat) ? std::vector<T>()
                                           : fixedJunctionNormals    ? *fixedJunctionNormals
                                                                     : wallJunctionNormals(fm, metrics);
    const long nb = static_cast<long>(fm.blocks.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (long b = 0; b < nb; ++b) {
        const FlowBlock& blk = fm.blocks[b];
        const BlockView<const T> qb{q + kVars * blk.offset, blk.dims, kVars};
        const BlockView<const T> mb{metrics + kMetricWidth * blk.offset, blk.dims, kMetricWidth};
        const BlockView<T> rb{r + kVars * blk.offset, blk.dims, kVars};
        if (o.terms & kInviscid) {
            if (o.scheme == InviscidScheme::EntropyConservative) {
                entropyConservativeTerm(qb, mb, gamma, rb);
            } else {
                inviscidTerm(qb, mb, gamma, rb);
            }
        }
        if (o.terms & kDissipation) {
            addDissipation(qb, mb, o.dissipation, gamma, o.lumpedDissipation, o.freezeCoefficients,
                           rb);
        }
        if (o.terms & kBoundarySat) boundaryTerm(blk, qb, mb, o.freeStream, o.scheme, junctionNormals, rb);
    }
    if (o.terms & kInterfaceSat) interfaceTerm(fm, metrics, q, o.freeStream, o.scheme, r);
}

std::vector<double> alphaDerivative(const FlowMesh& fm, const std::vector<double>& metrics, const double* q,
                                    const ResidualOptions& o) {
    using cplx = std::complex<double>;
    std::vector<double> out(kVars * static_cast<std::size_t>(fm.nodeCount), 0.0);
    if (!(o.terms & kBoundarySat)) return out;
    const FreeStream& fs = o.freeStream;
    const auto s = fs.state();
    // d q_inf / d alpha (per radian): the velocity turns in the X-Z plane; rho and E stay.
    const double a = fs.alpha();
    const double w[kVars] = {0.0, -fs.mach * std::sin(a), 0.0, fs.mach * std::cos(a), 0.0};
    constexpr double h = 1e-30;
    const double perDegree = 3.14159265358979323846 / 180.0;
    cplx qinf[kVars];
    for (int v = 0; v < kVars; ++v) qinf[v] = cplx(s[v], h * w[v]);
    const long nb = static_cast<long>(fm.blocks.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (long b = 0; b < nb; ++b) {
        const FlowBlock& blk = fm.blocks[b];
        for (int f = 0; f < 6; ++f) {
            if (blk.faces[f].kind != mesh::BoundaryKind::Farfield) continue;
            for (long node : faceNodes(blk.dims, f)) {
                const long g = blk.offset + node;
                double nr[3];
                outwardNormal(&metrics[kMetricWidth * static_cast<std::size_t>(g)], f, nr);
                const cplx n[3] = {nr[0], nr[1], nr[2]};
                cplx qc[kVars], flux[kVars];
                for (int v = 0; v < kVars; ++v) qc[v] = q[kVars * g + v];
                // The SAT is 2 (F*(q, q_inf, n) - F_n(q)); F_n(q) does not depend on alpha.
                if (o.scheme == InviscidScheme::EntropyConservative) {
                    entropyUpwindFlux(qc, qinf, n, fs.gamma, flux);
                } else {
                    upwindFlux(qc, qinf, n, fs.gamma, flux);
                }
                for (int v = 0; v < kVars; ++v) out[kVars * g + v] += 2.0 * flux[v].imag() / h * perDegree;
            }
        }
    }
    return out;
}

std::vector<double> freeStreamState(const FlowMesh& fm, const FreeStream& fs) {
    const auto s = fs.state();
    std::vector<double> q(kVars * static_cast<std::size_t>(fm.nodeCount));
    for (long n = 0; n < fm.nodeCount; ++n) {
        for (int v = 0; v < kVars; ++v) q[kVars * n + v] = s[v];
    }
    return q;
}

#define AERO_INSTANTIATE(T)                                                                        \
    template std::vector<T> wallJunctionNormals<T>(const FlowMesh&, const T*);                     \
    template void residual<T>(const FlowMesh&, const T*, const T*, const ResidualOptions&, T*,     \
                              const std::vector<T>*);
AERO_FLOW_SCALARS(AERO_INSTANTIATE)
#undef AERO_INSTANTIATE

}  // namespace aero::flow
