#pragma once
// The application state of the desktop application: one project, which IS a case file
// (`aeroform.case` v1, see io/CaseFile.h), so `aeroform-cli deform PROJECT.json` runs what the
// GUI shows. The document holds
//   the case                  lattices, design variables, values, lattice displacements;
//   the baseline geometry     loaded once per project (file-backed, or the generated sample);
//   the evaluator             the one pipeline, study::CaseEvaluator (its FFD model embedded
//                             once), rebuilt only when lattices or variables change; the
//                             document asks it for the shape stage only, with its own values and
//                             displacements, in its editor mode (a non-injective lattice's shape
//                             is kept for display, points outside every lattice are reported);
//   the current state         design values, moved lattices B, deformed patches A, injectivity.
// Every edit is an undoable command on undoStack() that swaps the whole case (before/after), so
// undo restores the state exactly (the deformation is recomputed from the case with the same
// arithmetic). Drags are previews on top of the committed state until they are committed.
//
// No numerics here: everything is computed by libcore (CaseEvaluator's shape stage: the moved
// lattices, injectivity, deformed patches and unique points; designValues, dUniqueDv). GUI thread
// only.
// Loading, saving and edits throw aero::Error (with a message for the user) and then leave the
// document unchanged.
#include <QObject>
#include <QString>
#include <QStringList>
#include <QVector>
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "ffd/Injectivity.h"
#include "io/CaseFile.h"
#include "io/Options.h"

class QUndoStack;

namespace aero::study {
class CaseEvaluator;
struct Evaluation;
}  // namespace aero::study

namespace aero::ui {

class Document : public QObject {
    Q_OBJECT

  public:
    explicit Document(QObject* parent = nullptr);
    ~Document() override;

    // ---- State -------------------------------------------------------------------------------
    bool hasGeometry() const;
    /// The project. geometry is the baseline's file (empty for the generated sample until the
    /// project is saved); path is the project file (empty until saved).
    const io::CaseFile& caseFile() const { return case_; }
    const geometry::PatchSet& baseline() const;
    /// The patches as shown: deformed by the lattices (and the current preview), or the
    /// baseline when there is no lattice.
    const geometry::PatchSet& shape() const;
    /// Null without lattices.
    const ffd::FfdModel* model() const;
    /// Design values in model order (empty without a model).
    const std::vector<double>& values() const { return values_; }
    /// Moved lattices B (one per case lattice), the preview included.
    const std::vector<ffd::Lattice>& lattices() const { return moved_; }
    /// One report per lattice for the lattices as shown.
    const std::vector<ffd::InjectivityReport>& injectivity() const { return reports_; }
    int latticeCount() const { return static_cast<int>(case_.lattices.size()); }

    /// Displayed name: project or geometry file name, or "Half-sphere (sample)".
    QString title() const { return title_; }
    /// The project file, empty if never saved.
    QString projectPath() const;
    bool isModified() const;
    QUndoStack* undoStack() const { return undo_; }
    /// Increases with every change of the committed state (for autosave).
    quint64 revision() const { return revision_; }
    /// True when the baseline was generated (the sample) and has no file yet.
    bool geometryGenerated() const { return generated_; }
    /// Problems of the current state for the user, one sentence each: non-injective lattices,
    /// control points outside every lattice. Empty when everything is fine.
    QStringList problems() const;
    /// Informational message of the last load (e.g. IGES conversions), may be empty.
    QString loadMessage() const { return loadMessage_; }

    /// Unique control points that could not be embedded (outside a lattice or not converged),
    /// at their baseline positions: 3 per point.
    std::vector<double> failedPoints() const;
    /// dA/dv of design variable `var` scattered into patch control nets: a patch set with the
    /// baseline's knots and weights whose control points are the derivatives, so that
    /// sampling it gives dS/dv of the surfaces (S is linear in its control points). Empty set
    /// without a model or for a bad index.
    geometry::PatchSet shapeDerivative(int var) const;
    /// The unique control points of the geometry as shown (deformed, a drag preview included),
    /// 3 per point in geometry::buildControlPointIndex order of the baseline: the wall the mesh
    /// control grid must reach (FfdModel::uniqueWith). Empty without geometry.
    std::vector<double> uniquePoints() const;

