#include "Document.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QUndoCommand>
#include <QUndoStack>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <vector>

#include "Text.h"
#include "cad/Iges.h"
#include "common/Error.h"
#include "geometry/HalfSphere.h"
#include "geometry/Topology.h"
#include "io/CaseWriter.h"
#include "io/GeometryVtk.h"
#include "io/PatchSetJson.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"
#include "study/Optimization.h"

namespace aero::ui {

namespace {

// The paper's first FFD level around the half-sphere (samples/half_sphere_ffd.json without its
// outputs): a 6x6x2 lattice, cubic in X and Y, linear in Z, six spanwise stations, 89 variables.
constexpr const char* kPaperCase = R"({
  "format": "aeroform.case", "version": 1, "geometry": "",
  "lattices": [{"name": "body", "counts": [6, 6, 2], "degrees": [3, 3, 1], "padding": [0.05, 0.0, 0.05]}],
  "design_variables": {"stations": [{
    "lattice": "body", "direction": 1, "bits": ["001", "011", "011", "011", "011", "011"],
    "section_scaling": true, "taper": true, "vertical": "z", "streamwise": "x",
    "translation_bound": 3.0, "scaling_bounds": [0.2, 2.0], "taper_bounds": [0.3, 2.0]}]},
  "embedding": {"tolerance": 1e-12, "allow_outside": false},
  "constraints": {"symmetry": true, "station_gap": 0.05, "min_volume": "initial"}
})";

// Undo command ids (QUndoCommand::id): only commands of the same id can merge.
constexpr int kSetValueId = 1;

std::string toStd(const QString& path) {
    return QFile::encodeName(path).toStdString();
}
QString fromStd(const std::string& path) {
    return QFile::decodeName(QByteArray::fromStdString(path));
}

std::string lowerExtension(const std::string& path) {
    return QFileInfo(fromStd(path)).suffix().toLower().toStdString();
}

// Patch set from .json (native), .igs/.iges or .stp/.step (other names are sniffed), in the file's
// unit and with its trims. `message` summarizes what the reader did when it is worth saying.
geometry::PatchSet loadGeometry(const std::string& path, QString* message) {
    cad::ReadReport report;
    geometry::PatchSet set = study::loadGeometry(path, &report);
    const int converted = report.count(cad::SurfaceOutcome::Converted), ignored = report.count(cad::SurfaceOutcome::Ignored);
    if (message && (converted > 0 || ignored > 0 || set.trimmedCount() > 0 || !report.warnings.empty() || !set.unit.empty())) {
        QString m = QObject::tr("%1, unit %2: %3 patches (%4 trimmed)")
                        .arg(QString::fromStdString(report.format))
                        .arg(set.unit.empty() ? QObject::tr("not stated") : QString::fromStdString(set.unit))
                        .arg(set.size())
                        .arg(set.trimmedCount());
        if (converted > 0) m += QObject::tr("; %1 converted to NURBS").arg(converted);
        if (ignored > 0) m += QObject::tr("; %1 entities ignored").arg(ignored);
        if (!report.warnings.empty())
            m += QObject::tr("; %1 warning(s): %2").arg(static_cast<int>(report.warnings.size())).arg(QString::fromStdString(report.warnings.front()));
        *message = m;
    }
    return set;
}

// Canonical text of everything the FFD model is built from: two cases with the same key build
// the same model (values, displacements, constraints and outputs do not matter).
std::string modelKey(const io::CaseFile& c) {
    io::CaseFile k;
    k.lattices = c.lattices;
    k.stations = c.stations;
    k.pointVariables = c.pointVariables;
    k.embedding = c.embedding;
    return io::formatCase(k);
}

// Canonical text of the case's mesh options (to notice that they changed).
std::string meshKey(const io::CaseFile& c) {
    io::CaseFile k;
    k.mesh = c.mesh;
    k.mesh.present = true;
    return io::formatCase(k);
}

// Canonical text of the case's flow options.
std::string flowKey(const io::CaseFile& c) {
    io::CaseFile k;
    k.flow = c.flow;
    k.flow.present = true;
    return io::formatCase(k);
}

// Canonical text of the case's optimization problem: its section and the volume constraint.
std::string optimizationKey(const io::CaseFile& c) {
    io::CaseFile k;
    k.path = c.path;
    k.optimization = c.optimization;
    k.flow.present = c.optimization.present;
    std::string key = io::formatCase(k);
    key += c.minVolume ? (std::isnan(*c.minVolume) ? "\nmin_volume initial"
                                                   : "\nmin_volume " + std::to_string(*c.minVolume))
                       : "\nmin_volume none";
    return key;
}

