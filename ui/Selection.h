#pragma once
// What the user has selected: the geometry, some patches, a lattice, or points of one lattice.
// Shared by the model tree, the property panel, the scenes and the lattice editor; GUI thread
// only. Selections are not edits (not undoable, not saved).
#include <QObject>
#include <algorithm>
#include <vector>

namespace aero::ui {

class Selection : public QObject {
    Q_OBJECT

  public:
    enum class Kind { None, Geometry, Patches, Lattice, LatticePoints };

    explicit Selection(QObject* parent = nullptr) : QObject(parent) {}

    Kind kind() const { return kind_; }
    /// Selected patches (0-based, sorted) for Kind::Patches.
    const std::vector<int>& patches() const { return patches_; }
    /// The lattice of Kind::Lattice and Kind::LatticePoints, else -1.
    int lattice() const { return lattice_; }
    /// Flat control-point indices (i + nx (j + ny k), sorted) for Kind::LatticePoints.
    const std::vector<int>& points() const { return points_; }
    bool hasPoint(int lattice, int point) const {
        return kind_ == Kind::LatticePoints && lattice == lattice_ &&
               std::binary_search(points_.begin(), points_.end(), point);
    }

    void clear() { set(Kind::None, {}, -1, {}); }
    void selectGeometry() { set(Kind::Geometry, {}, -1, {}); }
    void selectPatches(std::vector<int> patches) {
        if (patches.empty()) return clear();
        set(Kind::Patches, std::move(patches), -1, {});
    }
    void selectLattice(int lattice) { set(Kind::Lattice, {}, lattice, {}); }
    void selectPoints(int lattice, std::vector<int> points) {
        if (points.empty()) return selectLattice(lattice);
        set(Kind::LatticePoints, {}, lattice, std::move(points));
    }
    /// Adds or removes one point (a point of another lattice starts a new selection).
    void togglePoint(int lattice, int point) {
        std::vector<int> pts = (kind_ == Kind::LatticePoints && lattice_ == lattice) ? points_ : std::vector<int>{};
        const auto it = std::lower_bound(pts.begin(), pts.end(), point);
        if (it != pts.end() && *it == point)
            pts.erase(it);
        else
            pts.insert(it, point);
        selectPoints(lattice, std::move(pts));
    }

  signals:
    void changed();

  private:
    void set(Kind kind, std::vector<int> patches, int lattice, std::vector<int> points) {
        std::sort(patches.begin(), patches.end());
        patches.erase(std::unique(patches.begin(), patches.end()), patches.end());
        std::sort(points.begin(), points.end());
        points.erase(std::unique(points.begin(), points.end()), points.end());
        if (kind == kind_ && patches == patches_ && lattice == lattice_ && points == points_) return;
        kind_ = kind;
        patches_ = std::move(patches);
        lattice_ = lattice;
        points_ = std::move(points);
        emit changed();
    }

    Kind kind_ = Kind::None;
    std::vector<int> patches_;
    int lattice_ = -1;
    std::vector<int> points_;
};

}  // namespace aero::ui