    // ---- Load, save, export (no undo; a load clears the undo stack) --------------------------
    /// A new project around a geometry file (.igs, .iges, .json patch set).
    void newFromGeometry(const QString& path);
    /// The paper's half-sphere; with the paper's 6x6x2 lattice and 89 station variables.
    void newFromSample(bool withPaperLattice);
    /// Opens a project (case file) with its geometry.
    void openProject(const QString& path);
    /// The slow half of newFromGeometry / openProject (`project`): reads and checks the files
    /// into a state that is not current yet. Touches no document, so it may run on a worker
    /// thread (ProjectFiles reads there, with a Cancel button: cad::OcctCancelScope). Throws what
    /// those throw.
    struct Loaded;
    static std::shared_ptr<Loaded> read(const QString& path, bool project);
    /// The other half, on the GUI thread: makes what read() returned current.
    void adoptRead(const std::shared_ptr<Loaded>& loaded);
    /// Recovers an autosaved case; the document stays modified and remembers `projectPath`
    /// (may be empty) as where it belongs. `generated`: the geometry was the sample.
    void recover(const QString& autosavedCase, const QString& projectPath, bool generated, const QString& title);
    /// Saves the project (temp file + rename). A generated geometry is first written next to
    /// it as <stem>.geometry.json (exact JSON), which the project then refers to; that file
    /// belongs to the project, so Save As writes it again next to the new location. Other
    /// geometry files are referred to where they are (relative path when possible).
    void saveProject(const QString& path);
    /// Writes the case as the autosave at `casePath` without touching the document's own path
    /// or modified state. A generated geometry is written once to `geometryPath`.
    void writeAutosave(const QString& casePath, const QString& geometryPath) const;
    /// The deformed geometry: .igs/.iges (exact, 17 digits) or .json patch set.
    void exportGeometry(const QString& path) const;
    /// Deformed patches, control nets and lattices with displacement fields (.vtm + pieces).
    void exportVtk(const QString& path) const;

    // ---- Edits (each pushes one undoable command) ------------------------------------------
    /// Adds a lattice (and, if given, its station design variables: `stations->lattice` is
    /// set to the new lattice). Throws CaseError for a duplicate name.
    void addLattice(const io::LatticeCase& lattice, const std::optional<ffd::StationSpec>& stations = {});
    /// Replaces the specification of lattice `l` (counts, degrees, padding, patches, name).
    /// Displacements, point variables and station groups that no longer fit are dropped (the
    /// command's text says how many); values of variables that disappeared too.
    void editLattice(int l, const io::LatticeCase& lattice);
    void removeLattice(int l);
    /// Moves control points (flat indices) of lattice l by delta (world units): adds to the
    /// case's displacements (indexed in the refined lattice, as case files are).
    void moveLatticePoints(int l, const std::vector<int>& points, const std::array<double, 3>& delta);
    /// Moves one point so that it lies at `position`.
    void setLatticePointPosition(int l, int point, const std::array<double, 3>& position);
    /// Removes the displacements of these points (back to B(v)).
    void resetLatticePoints(int l, const std::vector<int>& points);
    /// Sets design variable `var` (clamped to its bounds). Consecutive calls with the same
    /// non-zero `gesture` and variable merge into one undo step (a slider drag).
    void setDesignValue(int var, double value, int gesture = 0);
    void resetDesignValues();
    /// Sets the case's mesh level ("coarse", "medium", "paper"; a new level resets the grid
    /// options to its defaults) and elasticity increments (>= 1). Throws CaseError for an
    /// unknown level. No-op when nothing changes.
    void setMeshOptions(const std::string& level, int increments);

