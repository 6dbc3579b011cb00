#include "flow/Gmres.h"

#include "flow/ChunkedSum.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <new>
#include <numeric>
#include <type_traits>

namespace aero::flow {

namespace {

// Sums over long vectors are taken in fixed chunks of rows, the chunk sums added in chunk order
// by one thread: the same bits on any number of threads and in every run (an optimization that is
// resumed replays its history and must see the same iterates).
constexpr long kChunk = 2048;

long chunkCount(long n) { return (n + kChunk - 1) / kChunk; }

// partial[c * k + i] for chunk c -> out[i] (i < k), in chunk order.
void sumChunks(const std::vector<double>& partial, long chunks, int k, double* out) {
    for (int i = 0; i < k; ++i) out[i] = 0;
    for (long c = 0; c < chunks; ++c) {
        for (int i = 0; i < k; ++i) out[i] += partial[static_cast<std::size_t>(c * k + i)];
    }
}

double dot(long n, const double* a, const double* b, std::vector<double>& partial) {
    const long chunks = chunkCount(n);
    partial.assign(chunks, 0.0);
#pragma omp parallel for schedule(static)
    for (long c = 0; c < chunks; ++c) {
        const long end = std::min(n, (c + 1) * kChunk);
        double s = 0;
        for (long l = c * kChunk; l < end; ++l) s += a[l] * b[l];
        partial[c] = s;
    }
    double s = 0;
    sumChunks(partial, chunks, 1, &s);
    return s;
}

// Classical Gram-Schmidt against the k vectors V[0..k): h = V^T w, w -= V h, repeated once when
// the first pass cancelled most of w (the Daniel-Gragg-Kaufman-Stewart test: ||w|| fell below
// `below` of its length before; 1/sqrt(2): "twice is enough"). Returns ||w||. Each pass is one
// sweep over the basis for the dot products and one for the update, in fixed row chunks.
template <class B>
double orthogonalize(long n, const std::vector<B*>& V, int k, double* w, double* h, std::vector<double>& partial,
                     double below) {
    const long chunks = chunkCount(n);
    const int width = k + 1;  // k dot products and the squared norm
    partial.assign(static_cast<std::size_t>(chunks * width), 0.0);
    std::vector<double> g(width), total(k, 0.0);
    // The dot products, and ||w||^2 before the pass. Four dot products at a time: each is still
    // one sum in index order (the same bits), but the four chains of additions overlap instead
    // of each waiting for the last addition (a single chain is limited by the adder's latency,
    // not by memory), and w is read once for four.
    auto project = [&] {
#pragma omp parallel for schedule(static)
        for (long c = 0; c < chunks; ++c) {
            const long first = c * kChunk, end = std::min(n, first + kChunk);
            int i = 0;
            for (; i + 4 <= k; i += 4) {
                const B *v0 = V[i], *v1 = V[i + 1], *v2 = V[i + 2], *v3 = V[i + 3];
                double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
                for (long l = first; l < end; ++l) {
                    const double wl = w[l];
                    s0 += static_cast<double>(v0[l]) * wl;
                    s1 += static_cast<double>(v1[l]) * wl;
                    s2 += static_cast<double>(v2[l]) * wl;
                    s3 += static_cast<double>(v3[l]) * wl;
                }
                double* out = &partial[static_cast<std::size_t>(c * width + i)];
                out[0] = s0;
                out[1] = s1;
                out[2] = s2;
                out[3] = s3;
            }
            for (; i < k; ++i) {
                const B* v = V[i];
                double s = 0;
                for (long l = first; l < end; ++l) s += static_cast<double>(v[l]) * w[l];
                partial[static_cast<std::size_t>(c * width + i)] = s;
            }
            double s = 0;
            for (long l = first; l < end; ++l) s += w[l] * w[l];
            partial[static_cast<std::size_t>(c * width + k)] = s;
        }
        sumChunks(partial, chunks, width, g.data());
    };
    // w -= V g, and ||w||^2 after. Four vectors at a time, each value of w subtracted from in
    // the same order as one vector at a time (the same bits), kept in a register meanwhile.
    auto subtract = [&] {
#pragma omp parallel for schedule(static)
        for (long c = 0; c < chunks; ++c) {
            const long first = c * kChunk, end = std::min(n, first + kChunk);
            int i = 0;
            for (; i + 4 <= k; i += 4) {
                const B *v0 = V[i], *v1 = V[i + 1], *v2 = V[i + 2], *v3 = V[i + 3];
                const double g0 = g[i], g1 = g[i + 1], g2 = g[i + 2], g3 = g[i + 3];
                for (long l = first; l < end; ++l) {
                    double x = w[l];
                    x -= g0 * static_cast<double>(v0[l]);
                    x -= g1 * static_cast<double>(v1[l]);
                    x -= g2 * static_cast<double>(v2[l]);
                    x -= g3 * static_cast<double>(v3[l]);
                    w[l] = x;
                }
            }
            for (; i < k; ++i) {
                const B* v = V[i];
                const double gi = g[i];
                for (long l = first; l < end; ++l) w[l] -= gi * static_cast<double>(v[l]);
            }
            double s = 0;
            for (long l = first; l < end; ++l) s += w[l] * w[l];
            partial[static_cast<std::size_t>(c * width + k)] = s;
        }
        double s = 0;
        for (long c = 0; c < chunks; ++c) s += partial[static_cast<std::size_t>(c * width + k)];
        return s;
    };
    project();
    const double before = g[k];
    for (int i = 0; i < k; ++i) total[i] += g[i];
    double after = subtract();
    if (after < below * below * before) {  // ||w|| fell below `below` of its length: once more
        project();
        for (int i = 0; i < k; ++i) total[i] += g[i];
        after = subtract();
    }
    for (int i = 0; i < k; ++i) h[i] = total[i];
    return std::sqrt(after);
}

void scale(long n, double* v, double a) {
#pragma omp parallel for schedule(static)
    for (long l = 0; l < n; ++l) v[l] *= a;
}

// out = sum_i coef[i] V_i over the first `count` vectors (out may not alias a V_i).
template <class B>
void combine(long n, const std::vector<B*>& V, int count, const double* coef, double* out) {
#pragma omp parallel for schedule(static)
    for (long c = 0; c < chunkCount(n); ++c) {
        const long first = c * kChunk, end = std::min(n, first + kChunk);
        for (long l = first; l < end; ++l) out[l] = 0;
        for (int i = 0; i < count; ++i) {
            const B* v = V[i];
            const double a = coef[i];
            for (long l = first; l < end; ++l) out[l] += a * static_cast<double>(v[l]);
        }
    }
}

// V_i <- sum_j Q(j, i) V_j for i = 0..Q.cols()-1, over the first Q.rows() vectors, in place: row
// block by row block through a small buffer, so the new basis needs no second set of vectors
// (on the 903k-node grid that set was 21 vectors, 760 MB). Each value is summed in the same order
// as combine() would, so the result is the same to the bit.
template <class B>
void combineInPlace(long n, const std::vector<B*>& V, const Eigen::MatrixXd& Q) {
    const int rows = static_cast<int>(Q.rows()), cols = static_cast<int>(Q.cols());
#pragma omp parallel
    {
        std::vector<double> buffer(static_cast<std::size_t>(cols) * kChunk);
#pragma omp for schedule(static)
        for (long c = 0; c < chunkCount(n); ++c) {
            const long first = c * kChunk, end = std::min(n, first + kChunk), len = end - first;
            for (int i = 0; i < cols; ++i) {
                double* out = &buffer[static_cast<std::size_t>(i) * kChunk];
                for (long l = 0; l < len; ++l) out[l] = 0;
                for (int j = 0; j < rows; ++j) {
                    const B* v = V[j] + first;
                    const double a = Q(j, i);
                    for (long l = 0; l < len; ++l) out[l] += a * static_cast<double>(v[l]);
                }
            }
            for (int i = 0; i < cols; ++i) {
                const double* in = &buffer[static_cast<std::size_t>(i) * kChunk];
                B* out = V[i] + first;
                for (long l = 0; l < len; ++l) out[l] = static_cast<B>(in[l]);
            }
        }
    }
}

// The harmonic Ritz vectors of the `want` harmonic Ritz values of smallest modulus of the
// (m+1) x m Arnoldi matrix Hbar, as real columns (a complex pair as its real and imaginary parts,
// kept together), m rows each. Empty when H_m is singular.
Eigen::MatrixXd harmonicRitzVectors(const Eigen::MatrixXd& Hbar, int m, int want) {
    const Eigen::MatrixXd Hm = Hbar.topLeftCorner(m, m);
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(Hm.transpose());
    if (!(std::abs(lu.determinant()) > 0)) return {};
    // Harmonic Ritz pairs: (H_m + H_m^-T r^T r) g = theta g, r the last row of Hbar.
    const Eigen::RowVectorXd r = Hbar.row(m);
    const Eigen::VectorXd f = lu.solve(r.transpose());
    const Eigen::MatrixXd G = Hm + f * r;
    Eigen::EigenSolver<Eigen::MatrixXd> es(G);
    if (es.info() != Eigen::Success) return {};
    const Eigen::VectorXcd theta = es.eigenvalues();
    std::vector<int> idx(m);
    std::iota(idx.begin(), idx.end(), 0);
    std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return std::abs(theta[a]) < std::abs(theta[b]); });
    std::vector<Eigen::VectorXd> cols;
    std::vector<bool> used(m, false);
    for (int t = 0; t < m && static_cast<int>(cols.size()) < want; ++t) {
        const int i = idx[t];
        if (used[i]) continue;
        used[i] = true;
        const Eigen::VectorXcd g = es.eigenvectors().col(i);
        if (std::abs(theta[i].imag()) <= 1e-14 * std::abs(theta[i])) {
            cols.push_back(g.real());
            continue;
        }
        // A complex pair: both parts, or neither when they do not fit.
        if (static_cast<int>(cols.size()) + 2 > want) break;
        for (int u = 0; u < m; ++u) {
            if (!used[u] && std::abs(theta[u] - std::conj(theta[i])) <= 1e-12 * std::abs(theta[i])) {
                used[u] = true;
                break;
            }
        }
        cols.push_back(g.real());
        cols.push_back(g.imag());
    }
    Eigen::MatrixXd P(m, static_cast<Eigen::Index>(cols.size()));
    for (std::size_t c = 0; c < cols.size(); ++c) P.col(static_cast<Eigen::Index>(c)) = cols[c];
    return P;
}

}  // namespace

