#include "OptimizationHistory.h"

#include <algorithm>
#include <cstring>

namespace aero::ui {

using Kind = study::OptimizationRecord::Kind;

void OptimizationHistory::clear() {
    header_.reset();
    gradient_.reset();
    evaluations_.clear();
    iterations_.clear();
}

void OptimizationHistory::add(const study::OptimizationRecord& r,
                              std::shared_ptr<const EvaluationSnapshot> snapshot) {
    switch (r.kind) {
        case Kind::Header:
            header_ = r;
            break;
        case Kind::Values: {
            if (r.index < 1) return;
            const auto k = static_cast<std::size_t>(r.index);
            if (!r.replayed && evaluations_.size() >= k) {
                // A new evaluation with a number the history holds: what followed it is gone (a
                // resumed run that left the recorded path, or a stop discarded it).
                evaluations_.resize(k - 1);
                std::erase_if(iterations_, [&](const study::OptimizationRecord& it) {
                    return it.evaluations >= r.index;
                });
            }
            while (evaluations_.size() < k) {
                Evaluation missing;
                missing.record.kind = Kind::Values;
                missing.record.index = static_cast<int>(evaluations_.size()) + 1;
                missing.record.ok = false;
                missing.record.status = "missing";
                evaluations_.push_back(std::move(missing));
            }
            Evaluation& e = evaluations_[k - 1];
            e.record = r;
            // A replayed evaluation (Resume) whose solution this session still holds keeps it:
            // the same design, solved then; the replay brings its shape only.
            const bool keep = r.replayed && snapshot && e.snapshot && e.snapshot->flow &&
                              e.snapshot->values == snapshot->values &&
                              e.snapshot->alphaDeg == snapshot->alphaDeg;
            if (snapshot && !keep) e.snapshot = std::move(snapshot);
            dropOldFlows();
            break;
        }
        case Kind::Gradient:
            gradient_ = r;
            break;
        case Kind::Iteration: {
            auto it = std::find_if(
                iterations_.begin(), iterations_.end(),
                [&](const study::OptimizationRecord& x) { return x.index == r.index; });
            if (it != iterations_.end()) {
                *it = r;
            } else {
                iterations_.push_back(r);
                std::sort(iterations_.begin(), iterations_.end(),
                          [](const auto& a, const auto& b) { return a.index < b.index; });
            }
            break;
        }
    }
}

void OptimizationHistory::setSnapshot(int index,
                                      std::shared_ptr<const EvaluationSnapshot> snapshot) {
    if (index < 1 || index > evaluationCount()) return;
    evaluations_[static_cast<std::size_t>(index - 1)].snapshot = std::move(snapshot);
    dropOldFlows();
}

const OptimizationHistory::Evaluation* OptimizationHistory::evaluation(int index) const {
    if (index < 1 || index > evaluationCount()) return nullptr;
    return &evaluations_[static_cast<std::size_t>(index - 1)];
}

int OptimizationHistory::failedEvaluations() const {
    return static_cast<int>(std::count_if(evaluations_.begin(), evaluations_.end(),
                                          [](const Evaluation& e) { return !e.record.ok; }));
}

int OptimizationHistory::latestIterate() const {
    if (iterations_.empty()) return 0;
    const std::vector<double>& x = iterations_.back().x;
    for (auto it = evaluations_.rbegin(); it != evaluations_.rend(); ++it) {
        const std::vector<double>& y = it->record.x;
        if (y.size() == x.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0)
            return it->record.index;
    }
    return 0;
}

int OptimizationHistory::flowsKept() const {
    return static_cast<int>(
        std::count_if(evaluations_.begin(), evaluations_.end(),
                      [](const Evaluation& e) { return e.snapshot && e.snapshot->flow; }));
}

void OptimizationHistory::dropOldFlows() {
    // The newest keptFlows_ solutions stay, and the first evaluation's (the start, to compare
    // with).
    int kept = 0;
    for (auto it = evaluations_.rbegin(); it != evaluations_.rend(); ++it) {
        if (!it->snapshot || !it->snapshot->flow) continue;
        if (it->record.index == 1) continue;
        if (++kept <= keptFlows_) continue;
        auto lighter = std::make_shared<EvaluationSnapshot>(*it->snapshot);
        lighter->flow.reset();
        it->snapshot = std::move(lighter);
    }
}

}  // namespace aero::ui
