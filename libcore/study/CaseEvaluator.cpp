#include "study/CaseEvaluator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>

#include "common/Error.h"
#include "common/Format.h"
#include "flow/ChunkedSum.h"
#include "flow/Metrics.h"
#include "flow/Residual.h"
#include "io/FlowFiles.h"
#include "mesh/Extrusion.h"

namespace aero::study {

namespace {

// True if `wall` (unique control points, 3 each) equals the mesh's wall control nodes to
// round-off of the body size.
bool sameWall(const mesh::MultiBlockMesh& m, const std::vector<double>& wall) {
    if (wall.size() != 3 * m.surfaceNode.size() || wall.empty()) return false;
    double lo[3] = {wall[0], wall[1], wall[2]}, hi[3] = {wall[0], wall[1], wall[2]};
    double largest = 0;
    for (std::size_t u = 0; u < m.surfaceNode.size(); ++u) {
        for (std::size_t c = 0; c < 3; ++c) {
            const double x = wall[3 * u + c];
            lo[c] = std::min(lo[c], x);
            hi[c] = std::max(hi[c], x);
            largest = std::max(largest, std::abs(x - m.control[3 * static_cast<std::size_t>(m.surfaceNode[u]) + c]));
        }
    }
    const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    return largest <= 1e-12 * size;
}

double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double tidy(double x) { return std::abs(x) < 1e-12 ? 0.0 : x; }

std::string describe(const FlowLocation& l) {
    return format("block %d '%s' node (%d, %d, %d) at (%.4g, %.4g, %.4g), %s", l.block, l.blockName.c_str(), l.node[0],
                  l.node[1], l.node[2], tidy(l.x[0]), tidy(l.x[1]), tidy(l.x[2]), l.boundary.c_str());
}

}  // namespace

std::string describeWallBend(const mesh::WallBend& b) {
    return format("the wall turns by %.0f degrees from one grid node to the next at block %d '%s' node (%d, %d, %d) "
                  "(x %.3g, %.3g, %.3g), a fold or a bend tighter than the grid spacing: smooth the shape there or "
                  "refine the grid (mesh.refine)",
                  b.degrees, b.block, b.blockName.c_str(), b.node[0], b.node[1], b.node[2], tidy(b.x[0]), tidy(b.x[1]),
                  tidy(b.x[2]));
}

namespace {

// The location of global flow node g: block, (i, j, k), coordinates and the faces it lies on.
FlowLocation locate(const flow::FlowMesh& fm, const std::vector<double>& x, long g, double value) {
    FlowLocation l;
    l.value = value;
    for (std::size_t b = 0; b < fm.blocks.size(); ++b) {
        const flow::FlowBlock& blk = fm.blocks[b];
        if (g < blk.offset || g >= blk.offset + blk.nodeCount()) continue;
        l.block = static_cast<int>(b);
        l.blockName = blk.name;
        const auto idx = flow::nodeIndex(blk.dims, g - blk.offset);
        l.node = idx;
        std::string where;
        for (int f = 0; f < 6; ++f) {
            if (!flow::onFace(blk.dims, g - blk.offset, f)) continue;
            const std::string kind = mesh::boundaryName(blk.faces[f].kind);
            if (where.find(kind) == std::string::npos) where += (where.empty() ? "" : "/") + kind;
        }
        l.boundary = where.empty() ? "interior" : "on the " + where + " boundary";
        break;
    }
    for (int c = 0; c < 3; ++c) l.x[c] = x[3 * g + c];
    return l;
}

// The functionals and the fields a user checks the answer against, at f.q: forces, the largest
// local Mach number and entropy change, the largest residual per volume. Returns the Mach number
// per node.
std::vector<double> measureFlow(FlowResult& f, const flow::ResidualOptions& ro, const flow::ForceReference& reference) {
    f.forces = flow::integrateForces(f.mesh, f.metrics, f.x, f.q, ro.freeStream, reference);
    const std::vector<double> s = flow::entropy(f.mesh, f.q, ro.freeStream);
    std::vector<double> mach = flow::machNumber(f.mesh, f.q, ro.freeStream.gamma);
    long im = 0, is = 0;
    for (long i = 0; i < f.mesh.nodeCount; ++i) {
        if (mach[i] > mach[im]) im = i;
        if (std::abs(s[i]) > std::abs(s[is])) is = i;
    }
    f.maxMach = locate(f.mesh, f.x, im, mach[im]);
    f.maxEntropy = locate(f.mesh, f.x, is, s[is]);
    std::vector<double> r(5 * static_cast<std::size_t>(f.mesh.nodeCount));
    flow::residual(f.mesh, f.metrics.data(), f.q.data(), ro, r.data());
    long ir = 0;
    double worst = -1;
    for (long i = 0; i < f.mesh.nodeCount; ++i) {
        double v = 0;
        for (int k = 0; k < 5; ++k) v = std::max(v, std::abs(r[5 * i + k]));
        v /= f.metrics[flow::kMetricWidth * i + 9];
        if (v > worst) {
            worst = v;
            ir = i;
        }
    }
    f.largestResidual = locate(f.mesh, f.x, ir, worst);
    return mach;
}

// Grid sequencing's coarser levels at most (the 903k paper grid uses two: 123k and 21k nodes).
constexpr int kMaxSequencingLevels = 4;

// A coarser sampling of the same analytic grid for grid sequencing: 2^-level of the intervals.
mesh::ExtrusionOptions coarser(mesh::ExtrusionOptions o, int level) {
    o.refine *= std::ldexp(1.0, -level);
    return o;
}

// Empty when two samplings' block corners (io::blockCorners) are the same points, i.e. the
// samplings are of the same analytic grid; else the first that differs, for an error message.
std::string sameCorners(const std::vector<std::array<double, 24>>& file, const std::vector<std::array<double, 24>>& here) {
    for (std::size_t b = 0; b < here.size() && b < file.size(); ++b) {
        for (int c = 0; c < 8; ++c) {
            double gap = 0, size = 1;
            for (int d = 0; d < 3; ++d) {
                gap = std::max(gap, std::abs(file[b][3 * c + d] - here[b][3 * c + d]));
                size = std::max(size, std::abs(here[b][3 * c + d]));
            }
            if (gap > 1e-8 * size) {
                return format("; its block %zu's corner %d is at (%.6g, %.6g, %.6g), this grid's at (%.6g, %.6g, %.6g): it is "
                              "not another sampling of this grid (another mesh level, farfield radius or shape)",
                              b, c, file[b][3 * c], file[b][3 * c + 1], file[b][3 * c + 2], here[b][3 * c], here[b][3 * c + 1],
                              here[b][3 * c + 2]);
            }
        }
    }
    return file.size() == here.size() ? "" : "; its blocks are not this grid's";
}

// The free stream's residual norm on a grid: what relative tolerances refer to.
double freeStreamResidual(const flow::FlowMesh& fm, const std::vector<double>& metrics, const flow::ResidualOptions& ro) {
    const std::vector<double> q = flow::freeStreamState(fm, ro.freeStream);
    std::vector<double> r(q.size());
    flow::residual(fm, metrics.data(), q.data(), ro, r.data());
    // Summed as the solver sums its residual (ChunkedSum.h): a solve from the free stream starts
    // at exactly this residual, so its first step is exact (NewtonOptions::exactBelow 1) on any
    // thread count; a serial sum here made it depend on the last bit of the solver's sum.
    return std::sqrt(flow::chunkedDot(static_cast<long>(r.size()), r.data(), r.data()));
}

}  // namespace

const char* stageName(Stage s) {
    switch (s) {
        case Stage::Shape:
            return "shape";
        case Stage::Mesh:
            return "mesh";
        case Stage::Flow:
            return "flow";
    }
    return "unknown";
}

const char* evaluationStatusName(EvaluationStatus s) {
    switch (s) {
        case EvaluationStatus::Ok:
            return "ok";
        case EvaluationStatus::InvalidShape:
            return "invalid-shape";
        case EvaluationStatus::InvalidMesh:
            return "invalid-mesh";
        case EvaluationStatus::FlowNotConverged:
            return "flow-not-converged";
        case EvaluationStatus::Cancelled:
            return "cancelled";
    }
    return "unknown";
}

struct CaseEvaluator::Baseline {
    mesh::MultiBlockMesh fine;                      // the case's level, extruded around the baseline
    std::vector<mesh::MultiBlockMesh> coarse;       // grid sequencing's levels, on demand: half, a
                                                    // quarter, ... of the grid intervals
    std::vector<mesh::StructuredGrid> grids;        // x = N b of `fine`, on demand
};

CaseEvaluator::CaseEvaluator(io::CaseFile c, geometry::PatchSet baseline, const Log& log)
    : case_(std::move(c)), baseline_(std::move(baseline)), log_(log) {
    if (case_.lattices.empty()) return;
    model_ = std::make_unique<ffd::FfdModel>(io::buildModel(case_, baseline_));
    const ffd::EmbeddingSummary& emb = model_->summary();
    if (log_) {
        log_(format("embedded %d of %d unique control points in %zu lattice(s), max error %.2e, %.3f s", emb.embedded,
                    emb.unique, model_->lattices().size(), emb.maxError, emb.seconds));
    }
    if (!emb.failures.empty()) {
        int outside = 0;
        for (const auto& f : emb.failures) outside += f.outside ? 1 : 0;
        if (log_) {
            log_(format("%d control point(s) outside every lattice, %d not converged:", outside,
                        static_cast<int>(emb.failures.size()) - outside));
            for (std::size_t i = 0; i < emb.failures.size() && i < 10; ++i) {
                const auto& f = emb.failures[i];
                const double* x = &model_->index().points[3 * f.point];
                log_(format("  control point (%.6g, %.6g, %.6g) of %s: %s, %.3e away", x[0], x[1], x[2],
                            baseline_.describe(f.patch).c_str(), f.outside ? "outside" : "not converged", f.distance));
            }
            if (emb.failures.size() > 10) log_(format("  ... and %zu more", emb.failures.size() - 10));
        }
        if (!case_.allowOutside) {
            throw GeometryError("'" + case_.path + "': " + std::to_string(emb.failures.size()) +
                                " control point(s) could not be embedded (enlarge the lattice padding, or set "
                                "embedding.allow_outside to keep them fixed)");
        }
    }
    caseValues_ = io::designValues(case_, *model_);
    (void)io::movedLattices(case_, *model_, caseValues_);  // checks the displacements (CaseError)
}

CaseEvaluator::~CaseEvaluator() = default;

int CaseEvaluator::variableCount() const { return model_ ? model_->design().size() : 0; }

io::CaseFile CaseEvaluator::designCase(const std::vector<double>& v, std::optional<double> alphaDeg,
                                      const std::string& description) const {
    if (static_cast<int>(v.size()) != variableCount()) {
        throw CaseError(format("'%s': a design of %zu values for %d design variables", case_.path.c_str(), v.size(),
                               variableCount()));
    }
    io::CaseFile one = case_;
    one.values.clear();
    if (model_) {
        const auto& vars = model_->design().variables();
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (v[i] != vars[i].baseline) one.values[vars[i].name] = v[i];
        }
    }
    if (alphaDeg) one.flow.freeStream.alphaDeg = *alphaDeg;
    one.description = description;
    for (std::string* out : {&one.outputGeometry, &one.outputVtk, &one.outputMeshVtk, &one.outputControlVtk,
                             &one.outputPlot3d, &one.outputFlowVtk, &one.outputResidualCsv, &one.outputRestart,
                             &one.outputWallPressure}) {
        out->clear();
    }
    one.optimization = io::OptimizationCase{};
    return one;
}