double chunkedDot(long n, const double* a, const double* b) {
    std::vector<double> partial;
    return dot(n, a, b, partial);
}

void GmresWorkspace::reserve(long n, int vectors, int singleVectors) {
    if (n != n_) {
        freeVectors();  // (lent storage stays lent for the new size)
        n_ = n;
        stride_ = (static_cast<std::size_t>(n) + 15) / 16 * 16;
    }
    // Freed before the new size is allocated, so the peak is the larger of the two.
    if (vectors > vectors_) {
        basis_.reset();
        basis_.reset(new double[stride_ * static_cast<std::size_t>(vectors)]);
        vectors_ = vectors;
    }
    if (singleVectors > singleVectors_) {
        single_.reset();
        const std::size_t count = stride_ * static_cast<std::size_t>(singleVectors);
        if (lent_ && count * sizeof(float) <= lentBytes_) {
            singleData_ = ::new (lent_) float[count];  // (no initialization, as below)
        } else {
            single_.reset(new float[count]);
            singleData_ = single_.get();
        }
        singleVectors_ = singleVectors;
    }
}

void GmresWorkspace::lend(void* storage, std::size_t bytes) {
    single_.reset();
    singleData_ = nullptr;
    singleVectors_ = 0;
    lent_ = storage;
    lentBytes_ = storage ? bytes : 0;
}

