#include "ffd/DesignVariables.h"

#include <complex>

#include "common/Error.h"

namespace aero::ffd {

namespace {
const char* kAxis = "xyz";
}

DesignSpace::DesignSpace(std::vector<Lattice> lattices) : lattices_(std::move(lattices)) {}

int DesignSpace::addStations(const StationSpec& spec) {
    if (spec.lattice < 0 || spec.lattice >= static_cast<int>(lattices_.size())) {
        throw CaseError("design_variables.stations.lattice: no lattice " + std::to_string(spec.lattice));
    }
    if (spec.direction < 0 || spec.direction > 2) {
        throw CaseError("design_variables.stations.direction: must be 0, 1 or 2, got " + std::to_string(spec.direction));
    }
    if (spec.vertical < 0 || spec.vertical > 2 || spec.streamwise < 0 || spec.streamwise > 2) {
        throw CaseError("design_variables.stations: vertical and streamwise axes must be 0, 1 or 2");
    }
    const Lattice& L = lattices_[spec.lattice];
    const int nStations = L.count[spec.direction];
    if (!spec.bits.empty() && static_cast<int>(spec.bits.size()) != nStations) {
        throw CaseError("design_variables.stations.bits: " + std::to_string(spec.bits.size()) + " bit strings for " +
                        std::to_string(nStations) + " stations");
    }
    // Every bit string is checked before anything is added, so a refused spec changes nothing.
    for (std::size_t s = 0; s < spec.bits.size(); ++s) {
        const std::string& b = spec.bits[s];
        if (b.size() != 3 || b.find_first_not_of("01") != std::string::npos) {
            throw CaseError("design_variables.stations.bits[" + std::to_string(s) + "]: expected three 0/1 digits (zyx), got '" + b + "'");
        }
    }
    const int before = size();
    const int first = static_cast<int>(stations_.size());
    for (int s = 0; s < nStations; ++s) {
        Station st;
        st.lattice = spec.lattice;
        st.group = groups_;
        st.ordinal = s;
        for (int k = 0; k < L.count[2]; ++k) {
            for (int j = 0; j < L.count[1]; ++j) {
                for (int i = 0; i < L.count[0]; ++i) {
                    const int ijk[3] = {i, j, k};
                    if (ijk[spec.direction] == s) st.points.push_back(L.index(i, j, k));
                }
            }
        }
        for (int a : st.points) {
            for (int c = 0; c < 3; ++c) st.reference[c] += L.points[3 * a + c] / st.points.size();
        }
        stations_.push_back(std::move(st));
    }
    const std::string prefix = (spec.prefix.empty() ? "L" + std::to_string(spec.lattice) : spec.prefix) + ".S";
    for (int s = 0; s < nStations; ++s) {
        const int sid = first + s;
        const std::string sname = prefix + std::to_string(s);
        if (!spec.bits.empty()) {
            const std::string& b = spec.bits[s];
            for (int axis = 0; axis < 3; ++axis) {
                if (b[2 - axis] != '1') continue;
                DesignVariable d;
                d.name = sname + ".t" + kAxis[axis];
                d.kind = VariableKind::Translate;
                d.lattice = spec.lattice;
                d.station = sid;
                d.axis = axis;
                d.baseline = 0;
                d.lower = -spec.translationBound;
                d.upper = spec.translationBound;
                d.scale = spec.translationBound;
                variables_.push_back(d);
            }
        }
    }
    if (spec.sectionScaling) {
        for (int s = 0; s < nStations; ++s) {
            for (int a : stations_[first + s].points) {
                DesignVariable d;
                d.name = prefix + std::to_string(s) + ".P" + std::to_string(a) + ".s" + kAxis[spec.vertical];
                d.kind = VariableKind::SectionScale;
                d.lattice = spec.lattice;
                d.station = first + s;
                d.point = a;
                d.axis = spec.vertical;
                d.baseline = 1;
                d.lower = spec.scalingBounds[0];
                d.upper = spec.scalingBounds[1];
                variables_.push_back(d);
            }
        }
    }
    if (spec.taper) {
        for (int s = 0; s < nStations; ++s) {
            DesignVariable d;
            d.name = prefix + std::to_string(s) + ".taper" + kAxis[spec.streamwise];
            d.kind = VariableKind::Taper;
            d.lattice = spec.lattice;
            d.station = first + s;
            d.axis = spec.streamwise;
            d.baseline = 1;
            d.lower = spec.taperBounds[0];
            d.upper = spec.taperBounds[1];
            variables_.push_back(d);
        }
    }
    ++groups_;
    return size() - before;
}

void DesignSpace::addPointCoordinate(int lattice, int point, int axis, double lower, double upper,
                                     const std::string& prefix) {
    if (lattice < 0 || lattice >= static_cast<int>(lattices_.size()) || point < 0 ||
        point >= lattices_[lattice].controlCount() || axis < 0 || axis > 2) {
        throw CaseError("design variable: no lattice point " + std::to_string(point) + " / axis " +
                        std::to_string(axis) + " in lattice " + std::to_string(lattice));
    }
    if (!(lower <= 0.0 && 0.0 <= upper)) {
        throw CaseError("design variable on lattice point " + std::to_string(point) + ": bounds [" +
                        std::to_string(lower) + ", " + std::to_string(upper) + "] must contain 0 (the baseline)");
    }
    DesignVariable d;
    d.name = (prefix.empty() ? "L" + std::to_string(lattice) : prefix) + ".P" + std::to_string(point) + "." + kAxis[axis];
    d.kind = VariableKind::PointCoordinate;
    d.lattice = lattice;
    d.point = point;
    d.axis = axis;
    d.baseline = 0;
    d.lower = lower;
    d.upper = upper;
    d.scale = std::max(std::abs(lower), std::abs(upper));
    variables_.push_back(d);
}

std::vector<double> DesignSpace::baselineValues() const {
    std::vector<double> v;
    for (const auto& d : variables_) v.push_back(d.baseline);
    return v;
}

int DesignSpace::find(const std::string& name) const {
    for (int i = 0; i < size(); ++i) {
        if (variables_[i].name == name) return i;
    }
    return -1;
}

template <class T>
std::vector<T> DesignSpace::latticePoints(int lattice, std::span<const T> v) const {
    const Lattice& L = lattices_[lattice];
    std::vector<T> B(L.points.begin(), L.points.end());
    for (int i = 0; i < size(); ++i) {
        const DesignVariable& d = variables_[i];
        if (d.lattice != lattice) continue;
        const T dv = v[i] - T(d.baseline);
        switch (d.kind) {
            case VariableKind::Translate:
                for (int a : stations_[d.station].points) B[3 * a + d.axis] += dv;
                break;
            case VariableKind::SectionScale: {
                const double ref = stations_[d.station].reference[d.axis];
                B[3 * d.point + d.axis] += dv * (L.points[3 * d.point + d.axis] - ref);
                break;
            }
            case VariableKind::Taper: {
                const double ref = stations_[d.station].reference[d.axis];
                for (int a : stations_[d.station].points) B[3 * a + d.axis] += dv * (L.points[3 * a + d.axis] - ref);
                break;
            }
            case VariableKind::PointCoordinate:
                B[3 * d.point + d.axis] += dv;
                break;
        }
    }
    return B;
}

Lattice DesignSpace::lattice(int lattice, std::span<const double> v) const {
    Lattice L = lattices_[lattice];
    L.points = latticePoints<double>(lattice, v);
    return L;
}

Eigen::SparseMatrix<double> DesignSpace::jacobian(int lattice) const {
    const Lattice& L = lattices_[lattice];
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < size(); ++i) {
        const DesignVariable& d = variables_[i];
        if (d.lattice != lattice) continue;
        switch (d.kind) {
            case VariableKind::Translate:
                for (int a : stations_[d.station].points) t.emplace_back(3 * a + d.axis, i, 1.0);
                break;
            case VariableKind::SectionScale:
                t.emplace_back(3 * d.point + d.axis, i,
                               L.points[3 * d.point + d.axis] - stations_[d.station].reference[d.axis]);
                break;
            case VariableKind::Taper:
                for (int a : stations_[d.station].points) {
                    t.emplace_back(3 * a + d.axis, i, L.points[3 * a + d.axis] - stations_[d.station].reference[d.axis]);
                }
                break;
            case VariableKind::PointCoordinate:
                t.emplace_back(3 * d.point + d.axis, i, 1.0);
                break;
        }
    }
    Eigen::SparseMatrix<double> J(3 * L.controlCount(), size());
    J.setFromTriplets(t.begin(), t.end());
    return J;
}

template std::vector<double> DesignSpace::latticePoints(int, std::span<const double>) const;
template std::vector<std::complex<double>> DesignSpace::latticePoints(int, std::span<const std::complex<double>>) const;

}  // namespace aero::ffd