// The case parser's checks of an optimization section that involve more than one key
// (io/CaseFile.cpp), for edits made in the window.
void checkOptimization(const io::CaseFile& c) {
    const io::OptimizationCase& oc = c.optimization;
    if (!oc.present) return;
    if (oc.alphaLower >= oc.alphaUpper)
        throw CaseError("optimization.alpha_upper: must be above alpha_lower");
    if (oc.alphaVariable && !(c.flow.freeStream.alphaDeg >= oc.alphaLower &&
                              c.flow.freeStream.alphaDeg <= oc.alphaUpper))
        throw CaseError(
            "optimization.alpha_lower: flow.alpha (the start) lies outside [alpha_lower, "
            "alpha_upper]");
    if (oc.objective == "pressure" && oc.targetPressure.empty())
        throw CaseError(
            "optimization.target_pressure: the objective 'pressure' needs the target's wall "
            "pressures (set "
            "optimization.target_pressure in the case file)");
    if (oc.objective == "pressure" && oc.maximize)
        throw CaseError("optimization.sense: the pressure mismatch is minimized");
}

std::array<int, 3> unflatten(const ffd::Lattice& L, int a) {
    return {a % L.count[0], (a / L.count[0]) % L.count[1], a / (L.count[0] * L.count[1])};
}

QString formatPoint(const std::array<double, 3>& x) {
    return QStringLiteral("(%1, %2, %3)").arg(x[0], 0, 'g', 4).arg(x[1], 0, 'g', 4).arg(x[2], 0, 'g', 4);
}

// The document's evaluator: the case's, in the editor's mode: control points outside every
// lattice are reported as a problem (problems()) rather than refused.
std::unique_ptr<study::CaseEvaluator> makeEvaluator(const io::CaseFile& c, const geometry::PatchSet& baseline) {
    io::CaseFile display = c;
    display.allowOutside = true;
    return std::make_unique<study::CaseEvaluator>(std::move(display), baseline);
}

// The shape stage for design values v and lattice point displacements d, keeping the shape of
// a non-injective lattice (the user sees the fold and the problem).
study::Evaluation shapeStage(study::CaseEvaluator& ev, const std::vector<double>& v,
                             const std::vector<io::DisplacementCase>& d) {
    study::EvaluationRequest r;
    r.mesh = false;
    r.flow = false;
    r.keepInvalidShape = true;
    r.displacements = d;
    return ev.evaluate(v, r);
}

// The state a case builds to. Computed completely before anything is committed.
struct Built {
    std::unique_ptr<study::CaseEvaluator> evaluator;  // null: reuse the current one
    std::string key;
    std::vector<double> values;
    study::Evaluation shape;
};

Built build(const io::CaseFile& c, const geometry::PatchSet& baseline, study::CaseEvaluator* current,
            const std::string& currentKey) {
    Built b;
    b.key = modelKey(c);
    study::CaseEvaluator* ev = current;
    if (!current || b.key != currentKey) {
        b.evaluator = makeEvaluator(c, baseline);
        ev = b.evaluator.get();
    }
    if (ev->model()) b.values = io::designValues(c, *ev->model());
    b.shape = shapeStage(*ev, b.values, c.displacements);
    return b;
}

}  // namespace

// ---- Undo commands --------------------------------------------------------------------------

/// Every edit swaps the whole case: undo and redo re-derive the state from it, exactly.
class CaseEditCommand : public QUndoCommand {
  public:
    CaseEditCommand(Document* doc, const QString& text, io::CaseFile before, io::CaseFile after)
        : QUndoCommand(text), doc_(doc), before_(std::move(before)), after_(std::move(after)) {}

    void redo() override {
        if (firstRedo_) {  // the document already shows `after` (it was validated by applying it)
            firstRedo_ = false;
            return;
        }
        apply(after_);
    }
    void undo() override { apply(before_); }

    const io::CaseFile& afterState() const { return after_; }

  protected:
    void setAfterState(const io::CaseFile& after) { after_ = after; }

  private:
    void apply(const io::CaseFile& c) {
        try {
            doc_->applyCase(c);
        } catch (const aero::Error& e) {  // both states were valid once: not expected
            qWarning("undo/redo failed: %s", e.what());
        }
    }

    Document* doc_;
    io::CaseFile before_, after_;
    bool firstRedo_ = true;
};