std::size_t GmresWorkspace::singleBytes(long n, int singleVectors) {
    return (static_cast<std::size_t>(n) + 15) / 16 * 16 * static_cast<std::size_t>(singleVectors) * sizeof(float);
}

void GmresWorkspace::freeVectors() {
    basis_.reset();
    single_.reset();
    singleData_ = nullptr;
    n_ = 0;
    stride_ = 0;
    vectors_ = singleVectors_ = 0;
}

void GmresWorkspace::release() {
    freeVectors();
    lent_ = nullptr;
    lentBytes_ = 0;
}

namespace {

// Basis vector i of type B: the workspace's double vector i, or its float vector i.
template <class B>
B* basisVector(GmresWorkspace& ws, int i) {
    if constexpr (std::is_same_v<B, double>) {
        return ws.vector(i);
    } else {
        return ws.singleVector(i);
    }
}

template <class B>
GmresReport gmresWith(long n, const LinearMap& A, const LinearMap& M, const double* b, double* x,
                      const GmresOptions& o, GmresWorkspace* workspace) {
    constexpr bool kDouble = std::is_same_v<B, double>;
    GmresReport rep;
    const int m = std::max(1, o.restart);
    const int deflation = std::clamp(o.deflation, 0, std::max(0, m - 2));
    std::vector<double> partial;
    const double bnorm = std::sqrt(dot(n, b, b, partial));
    if (bnorm == 0) {
        std::fill(x, x + n, 0.0);
        rep.relativeResidual = 0;
        rep.converged = true;
        return rep;
    }
    GmresWorkspace local;
    GmresWorkspace& ws = workspace ? *workspace : local;
    // m + 1 basis vectors, z, and with deflation one scratch vector for the update of x (V[m]
    // must survive it: the deflated restart's new basis is built from all m + 1). A float basis
    // needs two double work vectors besides: w, the new Arnoldi vector before it is stored, and
    // the scratch (w is free when x is updated).
    ws.reserve(n, kDouble ? m + 2 + (deflation > 0 ? 1 : 0) : 3, kDouble ? 0 : m + 1);
    std::vector<B*> V(m + 1);
    for (int i = 0; i <= m; ++i) V[i] = basisVector<B>(ws, i);
    double* z = kDouble ? ws.vector(m + 1) : ws.vector(0);
    double* w = kDouble ? nullptr : ws.vector(1);
    double* scratch = kDouble ? (deflation > 0 ? ws.vector(m + 2) : ws.vector(m)) : ws.vector(2);
    // v -> double (in `to`) and double -> v (float basis only).
    auto widen = [n](const B* v, double* to) {
#pragma omp parallel for schedule(static)
        for (long l = 0; l < n; ++l) to[l] = static_cast<double>(v[l]);
    };
    auto store = [n](const double* from, double a, B* v) {
#pragma omp parallel for schedule(static)
        for (long l = 0; l < n; ++l) v[l] = static_cast<B>(a * from[l]);
    };

    Eigen::MatrixXd Hbar = Eigen::MatrixXd::Zero(m + 1, m);
    Eigen::VectorXd c = Eigen::VectorXd::Zero(m + 1), y;
    std::vector<double> h(m + 1);
    int kept = 0;           // basis vectors carried over a deflated restart (Hbar's first columns)
    bool fresh = true;      // start the next cycle from the true residual
    bool useDeflation = deflation > 0;
    bool deflated = false;  // a deflated restart happened since the last true residual
    // A zero initial guess (every Newton step's) needs no product for its residual: r = b. On
    // the flow's exact systems a product is a complex residual evaluation, as dear as a GMRES
    // iteration's.
    bool zeroGuess = std::all_of(x, x + n, [](double v) { return v == 0.0; });
    while (rep.iterations < o.maxIterations) {
        if (fresh) {
            // r = b - A x
            double* r = w;  // a float basis: r in the double work vector, stored scaled in V[0]
            if constexpr (kDouble) r = V[0];
            if (zeroGuess) {
#pragma omp parallel for schedule(static)
                for (long i = 0; i < n; ++i) r[i] = b[i];
                zeroGuess = false;
            } else {
                A(x, r);
#pragma omp parallel for schedule(static)
                for (long i = 0; i < n; ++i) r[i] = b[i] - r[i];
            }
            const double beta = std::sqrt(dot(n, r, r, partial));
            rep.relativeResidual = beta / bnorm;
            if (rep.relativeResidual <= o.tolerance) {
                rep.converged = true;
                return rep;
            }
            if constexpr (kDouble) {
                scale(n, r, 1.0 / beta);
            } else {
                store(r, 1.0 / beta, V[0]);
            }
            deflated = false;
            Hbar.setZero();
            c.setZero();
            c[0] = beta;
            kept = 0;
        }
        int j = kept;
        Eigen::HouseholderQR<Eigen::MatrixXd> qr;
        for (; j < m && rep.iterations < o.maxIterations; ++j) {
            ++rep.iterations;
            double hn = 0;
            if constexpr (kDouble) {
                if (M) {
                    M(V[j], z);
                    A(z, V[j + 1]);
                } else {
                    A(V[j], V[j + 1]);
                }
                hn = orthogonalize(n, V, j + 1, V[j + 1], h.data(), partial, o.reorthogonalizeBelow);
                if (hn > 0) scale(n, V[j + 1], 1.0 / hn);
            } else {
                widen(V[j], w);
                if (M) {
                    M(w, z);
                    A(z, w);
                } else {
                    A(w, z);
                    std::swap(w, z);
                }
                hn = orthogonalize(n, V, j + 1, w, h.data(), partial, o.reorthogonalizeBelow);
                store(w, hn > 0 ? 1.0 / hn : 0.0, V[j + 1]);
            }
            for (int i = 0; i <= j; ++i) Hbar(i, j) = h[i];
            Hbar(j + 1, j) = hn;
            // min || c - Hbar y || over the first j + 1 columns: its residual is the last entry
            // of Q^T c (no cancellation, unlike forming c - Hbar y).
            qr.compute(Hbar.topLeftCorner(j + 2, j + 1));
            const Eigen::VectorXd qc = qr.householderQ().transpose() * c.head(j + 2);
            rep.relativeResidual = std::abs(qc[j + 1]) / bnorm;
            if (!std::isfinite(rep.relativeResidual)) return rep;
            // Converged, or a happy breakdown (the Krylov space is invariant: the solution is in it).
            if (rep.relativeResidual <= o.tolerance || hn == 0) {
                ++j;
                break;
            }
        }
        if (j == kept) return rep;  // no new column (iteration limit)
        // y of the last least-squares problem; x += M^-1 (V y).
        y = qr.solve(c.head(j + 1));
        combine(n, V, j, y.data(), z);
        if (M) {
            M(z, scratch);
#pragma omp parallel for schedule(static)
            for (long l = 0; l < n; ++l) x[l] += scratch[l];
        } else {
#pragma omp parallel for schedule(static)
            for (long l = 0; l < n; ++l) x[l] += z[l];
        }
        // (Without deflation V[m] was the scratch: harmless, it is rebuilt or the cycle ends.)
        if (rep.relativeResidual <= o.tolerance) {
            if (!deflated && kDouble) {
                rep.converged = true;
                return rep;
            }
            // After deflated restarts the estimate is the small problem's, carried over cycles
            // whose Arnoldi relations hold only to round-off times their conditioning; with a
            // float basis they hold only to float round-off times the conditioning (a grid
            // system's estimate said 1e-12 where the truth was 6e-8): check the true residual
            // and, if it is off, go on with restarts from it (plain ones after deflated cycles).
            A(x, z);
#pragma omp parallel for schedule(static)
            for (long l = 0; l < n; ++l) z[l] = b[l] - z[l];
            const double truth = std::sqrt(dot(n, z, z, partial)) / bnorm;
            if (truth <= 10 * o.tolerance) {
                rep.relativeResidual = truth;
                rep.converged = true;
                return rep;
            }
            if (deflated) useDeflation = false;
            deflated = false;
        }
        if (o.hopeless > 0 && rep.iterations < o.maxIterations) {
            const double rate = std::log(std::max(rep.relativeResidual, 1e-300)) / rep.iterations;
            if (std::exp(rate * o.maxIterations) > o.hopeless) {
                rep.gaveUp = true;
                return rep;
            }
        }
        if (rep.iterations >= o.maxIterations) return rep;
        fresh = true;
        if (useDeflation && j == m && Hbar(m, m - 1) > 0) {
            // GMRES-DR: the new basis is V_{m+1} Q, Q the orthonormalized [harmonic Ritz vectors,
            // the residual's coefficients], so that A M^-1 V_new(:, 0..k) = V_new Hbar_new.
            const Eigen::MatrixXd P = harmonicRitzVectors(Hbar, m, deflation);
            const int k = static_cast<int>(P.cols());
            if (k > 0) {
                Eigen::MatrixXd W = Eigen::MatrixXd::Zero(m + 1, k + 1);
                W.topLeftCorner(m, k) = P;
                W.col(k) = c - Hbar * y;
                Eigen::HouseholderQR<Eigen::MatrixXd> wq(W);
                const Eigen::MatrixXd Q = wq.householderQ() * Eigen::MatrixXd::Identity(m + 1, k + 1);
                bool ok = Q.allFinite();
                if (ok) {
                    const Eigen::MatrixXd Hnew = Q.transpose() * Hbar * Q.topLeftCorner(m, k);
                    const Eigen::VectorXd cnew = Q.transpose() * (c - Hbar * y);
                    ok = Hnew.allFinite() && cnew.allFinite();
                    if (ok) {
                        kept = k;
                        Hbar.setZero();
                        Hbar.topLeftCorner(k + 1, k) = Hnew;
                        c.setZero();
                        c.head(k + 1) = cnew;
                        fresh = false;
                        deflated = true;
                    }
                }
                if (!fresh) {
                    // V[m] is intact: with deflation the update of x used its own scratch vector.
                    combineInPlace(n, V, Q);
                }
            }
        }
    }
    return rep;
}

}  // namespace

GmresReport gmres(long n, const LinearMap& A, const LinearMap& M, const double* b, double* x,
                  const GmresOptions& o, GmresWorkspace* workspace) {
    return o.singleBasis ? gmresWith<float>(n, A, M, b, x, o, workspace)
                         : gmresWith<double>(n, A, M, b, x, o, workspace);
}

}  // namespace aero::flow
