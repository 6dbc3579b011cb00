#include "adjoint/Functionals.h"

#include <cmath>
#include <complex>

#include "common/Error.h"
#include "flow/Metrics.h"

namespace aero::adjoint {

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;

struct Entry {
    Functional f;
    const char* name;
};
constexpr Entry kTable[] = {{Functional::CL, "CL"}, {Functional::CD, "CD"}, {Functional::CM, "CM"}, {Functional::CY, "CY"}};

}  // namespace

void functionalWeights(Functional f, const flow::FreeStream& fs, const flow::ForceReference& ref, double wF[3],
                       double wM[3]) {
    const double qs = fs.dynamicPressure() * ref.area;
    const double ca = std::cos(fs.alpha()), sa = std::sin(fs.alpha());
    for (int c = 0; c < 3; ++c) wF[c] = wM[c] = 0;
    switch (f) {
        case Functional::CL:
            wF[0] = -sa / qs;
            wF[2] = ca / qs;
            break;
        case Functional::CD:
            wF[0] = ca / qs;
            wF[2] = sa / qs;
            break;
        case Functional::CM:
            wM[1] = 1.0 / (qs * ref.length);
            break;
        case Functional::CY:
            wF[1] = 1.0 / qs;
            break;
    }
}

Functional functionalByName(const std::string& name) {
    std::string list;
    for (const Entry& e : kTable) {
        if (name == e.name) return e.f;
        list += std::string(list.empty() ? "" : ", ") + e.name;
    }
    throw CaseError("unknown functional '" + name + "' (expected " + list + ")");
}

const char* functionalName(Functional f) {
    for (const Entry& e : kTable) {
        if (e.f == f) return e.name;
    }
    return "?";
}

double functionalValue(Functional f, const flow::ForceCoefficients& c) {
    switch (f) {
        case Functional::CL:
            return c.CL;
        case Functional::CD:
            return c.CD;
        case Functional::CM:
            return c.CM;
        case Functional::CY:
            return c.CY;
    }
    return 0;
}

std::vector<double> stateGradient(Functional f, const flow::FlowMesh& fm, const std::vector<double>& metrics,
                                  const std::vector<double>& x, const std::vector<double>& q,
                                  const flow::FreeStream& fs, const flow::ForceReference& ref) {
    using C = std::complex<double>;
    double wF[3], wM[3];
    functionalWeights(f, fs, ref, wF, wM);
    std::vector<double> g(q.size(), 0.0);
    constexpr double h = 1e-30;  // complex step: exact to round-off
    for (const flow::WallNode& w : flow::wallNodes(fm)) {
        C m[flow::kMetricWidth], xn[3], qn[flow::kVars];
        for (int k = 0; k < flow::kMetricWidth; ++k) m[k] = metrics[flow::kMetricWidth * w.node + k];
        for (int k = 0; k < 3; ++k) xn[k] = x[3 * w.node + k];
        for (int v = 0; v < flow::kVars; ++v) {
            for (int k = 0; k < flow::kVars; ++k) qn[k] = q[flow::kVars * w.node + k];
            qn[v] += C(0, h);
            C dF[3], dM[3];
            flow::wallNodeForce(w, m, xn, qn, fs, ref.point, dF, dM);
            double s = 0;
            for (int c = 0; c < 3; ++c) s += wF[c] * dF[c].imag() + wM[c] * dM[c].imag();
            g[flow::kVars * w.node + v] += s / h;
        }
    }
    return g;
}

double alphaPartial(Functional f, const flow::ForceCoefficients& c) {
    // CL = -Fx sin a + Fz cos a, CD = Fx cos a + Fz sin a (coefficients): dCL/da = -CD, dCD/da = CL.
    switch (f) {
        case Functional::CL:
            return -c.CD * kDegree;
        case Functional::CD:
            return c.CL * kDegree;
        case Functional::CM:
        case Functional::CY:
            return 0;
    }
    return 0;
}

}  // namespace aero::adjoint