/// A design-variable change; consecutive changes of one variable within one gesture (a slider
/// drag) merge into a single undo step.
class SetDesignValueCommand : public CaseEditCommand {
  public:
    SetDesignValueCommand(Document* doc, const QString& text, io::CaseFile before, io::CaseFile after, qint64 mergeKey)
        : CaseEditCommand(doc, text, std::move(before), std::move(after)), mergeKey_(mergeKey) {}

    int id() const override { return kSetValueId; }
    bool mergeWith(const QUndoCommand* other) override {
        const auto* o = static_cast<const SetDesignValueCommand*>(other);
        if (mergeKey_ == 0 || o->mergeKey_ != mergeKey_) return false;
        setAfterState(o->afterState());
        setText(o->text());
        return true;
    }

  private:
    qint64 mergeKey_;
};

// ---- Document -------------------------------------------------------------------------------

struct Document::Loaded {
    io::CaseFile c;
    std::unique_ptr<geometry::PatchSet> baseline;
    bool generated = false;
    QString title;
    QString message;
};

Document::Document(QObject* parent) : QObject(parent), undo_(new QUndoStack(this)) {
    connect(undo_, &QUndoStack::cleanChanged, this, [this] { setForceModified(forceModified_); });
}

Document::~Document() = default;

const ffd::FfdModel* Document::model() const {
    return evaluator_ ? evaluator_->model() : nullptr;
}

bool Document::hasGeometry() const {
    return baseline_ != nullptr;
}

const geometry::PatchSet& Document::baseline() const {
    static const geometry::PatchSet kEmpty;
    return baseline_ ? *baseline_ : kEmpty;
}

const geometry::PatchSet& Document::shape() const {
    return shape_ ? *shape_ : baseline();
}

QString Document::projectPath() const {
    return fromStd(case_.path);
}

bool Document::isModified() const {
    return forceModified_ || !undo_->isClean();
}

void Document::setForceModified(bool on) {
    forceModified_ = on;
    const bool now = isModified();
    if (now != lastModified_) {
        lastModified_ = now;
        emit modifiedChanged(now);
    }
}

void Document::setTitle(const QString& title) {
    title_ = title;
    emit titleChanged();
}

QStringList Document::problems() const {
    QStringList out;
    for (std::size_t l = 0; l < reports_.size() && l < case_.lattices.size(); ++l) {
        const ffd::InjectivityReport& r = reports_[l];
        if (r.injective) continue;
        out << tr("Lattice '%1' is not injective: det J changes sign near %2, so the geometry inside can fold "
                  "over itself (highlighted in red). Move the points back or undo.")
                   .arg(QString::fromStdString(case_.lattices[l].name), formatPoint(r.minPoint));
    }
    if (const ffd::FfdModel* m = model()) {
        int outside = 0, notConverged = 0;
        for (const auto& f : m->summary().failures) (f.outside ? outside : notConverged) += 1;
        if (outside > 0)
            out << tr("%1 lie outside every lattice and do not follow the deformation (highlighted in "
                      "magenta). Enlarge the lattice padding.")
                       .arg(counted(outside, tr("control point"), tr("control points")));
        if (notConverged > 0)
            out << tr("%1 could not be embedded (no convergence) and stay fixed.")
                       .arg(counted(notConverged, tr("control point"), tr("control points")));
    }
    return out;
}

std::vector<double> Document::failedPoints() const {
    std::vector<double> out;
    const ffd::FfdModel* m = model();
    if (!m) return out;
    for (const auto& f : m->summary().failures)
        for (int k = 0; k < 3; ++k) out.push_back(m->index().points[3 * static_cast<std::size_t>(f.point) + k]);
    return out;
}

geometry::PatchSet Document::shapeDerivative(int var) const {
    const ffd::FfdModel* m = model();
    if (!m || !baseline_ || var < 0 || var >= m->design().size()) return {};
    if (!dAdv_) dAdv_ = std::make_unique<Eigen::SparseMatrix<double>>(m->dUniqueDv());
    std::vector<double> column(3 * static_cast<std::size_t>(m->index().uniqueCount()), 0.0);
    for (Eigen::SparseMatrix<double>::InnerIterator it(*dAdv_, var); it; ++it)
        column[static_cast<std::size_t>(it.row())] = it.value();
    geometry::PatchSet d = *baseline_;
    ffd::scatter(m->index(), column, d);
    return d;
}

std::vector<double> Document::uniquePoints() const {
    return baseline_ ? unique_ : std::vector<double>{};
}

std::array<double, 3> Document::displacement(int l, int point) const {
    if (l < 0 || l >= static_cast<int>(committed_.size())) return {0, 0, 0};
    const auto idx = unflatten(committed_[static_cast<std::size_t>(l)], point);
    for (const auto& d : case_.displacements)
        if (d.lattice == l && d.index == idx) return d.delta;
    return {0, 0, 0};
}

