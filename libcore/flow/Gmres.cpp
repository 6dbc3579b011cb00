#include "flow/Gmres.h"

#include <cmath>
#include <vector>

namespace aero::flow {

namespace {

double dot(long n, const double* a, const double* b) {
    double s = 0;
#pragma omp parallel for reduction(+ : s) schedule(static)
    for (long i = 0; i < n; ++i) s += a[i] * b[i];
    return s;
}

}  // namespace

GmresReport gmres(long n, const LinearMap& A, const LinearMap& M, const double* b, double* x,
                  const GmresOptions& o) {
    GmresReport rep;
    const int m = std::max(1, o.restart);
    const double bnorm = std::sqrt(dot(n, b, b));
    if (bnorm == 0) {
        std::fill(x, x + n, 0.0);
        rep.relativeResidual = 0;
        rep.converged = true;
        return rep;
    }
    std::vector<std::vector<double>> V(m + 1, std::vector<double>(n));
    std::vector<double> H((m + 1) * m), cs(m), sn(m), g(m + 1), y(m), w(n), z(n);
    auto h = [&](int i, int j) -> double& { return H[i * m + j]; };

    while (rep.iterations < o.maxIterations) {
        // r = b - A x
        A(x, w.data());
#pragma omp parallel for schedule(static)
        for (long i = 0; i < n; ++i) w[i] = b[i] - w[i];
        const double beta = std::sqrt(dot(n, w.data(), w.data()));
        rep.relativeResidual = beta / bnorm;
        if (rep.relativeResidual <= o.tolerance) {
            rep.converged = true;
            return rep;
        }
#pragma omp parallel for schedule(static)
        for (long i = 0; i < n; ++i) V[0][i] = w[i] / beta;
        std::fill(g.begin(), g.end(), 0.0);
        g[0] = beta;
        int j = 0;
        for (; j < m && rep.iterations < o.maxIterations; ++j) {
            ++rep.iterations;
            if (M) {
                M(V[j].data(), z.data());
                A(z.data(), w.data());
            } else {
                A(V[j].data(), w.data());
            }
            for (int i = 0; i <= j; ++i) {
                h(i, j) = dot(n, w.data(), V[i].data());
                const double hij = h(i, j);
                const double* vi = V[i].data();
#pragma omp parallel for schedule(static)
                for (long l = 0; l < n; ++l) w[l] -= hij * vi[l];
            }
            const double hnext = std::sqrt(dot(n, w.data(), w.data()));
            h(j + 1, j) = hnext;
            if (hnext > 0) {
                const double inv = 1.0 / hnext;
#pragma omp parallel for schedule(static)
                for (long l = 0; l < n; ++l) V[j + 1][l] = w[l] * inv;
            }
            for (int i = 0; i < j; ++i) {
                const double t = cs[i] * h(i, j) + sn[i] * h(i + 1, j);
                h(i + 1, j) = -sn[i] * h(i, j) + cs[i] * h(i + 1, j);
                h(i, j) = t;
            }
            const double r = std::hypot(h(j, j), h(j + 1, j));
            cs[j] = r > 0 ? h(j, j) / r : 1.0;
            sn[j] = r > 0 ? h(j + 1, j) / r : 0.0;
            h(j, j) = r;
            h(j + 1, j) = 0;
            g[j + 1] = -sn[j] * g[j];
            g[j] = cs[j] * g[j];
            rep.relativeResidual = std::abs(g[j + 1]) / bnorm;
            if (!std::isfinite(rep.relativeResidual)) return rep;
            // Converged, or a happy breakdown (the Krylov space is invariant: the solution is
            // in it). The Arnoldi value, not h(j + 1, j), which the rotation has just zeroed.
            if (rep.relativeResidual <= o.tolerance || hnext == 0) {
                ++j;
                break;
            }
        }
        // x += M^-1 (V y), H y = g (upper triangular, j columns)
        for (int i = j - 1; i >= 0; --i) {
            double s = g[i];
            for (int k = i + 1; k < j; ++k) s -= h(i, k) * y[k];
            y[i] = h(i, i) != 0 ? s / h(i, i) : 0.0;
        }
        std::fill(w.begin(), w.end(), 0.0);
        for (int i = 0; i < j; ++i) {
            const double yi = y[i];
            const double* vi = V[i].data();
#pragma omp parallel for schedule(static)
            for (long l = 0; l < n; ++l) w[l] += yi * vi[l];
        }
        if (M) {
            M(w.data(), z.data());
        } else {
            z = w;
        }
#pragma omp parallel for schedule(static)
        for (long l = 0; l < n; ++l) x[l] += z[l];
        if (rep.relativeResidual <= o.tolerance) {
            rep.converged = true;
            return rep;
        }
        if (o.hopeless > 0 && rep.iterations < o.maxIterations) {
            const double rate = std::log(std::max(rep.relativeResidual, 1e-300)) / rep.iterations;
            if (std::exp(rate * o.maxIterations) > o.hopeless) {
                rep.gaveUp = true;
                return rep;
            }
        }
    }
    return rep;
}

}  // namespace aero::flow