std::vector<ffd::LinearConstraint> CaseEvaluator::linearConstraints() const {
    std::vector<ffd::LinearConstraint> out;
    if (!model_) return out;
    if (case_.symmetry) out = model_->symmetryConstraints();
    if (case_.stationGap) {
        for (auto& g : model_->stationGapConstraints(*case_.stationGap)) out.push_back(std::move(g));
    }
    if (case_.stationSecondDifference) {
        for (auto& g : model_->stationSecondDifferenceConstraints(*case_.stationSecondDifference)) {
            out.push_back(std::move(g));
        }
    }
    return out;
}

const mesh::MultiBlockMesh& CaseEvaluator::baselineMesh() {
    if (!mesh_) {
        const auto t = std::chrono::steady_clock::now();
        mesh_ = std::make_unique<Baseline>();
        mesh_->fine = mesh::extrudeToFarfield(baseline_, case_.mesh.extrusion);
        if (log_) {
            log_(format("level '%s': %zu blocks, %d control nodes, %ld grid nodes (%.3f s)", case_.mesh.level.c_str(),
                        mesh_->fine.blocks.size(), mesh_->fine.controlCount(), mesh_->fine.gridNodeCount(), since(t)));
        }
    }
    return mesh_->fine;
}

const std::vector<mesh::StructuredGrid>& CaseEvaluator::baselineGrids() {
    baselineMesh();
    if (mesh_->grids.empty()) mesh_->grids = mesh::regenerateAll(mesh_->fine);
    return mesh_->grids;
}

void CaseEvaluator::evaluateShape(Evaluation& e, const EvaluationRequest& request) const {
    const auto t = std::chrono::steady_clock::now();
    if (!model_) {
        e.shape = baseline_;
        e.uniqueSurface = geometry::buildControlPointIndex(baseline_, 1e-10).points;
        e.secondsShape = since(t);
        return;
    }
    if (static_cast<int>(e.values.size()) != model_->design().size()) {
        throw Error("evaluate: " + std::to_string(e.values.size()) + " design values for " +
                    std::to_string(model_->design().size()) + " variables");
    }
    if (request.displacements) {
        io::CaseFile c = case_;  // only the displacements differ
        c.displacements = *request.displacements;
        e.lattices = io::movedLattices(c, *model_, e.values);
    } else {
        e.lattices = io::movedLattices(case_, *model_, e.values);
    }
    for (std::size_t l = 0; l < e.lattices.size(); ++l) {
        const ffd::InjectivityReport r = ffd::checkInjectivity(e.lattices[l]);
        e.injectivity.push_back(r);
        if (!r.injective && e.status == EvaluationStatus::Ok) {
            e.status = EvaluationStatus::InvalidShape;
            e.message = format("lattice '%s' is not injective: det J changes sign near parameters (%.3f, %.3f, %.3f), "
                               "world point (%.4g, %.4g, %.4g); the embedded geometry could self-intersect (move the "
                               "lattice points there apart, or bound the design variables that cross them)",
                               model_->lattices()[l].name.c_str(), r.minAt[0], r.minAt[1], r.minAt[2], r.minPoint[0],
                               r.minPoint[1], r.minPoint[2]);
        }
    }
    if (e.status == EvaluationStatus::Ok || request.keepInvalidShape) {
        e.uniqueSurface = model_->uniqueWith(e.lattices);
        e.shape = model_->deformWith(e.lattices);
    }
    e.secondsShape = since(t);
}