// ---- Loading ----------------------------------------------------------------------------------

void Document::adopt(Loaded&& in) {
    Built b = build(in.c, *in.baseline, nullptr, {});
    // Committed from here on (nothing below throws).
    undo_->clear();
    case_ = std::move(in.c);
    baseline_ = std::move(in.baseline);
    evaluator_ = std::move(b.evaluator);
    modelKey_ = b.key;
    dAdv_.reset();
    values_ = std::move(b.values);
    committed_ = b.shape.lattices;
    moved_.clear();
    shape_.reset();
    reports_.clear();
    previewing_ = false;
    generated_ = in.generated;
    // A project's own geometry file (written by an earlier save) travels with it on Save As.
    sidecar_ = false;
    if (!case_.path.empty() && !case_.geometry.empty()) {
        const QFileInfo project(fromStd(case_.path));
        sidecar_ = QFileInfo(fromStd(case_.geometry)).absoluteFilePath() ==
                   project.absoluteDir().filePath(project.completeBaseName() + QStringLiteral(".geometry.json"));
    }
    loadMessage_ = in.message;
    ++revision_;
    title_ = in.title;
    show(std::move(b.shape));
    emit reset();
    emit titleChanged();
    setForceModified(false);
}

std::shared_ptr<Document::Loaded> Document::read(const QString& path, bool project) {
    auto in = std::make_shared<Loaded>();
    const std::string file = toStd(QFileInfo(path).absoluteFilePath());
    if (project) in->c = io::readCase(file);
    in->baseline = std::make_unique<geometry::PatchSet>(loadGeometry(project ? in->c.geometry : file, &in->message));
    geometry::validate(*in->baseline);
    if (!project) in->c.geometry = file;
    in->title = QFileInfo(path).fileName();
    return in;
}

void Document::adoptRead(const std::shared_ptr<Loaded>& loaded) {
    if (!loaded || !loaded->baseline) throw Error("nothing was read");
    adopt(std::move(*loaded));
}

void Document::newFromGeometry(const QString& path) { adoptRead(read(path, false)); }

void Document::newFromSample(bool withPaperLattice) {
    Loaded in;
    if (withPaperLattice) in.c = io::parseCase(kPaperCase, "");
    in.c.geometry.clear();
    in.c.path.clear();
    in.baseline = std::make_unique<geometry::PatchSet>(geometry::makeHalfSphere());
    in.generated = true;
    in.title = tr("Half-sphere (sample)");
    adopt(std::move(in));
}

void Document::openProject(const QString& path) { adoptRead(read(path, true)); }

void Document::recover(const QString& autosavedCase, const QString& projectPath, bool generated, const QString& title) {
    Loaded in;
    in.c = io::readCase(toStd(autosavedCase));
    in.baseline = std::make_unique<geometry::PatchSet>(loadGeometry(in.c.geometry, &in.message));
    geometry::validate(*in.baseline);
    in.generated = generated;
    if (generated) in.c.geometry.clear();  // saving writes it next to the project again
    in.c.path = projectPath.isEmpty() ? std::string() : toStd(QFileInfo(projectPath).absoluteFilePath());
    in.title = title.isEmpty() ? QFileInfo(autosavedCase).fileName() : title;
    adopt(std::move(in));
    setForceModified(true);  // recovered work is not saved anywhere yet
}

void Document::saveProject(const QString& qpath) {
    if (!baseline_) throw InputError("nothing to save: no geometry is loaded");
    const QFileInfo info(qpath);
    const std::string path = toStd(info.absoluteFilePath());
    io::CaseFile c = case_;
    std::string geometryWritten;
    const std::string sidecar = toStd(info.absoluteDir().filePath(info.completeBaseName() + QStringLiteral(".geometry.json")));
    if (generated_ || c.geometry.empty() || (sidecar_ && c.geometry != sidecar)) {
        io::writePatchSetJson(*baseline_, sidecar);
        geometryWritten = sidecar;
        c.geometry = sidecar;
    }
    io::writeCase(c, path);
    case_.geometry = c.geometry;
    case_.path = path;
    sidecar_ = sidecar_ || generated_ || !geometryWritten.empty();
    generated_ = false;
    undo_->setClean();
    setForceModified(false);
    setTitle(info.fileName());
    if (!geometryWritten.empty())
        loadMessage_ = tr("The generated geometry was saved as %1 next to the project.")
                           .arg(QFileInfo(fromStd(geometryWritten)).fileName());
}

