#pragma once
// The VTK representation of the FFD lattices: control points (spheres) and the lines of each
// control net, with the state of every point and lattice shown by colour:
//   points     teal; displaced by the user: orange; selected: yellow and larger;
//   lines      slate; a lattice that is not injective: red, with a red marker where det J is
//              smallest (where the map folds).
// Lattices are small (tens to hundreds of points), so every update rebuilds the lattice
// polydata (the patch actors are not touched). No VTK type is exposed here.
//
// GUI thread only; destroy while the viewport's context can be made current (see PatchScene).
#include <array>
#include <memory>
#include <vector>

#include "ffd/Lattice.h"

class vtkRenderer;

namespace aero::ui {

struct LatticeView {
    ffd::Lattice lattice;                  // as shown (moved)
    bool injective = true;
    std::array<double, 3> foldAt{0, 0, 0};  // world point of the smallest det J (if not injective)
    std::vector<int> displaced;            // flat indices of points with a displacement
};

class LatticeScene {
  public:
    explicit LatticeScene(vtkRenderer* renderer);
    ~LatticeScene();
    LatticeScene(const LatticeScene&) = delete;
    LatticeScene& operator=(const LatticeScene&) = delete;

    void setLattices(std::vector<LatticeView> lattices);
    void clear();
    /// Points of `lattice` drawn as selected (one lattice at a time; -1: none).
    void setSelection(int lattice, const std::vector<int>& points);

    /// All lattices (a global switch) and each lattice on its own.
    void setVisible(bool visible);
    bool visible() const;
    void setLatticeVisible(int lattice, bool visible);
    /// True if the lattice is shown (global switch and its own).
    bool latticeVisible(int lattice) const;

    int latticeCount() const;
    const ffd::Lattice& lattice(int l) const;
    /// Control points of all lattices, 3 per point (to keep them in the camera's view).
    std::vector<double> allPoints() const;

  private:
    void rebuild();
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace aero::ui
