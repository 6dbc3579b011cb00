// The trilinear hexahedral element of the elasticity move (Elasticity.h, HexElement.h): Gauss
// points, volume, orthogonality and modulus with their derivatives, the element stiffness and
// the bilinear form with its gradient.
#include "mesh/HexElement.h"

#include <Eigen/Dense>
#include <cmath>
#include <complex>

#include "common/Scalar.h"

namespace aero::mesh {

namespace {

// Trilinear shape-function derivatives dN_a/dxi at (xi, eta, zeta) in [-1, 1]^3, VTK corner order.
constexpr int kCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                               {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

void shapeDerivatives(double xi, double eta, double zeta, double dN[8][3]) {
    for (int a = 0; a < 8; ++a) {
        const double sx = kCorner[a][0], sy = kCorner[a][1], sz = kCorner[a][2];
        dN[a][0] = 0.125 * sx * (1 + sy * eta) * (1 + sz * zeta);
        dN[a][1] = 0.125 * sy * (1 + sx * xi) * (1 + sz * zeta);
        dN[a][2] = 0.125 * sz * (1 + sx * xi) * (1 + sy * eta);
    }
}

// Gauss point q of the 2x2x2 rule: the shape-function derivatives dN (in xi), the Jacobian
// J(r, c) = dx_r/dxi_c and its determinant.
template <class T>
T gaussJacobian(const T* x, int q, double dN[8][3], Eigen::Matrix<T, 3, 3>& J) {
    const double g = 1.0 / std::sqrt(3.0);
    shapeDerivatives(g * kCorner[q][0], g * kCorner[q][1], g * kCorner[q][2], dN);
    J.setZero();
    for (int a = 0; a < 8; ++a) {
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) J(r, c) += x[3 * a + r] * dN[a][c];
        }
    }
    return J.determinant();
}

// The same and the physical shape-function gradients G(a, c) = dN_a/dx_c; returns det J.
template <class T>
T gaussGradients(const T* x, int q, T G[8][3]) {
    double dN[8][3];
    Eigen::Matrix<T, 3, 3> J;
    const T det = gaussJacobian(x, q, dN, J);
    const Eigen::Matrix<T, 3, 3> Jinv = J.inverse();
    for (int a = 0; a < 8; ++a) {
        for (int c = 0; c < 3; ++c) G[a][c] = dN[a][0] * Jinv(0, c) + dN[a][1] * Jinv(1, c) + dN[a][2] * Jinv(2, c);
    }
    return det;
}

}  // namespace

// The cell's volume: the sum over the 2x2x2 Gauss points of det J.
template <class T>
T cellVolume(const T* x) {
    T volume = T(0.0);
    for (int q = 0; q < 8; ++q) {
        double dN[8][3];
        Eigen::Matrix<T, 3, 3> J;
        volume += gaussJacobian(x, q, dN, J);
    }
    return volume;
}

// cellModulus for a cell whose volume is known (the assembly computes every volume first, for
// their mean).
template <class T>
T modulusWithVolume(const T* x, T vol, T meanVolume, const ElasticityOptions& o) {
    const T q = cellOrthogonality(x);  // declared in the header, defined below
    T e = T(1.0);
    if (realPart(vol) > 0) e *= std::pow(meanVolume / vol, o.sizeStiffening);
    // clamp(q, 0, 1), piecewise: its derivative is q's inside and 0 outside.
    const T qc = realPart(q) < 0 ? T(0.0) : (realPart(q) > 1 ? T(1.0) : q);
    e *= 1.0 + o.orthogonalityStiffening * (1.0 - qc);
    return e;
}

template <class T>
void cellMetrics(const T* x, T& volume, T& minScaled) {
    volume = cellVolume(x);
    T corners[8];
    cornerScaledJacobians(x, corners);
    minScaled = T(1.0);
    for (int a = 0; a < 8; ++a) {
        if (realPart(corners[a]) < realPart(minScaled)) minScaled = corners[a];  // the active corner's value
    }
}

