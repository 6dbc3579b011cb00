#include "mesh/VolumeFit.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "common/Error.h"
#include "nurbs/Basis.h"

namespace aero::mesh {

namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr const char* kDirName[3] = {"i", "j", "k"};

std::string who(const StructuredGrid& g) {
    return "volume fit of block '" + g.name + "'";
}

void checkGrid(const StructuredGrid& g) {
    for (int d = 0; d < 3; ++d) {
        if (g.dims[d] < 2) {
            throw GeometryError(who(g) + ": dims must be at least 2, got " +
                                std::to_string(g.dims[0]) + " x " + std::to_string(g.dims[1]) +
                                " x " + std::to_string(g.dims[2]));
        }
    }
    if (g.xyz.size() != 3 * static_cast<std::size_t>(g.nodeCount())) {
        throw GeometryError(who(g) + ": xyz has " + std::to_string(g.xyz.size()) +
                            " values, expected 3 * " + std::to_string(g.nodeCount()));
    }
    for (std::size_t a = 0; a < g.xyz.size(); ++a) {
        if (!std::isfinite(g.xyz[a])) {
            throw GeometryError(who(g) + ": node " + std::to_string(a / 3) +
                                " has a non-finite coordinate");
        }
    }
}

// The (count x n) operator mapping n line data to count control points: least squares with
// both ends interpolated (Piegl & Tiller 9.4.1 with the end points fixed).
RowMatrix lineOperator(const std::vector<double>& params, const std::vector<double>& knots,
                       int degree, int count, const StructuredGrid& g, int dir) {
    const int n = static_cast<int>(params.size());
    RowMatrix A = RowMatrix::Zero(count, n);
    A(0, 0) = 1.0;
    A(count - 1, n - 1) = 1.0;
    if (count == 2) return A;
    // Collocation matrix of the interior data rows 1..n-2 against all basis functions.
    Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n - 2, count);
    double row[nurbs::kMaxDegree + 1];
    for (int r = 1; r < n - 1; ++r) {
        const int span = nurbs::findSpan(knots, degree, count, params[r]);
        nurbs::basisFunctions(knots, degree, span, params[r], row);
        for (int a = 0; a <= degree; ++a) N(r - 1, span - degree + a) = row[a];
    }
    // Interior unknowns P_1..P_{count-2}: min |M P - (Q_interior - N_0 Q_0 - N_last Q_last)|.
    const Eigen::MatrixXd M = N.middleCols(1, count - 2);
    Eigen::MatrixXd R = Eigen::MatrixXd::Zero(n - 2, n);
    R.col(0) = -N.col(0);
    R.col(n - 1) = -N.col(count - 1);
    R.middleCols(1, n - 2) += Eigen::MatrixXd::Identity(n - 2, n - 2);
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(M);
    if (qr.rank() < count - 2) {
        throw GeometryError(who(g) + ", direction " + kDirName[dir] +
                            ": the least-squares fit is singular (rank " +
                            std::to_string(qr.rank()) + " of " + std::to_string(count - 2) +
                            "): some knot span holds no grid parameter; coincident nodes?");
    }
    A.middleRows(1, count - 2) = qr.solve(R);
    return A;
}

}  // namespace

std::vector<double> chordLengthParameters(const StructuredGrid& g, int dir) {
    const int n = g.dims[dir];
    const int o1 = (dir + 1) % 3, o2 = (dir + 2) % 3;
    std::vector<double> sum(n, 0.0), line(n);
    long lines = 0;
    int idx[3];
    for (int b = 0; b < g.dims[o2]; ++b) {
        for (int a = 0; a < g.dims[o1]; ++a) {
            idx[o1] = a;
            idx[o2] = b;
            idx[dir] = 0;
            const double* prev = g.at(idx[0], idx[1], idx[2]);
            line[0] = 0.0;
            for (int s = 1; s < n; ++s) {
                idx[dir] = s;
                const double* cur = g.at(idx[0], idx[1], idx[2]);
                const double dx = cur[0] - prev[0], dy = cur[1] - prev[1], dz = cur[2] - prev[2];
                line[s] = line[s - 1] + std::sqrt(dx * dx + dy * dy + dz * dz);
                prev = cur;
            }
            const double total = line[n - 1];
            if (!(total > 0)) continue;  // collapsed line (e.g. a polar axis): no information
            for (int s = 1; s < n; ++s) sum[s] += line[s] / total;
            ++lines;
        }
    }
    std::vector<double> u(n);
    for (int s = 0; s < n; ++s) {
        u[s] = lines > 0 ? sum[s] / static_cast<double>(lines) : static_cast<double>(s) / (n - 1);
    }
    u[0] = 0.0;
    u[n - 1] = 1.0;
    for (int s = 1; s < n; ++s) u[s] = std::clamp(u[s], u[s - 1], 1.0);  // guard round-off
    return u;
}

std::vector<double> fitKnots(const std::vector<double>& params, int degree, int count,
                             KnotPlacement placement) {
    if (placement == KnotPlacement::Uniform) return nurbs::uniformKnots(degree, count);
    const int m = static_cast<int>(params.size()) - 1;  // last data index
    const int n = count - 1;                            // last control index
    std::vector<double> U(static_cast<std::size_t>(count + degree + 1), 0.0);
    std::fill(U.end() - (degree + 1), U.end(), 1.0);
    if (n == m) {
        // Eq. 9.8: each interior knot is the mean of `degree` consecutive parameters.
        for (int j = 1; j <= n - degree; ++j) {
            double s = 0;
            for (int i = j; i < j + degree; ++i) s += params[i];
            U[j + degree] = s / degree;
        }
    } else {
        // Eq. 9.69: knots interpolated between parameters so that every span holds data.
        const double d = static_cast<double>(m + 1) / (n - degree + 1);
        for (int j = 1; j <= n - degree; ++j) {
            const int i = static_cast<int>(j * d);
            const double alpha = j * d - i;
            U[degree + j] = (1.0 - alpha) * params[i - 1] + alpha * params[i];
        }
    }
    return U;
}

