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
class RandomDesigns {
public:
    RandomDesigns(const CaseEvaluator& ev, std::uint64_t seed, double spread = 0.5);
    std::vector<double> next();

private:
    const CaseEvaluator* ev_;
    std::mt19937_64 rng_;
    double spread_;
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
