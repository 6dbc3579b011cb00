#include "flow/Outputs.h"

#include <complex>
#include <cmath>
#include <set>

#include "flow/Metrics.h"
#include "flow/Residual.h"
#include "flow/Sbp.h"

namespace aero::flow {

std::vector<WallNode> wallNodes(const FlowMesh& fm) {
    std::vector<WallNode> out;
    for (const FlowBlock& blk : fm.blocks) {
        for (int f = 0; f < 6; ++f) {
            if (blk.faces[f].kind != mesh::BoundaryKind::Wall) continue;
            const int d = faceDirection(f), a = d == 0 ? 1 : 0, b = d == 2 ? 1 : 2;
            for (long node : faceNodes(blk.dims, f)) {
                const int idx[3] = {static_cast<int>(node % blk.dims[0]),
                                    static_cast<int>((node / blk.dims[0]) % blk.dims[1]),
                                    static_cast<int>(node / (static_cast<long>(blk.dims[0]) * blk.dims[1]))};
                out.push_back({blk.offset + node, f, sbpWeight(idx[a], blk.dims[a]) * sbpWeight(idx[b], blk.dims[b])});
            }
        }
    }
    return out;
}

template <class T>
void wallNodeForce(const WallNode& w, const T* metrics, const T* x, const T* q, const FreeStream& fs,
                   const std::array<double, 3>& point, T dF[3], T dM[3]) {
    T n[3];
    outwardNormal(metrics, w.face, n);
    const T dp = pressure(q, fs.gamma) - fs.pressure();
    for (int c = 0; c < 3; ++c) dF[c] = w.weight * dp * n[c];
    const T r[3] = {x[0] - point[0], x[1] - point[1], x[2] - point[2]};
    dM[0] = r[1] * dF[2] - r[2] * dF[1];
    dM[1] = r[2] * dF[0] - r[0] * dF[2];
    dM[2] = r[0] * dF[1] - r[1] * dF[0];
}

template void wallNodeForce<double>(const WallNode&, const double*, const double*, const double*, const FreeStream&,
                                    const std::array<double, 3>&, double*, double*);
template void wallNodeForce<std::complex<double>>(const WallNode&, const std::complex<double>*, const std::complex<double>*,
                                                  const std::complex<double>*, const FreeStream&,
                                                  const std::array<double, 3>&, std::complex<double>*,
                                                  std::complex<double>*);

ForceCoefficients integrateForces(const FlowMesh& fm, const std::vector<double>& metrics,
                                  const std::vector<double>& x, const std::vector<double>& q,
                                  const FreeStream& fs, const ForceReference& ref) {
    double F[3] = {0, 0, 0}, Mo[3] = {0, 0, 0};
    for (const WallNode& w : wallNodes(fm)) {
        double dF[3], dM[3];
        wallNodeForce(w, &metrics[kMetricWidth * w.node], &x[3 * w.node], &q[kVars * w.node], fs, ref.point, dF, dM);
        for (int c = 0; c < 3; ++c) {
            F[c] += dF[c];
            Mo[c] += dM[c];
        }
    }
    ForceCoefficients c;
    const double qs = fs.dynamicPressure() * ref.area;
    for (int k = 0; k < 3; ++k) {
        c.force[k] = F[k] / qs;
        c.moment[k] = Mo[k] / (qs * ref.length);
    }
    const double ca = std::cos(fs.alpha()), sa = std::sin(fs.alpha());
    c.CD = c.force[0] * ca + c.force[2] * sa;
    c.CL = -c.force[0] * sa + c.force[2] * ca;
    c.CY = c.force[1];
    c.CM = c.moment[1];
    return c;
}

std::vector<double> pressureCoefficient(const FlowMesh& fm, const std::vector<double>& q, const FreeStream& fs) {
    std::vector<double> cp(fm.nodeCount);
    const double pinf = fs.pressure(), qinf = fs.dynamicPressure();
    for (long n = 0; n < fm.nodeCount; ++n) cp[n] = (pressure(&q[kVars * n], fs.gamma) - pinf) / qinf;
    return cp;
}

std::vector<double> machNumber(const FlowMesh& fm, const std::vector<double>& q, double gamma) {
    std::vector<double> m(fm.nodeCount);
    for (long n = 0; n < fm.nodeCount; ++n) {
        const double* a = &q[kVars * n];
        const double speed = std::sqrt(a[1] * a[1] + a[2] * a[2] + a[3] * a[3]) / a[0];
        m[n] = speed / soundSpeed(a, gamma);
    }
    return m;
}

std::vector<double> entropy(const FlowMesh& fm, const std::vector<double>& q, const FreeStream& fs) {
    std::vector<double> s(fm.nodeCount);
    const double sinf = fs.pressure();  // rho_inf = 1
    for (long n = 0; n < fm.nodeCount; ++n) {
        const double* a = &q[kVars * n];
        s[n] = pressure(a, fs.gamma) / std::pow(a[0], fs.gamma) / sinf - 1.0;
    }
    return s;
}

std::vector<SurfaceSample> surfacePressure(const FlowMesh& fm, const std::vector<double>& q, const FreeStream& fs) {
    std::vector<SurfaceSample> out;
    const double pinf = fs.pressure(), qinf = fs.dynamicPressure();
    for (std::size_t b = 0; b < fm.blocks.size(); ++b) {
        const FlowBlock& blk = fm.blocks[b];
        std::set<long> seen;
        for (int f = 0; f < 6; ++f) {
            if (blk.faces[f].kind != mesh::BoundaryKind::Wall) continue;
            for (long node : faceNodes(blk.dims, f)) {
                if (!seen.insert(node).second) continue;
                out.push_back({static_cast<int>(b), node,
                               (pressure(&q[kVars * (blk.offset + node)], fs.gamma) - pinf) / qinf});
            }
        }
    }
    return out;
}

}  // namespace aero::flow