void Document::writeAutosave(const QString& casePath, const QString& geometryPath) const {
    if (!baseline_) return;
    io::CaseFile c = case_;
    if (generated_ || c.geometry.empty()) {
        io::writePatchSetJson(*baseline_, toStd(geometryPath));
        c.geometry = toStd(QFileInfo(geometryPath).absoluteFilePath());
    }
    io::writeCase(c, toStd(QFileInfo(casePath).absoluteFilePath()));
}

void Document::exportGeometry(const QString& qpath) const {
    if (!baseline_) throw InputError("nothing to export: no geometry is loaded");
    const std::string path = toStd(qpath);
    const std::string ext = lowerExtension(path);
    const geometry::PatchSet deformed = model() ? model()->deformWith(committed_) : *baseline_;
    if (ext == "igs" || ext == "iges" || ext == "stp" || ext == "step" || ext == "json")
        study::saveGeometry(deformed, path);  // in the geometry's unit, trims kept (FFD leaves them valid)
    else
        throw InputError("'" + path + "': unknown extension (use .igs, .iges, .stp, .step or .json)");
}

void Document::exportVtk(const QString& qpath) const {
    if (!baseline_) throw InputError("nothing to export: no geometry is loaded");
    const geometry::PatchSet deformed = model() ? model()->deformWith(committed_) : *baseline_;
    std::vector<ffd::Lattice> base;
    if (model())
        for (const auto& spec : model()->lattices()) base.push_back(spec.lattice);
    io::writeVtm(toStd(qpath), io::geometryBlocks(deformed, baseline_.get(), committed_, &base));
}

// ---- Applying a case ---------------------------------------------------------------------------

void Document::applyCase(const io::CaseFile& nextIn) {
    if (!baseline_) throw InputError("no geometry is loaded");
    io::CaseFile next = nextIn;
    next.path = case_.path;  // the project's location and geometry are not part of edits
    next.geometry = case_.geometry;
    Built b = build(next, *baseline_, evaluator_.get(), modelKey_);
    const bool structure = b.evaluator != nullptr;  // lattices or variables were re-specified
    const bool valuesDiffer = b.values != values_;
    const bool meshDiffers = meshKey(next) != meshKey(case_);
    const bool flowDiffers = flowKey(next) != flowKey(case_);
    const bool optimizationDiffers = optimizationKey(next) != optimizationKey(case_);
    case_ = std::move(next);
    if (b.evaluator) {
        evaluator_ = std::move(b.evaluator);
        modelKey_ = b.key;
        dAdv_.reset();
    }
    values_ = std::move(b.values);
    committed_ = b.shape.lattices;
    previewing_ = false;
    ++revision_;
    if (structure) emit structureChanged();
    if (valuesDiffer || structure) emit valuesChanged();
    if (meshDiffers) emit meshOptionsChanged();
    if (flowDiffers) emit flowOptionsChanged();
    if (optimizationDiffers) emit optimizationOptionsChanged();
    show(std::move(b.shape));
}

study::Evaluation Document::evaluateShape(const std::vector<io::DisplacementCase>& displacements) const {
    return shapeStage(*evaluator_, values_, displacements);
}

void Document::show(study::Evaluation&& e) {
    auto next = std::make_unique<geometry::PatchSet>(std::move(e.shape));
    QVector<int> changed;
    const bool sameLayout = shape_ && shape_->size() == next->size();
    for (int p = 0; p < next->size(); ++p) {
        const auto& np = next->patches[static_cast<std::size_t>(p)];
        if (!sameLayout || shape_->patches[static_cast<std::size_t>(p)].points != np.points) changed.push_back(p);
    }
    shape_ = std::move(next);
    moved_ = std::move(e.lattices);
    reports_ = std::move(e.injectivity);
    unique_ = std::move(e.uniqueSurface);
    emit latticesMoved();
    if (!changed.isEmpty()) emit shapeChanged(changed);
    emit diagnosticsChanged();
}

void Document::edit(const QString& text, const io::CaseFile& next) {
    io::CaseFile before = case_;
    applyCase(next);  // throws: nothing changed, nothing pushed
    undo_->push(new CaseEditCommand(this, text, std::move(before), case_));
}

// ---- Edits ------------------------------------------------------------------------------------