template <class T>
void cornerScaledJacobians(const T* x, T* corners) {
    // Corner a's three edges go to its neighbours along xi, eta, zeta.
    const int nb[8][3] = {{1, 3, 4}, {0, 2, 5}, {3, 1, 6}, {2, 0, 7}, {5, 7, 0}, {4, 6, 1}, {7, 5, 2}, {6, 4, 3}};
    for (int a = 0; a < 8; ++a) {
        Eigen::Matrix<T, 3, 3> E;
        for (int d = 0; d < 3; ++d) {
            const double sign = (kCorner[a][d] < 0) ? 1.0 : -1.0;  // edges point into the cell
            for (int c = 0; c < 3; ++c) E(c, d) = sign * (x[3 * nb[a][d] + c] - x[3 * a + c]);
            T len2 = T(0.0);
            for (int c = 0; c < 3; ++c) len2 += E(c, d) * E(c, d);
            if (realPart(len2) > 0) E.col(d) /= std::sqrt(len2);
        }
        corners[a] = E.determinant();
    }
}

template <class T>
T cellOrthogonality(const T* x) {
    using std::exp;
    using std::log;
    T q[8];
    cornerScaledJacobians(x, q);
    double lowest = realPart(q[0]);
    for (int a = 1; a < 8; ++a) lowest = std::min(lowest, realPart(q[a]));
    T s = T(0.0);
    for (int a = 0; a < 8; ++a) s += exp(-kOrthogonalitySharpness * (q[a] - lowest));
    return lowest - log(s / 8.0) / kOrthogonalitySharpness;
}

template <class T>
T hexBilinear(const T* x, T E, double nu, const double* a, const double* b) {
    const T lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    const T mu = E / (2 * (1 + nu));
    T sum = T(0.0);
    for (int q = 0; q < 8; ++q) {
        T G[8][3];
        const T det = gaussGradients(x, q, G);
        // Displacement gradients A(i, c) = sum_n a_n,i dN_n/dx_c, and B alike.
        Eigen::Matrix<T, 3, 3> A = Eigen::Matrix<T, 3, 3>::Zero(), B = Eigen::Matrix<T, 3, 3>::Zero();
        for (int n = 0; n < 8; ++n) {
            for (int i = 0; i < 3; ++i) {
                for (int c = 0; c < 3; ++c) {
                    A(i, c) += a[3 * n + i] * G[n][c];
                    B(i, c) += b[3 * n + i] * G[n][c];
                }
            }
        }
        T v = lambda * A.trace() * B.trace();
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) v += mu * (A(i, j) * B(j, i) + A(i, j) * B(i, j));
        }
        sum += v * det;
    }
    return sum;
}

template <class T>
T cellModulus(const T* x, T meanVolume, const ElasticityOptions& o) {
    return modulusWithVolume(x, cellVolume(x), meanVolume, o);
}

CellGauss::CellGauss(const double* x) {
    for (int q = 0; q < 8; ++q) det[q] = gaussGradients(x, q, G[q]);
}