void CaseEvaluator::evaluateMesh(Evaluation& e, const EvaluationRequest& request, const ProgressFn& progress,
                                 const std::atomic<bool>* cancel) {
    auto say = [&](const std::string& s, double fraction = -1) {
        if (progress) {
            Progress p{Stage::Mesh, s, nullptr, false};
            p.fraction = fraction;
            progress(p);
        }
    };
    const auto t = std::chrono::steady_clock::now();
    if (!mesh_) say(format("generating the %s grid blocks", case_.mesh.level.c_str()), 0.0);
    baselineMesh();
    auto m = std::make_shared<MeshResult>();
    m->control = mesh_->fine;
    // The move is skipped when the shape's wall is the baseline's (to round-off of the body size).
    m->moved = model_ != nullptr && !sameWall(m->control, e.uniqueSurface);
    if (m->moved) {
        const int increments = case_.mesh.elasticity.increments;
        say(format("moving the control grid: increment 1 of %d", increments), 0.05);
        m->move = mesh::moveControlGrid(m->control, e.uniqueSurface, case_.mesh.elasticity, [&](int i, int n) {
            if (i < n) say(format("moving the control grid: increment %d of %d", i + 1, n), 0.05 + 0.85 * i / std::max(1, n));
        }, cancel, &m->history, &moveWorkspace_);
        say(format("moved the control grid: %d increments, %d PCG iterations, %d free DOFs, %.3f s",
                   static_cast<int>(m->move.cgIterations.size()), m->move.totalIterations, m->move.freeDofs,
                   m->move.seconds));
        if (m->move.status == mesh::SolveStatus::Cancelled) {
            e.status = EvaluationStatus::Cancelled;
            e.message = "cancelled during the mesh movement";
        } else if (m->move.status != mesh::SolveStatus::Converged) {
            e.status = EvaluationStatus::InvalidMesh;
            e.message = "the mesh movement did not converge: " + m->move.message;
        }
    }
    if (e.status != EvaluationStatus::Cancelled && !(cancel && cancel->load())) {
        // Also after a failed move (its last increment), so the user can look at it.
        say("regenerating the grid", 0.9);
        m->grids = mesh::regenerateAll(m->control);
        say("checking cell quality", 0.94);
        auto& q = m->cellQuality;
        for (const auto& g : m->grids) q.push_back(mesh::cellQuality(g));
        m->quality = mesh::summarize(m->grids, q, request.worstCells);
        m->spacingJump = mesh::largestSpacingJump(m->grids);
        m->wallBend = mesh::sharpestWallBend(m->grids, mesh::wallFaces(m->control));
        if (e.status == EvaluationStatus::Ok) {
            try {
                mesh::requirePositiveJacobians(m->grids, q);
            } catch (const GeometryError& err) {
                e.status = EvaluationStatus::InvalidMesh;
                e.message = std::string("the moved grid is folded: ") + err.what();
            }
        }
        say(format("regenerated %ld grid nodes; min scaled Jacobian %.3f, max aspect ratio %.3g", m->control.gridNodeCount(),
                   m->quality.scaledJacobian.min, m->quality.aspectRatio.max), 1.0);
    } else if (e.status == EvaluationStatus::Ok) {
        e.status = EvaluationStatus::Cancelled;
        e.message = "cancelled during the mesh stage";
    }
    e.mesh = std::move(m);
    e.secondsMesh = since(t);
}