FitResult fitVolume(const StructuredGrid& g, const FitOptions& o) {
    checkGrid(g);
    FitResult res;
    nurbs::Volume<double>& v = res.volume;
    std::array<RowMatrix, 3> A;
    for (int d = 0; d < 3; ++d) {
        const int p = o.degree[d], dims = g.dims[d];
        const std::string dirLabel = who(g) + ", direction " + kDirName[d];
        if (p < 1 || p > nurbs::kMaxDegree) {
            throw GeometryError(dirLabel + ": degree " + std::to_string(p) + " outside 1.." +
                                std::to_string(nurbs::kMaxDegree));
        }
        int count = o.count[d];
        if (count == 0) count = std::min(dims, std::max(p + 1, (dims - 1) / 4 + p));
        if (count < p + 1) {
            throw GeometryError(dirLabel + ": count " + std::to_string(count) +
                                " < degree + 1 = " + std::to_string(p + 1) + " (grid dims " +
                                std::to_string(dims) + ")");
        }
        if (count > dims) {
            throw GeometryError(dirLabel + ": count " + std::to_string(count) + " > grid dims " +
                                std::to_string(dims) + " (more control points than nodes)");
        }
        std::vector<double>& u = res.params[d];
        if (!o.params[d].empty()) {
            u = o.params[d];
            bool ok = static_cast<int>(u.size()) == dims && u.front() == 0.0 && u.back() == 1.0;
            for (std::size_t s = 1; ok && s < u.size(); ++s) ok = u[s] >= u[s - 1];
            if (!ok) {
                throw GeometryError(dirLabel + ": explicit params must be " + std::to_string(dims) +
                                    " non-decreasing values from 0 to 1 (got " +
                                    std::to_string(u.size()) + " values)");
            }
        } else if (o.parameterization == Parameterization::Uniform) {
            u.resize(dims);
            for (int s = 0; s < dims; ++s) u[s] = static_cast<double>(s) / (dims - 1);
        } else {
            u = chordLengthParameters(g, d);
        }
        v.degree[d] = p;
        v.count[d] = count;
        v.knots[d] = fitKnots(u, p, count, o.knots);
        nurbs::validateKnotVector(v.knots[d], p, count, dirLabel + " knots");
        A[d] = lineOperator(u, v.knots[d], p, count, g, d);
    }

    // Control net = (A2 (x) A1 (x) A0) X, one direction at a time; layouts [k][j][i][xyz].
    const int m0 = g.dims[0], m1 = g.dims[1], m2 = g.dims[2];
    const int n0 = v.count[0], n1 = v.count[1], n2 = v.count[2];
    using Lines3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
    std::vector<double> T0(static_cast<std::size_t>(m2) * m1 * n0 * 3);
#pragma omp parallel for schedule(static) if (static_cast<long>(m1) * m2 > 64)
    for (int line = 0; line < m1 * m2; ++line) {
        const Eigen::Map<const Lines3> X(&g.xyz[static_cast<std::size_t>(line) * m0 * 3], m0, 3);
        Eigen::Map<Lines3> Y(&T0[static_cast<std::size_t>(line) * n0 * 3], n0, 3);
        Y.noalias() = A[0] * X;
    }
    std::vector<double> T1(static_cast<std::size_t>(m2) * n1 * n0 * 3);
    for (int k = 0; k < m2; ++k) {
        const Eigen::Map<const RowMatrix> X(&T0[static_cast<std::size_t>(k) * m1 * n0 * 3], m1,
                                            n0 * 3);
        Eigen::Map<RowMatrix> Y(&T1[static_cast<std::size_t>(k) * n1 * n0 * 3], n1, n0 * 3);
        Y.noalias() = A[1] * X;
    }
    v.points.resize(static_cast<std::size_t>(n2) * n1 * n0 * 3);
    {
        const Eigen::Map<const RowMatrix> X(T1.data(), m2, static_cast<Eigen::Index>(n1) * n0 * 3);
        Eigen::Map<RowMatrix> Y(v.points.data(), n2, static_cast<Eigen::Index>(n1) * n0 * 3);
        Y.noalias() = A[2] * X;
    }
    nurbs::validate(v, who(g) + ": fitted volume");

    // Distances between the nodes and the volume at their parameters.
    std::vector<double> fitted(g.xyz.size());
    nurbs::sampleGrid(v, res.params[0], res.params[1], res.params[2], fitted.data());
    double maxSq = 0, sumSq = 0;
    const long nodes = g.nodeCount();
#pragma omp parallel for schedule(static) reduction(max : maxSq) reduction(+ : sumSq) \
    if (nodes > 16384)
    for (long a = 0; a < nodes; ++a) {
        const double dx = fitted[3 * a] - g.xyz[3 * a], dy = fitted[3 * a + 1] - g.xyz[3 * a + 1];
        const double dz = fitted[3 * a + 2] - g.xyz[3 * a + 2];
        const double sq = dx * dx + dy * dy + dz * dz;
        maxSq = std::max(maxSq, sq);
        sumSq += sq;
    }
    res.maxError = std::sqrt(maxSq);
    res.rmsError = std::sqrt(sumSq / static_cast<double>(nodes));
    return res;
}

}  // namespace aero::mesh
