#pragma once
// Designs to sweep a case's design space with (the robustness suite of docs/validation.md and
// `aeroform-cli sweep`): the case's own design scaled towards the baseline, and random designs.
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "study/CaseEvaluator.h"

namespace aero::study {

/// v0 + fraction (v_case - v0): 0 is the baseline (the undeformed geometry), 1 the case's design.
/// Clipped to the variables' bounds.
std::vector<double> scaledDesign(const CaseEvaluator& ev, double fraction);

/// Random designs: every variable drawn uniformly up to `spread` times its range (upper - lower)
/// away from its baseline value, clipped to its bounds (spread 0.5: "anywhere up to half of its
/// range away from the sphere's value"). Deterministic for a seed.
/// With `feasible`, only designs that satisfy the case's linear constraints (the optimizer's
/// feasible set: stations in order with the case's gap, symmetry) are returned: equality rows are
/// met by projecting the draw onto them, a draw that violates an inequality row (or leaves the
/// bounds after the projection) is redrawn and counted in linearRejections(). Independent uniform
/// draws at spread 0.5 put adjacent stations out of order most of the time, so without this
/// almost every draw has a folded lattice.
class RandomDesigns {
public:
    RandomDesigns(const CaseEvaluator& ev, std::uint64_t seed, double spread = 0.5, bool feasible = false);
    /// Throws CaseError if `feasible` and no feasible draw came in 10^6 tries.
    std::vector<double> next();
    long linearRejections() const { return linearRejections_; }

private:
    std::vector<double> draw();
    bool satisfies(const std::vector<double>& v) const;

    const CaseEvaluator* ev_;
    std::mt19937_64 rng_;
    double spread_;
    bool feasible_;
    std::vector<ffd::LinearConstraint> equalities_, inequalities_;
    long linearRejections_ = 0;
};

/// A random design whose shape and grid are valid: draws until the lattice is injective and the
/// moved grid has no folded cell (at most maxDraws), counting the rejected draws and keeping the
/// reason of the last one. `accepted` false if none of maxDraws was valid.
struct ValidDraw {
    std::vector<double> values;
    int rejected = 0;
    int rejectedShape = 0, rejectedMesh = 0;
    std::string lastReason;
    bool accepted = false;
};
ValidDraw drawValidDesign(CaseEvaluator& ev, RandomDesigns& designs, int maxDraws = 50,
                          const std::atomic<bool>* cancel = nullptr);

}  // namespace aero::study