void CaseEvaluator::evaluateFlow(Evaluation& e, const EvaluationRequest& request, const ProgressFn& progress,
                                 const std::atomic<bool>* cancel) {
    const auto t = std::chrono::steady_clock::now();
    auto say = [&](const std::string& s) {
        if (progress) progress({Stage::Flow, s, nullptr, false});
    };
    const MeshResult& m = *e.mesh;
    auto f = std::make_shared<FlowResult>();
    f->mesh = flow::makeFlowMesh(m.control, m.grids);
    f->x = flow::gatherCoordinates(f->mesh, m.grids);
    f->metrics = flow::computeMetrics(f->mesh, f->x);
    const flow::VolumeCheck vol = flow::checkVolumes(f->mesh, f->metrics);
    flow::ResidualOptions& ro = f->residualOptions;
    ro.freeStream = case_.flow.freeStream;
    if (request.alphaDeg) ro.freeStream.alphaDeg = *request.alphaDeg;
    ro.dissipation = case_.flow.dissipation;
    ro.scheme = case_.flow.scheme;
    e.flow = f;
    if (vol.minJinv <= 0) {
        const auto idx = flow::nodeIndex(f->mesh.blocks[vol.block].dims, vol.node);
        e.status = EvaluationStatus::InvalidMesh;
        e.message = format("the grid's metric volume is %.3g (not positive) at block %d '%s' node (%d, %d, %d)",
                           vol.minJinv, vol.block, f->mesh.blocks[vol.block].name.c_str(), idx[0], idx[1], idx[2]);
        e.secondsFlow = since(t);
        return;
    }
    say(format("flow grid: %zu blocks, %ld nodes, %zu interface patches", f->mesh.blocks.size(), f->mesh.nodeCount,
               f->mesh.interfaces.size()));
    const mesh::SpacingJump& jump = m.spacingJump;
    if (jump.ratio > kSpacingJumpWarning) {
        say(format("warning: the grid spacing jumps by a factor %.1f along %c at block %d '%s' node (%d, %d, %d) "
                   "(x %.3g, %.3g, %.3g); central differences are poor there and the flow may stall "
                   "(a finer level, a higher mesh.refine or a larger grid_wall_spacing reduces it)",
                   jump.ratio, "ijk"[jump.direction], jump.block, jump.blockName.c_str(), jump.node[0], jump.node[1],
                   jump.node[2], tidy(jump.x[0]), tidy(jump.x[1]), tidy(jump.x[2])));
    }
    if (m.wallBend.degrees > kWallBendWarning) {
        say("warning: " + describeWallBend(m.wallBend) + "; the flow there is not resolved and may not converge");
    }

    flow::NewtonOptions no = case_.flow.newton;
    const long n = 5 * f->mesh.nodeCount;
    // flow.max_seconds is the stage's budget: every solve gets what is left of it, and once it is
    // spent no retry, continuation stage or mode analysis starts.
    const double budget = case_.flow.maxSeconds;
    auto timeUp = [&] { return budget > 0 && since(t) >= budget; };
    auto limited = [&](flow::NewtonOptions o) {
        if (budget > 0) o.maxSeconds = std::max(budget - since(t), 1e-9);
        return o;
    };
    // Relative tolerances always refer to the free stream's residual on this grid, so a warm or
    // sequenced start converges to the same absolute level as a cold one.
    std::vector<double> q;
    no.referenceResidual = freeStreamResidual(f->mesh, f->metrics, ro);
    auto onIteration = [&](bool coarse, int offset = 0) {
        return [&, coarse, offset](const flow::FlowIteration& it) {
            if (progress) progress({Stage::Flow, "", &it, coarse, coarse ? offset : f->previousIterations});
        };
    };
    io::RestartContents file;
    if (request.start && !request.start->restartFile.empty()) file = io::readRestartContents(request.start->restartFile);
    bool sameLayout = file.dims.size() == f->mesh.blocks.size();
    for (std::size_t b = 0; sameLayout && b < file.dims.size(); ++b) sameLayout = file.dims[b] == f->mesh.blocks[b].dims;
    if (!file.q.empty() && !sameLayout && file.dims.size() == f->mesh.blocks.size()) {
        // Refused, with the layout's message and why, unless it samples this grid's blocks.
        const std::string otherGrid = file.info.samples.empty()
                                          ? "; the file does not record its grid parameters (version 1), so it cannot be "
                                            "interpolated onto this grid"
                                          : sameCorners(file.info.corners, io::blockCorners(f->mesh, f->x));
        if (!otherGrid.empty()) {
            try {
                io::checkRestartLayout(request.start->restartFile, file, f->mesh);
            } catch (const InputError& err) {
                throw InputError(err.what() + otherGrid);
            }
        }
        // Another sampling of this analytic grid (a finer or coarser mesh.refine of the same
        // blocks): its state interpolated in the grid parameters, as grid sequencing prolongs, is
        // a start, not the run continued (the orders refer to this grid's free stream).
        q = interpolateState(file.info.samples, file.q, gridParameters(m.control), f->mesh);
        no.cfl0 = std::max(no.cfl0, 10.0 * case_.flow.newton.cfl0);
        f->interpolatedRestart = static_cast<long>(file.q.size() / flow::kVars);
        say(format("restart from %s: %ld nodes of another sampling of this grid%s, interpolated onto its %ld nodes as the "
                   "initial state",
                   request.start->restartFile.c_str(), f->interpolatedRestart,
                   file.info.iterations > 0 ? format(" (%d iterations done, residual %.3e)", file.info.iterations,
                                                     file.info.residual).c_str()
                                            : "",
                   f->mesh.nodeCount));
    } else if (!file.q.empty()) {
        io::checkRestartLayout(request.start->restartFile, file, f->mesh);
        const io::RestartInfo& previous = file.info;
        q = std::move(file.q);
        const flow::FreeStream& fs = previous.freeStream;
        say(format("restart from %s:%s (Mach %g, alpha %g)", request.start->restartFile.c_str(),
                   previous.iterations > 0 ? format(" %d iterations done, residual %.3e", previous.iterations,
                                                    previous.residual).c_str()
                                           : " a flow state",
                   fs.mach, fs.alphaDeg));
        const bool same = fs.mach == ro.freeStream.mach && fs.alphaDeg == ro.freeStream.alphaDeg && fs.gamma == ro.freeStream.gamma;
        if (same && previous.initialResidual > 0) {
            // Continue the same run: orders, tolerances and the CFL law refer to its first residual.
            no.referenceResidual = previous.initialResidual;
            if (previous.cflBase > 0) no.cfl0 = previous.cflBase;
            ro.dissipation.lumping = std::max(ro.dissipation.lumping, previous.lumping);
            f->previousIterations = previous.iterations;
            f->restartContinued = true;
        } else {
            say(same ? "the restart records no run to continue (a state an optimization kept): it is only the initial guess"
                     : "the restart's free stream differs from the case's: it is only the initial guess");
        }
    } else if (request.start && !request.start->state.empty()) {
        if (static_cast<long>(request.start->state.size()) != n) {
            throw Error("evaluate: the initial flow state has " + std::to_string(request.start->state.size() / 5) +
                        " nodes, the grid " + std::to_string(f->mesh.nodeCount));
        }
        q = request.start->state;
        if (request.start->referenceResidual > 0) no.referenceResidual = request.start->referenceResidual;
        if (request.start->cflBase > 0) no.cfl0 = request.start->cflBase;
        if (request.start->lumping > 0) ro.dissipation.lumping = std::max(ro.dissipation.lumping, request.start->lumping);
    } else if (request.warmStart && static_cast<long>(warm_.size()) == n) {
        q = warm_;  // the tolerance stays relative to this grid's free-stream residual (above)
        f->warmStarted = true;
        say("warm start from the last converged state");
    } else if (!request.timeAccurate && request.sequencing.value_or(case_.flow.gridSequencing) && mesh_ &&
               f->mesh.nodeCount >= case_.flow.sequencingNodes) {
        // Grid sequencing: the same analytic grid sampled with half the intervals, and with half
        // of those again while the coarsest level still has sequencingNodes nodes. The coarsest
        // is solved from the free stream, each finer level from the state prolonged in the grid
        // parameters (the levels sample the same B-spline volumes), each to 1e-4 of its
        // free-stream residual. On the 903k paper grid the 123k level does not converge from the
        // free stream but does from the 21k level's state, in 9 iterations (docs/validation.md).
        struct Level {
            mesh::MultiBlockMesh mesh;
            flow::FlowMesh flow;
            std::vector<double> metrics;
        };
        std::vector<Level> levels;  // finest first
        long above = f->mesh.nodeCount;
        for (int k = 0; k < kMaxSequencingLevels; ++k) {
            if (static_cast<int>(mesh_->coarse.size()) <= k) {
                mesh_->coarse.push_back(mesh::extrudeToFarfield(baseline_, coarser(case_.mesh.extrusion, k + 1)));
            }
            Level level{mesh_->coarse[k], {}, {}};
            level.mesh.control = m.control.control;
            const std::vector<mesh::StructuredGrid> grids = mesh::regenerateAll(level.mesh);
            level.flow = flow::makeFlowMesh(level.mesh, grids);
            if (level.flow.nodeCount >= above) break;  // the sampling cannot get coarser
            level.metrics = flow::computeMetrics(level.flow, flow::gatherCoordinates(level.flow, grids));
            above = level.flow.nodeCount;
            levels.push_back(std::move(level));
            if (above < case_.flow.sequencingNodes) break;
        }
        std::vector<double> lq;  // the state handed on (empty: none yet)
        int done = 0;            // iterations of the coarser levels, for the progress's numbering
        for (int k = static_cast<int>(levels.size()) - 1; k >= 0; --k) {
            Level& level = levels[k];
            flow::NewtonOptions cno = case_.flow.newton;
            cno.relativeTolerance = std::max(cno.relativeTolerance, 1e-4);
            if (!lq.empty()) {
                lq = prolongState(levels[k + 1].mesh, levels[k + 1].flow, lq, level.mesh, level.flow);
                cno.referenceResidual = freeStreamResidual(level.flow, level.metrics, ro);
                cno.cfl0 = std::max(cno.cfl0, 10.0 * case_.flow.newton.cfl0);
            }
            say(format("grid sequencing: level %d of %zu on %ld nodes (%s the intervals)%s",
                       static_cast<int>(levels.size()) - k, levels.size(), level.flow.nodeCount,
                       k == 0 ? "half" : k == 1 ? "a quarter of" : "1/8 or less of",
                       lq.empty() ? ", from the free stream" : ""));
            FlowResult::SequencingLevel result{level.flow.nodeCount,
                                               flow::solveFlow(level.flow, level.metrics, ro, lq, limited(cno),
                                                               onIteration(true, done), cancel)};
            done += result.report.iterations;
            const flow::FlowStatus status = result.report.status;
            const std::string message = result.report.message;
            f->sequencing.push_back(std::move(result));
            if (status == flow::FlowStatus::Cancelled) {
                e.status = EvaluationStatus::Cancelled;
                e.message = "cancelled during the grid-sequencing pre-solve";
                e.secondsFlow = since(t);
                return;
            }
            if (status != flow::FlowStatus::Converged) {
                say("the level's solve did not converge (" + message + "): the case's grid starts from the free stream");
                lq.clear();
                break;
            }
            if (k == 0) {
                q = prolongState(level.mesh, level.flow, lq, m.control, f->mesh);
                no.cfl0 = std::max(no.cfl0, 10.0 * case_.flow.newton.cfl0);
                f->sequenced = true;
            }
        }
    }
    flow::FlowCheckpoint checkpoint;
    auto lastCheckpoint = std::chrono::steady_clock::now();
    bool checkpointBroken = false;
    io::RestartInfo grid;  // the grid's parameters and corners, which every checkpoint records
    if (!request.checkpointFile.empty()) {
        recordGrid(grid, m.control, f->mesh, f->x);
        checkpoint = [&](const std::vector<double>& state, const flow::FlowReport& sofar) {
            const auto now = std::chrono::steady_clock::now();
            if (checkpointBroken || std::chrono::duration<double>(now - lastCheckpoint).count() < request.checkpointSeconds) return;
            io::RestartInfo info;
            info.freeStream = ro.freeStream;
            info.iterations = f->previousIterations + sofar.iterations;
            info.residual = sofar.finalResidual;
            info.initialResidual = sofar.initialResidual;
            info.cflBase = sofar.cflBase;
            info.lumping = sofar.lumping;
            info.samples = grid.samples;
            info.corners = grid.corners;
            try {
                io::writeRestart(request.checkpointFile, f->mesh, state, info);
                ++f->checkpoints;
            } catch (const Error& err) {
                // A full disk must not stop the solve; the state is still written at the end.
                say(std::string("warning: checkpoint not written (no more tried in this run): ") + err.what());
                checkpointBroken = true;
                return;
            }
            lastCheckpoint = std::chrono::steady_clock::now();
        };
    }
    if (request.timeAccurate) {
        // Forward in physical time from the start chosen above, the forces after every step.
        const flow::TimeAccurateOptions& ta = *request.timeAccurate;
        flow::TimeAccurateOptions budgeted = ta;
        if (budget > 0) budgeted.maxSeconds = budgeted.maxSeconds > 0 ? std::min(budgeted.maxSeconds, budget) : budget;
        say(format("time-accurate: %d steps of %g (BDF2, dual time stepping), to t = %g; at most %d inner iterations "
                   "per step, each to %g of its start",
                   ta.steps, ta.timeStep, ta.steps * ta.timeStep, ta.maxInner, ta.innerTolerance));
        const flow::FlowReport none;
        auto onStep = [&](const flow::TimeStepRecord& rec, const std::vector<double>& state) {
            f->timeForces.push_back(
                flow::integrateForces(f->mesh, f->metrics, f->x, state, ro.freeStream, case_.flow.reference));
            const flow::ForceCoefficients& fc = f->timeForces.back();
            if (progress) {
                Progress p{Stage::Flow,
                           format("step %4d  t %8.3f  CL %9.5f  CD %9.5f  max Mach %5.2f  steady residual %.3e  inner %2d "
                                  "(%.1e)  GMRES %4d  %7.1f s%s",
                                  rec.step, rec.time, fc.CL, fc.CD, rec.maxMach, rec.steadyResidual, rec.innerIterations,
                                  rec.innerReduction, rec.linearIterations, rec.seconds,
                                  rec.timeStep < ta.timeStep ? format("  (time step %g)", rec.timeStep).c_str() : ""),
                           nullptr, false};
                p.fraction = std::min(1.0, rec.time / (ta.steps * ta.timeStep));
                p.timeStep = &rec;
                p.forces = &fc;
                progress(p);
            }
            if (checkpoint) checkpoint(state, none);  // a state to start from, not a steady run to continue
        };
        f->timeAccurate = flow::solveTimeAccurate(f->mesh, f->metrics, ro, q, no, budgeted, onStep, cancel);
        f->q = std::move(q);
        measureFlow(*f, ro, case_.flow.reference);
        std::vector<double> lift;
        for (const flow::ForceCoefficients& fc : f->timeForces) lift.push_back(fc.CL);
        f->timeVerdict = flow::describeUnsteadiness(f->timeAccurate, lift, no.relativeTolerance,
                                                    case_.flow.reference.length, ro.freeStream.mach);
        if (f->timeAccurate.cancelled) {
            e.status = EvaluationStatus::Cancelled;
            e.message = f->timeAccurate.message;
        } else if (!f->timeAccurate.completed) {
            e.status = EvaluationStatus::FlowNotConverged;
            e.message = "the time-accurate run stopped: " + f->timeAccurate.message;
            if (f->timeAccurate.breakdownNode >= 0) {
                e.message += " (at " + describe(locate(f->mesh, f->x, f->timeAccurate.breakdownNode, 0.0)) +
                             "; likely a crease or corner that the grid does not resolve: a smoother shape there or a "
                             "finer grid)";
            }
            e.message += "; so far " + f->timeVerdict;
        }
        e.secondsFlow = since(t);
        return;
    }
    flow::NewtonOptions first = no;
    const bool warmCapped = f->warmStarted && request.warmIterations && *request.warmIterations < no.maxIterations;
    if (warmCapped) first.maxIterations = std::max(1, *request.warmIterations);
    f->report = flow::solveFlow(f->mesh, f->metrics, ro, q, limited(first), onIteration(false), cancel, checkpoint);
    const int budgetIterations = f->report.iterations;  // accepted ones (rejected attempts count against the budget)
    if (warmCapped)
        f->report = extendWarmStart(
            std::move(f->report), no.relativeTolerance, f->budgetReport,
            [&](int more, double cfl) {
                flow::NewtonOptions rest = no;
                rest.maxIterations = more;
                if (cfl > 0) rest.cfl0 = cfl;
                return flow::solveFlow(f->mesh, f->metrics, ro, q, limited(rest), onIteration(false), cancel, checkpoint);
            },
            [&](int more, double relative) {
                say(format("the warm start's %s is spent while it converges (relative residual %.3g): %d more",
                           f->budgetReport.iterations > 0 ? "extension"
                                                          : format("budget of %d iterations", first.maxIterations).c_str(),
                           relative, more));
            });
    const flow::FlowStatus st = f->report.status;
    // A warm start cut by the request's budget failed as a stall does (the retries have the case's).
    const bool failed = st == flow::FlowStatus::Stalled || st == flow::FlowStatus::Diverged || st == flow::FlowStatus::NotANumber ||
                        (warmCapped && st == flow::FlowStatus::MaxIterations);
    if (f->warmStarted && request.coldRetry && failed && !timeUp()) {
        // The neighbour's state can sit in the basin of another branch after a large design step
        // (the optimizer's 98k evaluation 13: warm, stalled at 2e-2; cold with the switch
        // continuation, converged): the free stream is the start the cold solves are tuned for.
        // The retry has its own iteration budget and no grid sequencing; its iterations are
        // reported from 1 again (progress), the failed attempt is kept in warmReport.
        say(format("the warm start stopped (%s after %d iterations: %s): solving again from the free stream",
                   flow::flowStatusName(st), f->report.iterations, f->report.message.c_str()));
        f->warmReport = std::move(f->report);
        f->warmStarted = false;
        q.clear();
        f->report = flow::solveFlow(f->mesh, f->metrics, ro, q, limited(no), onIteration(false), cancel, checkpoint);
    } else if (f->sequenced && request.coldRetry && failed && !timeUp()) {
        // The same for a start from the coarser levels' answer, so that sequencing never loses a
        // design the solve from the free stream converges (and the dissipation continuation
        // below still follows a failure of that one).
        say(format("the start from the coarser grid's state stopped (%s after %d iterations: %s): solving again from "
                   "the free stream",
                   flow::flowStatusName(st), f->report.iterations, f->report.message.c_str()));
        f->sequencedReport = std::move(f->report);
        f->sequenced = false;
        no.cfl0 = case_.flow.newton.cfl0;
        q.clear();
        f->report = flow::solveFlow(f->mesh, f->metrics, ro, q, limited(no), onIteration(false), cancel, checkpoint);
    }
    const flow::FlowStatus last = f->report.status;
    if (request.dissipationRetry && !f->warmStarted && !f->restartContinued && !timeUp() &&
        (last == flow::FlowStatus::Stalled || last == flow::FlowStatus::Diverged || last == flow::FlowStatus::NotANumber)) {
        // Continuation in the dissipation (after Hicken and Zingg's dissipation-based
        // continuation, in steps that adapt, DissipationContinuation): with kappa2 and kappa4
        // several times the case's the steady state is smoother and the slow pseudo-time modes
        // that hold a creased design's solve (docs/validation.md) are damped, so the
        // pseudo-transient path reaches it; each smaller factor starts next to its answer, and so
        // does the case's own problem at the end, where Newton's steps converge. The answer is the
        // case's own residual's.
        say(format("the solve stopped (%s after %d iterations: %s): continuation in the dissipation from %g times "
                   "the case's",
                   flow::flowStatusName(last), f->report.iterations, f->report.message.c_str(), kDissipationFirst));
        f->failedReport = std::move(f->report);
        std::vector<double> failedState = std::move(q);
        // A stage from the free stream refers its tolerance and CFL law to its own start (the
        // free stream's residual, the same for every dissipation factor: a uniform state has
        // none). A stage from a state handed on refers them to the free stream's residual too, as
        // the case's own last stage does: referred to its own start, already small, it began at
        // the first stage's CFL (about 25 pseudo-time iterations to get back to Newton's steps)
        // and then sat at the round-off floor below 1e-10 of that start until the stall test
        // ended it (35 more): 120 of the 258 iterations of the paper level at refine 0.5.
        flow::NewtonOptions freeStreamStage = no;
        freeStreamStage.referenceResidual = 0;
        const flow::NewtonOptions& handedOnStage = no;
        DissipationContinuation plan;
        bool finished = false;      // an attempt at the case's own problem converged, or the time
                                    // limit stopped it: f->report
        bool cancelled = false;
        double timedOutAt = 0;      // > 0: the time limit stopped the stage at this factor
        std::vector<double> ownState;  // the last stage's, when it was a failed attempt at the
                                       // case's own problem from the state q holds
        for (double factor; (factor = plan.next()) > 0;) {
            const bool own = factor == 1.0;
            const bool started = plan.from() > 0;  // q holds the state handed on
            std::vector<double> qs = started ? q : flow::freeStreamState(f->mesh, ro.freeStream);
            ownState.clear();
            if (own) {
                flow::FlowReport rep =
                    flow::solveFlow(f->mesh, f->metrics, ro, qs, limited(no), onIteration(false), cancel, checkpoint);
                say(format("the case's own dissipation from the state at %g times: %s in %d iterations (relative residual %.2e)",
                           plan.from(), flow::flowStatusName(rep.status), rep.iterations, rep.relativeResidual()));
                if (rep.converged() || rep.status == flow::FlowStatus::Cancelled || rep.status == flow::FlowStatus::TimeLimit) {
                    // A time-limited attempt at the case's own problem is the answer as far as it got.
                    cancelled = rep.status == flow::FlowStatus::Cancelled;
                    finished = rep.status != flow::FlowStatus::Cancelled;
                    f->report = std::move(rep);
                    if (finished) q = std::move(qs);
                    break;
                }
                f->dissipationStages.push_back({factor, std::move(rep)});  // failed: q stays
                ownState = std::move(qs);
                plan.ended(false);
                continue;
            }
            flow::ResidualOptions stage = ro;
            stage.dissipation.kappa2 *= factor;
            stage.dissipation.kappa4 *= factor;
            FlowResult::DissipationStage ds{factor, flow::solveFlow(f->mesh, f->metrics, stage, qs,
                                                                    limited(started ? handedOnStage : freeStreamStage),
                                                                    onIteration(false), cancel)};
            say(format("continuation at %g times the dissipation%s: %s in %d iterations (relative residual %.2e)", factor,
                       started ? format(" (from the state at %g times)", plan.from()).c_str() : " (from the free stream)",
                       flow::flowStatusName(ds.report.status), ds.report.iterations, ds.report.relativeResidual()));
            const flow::FlowStatus stageStatus = ds.report.status;
            const bool handsOn = continuationHandsOn(ds.report, started);
            f->dissipationStages.push_back(std::move(ds));
            if (stageStatus == flow::FlowStatus::Cancelled) {
                cancelled = true;
                f->report = f->dissipationStages.back().report;
                break;
            }
            if (stageStatus == flow::FlowStatus::TimeLimit) {
                timedOutAt = factor;
                break;
            }
            if (handsOn) q = std::move(qs);
            plan.ended(handsOn);
        }
        if (!finished) {
            if (cancelled) {
                q = std::move(failedState);
            } else if (timedOutAt > 0) {
                // The stage's state solves another problem: the first attempt's state stands, and
                // its report with the time limit as the reason the stage ended.
                q = std::move(failedState);
                f->report = f->failedReport;
                f->report.status = flow::FlowStatus::TimeLimit;
                f->report.message = format("the continuation in the dissipation was stopped by the time limit at %g times "
                                           "the case's (the first attempt: %s)",
                                           timedOutAt, f->failedReport.message.c_str());
            } else if (!ownState.empty()) {
                // The last stage was the case's own problem from the state handed on: its attempt
                // is the answer as far as it got (solving it again from there would repeat it).
                f->report = std::move(f->dissipationStages.back().report);
                f->dissipationStages.pop_back();
                q = std::move(ownState);
            } else if (plan.from() > 0) {
                f->report = flow::solveFlow(f->mesh, f->metrics, ro, q, limited(no), onIteration(false), cancel, checkpoint);
            } else {
                // Not even the largest dissipation converged: the first attempt's state and report stand.
                q = std::move(failedState);
                f->report = f->failedReport;
            }
        }
    }
    f->q = std::move(q);
    const std::vector<double> mach = measureFlow(*f, ro, case_.flow.reference);

    if (f->report.status == flow::FlowStatus::Cancelled) {
        e.status = EvaluationStatus::Cancelled;
        e.message = f->report.message;
    } else if (!f->report.converged()) {
        e.status = EvaluationStatus::FlowNotConverged;
        std::string why = (f->report.status == flow::FlowStatus::TimeLimit
                               ? format("the flow stage's time limit (flow.max_seconds %g s) is spent: ", budget)
                               : std::string()) +
                          f->report.message + "; the largest residual per volume (" + format("%.3g", f->largestResidual.value) +
                          ") is at " + describe(f->largestResidual);
        if (m.spacingJump.ratio > 8.0) {
            why += format("; the grid spacing jumps by a factor %.1f at block %d '%s' node (%d, %d, %d) (a finer level, a higher "
                          "mesh.refine or a larger grid_wall_spacing reduces it)",
                          m.spacingJump.ratio, m.spacingJump.block, m.spacingJump.blockName.c_str(), m.spacingJump.node[0],
                          m.spacingJump.node[1], m.spacingJump.node[2]);
        }
        if (f->maxMach.value > 1.0) {
            // Past 10 it is no flow: pressure or density has collapsed to nearly zero there (a
            // state that was diverging; a 98k stall read "reaches 6558844.26"), not an expansion.
            why += f->maxMach.value > 10.0
                       ? format("; pressure or density is nearly zero at %s (local Mach number %.2g): the solve was diverging",
                                describe(f->maxMach).c_str(), f->maxMach.value)
                       : format("; the local Mach number reaches %.2f at %s", f->maxMach.value, describe(f->maxMach).c_str());
        }
        if (m.wallBend.degrees > kWallBendWarning) why += "; " + describeWallBend(m.wallBend);
        const double falling = stillFalling(f->report);
        if (warmCapped && f->warmStarted && f->report.status == flow::FlowStatus::MaxIterations) {
            // A step from a converged neighbour converges in 5-40 iterations; one that needs more
            // is crawling (2 % per iteration on the 98k sphere-to-wing path: a nearly singular
            // Newton matrix), and the optimizer is better off with a shorter step.
            why += format("; the warm start's budget of %d iterations (optimization.warm_start_iterations) is spent%s%s",
                          first.maxIterations,
                          f->budgetReport.iterations > 0
                              ? format(", and the %d more it got while converging fast",
                                       f->budgetReport.iterations + f->report.iterations - budgetIterations)
                                    .c_str()
                              : "",
                          falling > 0 ? format(" while it crawls (a factor of %.3g over the last %d iterations)", falling,
                                               kStillFallingWindow).c_str()
                                      : "");
        } else if (falling > 0) {
            // Stopped by the iteration limit while converging: nothing is wrong with the flow, and
            // a mode analysis (about 30 GMRES solves) would look for a cause that is not there.
            why += format("; the residual was still falling (by a factor of %.3g over the last %d iterations): more "
                          "flow.max_iterations, or continuing from the restart file, should converge it",
                          falling, kStillFallingWindow);
        } else if (request.stallModes.value_or(case_.flow.stallModes) && (f->report.status == flow::FlowStatus::Stalled ||
                                             f->report.status == flow::FlowStatus::MaxIterations)) {
            if (timeUp()) {
                why += format("; no search for growing modes: the time limit (flow.max_seconds %g s) is spent", budget);
            } else {
                why += stallModes(*f, mach, say, cancel);
            }
        }
        if (f->coldRetry()) {
            why += format(" (solved from the free stream after the warm start stopped: %s after %d iterations)",
                          flow::flowStatusName(f->warmReport.status), f->warmReport.iterations);
        }
        if (f->sequencedRetry()) {
            why += format(" (solved from the free stream after the start from the coarser grids' state stopped: %s after "
                          "%d iterations)",
                          flow::flowStatusName(f->sequencedReport.status), f->sequencedReport.iterations);
        }
        why += continuationSummary(*f, ro.dissipation.kappa4);
        e.message = why;
    } else {
        warm_ = f->q;
    }
    e.secondsFlow = since(t);
}