void Document::addLattice(const io::LatticeCase& lattice, const std::optional<ffd::StationSpec>& stations) {
    for (const auto& l : case_.lattices)
        if (l.name == lattice.name) throw CaseError("a lattice named '" + lattice.name + "' exists already");
    if (lattice.name.empty()) throw CaseError("a lattice needs a name");
    io::CaseFile next = case_;
    next.lattices.push_back(lattice);
    if (stations) {
        ffd::StationSpec s = *stations;
        s.lattice = static_cast<int>(next.lattices.size()) - 1;
        s.prefix = lattice.name;
        next.stations.push_back(std::move(s));
    }
    edit(tr("Add lattice '%1'").arg(QString::fromStdString(lattice.name)), next);
}

void Document::editLattice(int l, const io::LatticeCase& lattice) {
    if (l < 0 || l >= latticeCount()) return;
    for (int k = 0; k < latticeCount(); ++k)
        if (k != l && case_.lattices[static_cast<std::size_t>(k)].name == lattice.name)
            throw CaseError("a lattice named '" + lattice.name + "' exists already");
    if (lattice.name.empty()) throw CaseError("a lattice needs a name");
    io::CaseFile next = case_;
    const std::string oldName = next.lattices[static_cast<std::size_t>(l)].name;
    next.lattices[static_cast<std::size_t>(l)] = lattice;
    int dropped = 0;
    // Displacements and point variables index the refined lattice (as the case parser checks).
    const std::array<int, 3> refined = io::refinedCounts(lattice);
    auto fits = [&](const std::array<int, 3>& idx) {
        for (int d = 0; d < 3; ++d)
            if (idx[static_cast<std::size_t>(d)] >= refined[static_cast<std::size_t>(d)]) return false;
        return true;
    };
    std::erase_if(next.displacements, [&](const io::DisplacementCase& d) {
        const bool drop = d.lattice == l && !fits(d.index);
        dropped += drop ? 1 : 0;
        return drop;
    });
    std::erase_if(next.pointVariables, [&](const io::PointVariableCase& p) {
        const bool drop = p.lattice == l && !fits(p.index);
        dropped += drop ? 1 : 0;
        return drop;
    });
    std::erase_if(next.stations, [&](const ffd::StationSpec& s) {
        const bool drop = s.lattice == l && !s.bits.empty() &&
                          static_cast<int>(s.bits.size()) != lattice.counts[static_cast<std::size_t>(s.direction)];
        dropped += drop ? 1 : 0;
        return drop;
    });
    for (auto& s : next.stations)
        if (s.lattice == l) s.prefix = lattice.name;
    // Values follow a renamed lattice; values of variables that no longer exist are dropped.
    std::map<std::string, double> values;
    for (const auto& [name, value] : next.values) {
        if (oldName != lattice.name && name.rfind(oldName + ".", 0) == 0)
            values[lattice.name + name.substr(oldName.size())] = value;
        else
            values[name] = value;
    }
    next.values.clear();
    const ffd::FfdModel probe = io::buildModel(next, *baseline_);
    for (const auto& [name, value] : values) {
        const int i = probe.design().find(name);
        if (i < 0) continue;
        const auto& var = probe.design().variables()[static_cast<std::size_t>(i)];
        if (value >= var.lower && value <= var.upper) next.values[name] = value;
    }
    const int lostValues = static_cast<int>(values.size() - next.values.size());
    QString text = tr("Edit lattice '%1'").arg(QString::fromStdString(lattice.name));
    if (dropped + lostValues > 0) text += tr(" (dropped %1 that no longer fit)").arg(counted(dropped + lostValues, tr("item"), tr("items")));
    edit(text, next);
}

void Document::removeLattice(int l) {
    if (l < 0 || l >= latticeCount()) return;
    io::CaseFile next = case_;
    const std::string name = next.lattices[static_cast<std::size_t>(l)].name;
    next.lattices.erase(next.lattices.begin() + l);
    auto shift = [l](int& lattice) {
        if (lattice > l) --lattice;
    };
    std::erase_if(next.displacements, [l](const auto& d) { return d.lattice == l; });
    std::erase_if(next.pointVariables, [l](const auto& p) { return p.lattice == l; });
    std::erase_if(next.stations, [l](const auto& s) { return s.lattice == l; });
    for (auto& d : next.displacements) shift(d.lattice);
    for (auto& p : next.pointVariables) shift(p.lattice);
    for (auto& s : next.stations) shift(s.lattice);
    std::erase_if(next.values, [&](const auto& kv) { return kv.first.rfind(name + ".", 0) == 0; });
    edit(tr("Remove lattice '%1'").arg(QString::fromStdString(name)), next);
}

