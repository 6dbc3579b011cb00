#pragma once
// What the window knows of an optimization's history: the records study::optimizeCase wrote or
// replayed (study/Optimization.h), kept by number, with each evaluation's snapshot (its design,
// shape, lattices and, while kept, its flow solution: OptimizationRun.h). The plots, the history
// slider and the panel read it; the runner fills it as the records arrive.
//   evaluations  values records by number (1, 2, ...), each with its snapshot;
//   iterations   the optimizer's major iterations by number (0: the start);
//   gradient     the last gradient record (dJ/dv of the optimizer's variables).
// A replayed record (a resumed run, or a history read back) replaces the one of the same number
// (keeping the solution this session has of that same design);
// a new evaluation numbered k drops whatever the history held from k on (a run that left the
// recorded path). Flow solutions are large (the grid, the state and four fields per node): only
// the newest `keptFlows` of them are kept, besides the first evaluation's.
// Plain C++ (no Qt), GUI thread.
#include <memory>
#include <optional>
#include <vector>

#include "OptimizationRun.h"
#include "study/Optimization.h"

namespace aero::ui {

class OptimizationHistory {
  public:
    struct Evaluation {
        study::OptimizationRecord record;                    // kind Values
        std::shared_ptr<const EvaluationSnapshot> snapshot;  // null until known
    };

    void clear();
    /// Takes a record (and, for a values record, its snapshot).
    void add(const study::OptimizationRecord& r,
             std::shared_ptr<const EvaluationSnapshot> snapshot = nullptr);
    /// Replaces the snapshot of evaluation `index` (e.g. after its flow was solved again).
    void setSnapshot(int index, std::shared_ptr<const EvaluationSnapshot> snapshot);

    bool empty() const { return evaluations_.empty() && iterations_.empty(); }
    int evaluationCount() const { return static_cast<int>(evaluations_.size()); }
    /// Evaluation number `index` (from 1), or null.
    const Evaluation* evaluation(int index) const;
    const std::vector<Evaluation>& evaluations() const { return evaluations_; }
    int failedEvaluations() const;
    /// Major iterations in order (iteration 0, the start, first).
    const std::vector<study::OptimizationRecord>& iterations() const { return iterations_; }
    const std::optional<study::OptimizationRecord>& header() const { return header_; }
    const std::optional<study::OptimizationRecord>& lastGradient() const { return gradient_; }
    /// The evaluation at the optimizer's latest iterate (the x of the last iteration record), or 0.
    int latestIterate() const;

    void setKeptFlows(int n) { keptFlows_ = n; }
    int keptFlows() const { return keptFlows_; }
    /// Evaluations whose flow solution is kept.
    int flowsKept() const;

  private:
    void dropOldFlows();

    std::optional<study::OptimizationRecord> header_, gradient_;
    std::vector<Evaluation> evaluations_;
    std::vector<study::OptimizationRecord> iterations_;
    int keptFlows_ = 25;
};

}  // namespace aero::ui