int warmStartFinish(const flow::FlowReport& r, double relativeTolerance) {
    const int h = static_cast<int>(r.history.size());
    if (r.status != flow::FlowStatus::MaxIterations || h <= kStillFallingWindow || !(relativeTolerance > 0)) return 0;
    const double before = r.history[h - 1 - kStillFallingWindow].relativeResidual, now = r.history[h - 1].relativeResidual;
    if (!(now > 0 && now < before)) return 0;
    const double needed = std::log(now / relativeTolerance) / (std::log(before / now) / kStillFallingWindow);
    if (!(needed <= kWarmFinishMost)) return 0;
    // The history holds accepted iterations, the grant counts attempts: as many attempts per
    // accepted iteration as the window had (1 where it spans two solves, whose attempts are
    // numbered from 1 again: the difference then undercounts), at most kWarmAttemptsPerAccepted.
    const int attempts = r.history[h - 1].iteration - r.history[h - 1 - kStillFallingWindow].iteration;
    const double perAccepted =
        std::clamp(static_cast<double>(attempts) / kStillFallingWindow, 1.0, kWarmAttemptsPerAccepted);
    return static_cast<int>(std::ceil(needed * perAccepted)) + 2;
}

namespace {

// `from`'s iterations after `to`'s, as one report: counts, time and history add up; the status,
// the residual and the CFL law's base are where `from` ended.
void appendReport(flow::FlowReport& to, const flow::FlowReport& from) {
    if (to.history.empty() && to.iterations == 0) {
        to = from;
        return;
    }
    to.history.insert(to.history.end(), from.history.begin(), from.history.end());
    to.iterations += from.iterations;
    to.linearIterations += from.linearIterations;
    to.seconds += from.seconds;
    to.status = from.status;
    to.message = from.message;
    to.finalResidual = from.finalResidual;
    to.cflBase = from.cflBase;
    to.lumping = from.lumping;
}

}  // namespace