void Document::moveLatticePoints(int l, const std::vector<int>& points, const std::array<double, 3>& delta) {
    if (l < 0 || l >= static_cast<int>(committed_.size()) || points.empty()) return;
    const ffd::Lattice& L = committed_[static_cast<std::size_t>(l)];
    io::CaseFile next = case_;
    for (int a : points) {
        if (a < 0 || a >= L.controlCount()) continue;
        const auto idx = unflatten(L, a);  // indices of the refined lattice, as case files store them
        auto it = std::find_if(next.displacements.begin(), next.displacements.end(),
                               [&](const io::DisplacementCase& d) { return d.lattice == l && d.index == idx; });
        if (it == next.displacements.end()) {
            next.displacements.push_back({l, idx, delta});
        } else {
            for (int k = 0; k < 3; ++k) it->delta[static_cast<std::size_t>(k)] += delta[static_cast<std::size_t>(k)];
            if (it->delta == std::array<double, 3>{0, 0, 0}) next.displacements.erase(it);
        }
    }
    edit(tr("Move %1").arg(counted(static_cast<long long>(points.size()), tr("lattice point"), tr("lattice points"))), next);
}

void Document::setLatticePointPosition(int l, int point, const std::array<double, 3>& position) {
    if (l < 0 || l >= static_cast<int>(committed_.size())) return;
    const ffd::Lattice& L = committed_[static_cast<std::size_t>(l)];
    if (point < 0 || point >= L.controlCount()) return;
    std::array<double, 3> delta{};
    for (int k = 0; k < 3; ++k)
        delta[static_cast<std::size_t>(k)] = position[static_cast<std::size_t>(k)] - L.points[3 * static_cast<std::size_t>(point) + k];
    if (delta == std::array<double, 3>{0, 0, 0}) return;
    moveLatticePoints(l, {point}, delta);
}

void Document::resetLatticePoints(int l, const std::vector<int>& points) {
    if (l < 0 || l >= static_cast<int>(committed_.size())) return;
    const ffd::Lattice& L = committed_[static_cast<std::size_t>(l)];
    io::CaseFile next = case_;
    const auto before = next.displacements.size();
    for (int a : points) {
        const auto idx = unflatten(L, a);
        std::erase_if(next.displacements, [&](const io::DisplacementCase& d) { return d.lattice == l && d.index == idx; });
    }
    if (next.displacements.size() == before) return;
    edit(tr("Reset %1").arg(counted(static_cast<long long>(before - next.displacements.size()), tr("lattice point"), tr("lattice points"))), next);
}

void Document::setDesignValue(int var, double value, int gesture) {
    const ffd::FfdModel* m = model();
    if (!m || var < 0 || var >= m->design().size()) return;
    const ffd::DesignVariable& d = m->design().variables()[static_cast<std::size_t>(var)];
    value = std::clamp(value, d.lower, d.upper);
    if (value == values_[static_cast<std::size_t>(var)]) return;
    io::CaseFile next = case_;
    if (value == d.baseline)
        next.values.erase(d.name);
    else
        next.values[d.name] = value;
    const qint64 key = gesture != 0 ? (static_cast<qint64>(gesture) << 32) + var + 1 : 0;
    io::CaseFile before = case_;
    applyCase(next);
    undo_->push(new SetDesignValueCommand(this, tr("Set %1 = %2").arg(QString::fromStdString(d.name)).arg(value, 0, 'g', 6),
                                          std::move(before), case_, key));
}

void Document::resetDesignValues() {
    if (case_.values.empty()) return;
    io::CaseFile next = case_;
    next.values.clear();
    edit(tr("Reset design variables"), next);
}

void Document::setMeshOptions(const std::string& level, int increments) {
    if (increments < 1) throw CaseError("mesh.increments: must be at least 1");
    io::CaseFile next = case_;
    if (level != next.mesh.level) {
        next.mesh.extrusion = mesh::extrusionLevel(level);  // throws CaseError naming the level
        next.mesh.level = level;
    }
    next.mesh.elasticity.increments = increments;
    next.mesh.present = true;
    if (meshKey(next) == meshKey(case_)) return;  // e.g. the level chosen again
    edit(tr("Set mesh level %1, %2").arg(QString::fromStdString(level), counted(increments, tr("increment"), tr("increments"))), next);
}

