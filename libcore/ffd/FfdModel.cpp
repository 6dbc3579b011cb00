#include "ffd/FfdModel.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <limits>

#include "geometry/EnclosedVolume.h"

namespace aero::ffd {

FfdModel::FfdModel(geometry::PatchSet baseline, std::vector<LatticeSpec> lattices, const EmbeddingOptions& o)
    : baseline_(std::move(baseline)), specs_(std::move(lattices)) {
    const auto t0 = std::chrono::steady_clock::now();
    index_ = geometry::buildControlPointIndex(baseline_, 1e-10);
    summary_.unique = index_.uniqueCount();
    std::vector<bool> owned(index_.uniqueCount(), false), requested(index_.uniqueCount(), false);
    std::vector<EmbeddingFailure> failures;
    for (const LatticeSpec& spec : specs_) {
        Embedding e = embed(baseline_, spec.lattice, spec.patches, o);
        // Keep only points no earlier lattice owns.
        Embedding mine;
        mine.index = index_;
        mine.iterationsMax = e.iterationsMax;
        mine.seconds = e.seconds;
        for (std::size_t p = 0; p < e.points.size(); ++p) {
            const int u = e.points[p];
            requested[u] = true;
            if (owned[u]) continue;
            owned[u] = true;
            mine.points.push_back(u);
            mine.params.insert(mine.params.end(), &e.params[3 * p], &e.params[3 * p] + 3);
        }
        for (const auto& f : e.failures) {
            requested[f.point] = true;
            failures.push_back(f);
        }
        mine.maxError = e.maxError;
        summary_.maxError = std::max(summary_.maxError, e.maxError);
        embeddings_.push_back(std::move(mine));
    }
    for (const auto& f : failures) {
        const bool already = std::any_of(summary_.failures.begin(), summary_.failures.end(),
                                         [&](const EmbeddingFailure& g) { return g.point == f.point; });
        if (!owned[f.point] && !already) summary_.failures.push_back(f);
    }
    for (int u = 0; u < index_.uniqueCount(); ++u) {
        summary_.embedded += owned[u] ? 1 : 0;
        summary_.fixed += requested[u] ? 0 : 1;
    }
    std::vector<Lattice> ls;
    for (const auto& s : specs_) ls.push_back(s.lattice);
    design_ = std::make_unique<DesignSpace>(std::move(ls));
    summary_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

template <class T>
std::vector<T> FfdModel::uniquePoints(std::span<const T> v) const {
    std::vector<T> A(index_.points.begin(), index_.points.end());
    for (std::size_t l = 0; l < specs_.size(); ++l) {
        const Embedding& e = embeddings_[l];
        nurbs::Volume<T> L;
        L.degree = specs_[l].lattice.degree;
        L.count = specs_[l].lattice.count;
        L.knots = specs_[l].lattice.knots;
        L.weights.assign(specs_[l].lattice.weights.begin(), specs_[l].lattice.weights.end());
        L.points = design_->latticePoints<T>(static_cast<int>(l), v);
        for (std::size_t p = 0; p < e.points.size(); ++p) {
            const nurbs::Vec3<T> P = nurbs::evaluate(L, T(e.params[3 * p]), T(e.params[3 * p + 1]), T(e.params[3 * p + 2]));
            for (int c = 0; c < 3; ++c) A[3 * e.points[p] + c] = P[c];
        }
    }
    return A;
}

geometry::PatchSet FfdModel::deform(std::span<const double> v) const {
    std::vector<Lattice> moved;
    for (std::size_t l = 0; l < specs_.size(); ++l) moved.push_back(design_->lattice(static_cast<int>(l), v));
    return deformWith(moved);
}

std::vector<double> FfdModel::uniqueWith(const std::vector<Lattice>& moved) const {
    std::vector<double> A = index_.points;
    for (std::size_t l = 0; l < specs_.size(); ++l) deformUnique(moved[l], embeddings_[l], A);
    return A;
}

geometry::PatchSet FfdModel::deformWith(const std::vector<Lattice>& moved) const {
    geometry::PatchSet out = baseline_;
    scatter(index_, uniqueWith(moved), out);
    return out;
}

Eigen::SparseMatrix<double> FfdModel::dUniqueDv() const {
    const int n = design_->size();
    Eigen::SparseMatrix<double> D(3 * index_.uniqueCount(), n);
    for (std::size_t l = 0; l < specs_.size(); ++l) {
        const Eigen::SparseMatrix<double, Eigen::RowMajor> W = sensitivity(specs_[l].lattice, embeddings_[l]);
        const Eigen::SparseMatrix<double> J = design_->jacobian(static_cast<int>(l));  // (3 nB) x n
        // Row c of J for coordinate c of lattice point a: J.row(3a + c). A_p,c = sum_a W(p,a) B_a,c.
        for (int c = 0; c < 3; ++c) {
            Eigen::SparseMatrix<double> Jc(W.cols(), n);
            std::vector<Eigen::Triplet<double>> t;
            for (int k = 0; k < J.outerSize(); ++k) {
                for (Eigen::SparseMatrix<double>::InnerIterator it(J, k); it; ++it) {
                    if (it.row() % 3 == c) t.emplace_back(static_cast<int>(it.row() / 3), static_cast<int>(it.col()), it.value());
                }
            }
            Jc.setFromTriplets(t.begin(), t.end());
            const Eigen::SparseMatrix<double> Pc = W * Jc;  // embedded points x n
            std::vector<Eigen::Triplet<double>> out;
            for (int k = 0; k < Pc.outerSize(); ++k) {
                for (Eigen::SparseMatrix<double>::InnerIterator it(Pc, k); it; ++it) {
                    out.emplace_back(3 * embeddings_[l].points[it.row()] + c, static_cast<int>(it.col()), it.value());
                }
            }
            Eigen::SparseMatrix<double> add(D.rows(), n);
            add.setFromTriplets(out.begin(), out.end());
            D += add;
        }
    }
    return D;
}

double FfdModel::volume(std::span<const double> v) const { return geometry::enclosedVolume(deform(v)); }

std::vector<double> FfdModel::volumeGradient(std::span<const double> v) const {
    const geometry::PatchSet set = deform(v);
    const std::vector<double> g = geometry::enclosedVolumeGradient(set);
    // Sum the non-unique gradient onto unique points, then chain with dA/dv.
    Eigen::VectorXd gu = Eigen::VectorXd::Zero(3 * index_.uniqueCount());
    for (std::size_t a = 0; a < index_.toUnique.size(); ++a) {
        for (int c = 0; c < 3; ++c) gu[3 * index_.toUnique[a] + c] += g[3 * a + c];
    }
    const Eigen::VectorXd dv = dUniqueDv().transpose() * gu;
    return std::vector<double>(dv.data(), dv.data() + dv.size());
}

std::vector<LinearConstraint> FfdModel::symmetryConstraints(double planeTolerance) const {
    const Eigen::SparseMatrix<double> D = dUniqueDv();
    const int n = design_->size();
    std::vector<Eigen::VectorXd> rows;
    for (const Embedding& e : embeddings_) {
        for (int u : e.points) {
            if (std::abs(index_.points[3 * u + 1]) > planeTolerance) continue;
            Eigen::VectorXd r = D.row(3 * u + 1).transpose();
            if (r.norm() > 0) rows.push_back(r);
        }
    }
    std::vector<LinearConstraint> out;
    if (rows.empty()) return out;
    Eigen::MatrixXd A(n, static_cast<int>(rows.size()));
    for (std::size_t i = 0; i < rows.size(); ++i) A.col(static_cast<int>(i)) = rows[i];
    // Independent rows: column-pivoted QR of A^T's columns picks a well-conditioned subset.
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    qr.setThreshold(1e-10);
    const Eigen::VectorXd vb = Eigen::Map<const Eigen::VectorXd>(design_->baselineValues().data(), n);
    for (int r = 0; r < qr.rank(); ++r) {
        const int col = qr.colsPermutation().indices()[r];
        LinearConstraint c;
        c.name = "symmetry[" + std::to_string(r) + "]";
        c.row.assign(A.col(col).data(), A.col(col).data() + n);
        c.lower = c.upper = A.col(col).dot(vb);  // y stays at its baseline value 0
        out.push_back(std::move(c));
    }
    return out;
}

std::vector<LinearConstraint> FfdModel::stationGapConstraints(double minGap) const {
    const auto& st = design_->stations();
    const int n = design_->size();
    const std::vector<double> vb = design_->baselineValues();
    std::vector<LinearConstraint> out;
    for (std::size_t s = 0; s + 1 < st.size(); ++s) {
        const Station &a = st[s], &b = st[s + 1];
        if (a.group != b.group) continue;
        nurbs::Vec3<double> e(b.reference[0] - a.reference[0], b.reference[1] - a.reference[1],
                              b.reference[2] - a.reference[2]);
        const double g0 = e.norm();
        e /= g0;
        // Centroid position along e: mean over the station of e . B_a(v); its v-derivative from dB/dv.
        const Eigen::SparseMatrix<double> J = design_->jacobian(a.lattice);
        Eigen::VectorXd row = Eigen::VectorXd::Zero(n);
        for (int c = 0; c < 3; ++c) {
            for (int p : b.points) row += (e[c] / b.points.size()) * J.row(3 * p + c).transpose();
            for (int p : a.points) row -= (e[c] / a.points.size()) * J.row(3 * p + c).transpose();
        }
        LinearConstraint c;
        c.name = "station_gap[" + std::to_string(a.ordinal) + "," + std::to_string(b.ordinal) + "]";
        c.row.assign(row.data(), row.data() + n);
        // g(v) = g0 + row . (v - vb) >= minGap
        c.lower = minGap - g0 + row.dot(Eigen::Map<const Eigen::VectorXd>(vb.data(), n));
        c.upper = std::numeric_limits<double>::infinity();
        out.push_back(std::move(c));
    }
    return out;
}

namespace {

// Whether r lies on the segment between a and +-b: then |a . d| <= M and |b . d| <= M imply
// |r . d| <= M, and the row r adds nothing to the bound.
bool onSegment(const Eigen::VectorXd& r, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    for (double sign : {1.0, -1.0}) {
        const Eigen::VectorXd e = sign * b - a;
        const double ee = e.squaredNorm();
        if (ee == 0) continue;
        const double t = (r - a).dot(e) / ee;
        if (t >= -1e-12 && t <= 1 + 1e-12 && (r - a - t * e).norm() <= 1e-12 * (1 + r.norm())) return true;
    }
    return false;
}

}  // namespace

std::vector<LinearConstraint> FfdModel::stationSecondDifferenceConstraints(double maxDifference) const {
    const auto& st = design_->stations();
    const int n = design_->size();
    const std::vector<double> baseline = design_->baselineValues();
    const Eigen::Map<const Eigen::VectorXd> vb(baseline.data(), n);
    const char* axes = "xyz";
    std::vector<LinearConstraint> out;
    for (std::size_t s = 1; s + 1 < st.size(); ++s) {
        const Station &a = st[s - 1], &b = st[s], &c = st[s + 1];
        if (a.group != b.group || b.group != c.group) continue;
        // Stations of a group walk one lattice direction in the same order over the other two,
        // so the m-th point of each lies on one lattice line across the stations.
        const Eigen::SparseMatrix<double, Eigen::RowMajor> J = design_->jacobian(b.lattice);
        for (int ax = 0; ax < 3; ++ax) {
            std::vector<Eigen::VectorXd> rows;
            std::vector<int> points;
            for (std::size_t m = 0; m < b.points.size(); ++m) {
                Eigen::VectorXd row = J.row(3 * a.points[m] + ax).transpose();
                row -= 2.0 * J.row(3 * b.points[m] + ax).transpose();
                row += J.row(3 * c.points[m] + ax).transpose();
                if (row.cwiseAbs().maxCoeff() < 1e-14) continue;
                rows.push_back(std::move(row));
                points.push_back(b.points[m]);
            }
            // Leave out the rows implied by two others (a repeat, or a point between two whose
            // rows differ only by its coordinate, as a taper's do): kept rows imply them still.
            std::vector<bool> kept(rows.size(), true);
            for (std::size_t m = rows.size(); m-- > 0;) {  // the later ones go first: names keep low indices
                for (std::size_t i = 0; i < rows.size() && kept[m]; ++i) {
                    for (std::size_t j = i; j < rows.size() && kept[m]; ++j) {
                        if (i == m || j == m || !kept[i] || !kept[j]) continue;
                        if (onSegment(rows[m], rows[i], rows[j])) kept[m] = false;
                    }
                }
            }
            for (std::size_t m = 0; m < rows.size(); ++m) {
                if (!kept[m]) continue;
                LinearConstraint k;
                k.name = "station_second_difference[" + std::to_string(b.ordinal) + ", point " +
                         std::to_string(points[m]) + ", " + axes[ax] + "]";
                // The displacement's second difference row . (v - vb) lies in [-max, max].
                const double shift = rows[m].dot(vb);
                k.row.assign(rows[m].data(), rows[m].data() + n);
                k.lower = shift - maxDifference;
                k.upper = shift + maxDifference;
                out.push_back(std::move(k));
            }
        }
    }
    return out;
}

std::pair<double, std::string> FfdModel::largestStationSecondDifference(std::span<const double> v) const {
    std::pair<double, std::string> worst{0.0, ""};
    for (const LinearConstraint& k : stationSecondDifferenceConstraints(0.0)) {
        double value = -k.lower;  // lower = shift at a zero bound
        for (std::size_t i = 0; i < v.size(); ++i) value += k.row[i] * v[i];
        if (std::abs(value) > worst.first) worst = {std::abs(value), k.name};
    }
    return worst;
}

template std::vector<double> FfdModel::uniquePoints(std::span<const double>) const;
template std::vector<std::complex<double>> FfdModel::uniquePoints(std::span<const std::complex<double>>) const;

}  // namespace aero::ffd
