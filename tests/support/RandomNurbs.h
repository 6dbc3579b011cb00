#pragma once
// Random NURBS entities for property tests: clamped knot vectors with non-uniform spacing and
// interior multiplicities, optional positive weights. Deterministic for a given seed.
#include <algorithm>
#include <random>
#include <vector>

#include "nurbs/Surface.h"
#include "nurbs/Volume.h"

namespace aero::test {

inline std::vector<double> randomKnots(std::mt19937& rng, int degree, int count, double a = 0.0, double b = 1.0) {
    std::uniform_real_distribution<double> U(a, b);
    std::vector<double> interior;
    const int nInterior = count - degree - 1;
    while (static_cast<int>(interior.size()) < nInterior) {
        const double k = U(rng);
        // Sometimes repeat a knot (multiplicity up to the degree).
        int mult = 1;
        if (degree > 1 && std::uniform_int_distribution<int>(0, 3)(rng) == 0) {
            mult = std::uniform_int_distribution<int>(2, degree)(rng);
        }
        for (int m = 0; m < mult && static_cast<int>(interior.size()) < nInterior; ++m) interior.push_back(k);
    }
    std::sort(interior.begin(), interior.end());
    std::vector<double> knots(degree + 1, a);
    knots.insert(knots.end(), interior.begin(), interior.end());
    knots.insert(knots.end(), degree + 1, b);
    return knots;
}

inline std::vector<double> randomPoints(std::mt19937& rng, int count, double scale = 1.0) {
    std::uniform_real_distribution<double> U(-scale, scale);
    std::vector<double> p(3 * static_cast<std::size_t>(count));
    for (double& x : p) x = U(rng);
    return p;
}

inline std::vector<double> randomWeights(std::mt19937& rng, int count) {
    std::uniform_real_distribution<double> W(0.5, 2.0);
    std::vector<double> w(count);
    for (double& x : w) x = W(rng);
    return w;
}

inline nurbs::Curve<double> randomCurve(std::mt19937& rng, int degree, int count, bool rational) {
    nurbs::Curve<double> c;
    c.degree = degree;
    c.knots = randomKnots(rng, degree, count);
    c.points = randomPoints(rng, count);
    if (rational) c.weights = randomWeights(rng, count);
    return c;
}

inline nurbs::Surface<double> randomSurface(std::mt19937& rng, int pu, int pv, int nu, int nv, bool rational) {
    nurbs::Surface<double> s;
    s.degreeU = pu;
    s.degreeV = pv;
    s.countU = nu;
    s.countV = nv;
    s.knotsU = randomKnots(rng, pu, nu);
    s.knotsV = randomKnots(rng, pv, nv);
    s.points = randomPoints(rng, nu * nv);
    if (rational) s.weights = randomWeights(rng, nu * nv);
    return s;
}

inline nurbs::Volume<double> randomVolume(std::mt19937& rng, std::array<int, 3> degree, std::array<int, 3> count,
                                          bool rational) {
    nurbs::Volume<double> v;
    v.degree = degree;
    v.count = count;
    for (int d = 0; d < 3; ++d) v.knots[d] = randomKnots(rng, degree[d], count[d]);
    v.points = randomPoints(rng, v.controlCount());
    if (rational) v.weights = randomWeights(rng, v.controlCount());
    return v;
}

/// A lattice-like volume: a smoothly perturbed box [0,Lx]x[0,Ly]x[0,Lz] (injective).
inline nurbs::Volume<double> boxVolume(std::array<int, 3> degree, std::array<int, 3> count, std::array<double, 3> L,
                                       double wobble, bool rational, unsigned seed = 1) {
    std::mt19937 rng(seed);
    nurbs::Volume<double> v;
    v.degree = degree;
    v.count = count;
    for (int d = 0; d < 3; ++d) v.knots[d] = randomKnots(rng, degree[d], count[d]);
    std::uniform_real_distribution<double> U(-wobble, wobble);
    v.points.resize(3 * static_cast<std::size_t>(v.controlCount()));
    for (int k = 0; k < count[2]; ++k) {
        for (int j = 0; j < count[1]; ++j) {
            for (int i = 0; i < count[0]; ++i) {
                const int a = v.index(i, j, k);
                const int ijk[3] = {i, j, k};
                for (int d = 0; d < 3; ++d) {
                    v.points[3 * a + d] = L[d] * ijk[d] / (count[d] - 1) + U(rng) * L[d] / count[d];
                }
            }
        }
    }
    if (rational) {
        std::uniform_real_distribution<double> W(0.8, 1.25);
        v.weights.resize(v.controlCount());
        for (double& w : v.weights) w = W(rng);
    }
    return v;
}

template <class T>
nurbs::Curve<T> cast(const nurbs::Curve<double>& c) {
    nurbs::Curve<T> r;
    r.degree = c.degree;
    r.knots = c.knots;
    r.points.assign(c.points.begin(), c.points.end());
    r.weights.assign(c.weights.begin(), c.weights.end());
    return r;
}

template <class T>
nurbs::Surface<T> cast(const nurbs::Surface<double>& s) {
    nurbs::Surface<T> r;
    r.degreeU = s.degreeU;
    r.degreeV = s.degreeV;
    r.countU = s.countU;
    r.countV = s.countV;
    r.knotsU = s.knotsU;
    r.knotsV = s.knotsV;
    r.points.assign(s.points.begin(), s.points.end());
    r.weights.assign(s.weights.begin(), s.weights.end());
    return r;
}

template <class T>
nurbs::Volume<T> cast(const nurbs::Volume<double>& v) {
    nurbs::Volume<T> r;
    r.degree = v.degree;
    r.count = v.count;
    r.knots = v.knots;
    r.points.assign(v.points.begin(), v.points.end());
    r.weights.assign(v.weights.begin(), v.weights.end());
    return r;
}

}  // namespace aero::test