void Document::setOption(Section section, const std::string& key, const io::OptionValue& value) {
    io::CaseFile next = case_;
    auto apply = [&](const auto& table, auto& target, const char* name) {
        const auto& option = io::findOption(table, key);  // a programming error for an unknown key
        if (const std::string why = option.spec.check(value); !why.empty())
            throw CaseError(std::string(name) + "." + key + ": " + why);
        option.set(target, value);
        target.present = true;
    };
    const char* name = section == Section::Flow   ? "flow"
                       : section == Section::Mesh ? "mesh"
                                                  : "optimization";
    if (section == Section::Flow) {
        apply(io::flowOptions(), next.flow, name);
        if (flowKey(next) == flowKey(case_)) return;
    } else if (section == Section::Mesh) {
        apply(io::meshOptions(), next.mesh, name);
        if (meshKey(next) == meshKey(case_)) return;
    } else {
        apply(io::optimizationOptions(), next.optimization, name);
        next.flow.present = true;  // the objective is a flow functional (as the parser demands)
        checkOptimization(next);
        if (optimizationKey(next) == optimizationKey(case_)) return;
    }
    edit(tr("Set %1.%2 = %3")
             .arg(QLatin1String(name), QString::fromStdString(key),
                  QString::fromStdString(io::formatOptionValue(value))),
         next);
}

void Document::setMinVolume(std::optional<double> minimum) {
    if (minimum && !std::isnan(*minimum) && !(*minimum > 0))
        throw CaseError("constraints.min_volume: must be positive");
    io::CaseFile next = case_;
    next.minVolume = minimum;
    if (optimizationKey(next) == optimizationKey(case_)) return;
    edit(!minimum               ? tr("Remove the volume constraint")
         : std::isnan(*minimum) ? tr("Keep the start's volume")
                                : tr("Keep the volume at least %1").arg(*minimum, 0, 'g', 6),
         next);
}

void Document::setStartDesign(const std::string& path) {
    if (path == case_.optimization.startDesign) return;
    io::CaseFile next = case_;
    next.optimization.startDesign = path;
    next.optimization.present = true;
    next.flow.present = true;  // the objective is a flow functional (as the parser demands)
    if (!path.empty()) {
        if (const std::string why = io::startDesignPathProblem(path); !why.empty())
            throw CaseError("optimization.start_design: '" + path + "' " + why);
        const ffd::FfdModel* m = model();
        if (!m) throw CaseError("optimization.start_design: the case has no design variables to start from");
        study::startDesign(next, *m, values_);  // refuses, naming the variable, what does not fit
    }
    edit(path.empty() ? tr("Start the optimization from the case's own design")
                      : tr("Start the optimization from %1").arg(QFileInfo(QString::fromStdString(path)).fileName()),
         next);
}

void Document::setDesign(const std::vector<double>& values, std::optional<double> alphaDeg,
                         const QString& text) {
    const ffd::FfdModel* m = model();
    if (!m || static_cast<int>(values.size()) != m->design().size())
        throw CaseError("the design has " + std::to_string(values.size()) +
                        " values; the case has " + std::to_string(m ? m->design().size() : 0) +
                        " design variables");
    io::CaseFile next = case_;
    const auto& vars = m->design().variables();
    for (std::size_t i = 0; i < vars.size(); ++i) {
        const ffd::DesignVariable& d = vars[i];
        const double v = std::clamp(values[i], d.lower, d.upper);
        if (v == d.baseline)
            next.values.erase(d.name);
        else
            next.values[d.name] = v;
    }
    if (alphaDeg) {
        next.flow.freeStream.alphaDeg = *alphaDeg;
        next.flow.present = true;
    }
    if (next.values == case_.values && flowKey(next) == flowKey(case_)) return;
    edit(text, next);
}

// ---- Preview ----------------------------------------------------------------------------------

void Document::previewLatticeMove(int l, const std::vector<int>& points, const std::array<double, 3>& delta) {
    if (!model() || l < 0 || l >= static_cast<int>(committed_.size())) return;
    // The case's displacements with the drag's added: the shape stage computes the rest.
    std::vector<io::DisplacementCase> displacements = case_.displacements;
    const ffd::Lattice& L = committed_[static_cast<std::size_t>(l)];
    for (int a : points) {
        if (a < 0 || a >= L.controlCount()) continue;
        const auto idx = unflatten(L, a);
        auto it = std::find_if(displacements.begin(), displacements.end(),
                               [&](const io::DisplacementCase& d) { return d.lattice == l && d.index == idx; });
        if (it == displacements.end()) {
            displacements.push_back({l, idx, delta});
        } else {
            for (int k = 0; k < 3; ++k) it->delta[static_cast<std::size_t>(k)] += delta[static_cast<std::size_t>(k)];
        }
    }
    previewing_ = true;
    show(evaluateShape(displacements));
}

void Document::endPreview() {
    if (!previewing_) return;
    previewing_ = false;
    show(evaluateShape(case_.displacements));
}

}  // namespace aero::ui