flow::FlowReport extendWarmStart(flow::FlowReport report, double relativeTolerance, flow::FlowReport& before,
                                 const std::function<flow::FlowReport(int more, double cfl)>& solve,
                                 const std::function<void(int more, double relativeResidual)>& announce) {
    for (int extension = 0; extension < kWarmExtensions && !report.history.empty(); ++extension) {
        flow::FlowReport sofar = before;  // the rate over the last window may span two solves
        appendReport(sofar, report);
        const int more = warmStartFinish(sofar, relativeTolerance);
        if (more <= 0) break;
        announce(more, report.history.back().relativeResidual);
        const double cfl = report.cflBase;
        appendReport(before, report);
        report = solve(more, cfl);
    }
    return report;
}

bool continuationHandsOn(const flow::FlowReport& stage, bool started) {
    if (stage.status == flow::FlowStatus::Converged) return true;
    if (!started || (stage.status != flow::FlowStatus::Stalled && stage.status != flow::FlowStatus::MaxIterations)) return false;
    // A stage that stopped above the residual it started at has left its start's basin (the 98k
    // random design 8: 1.19 times the dissipation stalled at 4e-5, then 1.09 times from there
    // climbed from 5.6e-3 to 1.8e-2): the state before it is the better start for the next.
    return !stage.history.empty() && stage.finalResidual < stage.history.front().residual;
}

