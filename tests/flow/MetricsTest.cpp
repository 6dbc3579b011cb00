#include "flow/Metrics.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "FlowFixtures.h"
#include "flow/BlockView.h"
#include "flow/Residual.h"
#include "flow/Sbp.h"

using namespace aero;
using namespace aero::flow;
using namespace aero::flow::testing;

namespace {

// max over nodes of |sum_d D_d m_d| (per component) and of |m|, for one case.
void gclDefect(const FlowCase& c, double& defect, double& scale) {
    defect = 0;
    scale = 0;
    for (const FlowBlock& blk : c.fm.blocks) {
        const BlockView<const double> m{c.metrics.data() + kMetricWidth * blk.offset, blk.dims, kMetricWidth};
        for (int k = 0; k < blk.dims[2]; ++k) {
            for (int j = 0; j < blk.dims[1]; ++j) {
                for (int i = 0; i < blk.dims[0]; ++i) {
                    const int idx[3] = {i, j, k};
                    for (int comp = 0; comp < 3; ++comp) {
                        double s = 0;
                        for (int d = 0; d < 3; ++d) {
                            s += sbpDiff(m.at(i, j, k) + 3 * d + comp, kMetricWidth * m.stride(d), idx[d], blk.dims[d]);
                            scale = std::max(scale, std::abs(m.at(i, j, k)[3 * d + comp]));
                        }
                        defect = std::max(defect, std::abs(s));
                    }
                }
            }
        }
    }
}

}  // namespace

TEST(Metrics, AffineGridHasExactMetricsAndVolume) {
    // x = A xi + b: metrics are the cofactors of A, 1/J = det A, on every node (boundaries too).
    FlowCase c = wavyBox(5, mesh::BoundaryKind::Symmetry, 0.0);
    const double A[3][3] = {{0.3, 0.05, -0.02}, {0.01, 0.25, 0.04}, {0.03, -0.06, 0.2}};
    for (long n = 0; n < c.fm.nodeCount; ++n) {
        const double xi[3] = {c.x[3 * n], c.x[3 * n + 1], c.x[3 * n + 2]};
        for (int r = 0; r < 3; ++r) c.x[3 * n + r] = 1.0 + A[r][0] * xi[0] + A[r][1] * xi[1] + A[r][2] * xi[2];
    }
    c.metrics = computeMetrics(c.fm, c.x);
    const Eigen::Matrix3d M = (Eigen::Matrix3d() << A[0][0], A[0][1], A[0][2], A[1][0], A[1][1], A[1][2], A[2][0], A[2][1], A[2][2]).finished();
    // Block A: i, j, k run along x, y, z with spacings 1/4 (x: 2/8), 1/3, 1/5.
    const Eigen::Matrix3d dxdxi = M * Eigen::Vector3d(0.25, 1.0 / 3.0, 0.2).asDiagonal();
    const double det = dxdxi.determinant();
    const Eigen::Matrix3d grad = dxdxi.inverse();  // rows: grad(xi), grad(eta), grad(zeta)
    for (long n = 0; n < c.fm.blocks[0].nodeCount(); ++n) {
        const double* m = &c.metrics[kMetricWidth * n];
        for (int d = 0; d < 3; ++d) {
            for (int comp = 0; comp < 3; ++comp) EXPECT_NEAR(m[3 * d + comp], grad(d, comp) * det, 1e-15);
        }
        EXPECT_NEAR(m[9], det, 1e-15);
    }
}

TEST(Metrics, GeometricConservationHoldsOnTheHalfSphere) {
    const FlowCase& c = halfSphere(0.5);
    double defect, scale;
    gclDefect(c, defect, scale);
    RecordProperty("gcl_defect", std::to_string(defect));
    EXPECT_LT(defect, 1e-14 * scale) << "defect " << defect << " metric scale " << scale;
    const VolumeCheck v = checkVolumes(c.fm, c.metrics);
    EXPECT_GT(v.minJinv, 0.0) << "block " << v.block << " node " << v.node;
}

TEST(Metrics, InterfaceNormalsAreOppositeAndSymmetryNormalsAreAlongY) {
    const FlowCase& c = halfSphere(0.5);
    for (const InterfacePatch& ip : c.fm.interfaces) {
        for (const auto& pr : ip.nodes) {
            double na[3], nb[3];
            outwardNormal(&c.metrics[kMetricWidth * (c.fm.blocks[ip.blockA].offset + pr[0])], ip.faceA, na);
            outwardNormal(&c.metrics[kMetricWidth * (c.fm.blocks[ip.blockB].offset + pr[1])], ip.faceB, nb);
            const double len = std::sqrt(na[0] * na[0] + na[1] * na[1] + na[2] * na[2]);
            for (int a = 0; a < 3; ++a) ASSERT_NEAR(na[a], -nb[a], 1e-14 * len);
        }
    }
    int symmetryFaces = 0;
    for (const FlowBlock& blk : c.fm.blocks) {
        for (int f = 0; f < 6; ++f) {
            if (blk.faces[f].kind != mesh::BoundaryKind::Symmetry) continue;
            ++symmetryFaces;
            for (long node : faceNodes(blk.dims, f)) {
                double n[3];
                outwardNormal(&c.metrics[kMetricWidth * (blk.offset + node)], f, n);
                EXPECT_LT(n[1], 0.0);  // out of the y >= 0 domain
                EXPECT_LT(std::abs(n[0]) + std::abs(n[2]), 1e-12 * std::abs(n[1]));
            }
        }
    }
    EXPECT_EQ(symmetryFaces, 8);
}

TEST(Metrics, WavyBoxSatisfiesGeometricConservation) {
    const FlowCase c = wavyBox(9, mesh::BoundaryKind::Wall);
    double defect, scale;
    gclDefect(c, defect, scale);
    EXPECT_LT(defect, 1e-15 * scale * 10);
    EXPECT_GT(checkVolumes(c.fm, c.metrics).minJinv, 0.0);
}
