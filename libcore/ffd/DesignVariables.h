#pragma once
// Design variables v that move lattice control points B(v) (Section V of the paper):
// cross-section stations that translate, per-point section scalings, per-station taper,
// and plain per-point coordinates. The map is affine in v; dB/dv is assembled analytically
// and B(v) is a template on the scalar type so complex step can check it.
#include <Eigen/SparseCore>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "ffd/Lattice.h"

namespace aero::ffd {

enum class VariableKind {
    Translate,        // every point of a station moves along a world axis by v
    SectionScale,     // one point's `vertical` coordinate: ref + v * (b0 - ref) about its station
    Taper,            // a station's `streamwise` coordinates: ref + v * (b0 - ref)
    PointCoordinate,  // one point's world coordinate `axis` moves by v
};

struct DesignVariable {
    std::string name;
    VariableKind kind = VariableKind::PointCoordinate;
    int lattice = 0;
    int station = -1;   // Translate, SectionScale (its station), Taper
    int point = -1;     // SectionScale, PointCoordinate: lattice control-point index
    int axis = 0;       // world axis moved (0 x, 1 y, 2 z)
    double baseline = 0;   // the undeformed value: 0 for displacements, 1 for scalings
    double lower = -1, upper = 1;
    double scale = 1;      // typical magnitude, for optimizers
};

/// Stations: the slices of a lattice at constant index along `direction` (the paper: the
/// spanwise lattice direction). bits[s] is the paper's translation bit string of station s,
/// "zyx" (rightmost = X): "011" translates in X and Y.
struct StationSpec {
    std::string prefix;   // variable-name prefix (the lattice's name); "L<lattice>" if empty
    int lattice = 0;
    int direction = 1;
    std::vector<std::string> bits;  // one per station; empty: no translations
    bool sectionScaling = true;
    bool taper = true;
    int vertical = 2;    // world axis of the per-point section scaling
    int streamwise = 0;  // world axis of the taper
    double translationBound = 1.0;                 // |displacement| bound
    std::array<double, 2> scalingBounds{0.5, 2.0};  // factor bounds (section scaling)
    std::array<double, 2> taperBounds{0.5, 2.0};    // factor bounds (taper)
};

struct Station {
    int lattice = 0;
    int group = 0;    // which addStations call made it (stations of a group are adjacent)
    int ordinal = 0;  // index along the station direction
    std::vector<int> points;                 // lattice control-point indices
    std::array<double, 3> reference{0, 0, 0};  // centroid of the baseline points
};

class DesignSpace {
public:
    /// Baseline lattices (their control points are B at v = baseline).
    explicit DesignSpace(std::vector<Lattice> lattices);

    /// Adds the station variables of `spec`; returns the number added. Throws CaseError on a
    /// bad lattice index, direction, axis or bit string (naming it).
    int addStations(const StationSpec& spec);
    /// Adds one plain variable moving point `point` of `lattice` along world `axis`; its name is
    /// "<prefix>.P<point>.<axis>" ("L<lattice>" if prefix is empty).
    void addPointCoordinate(int lattice, int point, int axis, double lower, double upper,
                            const std::string& prefix = "");

    int size() const { return static_cast<int>(variables_.size()); }
    const std::vector<DesignVariable>& variables() const { return variables_; }
    std::vector<DesignVariable>& variables() { return variables_; }
    const std::vector<Station>& stations() const { return stations_; }
    const std::vector<Lattice>& baseline() const { return lattices_; }
    std::vector<double> baselineValues() const;
    /// Index of a variable by name, or -1.
    int find(const std::string& name) const;

    /// B(v) of one lattice: 3 * controlCount coordinates.
    template <class T>
    std::vector<T> latticePoints(int lattice, std::span<const T> v) const;
    /// The lattice with control points B(v).
    Lattice lattice(int lattice, std::span<const double> v) const;

    /// dB/dv of one lattice: (3 * controlCount) x size(), constant (the map is affine).
    Eigen::SparseMatrix<double> jacobian(int lattice) const;

private:
    std::vector<Lattice> lattices_;
    std::vector<Station> stations_;
    std::vector<DesignVariable> variables_;
    int groups_ = 0;
};

}  // namespace aero::ffd