void DissipationContinuation::ended(bool handedOn) {
    const double f = next_;
    ++stages_;
    next_ = 0;
    if (stages_ >= kDissipationMaxStages) return;
    if (from_ == 0 && !handedOn) {
        // Nothing to start from yet: climb, from the free stream, while the ladder goes up.
        const auto at = std::find(kDissipationLadder.begin(), kDissipationLadder.end(), f);
        if (at != kDissipationLadder.begin() && at != kDissipationLadder.end() && *at >= kDissipationFirst) next_ = *(at - 1);
        return;
    }
    if (handedOn) {
        from_ = f;
        if (f == 1.0) return;  // the case's own problem converged
        if (!targets_.empty()) {
            next_ = targets_.back();
            targets_.pop_back();
            return;
        }
        for (double l : kDissipationLadder) {
            if (l < f) {
                next_ = l;
                return;
            }
        }
        return;
    }
    // Missed from from_: halfway there in the exponent first, unless the step is already the finest.
    const double half = std::sqrt(from_ * f);
    if (from_ / half < kDissipationFinestRatio * (1 - 1e-12)) return;
    targets_.push_back(f);
    next_ = half;
}

std::string continuationSummary(const FlowResult& f, double kappa4) {
    if (!f.dissipationRetry()) return {};
    // The smallest factor whose stage converged, and the closest below it that missed: where the
    // steady flow stops being reached as the dissipation falls.
    double smallest = 0, missed = 0;
    for (const auto& ds : f.dissipationStages) {
        if (ds.report.converged() && (smallest == 0 || ds.factor < smallest)) smallest = ds.factor;
    }
    for (const auto& ds : f.dissipationStages) {
        if (!ds.report.converged() && ds.factor < smallest && ds.factor > missed) missed = ds.factor;
    }
    if (smallest > 0) {
        return format(" (after the first attempt stopped, %s after %d iterations, the continuation in the dissipation "
                      "converged down to %.3g times the case's (kappa4 %.3g) but not %s: this shape's steady flow was "
                      "not reached with less dissipation; it may have none (unsteady, separated flow); a smoother "
                      "shape, or kappa2 and kappa4 %.3g times the case's, converge)",
                      flow::flowStatusName(f.failedReport.status), f.failedReport.iterations, smallest, kappa4 * smallest,
                      missed > 0 ? format("at %.3g times or below", missed).c_str() : "at the case's own", smallest);
    }
    std::string tried;
    for (const auto& ds : f.dissipationStages) {
        tried += format("%s%g times: %s after %d iterations", tried.empty() ? "" : "; ", ds.factor,
                        flow::flowStatusName(ds.report.status), ds.report.iterations);
    }
    return format(" (solves with more dissipation did not converge either: %s)", tried.c_str());
}

double stillFalling(const flow::FlowReport& r) {
    const int h = static_cast<int>(r.history.size());
    if (r.status != flow::FlowStatus::MaxIterations || h <= kStillFallingWindow) return 0;
    const double before = r.history[h - 1 - kStillFallingWindow].residual, now = r.history[h - 1].residual;
    return now > 0 && now * kStillFallingFactor <= before ? before / now : 0;
}

int FlowResult::totalIterations() const {
    int n = report.iterations + budgetReport.iterations + warmReport.iterations + sequencedReport.iterations +
            failedReport.iterations;
    for (const DissipationStage& s : dissipationStages) n += s.report.iterations;
    return n;
}

namespace {

// The fastest-growing mode for a human: how fast, where, and what to do.
std::string describeMode(const adjoint::FlowMode& md, const FlowLocation& at) {
    const double re = md.rate.real(), im = std::abs(md.rate.imag());
    const std::string kind = im > 1e-3 * std::abs(md.rate) ? format("oscillating at %.2g", im) : std::string("not oscillating");
    return format("the linearized flow has a mode that grows in pseudo time (rate %.2g per CFL-1 step, %s), largest at %s, "
                  "local Mach number %.2f: the flow there is unstable in pseudo time on this grid at this "
                  "dissipation, likely unsteady (a separated region, e.g. behind a blunt trailing edge); a larger "
                  "flow.kappa4 may damp it, or change the shape there",
                  re, kind.c_str(), describe(at).c_str(), at.value);
}

}  // namespace