double modulusGradient(const double* x, const CellGauss& gauss, double meanVolume, const ElasticityOptions& o,
                       double* dE, double* dVolume, double* volume) {
    // Volume: sum over the Gauss points of det J, d det J / dx_a,r = det J G_a,r (G = dN J^-1).
    double vol = 0;
    for (int i = 0; i < 24; ++i) dVolume[i] = 0;
    for (int qp = 0; qp < 8; ++qp) {
        const double(&G)[8][3] = gauss.G[qp];
        const double det = gauss.det[qp];
        vol += det;
        for (int a = 0; a < 8; ++a) {
            for (int r = 0; r < 3; ++r) dVolume[3 * a + r] += det * G[a][r];
        }
    }
    // Corner scaled Jacobians q_a = det[e1 e2 e3] / (|e1| |e2| |e3|), edges e_d = s_d (x_nb - x_a):
    // dq/de1 = (e2 x e3) / L - q e1 / |e1|^2 (and cyclically).
    const int nb[8][3] = {{1, 3, 4}, {0, 2, 5}, {3, 1, 6}, {2, 0, 7}, {5, 7, 0}, {4, 6, 1}, {7, 5, 2}, {6, 4, 3}};
    double q[8], dq[8][24] = {};
    for (int a = 0; a < 8; ++a) {
        Eigen::Vector3d e[3];
        double len[3];
        bool degenerate = false;
        for (int d = 0; d < 3; ++d) {
            const double sign = (kCorner[a][d] < 0) ? 1.0 : -1.0;
            for (int c = 0; c < 3; ++c) e[d][c] = sign * (x[3 * nb[a][d] + c] - x[3 * a + c]);
            len[d] = e[d].norm();
            degenerate = degenerate || len[d] == 0;
        }
        if (degenerate) {
            // A zero edge: cornerScaledJacobians keeps the zero column, q = 0, and so do we
            // (a degenerate cell has no derivative worth having).
            q[a] = 0;
            continue;
        }
        const double L = len[0] * len[1] * len[2];
        q[a] = e[0].dot(e[1].cross(e[2])) / L;
        for (int d = 0; d < 3; ++d) {
            const Eigen::Vector3d g = e[(d + 1) % 3].cross(e[(d + 2) % 3]) / L - q[a] * e[d] / (len[d] * len[d]);
            const double sign = (kCorner[a][d] < 0) ? 1.0 : -1.0;
            for (int c = 0; c < 3; ++c) {
                dq[a][3 * nb[a][d] + c] += sign * g[c];
                dq[a][3 * a + c] -= sign * g[c];
            }
        }
    }
    // Smooth minimum: o = lowest - log(mean_a exp(-r (q_a - lowest))) / r, do/dq_a = softmin weights.
    double lowest = q[0];
    for (int a = 1; a < 8; ++a) lowest = std::min(lowest, q[a]);
    double w[8], sum = 0;
    for (int a = 0; a < 8; ++a) sum += (w[a] = std::exp(-kOrthogonalitySharpness * (q[a] - lowest)));
    const double orth = lowest - std::log(sum / 8.0) / kOrthogonalitySharpness;
    // E = size * ortho, size = (mean / vol)^s (1 when vol <= 0), ortho = 1 + c (1 - clamp(orth, 0, 1)).
    const double size = vol > 0 ? std::pow(meanVolume / vol, o.sizeStiffening) : 1.0;
    const bool inside = orth >= 0 && orth <= 1;
    const double qc = orth < 0 ? 0.0 : (orth > 1 ? 1.0 : orth);
    const double ortho = 1.0 + o.orthogonalityStiffening * (1.0 - qc);
    for (int i = 0; i < 24; ++i) {
        double dOrth = 0;
        if (inside) {
            for (int a = 0; a < 8; ++a) dOrth += w[a] / sum * dq[a][i];
        }
        const double dSize = vol > 0 ? -o.sizeStiffening * size / vol * dVolume[i] : 0.0;
        dE[i] = dSize * ortho - size * o.orthogonalityStiffening * dOrth;
    }
    if (volume) *volume = vol;
    return size * ortho;
}


double cellModulusGradient(const double* x, double meanVolume, const ElasticityOptions& o, double* dE,
                           double* dVolume, double* volume) {
    return modulusGradient(x, CellGauss(x), meanVolume, o, dE, dVolume, volume);
}

template <class T>
void hexStiffness(const T* x, T E, double nu, T* K) {
    const T lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    const T mu = E / (2 * (1 + nu));
    // K_ab(i, j) = sum_q (lambda G_a,i G_b,j + mu G_a,j G_b,i + mu delta_ij G_a . G_b) det_q with
    // G the physical shape-function gradients at Gauss point q. With M_ab = sum_q det_q G_a G_b^T
    // (one 3x3 outer product per pair and point, 9 multiply-adds): K_ab = lambda M_ab + mu M_ab^T
    // + mu tr(M_ab) I, 2.3x faster than summing K_ab itself point by point. The upper block
    // triangle (a <= b, 36 pairs) is computed, the lower one mirrored (K_ba = K_ab^T).
    T M[36][9];
    for (auto& pair : M) {
        for (T& v : pair) v = T(0.0);
    }
    for (int q = 0; q < 8; ++q) {
        T G[8][3];  // physical gradients G(a, c) = dN_a / dx_c
        const T det = gaussGradients(x, q, G);
        T Gd[8][3];
        for (int a = 0; a < 8; ++a) {
            for (int c = 0; c < 3; ++c) Gd[a][c] = G[a][c] * det;
        }
        int p = 0;
        for (int a = 0; a < 8; ++a) {
            for (int b = a; b < 8; ++b, ++p) {
                for (int i = 0; i < 3; ++i) {
                    for (int j = 0; j < 3; ++j) M[p][3 * i + j] += Gd[a][i] * G[b][j];
                }
            }
        }
    }
    int p = 0;
    for (int a = 0; a < 8; ++a) {
        for (int b = a; b < 8; ++b, ++p) {
            const T trace = M[p][0] + M[p][4] + M[p][8];
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) {
                    T v = lambda * M[p][3 * i + j] + mu * M[p][3 * j + i];
                    if (i == j) v += mu * trace;
                    K[(3 * a + i) * 24 + 3 * b + j] = v;
                    K[(3 * b + j) * 24 + 3 * a + i] = v;
                }
            }
        }
    }
}