    /// The case sections whose options are self-describing (io/Options.h).
    enum class Section { Flow, Mesh, Optimization };
    /// Sets option `key` of the case's flow or mesh section to `value`, checked as the case parser
    /// checks it (CaseError naming the key and its range). The section becomes present (it is
    /// written to the project). Mesh "level" resets the grid options to the level's, as in a case
    /// file. One undoable step; no-op when nothing changes.
    void setOption(Section section, const std::string& key, const io::OptionValue& value);
    /// The optimization's volume constraint (constraints.min_volume): none, the start's (NaN) or
    /// a value (> 0). One undoable step; no-op when nothing changes.
    void setMinVolume(std::optional<double> minimum);
    /// The design the optimization starts from (optimization.start_design): a case file's design
    /// values (absolute path), or "" for the case's own. Refused with a CaseError that names the
    /// file and the variable or value that does not fit this case (checked now, not at the run's
    /// start). One undoable step; no-op when nothing changes.
    void setStartDesign(const std::string& path);
    /// Sets every design variable (model order, clamped to its bounds) and, if given, the angle of
    /// attack (flow.alpha) in one undoable step named `text`: e.g. an optimization's evaluation
    /// taken over. Throws CaseError for a design of the wrong size.
    void setDesign(const std::vector<double>& values, std::optional<double> alphaDeg,
                   const QString& text);

    /// Displacement of a lattice point in the case (zero if none).
    std::array<double, 3> displacement(int l, int point) const;

    // ---- Live preview (not an edit, not saved) -----------------------------------------------
    /// Shows lattice l's points moved by delta on top of the committed state.
    void previewLatticeMove(int l, const std::vector<int>& points, const std::array<double, 3>& delta);
    /// Drops the preview: back to the committed state.
    void endPreview();
    bool previewing() const { return previewing_; }

    /// Makes `next` the committed state (keeping the document's geometry and path). Used by
    /// the undo commands; throws aero::Error if the case does not build (state unchanged).
    void applyCase(const io::CaseFile& next);

  signals:
    /// A different project or geometry: everything changed (scenes, tree, panels, camera).
    void reset();
    /// Lattices or design variables were added, removed or re-specified (model rebuilt).
    void structureChanged();
    /// Control points of these patches changed (shape()).
    void shapeChanged(const QVector<int>& patches);
    /// Lattice points moved (lattices()).
    void latticesMoved();
    /// Design values changed (values()).
    void valuesChanged();
    /// The case's mesh options (caseFile().mesh) changed.
    void meshOptionsChanged();
    /// The case's flow options (caseFile().flow) changed.
    void flowOptionsChanged();
    /// The case's optimization section or its volume constraint changed.
    void optimizationOptionsChanged();
    /// injectivity() or failed points changed; problems() says what is wrong.
    void diagnosticsChanged();
    void modifiedChanged(bool modified);
    /// title() or projectPath() changed.
    void titleChanged();

  private:
    /// Makes a loaded project current (builds everything first; throws and keeps the old
    /// state on failure). Clears the undo stack.
    void adopt(Loaded&& loaded);
    /// Validates `next` by applying it, then pushes a command that swaps before/after.
    void edit(const QString& text, const io::CaseFile& next);
    /// Publishes the shape stage's result (shape, lattices, injectivity, unique points).
    void show(study::Evaluation&& shape);
    /// The shape stage for the document's values and these displacements.
    study::Evaluation evaluateShape(const std::vector<io::DisplacementCase>& displacements) const;
    void setTitle(const QString& title);
    void setForceModified(bool on);

    io::CaseFile case_;
    std::unique_ptr<geometry::PatchSet> baseline_;
    std::unique_ptr<study::CaseEvaluator> evaluator_;  // null without geometry
    std::string modelKey_;  // canonical text of what the evaluator's model was built from
    std::vector<double> values_;
    std::vector<ffd::Lattice> committed_;  // moved lattices of the case
    std::vector<ffd::Lattice> moved_;      // as shown (committed_ or a preview)
    std::vector<double> unique_;           // the unique control points as shown
    std::unique_ptr<geometry::PatchSet> shape_;
    std::vector<ffd::InjectivityReport> reports_;
    bool previewing_ = false;
    bool generated_ = false;
    bool sidecar_ = false;  // the geometry file is the project's own <stem>.geometry.json
    bool forceModified_ = false;
    bool lastModified_ = false;
    quint64 revision_ = 0;
    QString title_;
    QString loadMessage_;
    QUndoStack* undo_ = nullptr;
    mutable std::unique_ptr<Eigen::SparseMatrix<double>> dAdv_;  // dUniqueDv() of model(), lazily
};

}  // namespace aero::ui
