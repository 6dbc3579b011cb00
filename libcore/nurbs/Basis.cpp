#include "nurbs/Basis.h"

#include <cmath>
#include <complex>
#include <sstream>
#include <type_traits>

#include "common/Error.h"
#include "common/Scalar.h"

namespace aero::nurbs {

void validateKnotVector(std::span<const double> knots, int degree, int count, std::string_view what) {
    auto fail = [&](const std::string& why) {
        std::ostringstream m;
        m << what << ": " << why;
        throw GeometryError(m.str());
    };
    if (degree < 1 || degree > kMaxDegree) {
        fail("degree " + std::to_string(degree) + " is outside [1, " + std::to_string(kMaxDegree) + "]");
    }
    if (count < degree + 1) {
        fail(std::to_string(count) + " control points are too few for degree " + std::to_string(degree));
    }
    const std::size_t expected = static_cast<std::size_t>(count + degree + 1);
    if (knots.size() != expected) {
        fail("knot vector has " + std::to_string(knots.size()) + " entries, expected " +
             std::to_string(expected) + " (control points + degree + 1)");
    }
    for (std::size_t i = 0; i < knots.size(); ++i) {
        if (!std::isfinite(knots[i])) fail("knot " + std::to_string(i) + " is not finite");
        if (i > 0 && knots[i] < knots[i - 1]) {
            std::ostringstream m;
            m.precision(17);
            m << "knot vector decreases at index " << i << " (" << knots[i - 1] << " > " << knots[i] << ")";
            fail(m.str());
        }
    }
    const int p = degree;
    for (int i = 1; i <= p; ++i) {
        if (knots[i] != knots[0] || knots[knots.size() - 1 - i] != knots.back()) {
            fail("knot vector is not clamped (the first and last " + std::to_string(p + 1) +
                 " knots must be equal)");
        }
    }
    if (!(knots.back() > knots.front())) fail("knot vector has an empty parameter range");
    // Interior multiplicity at most p (a multiplicity p+1 would disconnect the entity).
    int run = 1;
    for (std::size_t i = p + 2; i + p + 1 < knots.size(); ++i) {
        run = (knots[i] == knots[i - 1]) ? run + 1 : 1;
        if (run > p) {
            std::ostringstream m;
            m.precision(17);
            m << "interior knot " << knots[i] << " has multiplicity above the degree " << p;
            fail(m.str());
        }
    }
}

int findSpan(std::span<const double> knots, int degree, int count, double u) {
    const int n = count - 1;
    if (u >= knots[n + 1]) {
        // End of the domain: last non-empty span.
        int s = n;
        while (s > degree && knots[s] == knots[s + 1]) --s;
        return s;
    }
    if (u <= knots[degree]) {
        int s = degree;
        while (s < n && knots[s] == knots[s + 1]) ++s;
        return s;
    }
    int low = degree, high = n + 1;
    int mid = (low + high) / 2;
    while (u < knots[mid] || u >= knots[mid + 1]) {
        if (u < knots[mid]) {
            high = mid;
        } else {
            low = mid;
        }
        mid = (low + high) / 2;
    }
    return mid;
}

namespace {

// At the clamped ends the basis is exactly (1, 0, ..., 0) or (0, ..., 0, 1); the recursion
// would give 1 only up to round-off (x * (1/x)). Real parameters only: a complex-step
// parameter keeps the recursion so its derivative information survives.
template <class T>
bool exactEndValues(std::span<const double> knots, int degree, const T& u, T* N) {
    if constexpr (std::is_floating_point_v<T>) {
        const bool start = u <= knots[degree], end = u >= knots[knots.size() - degree - 1];
        if (start || end) {
            for (int j = 0; j <= degree; ++j) N[j] = T(0.0);
            N[start ? 0 : degree] = T(1.0);
            return true;
        }
    }
    return false;
}

}  // namespace

template <class T>
void basisFunctions(std::span<const double> knots, int degree, int span, const T& u, T* N) {
    if (exactEndValues(knots, degree, u, N)) return;
    T left[kMaxDegree + 1], right[kMaxDegree + 1];
    N[0] = T(1.0);
    for (int j = 1; j <= degree; ++j) {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        T saved = T(0.0);
        for (int r = 0; r < j; ++r) {
            const T temp = N[r] / (right[r + 1] + left[j - r]);
            N[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        N[j] = saved;
    }
}

template <class T>
void basisDerivatives(std::span<const double> knots, int degree, int span, const T& u, int nd, T* ders) {
    const int p = degree;
    T ndu[kMaxDegree + 1][kMaxDegree + 1];
    T left[kMaxDegree + 1], right[kMaxDegree + 1];
    ndu[0][0] = T(1.0);
    for (int j = 1; j <= p; ++j) {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        T saved = T(0.0);
        for (int r = 0; r < j; ++r) {
            ndu[j][r] = right[r + 1] + left[j - r];  // lower triangle: knot differences
            const T temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;  // upper triangle: basis values
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for (int j = 0; j <= p; ++j) ders[j] = ndu[j][p];
    exactEndValues(knots, degree, u, ders);
    const int top = nd < p ? nd : p;
    T a[2][kMaxDegree + 1];
    for (int r = 0; r <= p; ++r) {
        int s1 = 0, s2 = 1;
        a[0][0] = T(1.0);
        for (int k = 1; k <= top; ++k) {
            T d = T(0.0);
            const int rk = r - k, pk = p - k;
            if (r >= k) {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            const int j1 = (rk >= -1) ? 1 : -rk;
            const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
            for (int j = j1; j <= j2; ++j) {
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
                d += a[s2][j] * ndu[rk + j][pk];
            }
            if (r <= pk) {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k * (p + 1) + r] = d;
            std::swap(s1, s2);
        }
    }
    // Multiply by the factors p!/(p-k)!.
    double factor = p;
    for (int k = 1; k <= top; ++k) {
        for (int j = 0; j <= p; ++j) ders[k * (p + 1) + j] *= factor;
        factor *= (p - k);
    }
    for (int k = top + 1; k <= nd; ++k) {
        for (int j = 0; j <= p; ++j) ders[k * (p + 1) + j] = T(0.0);
    }
}

std::vector<double> uniformKnots(int degree, int count) {
    std::vector<double> k(static_cast<std::size_t>(count + degree + 1));
    const int spans = count - degree;
    for (int i = 0; i < static_cast<int>(k.size()); ++i) {
        if (i <= degree) {
            k[i] = 0.0;
        } else if (i >= count) {
            k[i] = 1.0;
        } else {
            k[i] = static_cast<double>(i - degree) / spans;
        }
    }
    return k;
}

template void basisFunctions<double>(std::span<const double>, int, int, const double&, double*);
template void basisFunctions<std::complex<double>>(std::span<const double>, int, int,
                                                    const std::complex<double>&, std::complex<double>*);
template void basisDerivatives<double>(std::span<const double>, int, int, const double&, int, double*);
template void basisDerivatives<std::complex<double>>(std::span<const double>, int, int,
                                                      const std::complex<double>&, int,
                                                      std::complex<double>*);

std::vector<double> spanSamples(std::span<const double> knots, int perSpan) {
    std::vector<double> s;
    for (std::size_t i = 0; i + 1 < knots.size(); ++i) {
        if (knots[i + 1] > knots[i]) {
            for (int t = 0; t < perSpan; ++t) s.push_back(knots[i] + (knots[i + 1] - knots[i]) * t / perSpan);
        }
    }
    s.push_back(knots.back());
    return s;
}

int nonEmptySpans(std::span<const double> knots) {
    int n = 0;
    for (std::size_t i = 0; i + 1 < knots.size(); ++i) n += knots[i + 1] > knots[i] ? 1 : 0;
    return n;
}

}  // namespace aero::nurbs
