#pragma once
// The first FFD level wired together: baseline patch set, lattices with their embeddings,
// design variables, and the geometric constraints of the paper (symmetry, station overlap,
// enclosed volume) with exact gradients. v -> B(v) -> A(v) -> patches.
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "ffd/DesignVariables.h"
#include "ffd/Embedding.h"
#include "geometry/PatchSet.h"

namespace aero::ffd {

struct LatticeSpec {
    std::string name;
    Lattice lattice;
    std::vector<int> patches;  // patches whose control points it owns (all if empty)
};

/// lower <= row . v <= upper.
struct LinearConstraint {
    std::string name;
    std::vector<double> row;
    double lower = 0, upper = 0;
};

struct EmbeddingSummary {
    int embedded = 0;       // unique control points embedded in some lattice
    int unique = 0;         // unique control points of the geometry
    int fixed = 0;          // unique points no lattice was asked to embed (they stay put)
    double maxError = 0;    // largest |V(xi) - t| over embedded points
    std::vector<EmbeddingFailure> failures;  // outside or not converged (never dropped)
    double seconds = 0;
};

class FfdModel {
public:
    /// Embeds the control points (each unique point belongs to the first lattice that
    /// embeds it). Failures are recorded in summary(), not thrown: callers decide.
    FfdModel(geometry::PatchSet baseline, std::vector<LatticeSpec> lattices, const EmbeddingOptions& o = {});

    const geometry::PatchSet& baseline() const { return baseline_; }
    const std::vector<LatticeSpec>& lattices() const { return specs_; }
    const std::vector<Embedding>& embeddings() const { return embeddings_; }
    const geometry::ControlPointIndex& index() const { return index_; }
    const EmbeddingSummary& summary() const { return summary_; }
    DesignSpace& design() { return *design_; }
    const DesignSpace& design() const { return *design_; }

    /// Unique control points A(v) (3 per point); templated for complex step.
    template <class T>
    std::vector<T> uniquePoints(std::span<const T> v) const;
    /// The deformed patch set at v.
    geometry::PatchSet deform(std::span<const double> v) const;
    /// Deformed patch set for explicitly moved lattices (one per spec), e.g. a GUI drag.
    geometry::PatchSet deformWith(const std::vector<Lattice>& moved) const;
    /// The deformed unique control points (3 per point, index() order) for moved lattices.
    std::vector<double> uniqueWith(const std::vector<Lattice>& moved) const;

    /// dA/dv: (3 * unique) x design().size(), exact (Eq. 3 times dB/dv).
    Eigen::SparseMatrix<double> dUniqueDv() const;

    double volume(std::span<const double> v) const;
    /// dV/dv, exact: dV/dA (analytic) dA/dB dB/dv.
    std::vector<double> volumeGradient(std::span<const double> v) const;

    /// Symmetry across Y = 0: embedded points on the plane keep y = 0 (independent rows only).
    std::vector<LinearConstraint> symmetryConstraints(double planeTolerance = 1e-12) const;
    /// Adjacent stations of each group keep at least `minGap` between their centroids along the
    /// station direction.
    std::vector<LinearConstraint> stationGapConstraints(double minGap) const;
    /// Three adjacent stations of a group bend each lattice point's displacement by at most
    /// `maxDifference`: |d(s-1) - 2 d(s) + d(s+1)| <= maxDifference per point of the station and
    /// per world axis (d = B(v) - B(baseline), case units). Rows that vanish, or that two kept
    /// rows imply (repeats, points between the chord's ends under a taper), are left out.
    std::vector<LinearConstraint> stationSecondDifferenceConstraints(double maxDifference) const;
    /// The largest |d(s-1) - 2 d(s) + d(s+1)| over the same rows at v, and the row's name.
    std::pair<double, std::string> largestStationSecondDifference(std::span<const double> v) const;

private:
    geometry::PatchSet baseline_;
    std::vector<LatticeSpec> specs_;
    std::vector<Embedding> embeddings_;   // one per lattice, owned points only
    geometry::ControlPointIndex index_;
    EmbeddingSummary summary_;
    std::unique_ptr<DesignSpace> design_;
};

}  // namespace aero::ffd
