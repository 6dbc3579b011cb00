#include "OptimizationRun.h"

#include <cmath>
#include <limits>

#include "common/Error.h"
#include "ffd/FfdModel.h"
#include "study/CaseEvaluator.h"

namespace aero::ui {

namespace {

using Kind = study::OptimizationRecord::Kind;

FlowRunProgress flowProgress(const study::Progress& p) {
    FlowRunProgress out;
    out.stage = p.stage;
    out.message = p.message;
    out.fraction = p.fraction;
    out.coarse = p.coarse;
    out.iterationOffset = p.iterationOffset;
    if (p.iteration) {
        out.hasIteration = true;
        out.iteration = *p.iteration;
    }
    return out;
}

// The shape stage alone at a design: what the optimizer's own iteration shapes are made of.
std::shared_ptr<EvaluationSnapshot> shapeSnapshot(study::CaseEvaluator& ev, int index,
                                                  const DesignPoint& d) {
    study::EvaluationRequest request;
    request.mesh = false;
    request.flow = false;
    request.keepInvalidShape = true;
    study::Evaluation e = ev.evaluate(d.values, request);
    auto s = std::make_shared<EvaluationSnapshot>();
    s->index = index;
    s->values = d.values;
    s->alphaDeg = d.alphaDeg;
    s->shape = std::move(e.shape);
    s->lattices = std::move(e.lattices);
    s->injectivity = std::move(e.injectivity);
    return s;
}

}  // namespace

DesignPoint designPoint(const io::CaseFile& c, const std::vector<ffd::DesignVariable>& variables,
                        const std::vector<double>& x) {
    // As study::optimizeCase maps its variables (study/Optimization.cpp: `design` and `alphaOf`).
    const io::OptimizationCase& oc = c.optimization;
    DesignPoint d;
    const std::size_t nv = variables.size();
    d.values.resize(nv);
    for (std::size_t i = 0; i < nv && i < x.size(); ++i) {
        const ffd::DesignVariable& v = variables[i];
        const double scale = oc.rangeScaling && v.upper > v.lower ? v.upper - v.lower : 1.0;
        d.values[i] = x[i] * scale;
    }
    const double alphaScale = oc.rangeScaling ? oc.alphaUpper - oc.alphaLower : 1.0;
    d.alphaDeg =
        oc.alphaVariable && x.size() > nv ? x[nv] * alphaScale : c.flow.freeStream.alphaDeg;
    return d;
}

std::shared_ptr<const FlowRunResult> keptSolution(const study::Evaluation& e) {
    if (!e.flow || e.flow->q.empty()) return nullptr;
    auto flow = std::make_shared<study::FlowResult>(*e.flow);
    flow->metrics.clear();  // the solver's; the view and the exports need the state and the grid
    flow->metrics.shrink_to_fit();
    auto r = std::make_shared<FlowRunResult>();
    r->status = e.status;
    r->message = e.message;
    r->fields = flowFields(*flow);
    for (int f = 0; f < kFlowFields; ++f) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (double v : r->fields[static_cast<std::size_t>(f)])
            if (std::isfinite(v)) {
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
        if (!(lo <= hi)) lo = hi = 0;
        r->range[static_cast<std::size_t>(f)] = {lo, hi};
    }
    r->wall = e.uniqueSurface;
    r->seconds = e.secondsShape + e.secondsMesh + e.secondsFlow;
    r->flow = std::move(flow);
    return r;
}

OptimizationRunResult runOptimization(const OptimizationRunInput& in,
                                      const OptimizationProgressFn& report,
                                      const std::atomic<bool>* cancel,
                                      const std::function<void()>& requestCancel) {
    OptimizationRunResult result;
    io::CaseFile c = in.caseFile;
    if (!c.optimization.present)
        throw CaseError("the case has no \"optimization\" section: set one up first");
    auto log = [&report](const std::string& line) {
        if (!report) return;
        OptimizationProgress p;
        p.kind = OptimizationProgress::Kind::Log;
        p.line = line;
        report(std::move(p));
    };
    study::CaseEvaluator ev(c, in.baseline, log);  // throws for a bad case, as the CLI reports it
    const std::vector<ffd::DesignVariable> variables =
        ev.model() ? ev.model()->design().variables() : std::vector<ffd::DesignVariable>{};

    // The snapshot of the evaluation whose values record comes next (made by onEvaluation).
    std::shared_ptr<EvaluationSnapshot> pending;
    bool pausing = false;

    study::OptimizationOptions o;
    o.resume = in.resume;
    o.fresh = in.fresh;
    o.cancel = cancel;
    o.log = log;
    o.progress = [&report](const study::Progress& p) {
        if (!report) return;
        OptimizationProgress out;
        out.kind = OptimizationProgress::Kind::Flow;
        out.flow = flowProgress(p);
        report(std::move(out));
    };
    o.onEvaluation = [&](const study::OptimizationRecord& r, const study::Evaluation& e) {
        std::shared_ptr<EvaluationSnapshot> s;
        if (e.shape.patches.empty()) {  // a non-injective lattice: its shape, kept for display
            s = shapeSnapshot(ev, r.index, {e.values, r.alphaDeg});
        } else {
            s = std::make_shared<EvaluationSnapshot>();
            s->index = r.index;
            s->values = e.values;
            s->alphaDeg = r.alphaDeg;
            s->shape = e.shape;
            s->lattices = e.lattices;
            s->injectivity = e.injectivity;
        }
        if (in.keepFlow) s->flow = keptSolution(e);
        pending = std::move(s);
    };
    o.onRecord = [&](const study::OptimizationRecord& r) {
        OptimizationProgress p;
        p.kind = OptimizationProgress::Kind::Record;
        p.record = r;
        if (r.kind == Kind::Values) {
            if (pending && pending->index == r.index && !r.replayed) {
                p.snapshot = std::move(pending);
            } else {
                // Replayed: not solved again, but its shape is cheap and exact.
                p.snapshot = shapeSnapshot(ev, r.index, designPoint(c, variables, r.x));
            }
            pending.reset();
            if (!r.replayed) result.lastRecordedEvaluation = r.index;
        }
        if (report) report(std::move(p));
        // A pause takes effect once a whole record is on disk: the optimizer then finds the
        // cancel flag before its next evaluation or gradient and ends; resume replays it all.
        if (in.pause && in.pause->load() && !r.replayed &&
            (r.kind == Kind::Values || r.kind == Kind::Gradient) && !pausing) {
            pausing = true;
            result.paused = true;
            if (requestCancel) requestCancel();
        }
    };
    result.summary = study::optimizeCase(ev, o);
    if (result.summary->result.status != optimize::Status::Cancelled) result.paused = false;
    return result;
}

LoadedHistory loadOptimizationHistory(const geometry::PatchSet& baseline, const io::CaseFile& c,
                                      const std::atomic<bool>* cancel) {
    LoadedHistory h;
    if (!c.optimization.present) throw CaseError("the case has no \"optimization\" section");
    h.records = study::readHistory(study::historyJsonlPath(c.optimization.history));
    study::CaseEvaluator ev(c, baseline);
    const std::vector<ffd::DesignVariable> variables =
        ev.model() ? ev.model()->design().variables() : std::vector<ffd::DesignVariable>{};
    for (const study::OptimizationRecord& r : h.records) {
        if (cancel && cancel->load()) break;
        if (r.kind != Kind::Values) continue;
        h.snapshots.push_back(shapeSnapshot(ev, r.index, designPoint(c, variables, r.x)));
    }
    return h;
}

}  // namespace aero::ui
