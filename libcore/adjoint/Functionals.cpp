#include "adjoint/Functionals.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include "common/Error.h"
#include "flow/Metrics.h"
#include "flow/Residual.h"

namespace aero::adjoint {

namespace {

using C = std::complex<double>;
constexpr double kDegree = 3.14159265358979323846 / 180.0;

struct Entry {
    Functional::Kind kind;
    const char* name;
};
constexpr Entry kTable[] = {{Functional::Kind::CL, "CL"},
                            {Functional::Kind::CD, "CD"},
                            {Functional::Kind::CM, "CM"},
                            {Functional::Kind::CY, "CY"},
                            {Functional::Kind::PressureMismatch, "pressure"},
                            {Functional::Kind::ForceCombination, "force combination"},
                            {Functional::Kind::WallMachSum, "wall_mach"}};

constexpr Functional::Kind kForceKinds[4] = {Functional::Kind::CL, Functional::Kind::CD, Functional::Kind::CM,
                                             Functional::Kind::CY};

template <class T>
T magnitude(const T n[3]) {
    return std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

// (|u| / c)^2 at one node: smooth everywhere, a stagnation point included, where |u| / c has a
// cone (complex-step safe: no abs, no max).
template <class T>
T localMachSquared(const T* q, double gamma) {
    const T u2 = (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) / (q[0] * q[0]);
    return u2 * q[0] / (gamma * flow::pressure(q, gamma));
}

}  // namespace

Functional Functional::pressureMismatch(std::vector<double> target) {
    return {Kind::PressureMismatch, std::make_shared<const std::vector<double>>(std::move(target)), nullptr, 0, 0};
}

Functional Functional::forceCombination(double cCL, double cCD, double cCM, double cCY) {
    Functional f;
    f.kind = Kind::ForceCombination;
    f.coefficients = std::make_shared<const std::array<double, 4>>(std::array<double, 4>{cCL, cCD, cCM, cCY});
    return f;
}

Functional Functional::wallMachSum(double rho, double machReference) {
    if (!(rho > 0) || !(machReference > 0) || !std::isfinite(machReference)) {
        throw Error("Functional::wallMachSum: rho and the reference Mach number must be positive");
    }
    Functional f;
    f.kind = Kind::WallMachSum;
    f.rho = rho;
    f.machReference = machReference;
    return f;
}

void functionalWeights(const Functional& f, const flow::FreeStream& fs, const flow::ForceReference& ref, double wF[3],
                       double wM[3]) {
    const double qs = fs.dynamicPressure() * ref.area;
    const double ca = std::cos(fs.alpha()), sa = std::sin(fs.alpha());
    for (int c = 0; c < 3; ++c) wF[c] = wM[c] = 0;
    if (f.kind == Functional::Kind::ForceCombination) {
        for (int b = 0; b < 4; ++b) {
            double bF[3], bM[3];
            functionalWeights(Functional{kForceKinds[b], nullptr, nullptr, 0, 0}, fs, ref, bF, bM);
            for (int c = 0; c < 3; ++c) {
                wF[c] += (*f.coefficients)[b] * bF[c];
                wM[c] += (*f.coefficients)[b] * bM[c];
            }
        }
        return;
    }
    switch (f.kind) {
        case Functional::Kind::CL:
            wF[0] = -sa / qs;
            wF[2] = ca / qs;
            break;
        case Functional::Kind::CD:
            wF[0] = ca / qs;
            wF[2] = sa / qs;
            break;
        case Functional::Kind::CM:
            wM[1] = 1.0 / (qs * ref.length);
            break;
        case Functional::Kind::CY:
            wF[1] = 1.0 / qs;
            break;
        case Functional::Kind::PressureMismatch:
        case Functional::Kind::ForceCombination:
        case Functional::Kind::WallMachSum:
            break;
    }
}

template <class T>
T wallNodeShare(const Functional& f, const flow::WallNode& w, std::size_t k, const T* metrics, const T* x, const T* q,
                const flow::FreeStream& fs, const flow::ForceReference& ref) {
    if (f.kind == Functional::Kind::PressureMismatch) {
        if (!f.targetPressure || k >= f.targetPressure->size()) {
            throw GeometryError("the target pressure has " + std::to_string(f.targetPressure ? f.targetPressure->size() : 0) +
                                " wall values; the grid has more wall nodes (another grid?)");
        }
        T n[3];
        flow::outwardNormal(metrics, w.face, n);
        const T d = flow::pressure(q, fs.gamma) - (*f.targetPressure)[k];
        return 0.5 * d * d * w.weight * magnitude(n);
    }
    if (f.kind == Functional::Kind::WallMachSum) {
        // (M^2 - M_ref^2) / (2 M_ref) is M - M_ref to first order near M_ref, without the cone of
        // M = sqrt(M^2) at a stagnation point.
        const double m = f.machReference;
        return std::exp(f.rho * (localMachSquared(q, fs.gamma) - m * m) / (2 * m));
    }
    double wF[3], wM[3];
    functionalWeights(f, fs, ref, wF, wM);
    T dF[3], dM[3];
    flow::wallNodeForce(w, metrics, x, q, fs, ref.point, dF, dM);
    T s = 0.0;
    for (int c = 0; c < 3; ++c) s += wF[c] * dF[c] + wM[c] * dM[c];
    return s;
}

template double wallNodeShare<double>(const Functional&, const flow::WallNode&, std::size_t, const double*, const double*,
                                      const double*, const flow::FreeStream&, const flow::ForceReference&);
template C wallNodeShare<C>(const Functional&, const flow::WallNode&, std::size_t, const C*, const C*, const C*,
                            const flow::FreeStream&, const flow::ForceReference&);

Functional functionalByName(const std::string& name) {
    std::string list;
    for (const Entry& e : kTable) {
        if (e.kind == Functional::Kind::PressureMismatch || e.kind == Functional::Kind::ForceCombination ||
            e.kind == Functional::Kind::WallMachSum) {
            continue;
        }
        if (name == e.name) return {e.kind, nullptr, nullptr, 0, 0};
        list += std::string(list.empty() ? "" : ", ") + e.name;
    }
    throw CaseError("unknown functional '" + name + "' (expected " + list + ")");
}

const char* functionalName(const Functional& f) {
    for (const Entry& e : kTable) {
        if (e.kind == f.kind) return e.name;
    }
    return "?";
}

double functionalValue(const Functional& f, const flow::ForceCoefficients& c) {
    if (f.kind == Functional::Kind::ForceCombination) {
        const auto& k = *f.coefficients;
        return k[0] * c.CL + k[1] * c.CD + k[2] * c.CM + k[3] * c.CY;
    }
    switch (f.kind) {
        case Functional::Kind::CL:
            return c.CL;
        case Functional::Kind::CD:
            return c.CD;
        case Functional::Kind::CM:
            return c.CM;
        case Functional::Kind::CY:
            return c.CY;
        case Functional::Kind::PressureMismatch:
        case Functional::Kind::ForceCombination:
        case Functional::Kind::WallMachSum:
            break;
    }
    throw Error(std::string("functionalValue: the ") + functionalName(f) + " needs the state, not the forces");
}

double functionalValue(const Functional& f, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                       const std::vector<double>& x, const std::vector<double>& q, const flow::FreeStream& fs,
                       const flow::ForceReference& ref) {
    const std::vector<flow::WallNode> wall = flow::wallNodes(fm);
    double s = 0;
    for (std::size_t k = 0; k < wall.size(); ++k) {
        const flow::WallNode& w = wall[k];
        s += wallNodeShare<double>(f, w, k, &metrics[flow::kMetricWidth * w.node], &x[3 * w.node], &q[flow::kVars * w.node],
                                   fs, ref);
    }
    return s;
}

std::vector<double> stateGradient(const Functional& f, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                  const std::vector<double>& x, const std::vector<double>& q,
                                  const flow::FreeStream& fs, const flow::ForceReference& ref) {
    std::vector<double> g(q.size(), 0.0);
    constexpr double h = 1e-30;  // complex step: exact to round-off
    const std::vector<flow::WallNode> wall = flow::wallNodes(fm);
    for (std::size_t k = 0; k < wall.size(); ++k) {
        const flow::WallNode& w = wall[k];
        C m[flow::kMetricWidth], xn[3], qn[flow::kVars];
        for (int i = 0; i < flow::kMetricWidth; ++i) m[i] = metrics[flow::kMetricWidth * w.node + i];
        for (int i = 0; i < 3; ++i) xn[i] = x[3 * w.node + i];
        for (int v = 0; v < flow::kVars; ++v) {
            for (int i = 0; i < flow::kVars; ++i) qn[i] = q[flow::kVars * w.node + i];
            qn[v] += C(0, h);
            g[flow::kVars * w.node + v] += wallNodeShare<C>(f, w, k, m, xn, qn, fs, ref).imag() / h;
        }
    }
    return g;
}

double alphaPartial(const Functional& f, const flow::ForceCoefficients& c) {
    // CL = -Fx sin a + Fz cos a, CD = Fx cos a + Fz sin a (coefficients): dCL/da = -CD, dCD/da = CL.
    if (f.kind == Functional::Kind::ForceCombination) {
        return (*f.coefficients)[0] * -c.CD * kDegree + (*f.coefficients)[1] * c.CL * kDegree;
    }
    switch (f.kind) {
        case Functional::Kind::CL:
            return -c.CD * kDegree;
        case Functional::Kind::CD:
            return c.CL * kDegree;
        case Functional::Kind::CM:
        case Functional::Kind::CY:
        case Functional::Kind::PressureMismatch:
        case Functional::Kind::ForceCombination:
        case Functional::Kind::WallMachSum:
            return 0;
    }
    return 0;
}

std::vector<double> wallMach(const flow::FlowMesh& fm, const std::vector<double>& q, double gamma) {
    std::vector<double> m;
    for (const flow::WallNode& w : flow::wallNodes(fm)) m.push_back(std::sqrt(localMachSquared(&q[flow::kVars * w.node], gamma)));
    return m;
}

double wallMachSmoothMax(const Functional& f, double S, double* dS) {
    if (f.kind != Functional::Kind::WallMachSum) throw Error("wallMachSmoothMax: not a wall Mach sum");
    // KS of (M^2 - M_ref^2) / (2 M_ref): M^2 <~ M_ref^2 + 2 M_ref ln(S) / rho.
    const double m = f.machReference;
    const double squared = std::max(m * m + 2 * m * std::log(S) / f.rho, 1e-300);
    const double smooth = std::sqrt(squared);
    if (dS) *dS = m / (f.rho * S * smooth);
    return smooth;
}

std::vector<double> wallPressure(const flow::FlowMesh& fm, const std::vector<double>& q, double gamma) {
    std::vector<double> p;
    for (const flow::WallNode& w : flow::wallNodes(fm)) p.push_back(flow::pressure(&q[flow::kVars * w.node], gamma));
    return p;
}

}  // namespace aero::adjoint