double hexBilinearGradient(const double* x, double nu, const double* a, const double* b, double* grad) {
    return bilinearGradient(CellGauss(x), nu, a, b, grad);
}

double bilinearGradient(const CellGauss& gauss, double nu, const double* a, const double* b, double* grad) {
    // s = sum_q det J_q Phi(A_q, B_q) with A = a^T G, G = dN J^-1 (8 x 3). For coordinate r of
    // corner n: d det = det G(n, r), dG = -G e_r G_n^T, so dA = -A e_r G_n^T (and dB alike), and
    // Phi being symmetric and bilinear, d Phi = -(G_n^T (P + Q))_r with
    // P = lambda tr(B) A + mu (B A + B^T A), Q = lambda tr(A) B + mu (A B + A^T B).
    const double lambda = nu / ((1 + nu) * (1 - 2 * nu));
    const double mu = 1.0 / (2 * (1 + nu));
    double sum = 0;
    for (int i = 0; i < 24; ++i) grad[i] = 0;
    for (int q = 0; q < 8; ++q) {
        const double det = gauss.det[q];
        const Eigen::Map<const Eigen::Matrix<double, 8, 3, Eigen::RowMajor>> G(&gauss.G[q][0][0]);
        Eigen::Matrix3d A = Eigen::Matrix3d::Zero(), B = Eigen::Matrix3d::Zero();
        for (int n = 0; n < 8; ++n) {
            for (int i = 0; i < 3; ++i) {
                for (int c = 0; c < 3; ++c) {
                    A(i, c) += a[3 * n + i] * G(n, c);
                    B(i, c) += b[3 * n + i] * G(n, c);
                }
            }
        }
        const double phi = lambda * A.trace() * B.trace() + mu * ((A * B).trace() + (A.array() * B.array()).sum());
        const Eigen::Matrix3d PQ = lambda * B.trace() * A + mu * (B * A + B.transpose() * A) + lambda * A.trace() * B +
                                   mu * (A * B + A.transpose() * B);
        sum += det * phi;
        const Eigen::Matrix<double, 8, 3> GPQ = G * PQ;
        for (int n = 0; n < 8; ++n) {
            for (int r = 0; r < 3; ++r) grad[3 * n + r] += det * (G(n, r) * phi - GPQ(n, r));
        }
    }
    return sum;
}

std::vector<double> cellStiffness(const MultiBlockMesh& m, int block, const ElasticityOptions& o, double meanVolume) {
    std::vector<double> E;
    forEachCell(m, m.blocks[block], [&](const double* x, const int*) { E.push_back(cellModulus(x, meanVolume, o)); });
    return E;
}

template void hexStiffness<double>(const double*, double, double, double*);
template double cellOrthogonality<double>(const double*);
template std::complex<double> cellOrthogonality<std::complex<double>>(const std::complex<double>*);
template double hexBilinear<double>(const double*, double, double, const double*, const double*);
template std::complex<double> hexBilinear<std::complex<double>>(const std::complex<double>*, std::complex<double>, double,
                                                                const double*, const double*);
template void cellMetrics<double>(const double*, double&, double&);
template void cellMetrics<std::complex<double>>(const std::complex<double>*, std::complex<double>&, std::complex<double>&);
template double cellModulus<double>(const double*, double, const ElasticityOptions&);
template std::complex<double> cellModulus<std::complex<double>>(const std::complex<double>*, std::complex<double>,
                                                                const ElasticityOptions&);
template void hexStiffness<std::complex<double>>(const std::complex<double>*, std::complex<double>, double,
                                                  std::complex<double>*);

template double cellVolume<double>(const double*);
template double modulusWithVolume<double>(const double*, double, double, const ElasticityOptions&);

}  // namespace aero::mesh