std::string CaseEvaluator::stallModes(FlowResult& f, const std::vector<double>& mach,
                                      const std::function<void(const std::string&)>& say,
                                      const std::atomic<bool>* cancel) const {
    if (cancel && cancel->load()) return {};
    if (!flow::isPhysical(f.mesh, f.q.data(), f.residualOptions.freeStream.gamma)) return {};
    say("looking for modes that grow in pseudo time at the final state (flow.stall_modes)");
    try {
        adjoint::ModeOptions mo;
        mo.cancel = cancel;
        f.modes = adjoint::pseudoTimeModes(f.mesh, f.metrics, f.q, f.residualOptions, mo);
    } catch (const std::exception& ex) {
        say(std::string("the mode analysis failed: ") + ex.what());
        return {};
    }
    if (cancel && cancel->load()) return {};
    // The summary is kept with the result (the GUI keeps 25 results, the optimizer its history):
    // not the eigenvectors (8 MB each at 98k nodes).
    for (adjoint::FlowMode& md : f.modes.modes) std::vector<std::complex<double>>().swap(md.vector);
    f.modesChecked = true;
    say(format("mode analysis: %d Arnoldi steps, %d GMRES iterations, %.1f s, %zu converged modes%s%s", f.modes.steps,
               f.modes.linearIterations, f.modes.seconds, f.modes.modes.size(), f.modes.failure.empty() ? "" : "; ",
               f.modes.failure.c_str()));
    if (const adjoint::FlowMode* g = f.modes.growing()) {
        f.modeAt = locate(f.mesh, f.x, g->node, mach[static_cast<std::size_t>(g->node)]);
        return "; " + describeMode(*g, f.modeAt);
    }
    if (!f.modes.conclusive()) {
        return format("; the mode analysis has no verdict (%s)",
                      f.modes.failure.empty() ? "no Ritz value converged" : f.modes.failure.c_str());
    }
    return format("; no mode of the linearized flow grows at the final state (%zu slowest checked, the slowest decays at "
                  "%.2g per CFL-1 step): a steady state may exist that the solver's path missed (flow.grid_sequencing, "
                  "or a warm start from a nearby converged design, may reach it)",
                  f.modes.modes.size(), -f.modes.modes.front().rate.real());
}

Evaluation CaseEvaluator::evaluate(const std::vector<double>& v, const EvaluationRequest& request,
                                   const ProgressFn& progress, const std::atomic<bool>* cancel) {
    Evaluation e;
    e.values = v;
    evaluateShape(e, request);
    if (!e.ok()) return e;
    const bool wantFlow = request.flow && case_.flow.present;
    if (!(request.mesh || wantFlow)) return e;
    if (cancel && cancel->load()) {
        e.status = EvaluationStatus::Cancelled;
        e.message = "cancelled before the mesh stage";
        return e;
    }
    evaluateMesh(e, request, progress, cancel);
    if (!e.ok() || !wantFlow) return e;
    if (cancel && cancel->load()) {
        e.status = EvaluationStatus::Cancelled;
        e.message = "cancelled before the flow stage";
        return e;
    }
    evaluateFlow(e, request, progress, cancel);
    return e;
}

std::vector<double> prolongState(const mesh::MultiBlockMesh& coarse, const flow::FlowMesh& coarseFlow,
                                 const std::vector<double>& q, const mesh::MultiBlockMesh& fine,
                                 const flow::FlowMesh& fineFlow) {
    if (coarse.blocks.size() != fine.blocks.size() || coarseFlow.blocks.size() != coarse.blocks.size() ||
        fineFlow.blocks.size() != fine.blocks.size()) {
        throw Error("prolongState: the two meshes have different blocks");
    }
    return interpolateState(gridParameters(coarse), q, gridParameters(fine), fineFlow);
}

void recordGrid(io::RestartInfo& info, const mesh::MultiBlockMesh& m, const flow::FlowMesh& fm, const std::vector<double>& x) {
    info.samples = gridParameters(m);
    info.corners = io::blockCorners(fm, x);
}

GridParameters gridParameters(const mesh::MultiBlockMesh& m) {
    GridParameters p;
    p.reserve(m.blocks.size());
    for (const auto& b : m.blocks) p.push_back(b.samples);
    return p;
}

std::vector<double> interpolateState(const GridParameters& from, const std::vector<double>& q, const GridParameters& to,
                                     const flow::FlowMesh& toFlow) {
    if (from.size() != to.size() || to.size() != toFlow.blocks.size()) {
        throw Error("interpolateState: the two samplings have different blocks");
    }
    std::size_t values = 0;
    for (std::size_t b = 0; b < to.size(); ++b) {
        values += 5 * from[b][0].size() * from[b][1].size() * from[b][2].size();
        for (int d = 0; d < 3; ++d) {
            if (from[b][d].empty() || to[b][d].size() != static_cast<std::size_t>(toFlow.blocks[b].dims[d])) {
                throw Error("interpolateState: block " + std::to_string(b) + "'s parameters do not match its nodes");
            }
        }
    }
    if (values != q.size()) throw Error("interpolateState: the state does not match its sampling");
    std::vector<double> out(5 * static_cast<std::size_t>(toFlow.nodeCount));
    long cOffset = 0;  // the first node of block b in q
    for (std::size_t b = 0; b < to.size(); ++b) {
        const auto& cs = from[b];
        const auto& fs = to[b];
        const flow::FlowBlock& fb = toFlow.blocks[b];
        // Per direction: for every target node, the source interval and the weight of its upper end.
        std::array<std::vector<int>, 3> lo;
        std::array<std::vector<double>, 3> w;
        for (int d = 0; d < 3; ++d) {
            const int nc = static_cast<int>(cs[d].size());
            lo[d].resize(fs[d].size());
            w[d].resize(fs[d].size());
            for (std::size_t i = 0; i < fs[d].size(); ++i) {
                if (nc == 1) continue;  // one node along d: its value throughout (lo 0, weight 0)
                const double u = fs[d][i];
                int a = static_cast<int>(std::upper_bound(cs[d].begin(), cs[d].end(), u) - cs[d].begin()) - 1;
                a = std::clamp(a, 0, nc - 2);
                const double h = cs[d][a + 1] - cs[d][a];
                lo[d][i] = a;
                w[d][i] = h > 0 ? std::clamp((u - cs[d][a]) / h, 0.0, 1.0) : 0.0;
            }
        }
        const long cni = static_cast<long>(cs[0].size()), cnj = static_cast<long>(cs[1].size());
#pragma omp parallel for schedule(static)
        for (int k = 0; k < fb.dims[2]; ++k) {
            for (int j = 0; j < fb.dims[1]; ++j) {
                for (int i = 0; i < fb.dims[0]; ++i) {
                    double* o = &out[5 * (fb.offset + i + static_cast<long>(fb.dims[0]) * (j + static_cast<long>(fb.dims[1]) * k))];
                    for (int v = 0; v < 5; ++v) o[v] = 0.0;
                    for (int c = 0; c < 8; ++c) {
                        const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
                        const double wt = (di ? w[0][i] : 1 - w[0][i]) * (dj ? w[1][j] : 1 - w[1][j]) * (dk ? w[2][k] : 1 - w[2][k]);
                        if (wt == 0.0) continue;
                        const long cn = cOffset + (lo[0][i] + di) + cni * ((lo[1][j] + dj) + cnj * (lo[2][k] + dk));
                        for (int v = 0; v < 5; ++v) o[v] += wt * q[5 * cn + v];
                    }
                }
            }
        }
        cOffset += cni * cnj * static_cast<long>(cs[2].size());
    }
    return out;
}

}  // namespace aero::study
