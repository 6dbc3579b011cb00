#pragma once
// Forward-mode dual numbers with N derivative directions: x = v + sum_k d_k eps_k with
// eps_j eps_k = 0. One evaluation of a function templated on the scalar type gives its value
// and N directional derivatives at once, exact to round-off, where complex step needs N
// evaluations (each about 4 times a real one). The grid sensitivities seed the 10 metric values
// of a node in 10 directions: 13 coloured residuals instead of 130 complex ones.
//
// Branches take the real part (realPart, absR, the comparisons below), as for complex step.
#include <array>
#include <cmath>

#include "common/Scalar.h"

namespace aero {

template <int N>
struct Dual {
    double v = 0.0;
    std::array<double, N> d{};

    Dual() = default;
    Dual(double x) : v(x) {}  // NOLINT(google-explicit-constructor): constants mix freely

    /// x + eps_k.
    static Dual variable(double x, int k) {
        Dual r(x);
        r.d[k] = 1.0;
        return r;
    }

    Dual& operator+=(const Dual& b) {
        v += b.v;
        for (int k = 0; k < N; ++k) d[k] += b.d[k];
        return *this;
    }
    Dual& operator-=(const Dual& b) {
        v -= b.v;
        for (int k = 0; k < N; ++k) d[k] -= b.d[k];
        return *this;
    }
    Dual& operator*=(const Dual& b) { return *this = *this * b; }
    Dual& operator/=(const Dual& b) { return *this = *this / b; }
    Dual& operator+=(double b) {
        v += b;
        return *this;
    }
    Dual& operator-=(double b) {
        v -= b;
        return *this;
    }
    Dual& operator*=(double b) {
        v *= b;
        for (int k = 0; k < N; ++k) d[k] *= b;
        return *this;
    }

    friend Dual operator-(const Dual& a) {
        Dual r;
        r.v = -a.v;
        for (int k = 0; k < N; ++k) r.d[k] = -a.d[k];
        return r;
    }
    friend Dual operator+(Dual a, const Dual& b) { return a += b; }
    friend Dual operator-(Dual a, const Dual& b) { return a -= b; }
    friend Dual operator+(Dual a, double b) { return a += b; }
    friend Dual operator+(double a, Dual b) { return b += a; }
    friend Dual operator-(Dual a, double b) { return a -= b; }
    friend Dual operator-(double a, const Dual& b) {
        Dual r = -b;
        r.v += a;
        return r;
    }
    friend Dual operator*(const Dual& a, const Dual& b) {
        Dual r;
        r.v = a.v * b.v;
        for (int k = 0; k < N; ++k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
        return r;
    }
    friend Dual operator*(Dual a, double b) { return a *= b; }
    friend Dual operator*(double a, Dual b) { return b *= a; }
    friend Dual operator/(const Dual& a, const Dual& b) {
        const double inv = 1.0 / b.v;
        Dual r;
        r.v = a.v * inv;
        for (int k = 0; k < N; ++k) r.d[k] = (a.d[k] - r.v * b.d[k]) * inv;
        return r;
    }
    friend Dual operator/(Dual a, double b) { return a *= 1.0 / b; }
    friend Dual operator/(double a, const Dual& b) {
        const double inv = 1.0 / b.v;
        Dual r;
        r.v = a * inv;
        const double s = -r.v * inv;
        for (int k = 0; k < N; ++k) r.d[k] = s * b.d[k];
        return r;
    }

    // Equality compares every part (as for std::complex: a seeded zero is not zero).
    friend bool operator==(const Dual& a, const Dual& b) { return a.v == b.v && a.d == b.d; }
    friend bool operator!=(const Dual& a, const Dual& b) { return !(a == b); }
};

/// y = f(x.v) + f'(x.v) (x - x.v).
template <int N>
inline Dual<N> chain(const Dual<N>& x, double f, double df) {
    Dual<N> r;
    r.v = f;
    for (int k = 0; k < N; ++k) r.d[k] = df * x.d[k];
    return r;
}

template <int N>
inline double realPart(const Dual<N>& x) {
    return x.v;
}
template <int N>
inline double real(const Dual<N>& x) {
    return x.v;
}
template <int N>
inline Dual<N> sqrt(const Dual<N>& x) {
    const double s = std::sqrt(x.v);
    return chain(x, s, 0.5 / s);
}
template <int N>
inline Dual<N> log(const Dual<N>& x) {
    return chain(x, std::log(x.v), 1.0 / x.v);
}
template <int N>
inline Dual<N> atanh(const Dual<N>& x) {
    return chain(x, std::atanh(x.v), 1.0 / (1.0 - x.v * x.v));
}
/// |x| analytic on each side: x or -x by the sign of the value (as absR for complex step).
template <int N>
inline Dual<N> absR(const Dual<N>& x) {
    return x.v < 0 ? -x : x;
}

}  // namespace aero
