// Qt Test of the application state (ui/Document) and autosave (ui/Autosave): edits, exact
// undo/redo, save/reopen round trips, recovery. No OpenGL needed.
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <QUndoStack>
#include <cmath>
#include <fstream>

#include "Autosave.h"
#include "Document.h"
#include "study/CaseEvaluator.h"
#include "cad/Iges.h"
#include "common/Error.h"
#include "geometry/HalfSphere.h"
#include "io/CaseFile.h"
#include "io/CaseWriter.h"
#include "io/PatchSetJson.h"

using aero::ui::Autosaver;
using aero::ui::Document;

namespace {

// Every control point of every patch, bit for bit.
bool samePoints(const aero::geometry::PatchSet& a, const aero::geometry::PatchSet& b) {
    if (a.size() != b.size()) return false;
    for (int p = 0; p < a.size(); ++p)
        if (a.patches[static_cast<std::size_t>(p)].points != b.patches[static_cast<std::size_t>(p)].points) return false;
    return true;
}

// The case as text, independent of where it is stored.
std::string caseText(const aero::io::CaseFile& c) {
    aero::io::CaseFile k = c;
    k.path.clear();
    k.geometry.clear();
    return aero::io::formatCase(k);
}

int variable(const Document& d, const std::string& name) {
    return d.model() ? d.model()->design().find(name) : -1;
}

}  // namespace

class DocumentTest : public QObject {
    Q_OBJECT

  private slots:
    void sampleHasThePapersModel();
    void latticeMoveMatchesTheFfdAndUndoesExactly();
    void previewDoesNotEditAndEndsExactly();
    void designValueGestureIsOneUndoStep();
    void shapeDerivativeMatchesFiniteDifferences();
    void nonInjectiveLatticeIsReported();
    void outsidePointsAreReported();
    void latticeEditsRebuildTheModelAndUndo();
    void renamingARefinedLatticeKeepsItsDisplacements();
    void saveAndReopenRestoresExactly();
    void meshOptionsAreUndoableAndSaved();
    void startDesignIsCheckedUndoableAndSaved();
    void autosaveAndRecoveryRestoreExactly();
    void failedLoadKeepsTheDocument();
    void exportsTheDeformedGeometryExactly();
};

void DocumentTest::sampleHasThePapersModel() {
    Document d;
    QSignalSpy reset(&d, &Document::reset);
    d.newFromSample(true);
    QCOMPARE(reset.count(), 1);
    QVERIFY(d.hasGeometry());
    QVERIFY(d.geometryGenerated());
    QCOMPARE(d.baseline().size(), 20);
    QVERIFY(d.model() != nullptr);
    QCOMPARE(d.model()->design().size(), 89);
    QCOMPARE(d.model()->summary().embedded, 521);
    QCOMPARE(d.latticeCount(), 1);
    QCOMPARE(d.injectivity().size(), std::size_t(1));
    QVERIFY(d.injectivity()[0].injective);
    QVERIFY(d.problems().isEmpty());
    QVERIFY(!d.isModified());
    QCOMPARE(d.undoStack()->count(), 0);

    d.newFromSample(false);
    QVERIFY(d.model() == nullptr);
    QVERIFY(samePoints(d.shape(), d.baseline()));
}

void DocumentTest::latticeMoveMatchesTheFfdAndUndoesExactly() {
    Document d;
    d.newFromSample(true);
    const aero::geometry::PatchSet before = d.shape();
    QSignalSpy shape(&d, &Document::shapeChanged);
    QSignalSpy modified(&d, &Document::modifiedChanged);
    const aero::ffd::Lattice& L0 = d.lattices()[0];
    const int a = L0.index(2, 3, 1);
    const std::array<double, 3> delta{0.125, -0.0625, 0.3};
    d.moveLatticePoints(0, {a}, delta);
    QVERIFY(d.isModified());
    QCOMPARE(modified.count(), 1);
    QCOMPARE(shape.count(), 1);
    QVERIFY(!shape.front().front().value<QVector<int>>().isEmpty());
    QCOMPARE(d.caseFile().displacements.size(), std::size_t(1));
    QCOMPARE(d.caseFile().displacements[0].index, (std::array<int, 3>{2, 3, 1}));
    QCOMPARE(d.caseFile().displacements[0].delta, delta);

    // The FFD, independently: the baseline model with that lattice point moved.
    const aero::ffd::FfdModel reference = aero::io::buildModel(d.caseFile(), aero::geometry::makeHalfSphere());
    aero::ffd::Lattice moved = reference.design().lattice(0, reference.design().baselineValues());
    for (int k = 0; k < 3; ++k) moved.points[3 * static_cast<std::size_t>(a) + k] += delta[static_cast<std::size_t>(k)];
    QVERIFY(samePoints(d.shape(), reference.deformWith({moved})));
    QVERIFY(!samePoints(d.shape(), before));

    // Moving the same point again accumulates in one displacement.
    d.moveLatticePoints(0, {a}, {-0.125, 0.0625, -0.3});
    QVERIFY(d.caseFile().displacements.empty());  // exactly back: the entry is dropped
    QCOMPARE(d.undoStack()->count(), 2);

    d.undoStack()->undo();
    d.undoStack()->undo();
    QVERIFY(samePoints(d.shape(), before));
    QVERIFY(d.caseFile().displacements.empty());
    QVERIFY(!d.isModified());
    d.undoStack()->redo();
    QVERIFY(samePoints(d.shape(), reference.deformWith({moved})));
}

void DocumentTest::previewDoesNotEditAndEndsExactly() {
    Document d;
    d.newFromSample(true);
    const aero::geometry::PatchSet before = d.shape();
    const quint64 revision = d.revision();
    d.previewLatticeMove(0, {0, 1}, {0, 0, 0.4});
    QVERIFY(d.previewing());
    QVERIFY(!samePoints(d.shape(), before));
    QCOMPARE(d.undoStack()->count(), 0);
    QCOMPARE(d.revision(), revision);
    QVERIFY(!d.isModified());
    d.endPreview();
    QVERIFY(!d.previewing());
    QVERIFY(samePoints(d.shape(), before));
}

void DocumentTest::designValueGestureIsOneUndoStep() {
    Document d;
    d.newFromSample(true);
    const aero::geometry::PatchSet before = d.shape();
    const int ty = variable(d, "body.S3.ty");
    QVERIFY(ty >= 0);
    for (int k = 1; k <= 5; ++k) d.setDesignValue(ty, 0.1 * k, /*gesture=*/7);
    QCOMPARE(d.undoStack()->count(), 1);
    QCOMPARE(d.values()[static_cast<std::size_t>(ty)], 0.5);
    QCOMPARE(d.caseFile().values.at("body.S3.ty"), 0.5);
    d.setDesignValue(ty, 0.25);  // no gesture: its own step
    d.setDesignValue(ty, 99.0);  // clamped to the bound (3.0)
    QCOMPARE(d.values()[static_cast<std::size_t>(ty)], 3.0);
    QCOMPARE(d.undoStack()->count(), 3);
    d.undoStack()->undo();
    QCOMPARE(d.values()[static_cast<std::size_t>(ty)], 0.25);
    d.undoStack()->undo();
    d.undoStack()->undo();
    QCOMPARE(d.values()[static_cast<std::size_t>(ty)], 0.0);
    QVERIFY(d.caseFile().values.empty());
    QVERIFY(samePoints(d.shape(), before));
    // Back at the baseline, the value is not stored.
    d.setDesignValue(ty, 0.5);
    d.setDesignValue(ty, 0.0);
    QVERIFY(d.caseFile().values.empty());
}

void DocumentTest::shapeDerivativeMatchesFiniteDifferences() {
    Document d;
    d.newFromSample(true);
    for (const char* name : {"body.S3.ty", "body.S2.taperx", "body.S4.P27.sz"}) {
        const int var = variable(d, name);
        QVERIFY2(var >= 0, name);
        const aero::geometry::PatchSet dA = d.shapeDerivative(var);
        QCOMPARE(dA.size(), 20);
        // A(v) is affine in v: a one-sided difference is exact up to round-off.
        std::vector<double> v = d.model()->design().baselineValues();
        const aero::geometry::PatchSet A0 = d.model()->deform(v);
        const double h = 1e-3;
        v[static_cast<std::size_t>(var)] += h;
        const aero::geometry::PatchSet A1 = d.model()->deform(v);
        double largest = 0, error = 0;
        for (int p = 0; p < 20; ++p)
            for (std::size_t k = 0; k < dA.patches[static_cast<std::size_t>(p)].points.size(); ++k) {
                const double fd = (A1.patches[static_cast<std::size_t>(p)].points[k] - A0.patches[static_cast<std::size_t>(p)].points[k]) / h;
                largest = std::max(largest, std::abs(dA.patches[static_cast<std::size_t>(p)].points[k]));
                error = std::max(error, std::abs(fd - dA.patches[static_cast<std::size_t>(p)].points[k]));
            }
        QVERIFY2(largest > 0.1, name);
        QVERIFY2(error < 1e-9, qPrintable(QStringLiteral("%1: %2").arg(QLatin1String(name)).arg(error)));
    }
    QVERIFY(d.shapeDerivative(-1).patches.empty());
}

void DocumentTest::nonInjectiveLatticeIsReported() {
    Document d;
    d.newFromSample(true);
    const aero::ffd::Lattice& L = d.lattices()[0];
    // Pull a top point (k = 1) far below the bottom layer: the lattice folds.
    const int a = L.index(2, 3, 1);
    const double height = L.points[3 * static_cast<std::size_t>(a) + 2] - L.points[3 * static_cast<std::size_t>(L.index(2, 3, 0)) + 2];
    QSignalSpy diagnostics(&d, &Document::diagnosticsChanged);
    const aero::geometry::PatchSet before = d.shape();
    d.moveLatticePoints(0, {a}, {0, 0, -5.0 * height});
    QVERIFY(diagnostics.count() >= 1);
    QVERIFY(!d.injectivity()[0].injective);
    // The folded shape is still shown (the evaluator's editor mode keeps it), and it is the one
    // pipeline's: the same shape study::CaseEvaluator gives for the document's case.
    QVERIFY(!samePoints(d.shape(), before));
    QVERIFY(samePoints(d.shape(), d.model()->deformWith(d.lattices())));
    QCOMPARE(d.uniquePoints(), d.model()->uniqueWith(d.lattices()));
    aero::study::CaseEvaluator ev(d.caseFile(), d.baseline());
    aero::study::EvaluationRequest shapeOnly;
    shapeOnly.mesh = shapeOnly.flow = false;
    const aero::study::Evaluation strict = ev.evaluate(d.values(), shapeOnly);
    QCOMPARE(strict.status, aero::study::EvaluationStatus::InvalidShape);  // what the mesh and flow would say
    shapeOnly.keepInvalidShape = true;
    QVERIFY(samePoints(ev.evaluate(d.values(), shapeOnly).shape, d.shape()));
    const QStringList problems = d.problems();
    QCOMPARE(problems.size(), 1);
    QVERIFY2(problems[0].contains(QStringLiteral("not injective")), qPrintable(problems[0]));
    QVERIFY2(problems[0].contains(QStringLiteral("body")), qPrintable(problems[0]));
    d.undoStack()->undo();
    QVERIFY(d.injectivity()[0].injective);
    QVERIFY(d.problems().isEmpty());
}

void DocumentTest::outsidePointsAreReported() {
    // A project whose explicit box leaves part of the geometry outside (allowed by the case).
    QTemporaryDir dir;
    const QString geometry = dir.filePath(QStringLiteral("sphere.json"));
    aero::io::writePatchSetJson(aero::geometry::makeHalfSphere(), geometry.toStdString());
    const QString project = dir.filePath(QStringLiteral("outside.json"));
    {
        std::ofstream out(project.toStdString());
        out << R"({"format": "aeroform.case", "version": 1, "geometry": "sphere.json",
                  "lattices": [{"name": "front", "counts": [4, 4, 2], "degrees": [3, 3, 1],
                                "box": {"origin": [-1.1, -0.01, -1.1], "size": [1.2, 1.2, 2.2]}}],
                  "embedding": {"allow_outside": true}})";
    }
    Document d;
    d.openProject(project);
    QVERIFY(d.model() != nullptr);
    const auto failed = d.failedPoints();
    QVERIFY(failed.size() > 0);
    QCOMPARE(failed.size() % 3, std::size_t(0));
    QCOMPARE(static_cast<int>(failed.size() / 3), static_cast<int>(d.model()->summary().failures.size()));
    for (std::size_t k = 0; k < failed.size(); k += 3) QVERIFY(failed[k] > 0.1);  // beyond the box's x = 0.1
    const QStringList problems = d.problems();
    QVERIFY(!problems.isEmpty());
    QVERIFY2(problems.join(QLatin1Char(' ')).contains(QStringLiteral("outside every lattice")), qPrintable(problems.join(QLatin1Char(' '))));
}

void DocumentTest::latticeEditsRebuildTheModelAndUndo() {
    Document d;
    d.newFromSample(false);
    QSignalSpy structure(&d, &Document::structureChanged);
    aero::io::LatticeCase lc;
    lc.name = "wing";
    lc.counts = {5, 4, 3};
    lc.degrees = {2, 2, 1};
    lc.padding = {0.1, 0.1, 0.1};
    lc.patches = {0, 1, 2, 3};
    aero::ffd::StationSpec st;
    st.direction = 1;
    st.bits.assign(4, "011");
    d.addLattice(lc, st);
    QCOMPARE(structure.count(), 1);
    QCOMPARE(d.latticeCount(), 1);
    QVERIFY(d.model()->design().size() > 0);
    QVERIFY(d.model()->design().find("wing.S1.tx") >= 0);
    QCOMPARE(d.model()->summary().embedded, d.model()->summary().unique - d.model()->summary().fixed);
    QVERIFY(d.model()->summary().fixed > 0);  // the other patches stay put
    QVERIFY_THROWS_EXCEPTION(aero::CaseError, d.addLattice(lc));  // duplicate name
    QCOMPARE(d.undoStack()->count(), 1);

    // A value and a displacement that survive an edit that keeps them valid...
    d.setDesignValue(d.model()->design().find("wing.S1.tx"), 0.2);
    d.moveLatticePoints(0, {d.lattices()[0].index(4, 3, 2)}, {0, 0, 0.1});
    lc.name = "inboard";
    lc.counts = {5, 4, 2};
    d.editLattice(0, lc);
    QCOMPARE(d.caseFile().lattices[0].name, std::string("inboard"));
    QVERIFY(d.caseFile().values.count("inboard.S1.tx") == 1);  // renamed with its lattice
    QVERIFY(d.caseFile().displacements.empty());               // k = 2 no longer exists
    QCOMPARE(d.lattices()[0].count, (std::array<int, 3>{5, 4, 2}));
    // ...and undo brings everything back, exactly.
    const std::string edited = caseText(d.caseFile());
    d.undoStack()->undo();
    QCOMPARE(d.caseFile().lattices[0].name, std::string("wing"));
    QCOMPARE(d.caseFile().displacements.size(), std::size_t(1));
    d.undoStack()->redo();
    QCOMPARE(caseText(d.caseFile()), edited);
    d.removeLattice(0);
    QVERIFY(d.model() == nullptr);
    QVERIFY(d.caseFile().values.empty());
    QVERIFY(samePoints(d.shape(), d.baseline()));
    d.undoStack()->undo();
    QCOMPARE(d.latticeCount(), 1);
}

// Displacements index the refined lattice: one beyond the unrefined counts (i = 6 of the 7 points
// after a knot insertion in i) survives a rename. The check compared with the unrefined counts
// and dropped it.
void DocumentTest::renamingARefinedLatticeKeepsItsDisplacements() {
    Document d;
    d.newFromSample(false);
    aero::io::LatticeCase lc;
    lc.name = "body";
    lc.counts = {6, 6, 2};
    lc.degrees = {3, 3, 1};
    lc.padding = {0.05, 0.05, 0.05};
    lc.refine = {{0, {0.5}}};
    d.addLattice(lc);
    QCOMPARE(d.lattices()[0].count, (std::array<int, 3>{7, 6, 2}));
    d.moveLatticePoints(0, {d.lattices()[0].index(6, 2, 1)}, {0.05, 0, 0});
    QCOMPARE(d.caseFile().displacements.size(), std::size_t(1));
    lc.name = "renamed";
    d.editLattice(0, lc);
    QCOMPARE(d.caseFile().lattices[0].name, std::string("renamed"));
    QCOMPARE(d.caseFile().displacements.size(), std::size_t(1));
    QCOMPARE(d.caseFile().displacements[0].index, (std::array<int, 3>{6, 2, 1}));
}

void DocumentTest::meshOptionsAreUndoableAndSaved() {
    Document d;
    d.newFromSample(true);
    QVERIFY(!d.caseFile().mesh.present);
    QCOMPARE(d.caseFile().mesh.level, std::string("coarse"));
    QSignalSpy changed(&d, &Document::meshOptionsChanged);
    d.setMeshOptions("coarse", 6);  // the defaults again: no edit
    QCOMPARE(d.undoStack()->count(), 0);
    QCOMPARE(changed.count(), 0);
    d.setMeshOptions("medium", 4);
    QCOMPARE(changed.count(), 1);
    QCOMPARE(d.undoStack()->count(), 1);
    QVERIFY(d.isModified());
    QCOMPARE(d.caseFile().mesh.extrusion.surfaceNodes, 23);  // the level's defaults
    QCOMPARE(d.caseFile().mesh.elasticity.increments, 4);
    QVERIFY_THROWS_EXCEPTION(aero::CaseError, d.setMeshOptions("huge", 4));
    QVERIFY_THROWS_EXCEPTION(aero::CaseError, d.setMeshOptions("medium", 0));
    QCOMPARE(d.undoStack()->count(), 1);

    QTemporaryDir dir;
    const QString path = dir.filePath(QStringLiteral("meshed.json"));
    d.saveProject(path);
    Document e;
    e.openProject(path);
    QVERIFY(e.caseFile().mesh.present);
    QCOMPARE(e.caseFile().mesh.level, std::string("medium"));
    QCOMPARE(e.caseFile().mesh.elasticity.increments, 4);
    QCOMPARE(caseText(e.caseFile()), caseText(d.caseFile()));

    d.undoStack()->undo();
    QCOMPARE(changed.count(), 2);
    QCOMPARE(d.caseFile().mesh.level, std::string("coarse"));
    QCOMPARE(d.caseFile().mesh.extrusion.surfaceNodes, 17);
    QCOMPARE(d.caseFile().mesh.elasticity.increments, 6);
}

void DocumentTest::saveAndReopenRestoresExactly() {
    QTemporaryDir dir;
    Document d;
    d.newFromSample(true);
    d.moveLatticePoints(0, {d.lattices()[0].index(1, 5, 1), d.lattices()[0].index(2, 5, 1)}, {0.05, 0.2, -0.1});
    d.setDesignValue(variable(d, "body.S5.taperx"), 0.7);
    d.setDesignValue(variable(d, "body.S2.tx"), 0.3);
    const QString path = dir.filePath(QStringLiteral("sphere_project.json"));
    QSignalSpy modified(&d, &Document::modifiedChanged);
    d.saveProject(path);
    QVERIFY(!d.isModified());
    QCOMPARE(modified.count(), 1);
    QCOMPARE(d.projectPath(), QFileInfo(path).absoluteFilePath());
    QVERIFY(!d.geometryGenerated());
    // The generated sample geometry went next to the project; the project refers to it.
    QVERIFY(QFileInfo::exists(dir.filePath(QStringLiteral("sphere_project.geometry.json"))));
    QFile file(path);
    QVERIFY(file.open(QIODevice::ReadOnly));
    QVERIFY(file.readAll().contains("\"geometry\": \"sphere_project.geometry.json\""));

    Document e;
    e.openProject(path);
    QCOMPARE(caseText(e.caseFile()), caseText(d.caseFile()));
    QCOMPARE(e.values(), d.values());
    QVERIFY(samePoints(e.shape(), d.shape()));
    QVERIFY(!e.isModified());
    QCOMPARE(e.title(), QStringLiteral("sphere_project.json"));

    // Save As elsewhere: the project's own geometry file goes along, the copy stands alone.
    const QString again = dir.filePath(QStringLiteral("copy/again.json"));
    QDir().mkpath(QFileInfo(again).absolutePath());
    e.saveProject(again);
    QVERIFY(QFileInfo::exists(dir.filePath(QStringLiteral("copy/again.geometry.json"))));
    QVERIFY(QFile::remove(dir.filePath(QStringLiteral("sphere_project.geometry.json"))));
    Document f;
    f.openProject(again);
    QCOMPARE(caseText(f.caseFile()), caseText(d.caseFile()));
    QVERIFY(samePoints(f.shape(), d.shape()));
    // A geometry that is not the project's own stays where it is.
    QTemporaryDir other;
    const QString iges = other.filePath(QStringLiteral("wing.igs"));
    aero::cad::writeIges(aero::geometry::makeHalfSphere(), iges.toStdString());
    Document g;
    g.newFromGeometry(iges);
    g.saveProject(dir.filePath(QStringLiteral("uses_iges.json")));
    QVERIFY(!QFileInfo::exists(dir.filePath(QStringLiteral("uses_iges.geometry.json"))));
    QCOMPARE(QFileInfo(QString::fromStdString(g.caseFile().geometry)).absoluteFilePath(), QFileInfo(iges).absoluteFilePath());
}

void DocumentTest::startDesignIsCheckedUndoableAndSaved() {
    // optimization.start_design from the window: another case's design, checked against this
    // case's variables when it is chosen (not at the run's start), one undoable edit, saved.
    Document d;
    d.newFromSample(true);
    QVERIFY(d.model() != nullptr);
    const auto& vars = d.model()->design().variables();
    QVERIFY(vars.size() > 2);
    const aero::ffd::DesignVariable& v = vars[1];
    QTemporaryDir dir;
    auto writeStart = [&](const QString& name, double value) {
        aero::io::CaseFile c = d.caseFile();
        c.values[v.name] = value;
        c.path = dir.filePath(name).toStdString();
        aero::io::writeCase(c, c.path);
        return c.path;
    };
    const std::string good = writeStart(QStringLiteral("coarse_best.json"), 0.5 * (v.baseline + v.upper));
    QSignalSpy changed(&d, &Document::optimizationOptionsChanged);
    d.setStartDesign("");  // already the case's own: no edit
    QCOMPARE(d.undoStack()->count(), 0);
    d.setStartDesign(good);
    QCOMPARE(d.undoStack()->count(), 1);
    QVERIFY(changed.count() >= 1);
    QCOMPARE(d.caseFile().optimization.startDesign, good);
    QVERIFY(d.caseFile().optimization.present);

    // Refused, naming what does not fit; the case keeps its start.
    const std::string outside = writeStart(QStringLiteral("outside.json"), v.upper + (v.upper - v.lower));
    try {
        d.setStartDesign(outside);
        QFAIL("a start outside the bounds was taken");
    } catch (const aero::CaseError& e) {
        const std::string what = e.what();
        QVERIFY2(what.find("optimization.start_design") != std::string::npos, e.what());
        QVERIFY2(what.find(v.name) != std::string::npos, e.what());
    }
    QVERIFY_THROWS_EXCEPTION(aero::CaseError, d.setStartDesign(dir.filePath(QStringLiteral("none.json")).toStdString()));
    QVERIFY_THROWS_EXCEPTION(aero::CaseError, d.setStartDesign(dir.filePath(QStringLiteral("start.igs")).toStdString()));
    QCOMPARE(d.undoStack()->count(), 1);
    QCOMPARE(d.caseFile().optimization.startDesign, good);

    // Saved (relative to the project) and read back as the same file.
    const QString project = dir.filePath(QStringLiteral("project.json"));
    d.saveProject(project);
    Document e;
    e.openProject(project);
    QCOMPARE(QFileInfo(QString::fromStdString(e.caseFile().optimization.startDesign)).canonicalFilePath(),
             QFileInfo(QString::fromStdString(good)).canonicalFilePath());

    d.undoStack()->undo();
    QVERIFY(d.caseFile().optimization.startDesign.empty());
}

void DocumentTest::autosaveAndRecoveryRestoreExactly() {
    QTemporaryDir dir;
    const QString autosaveDir = dir.filePath(QStringLiteral("autosave"));
    Document d;
    d.newFromSample(true);
    auto saver = std::make_unique<Autosaver>(&d, autosaveDir, 3600000);
    QVERIFY(!saver->saveNow());  // nothing to save yet
    d.moveLatticePoints(0, {d.lattices()[0].index(3, 4, 1)}, {0.1, 0.1, 0.1});
    d.setDesignValue(variable(d, "body.S1.ty"), 0.4);
    QVERIFY(saver->saveNow());
    QVERIFY(!saver->saveNow());  // unchanged since
    QVERIFY(QFileInfo::exists(saver->casePath()));
    // A live session is not offered for recovery.
    QVERIFY(Autosaver::findRecoverable(autosaveDir).isEmpty());

    // A crash: the session's files stay, its lock is gone.
    const QString crashed = dir.filePath(QStringLiteral("crashed"));
    QDir().mkpath(crashed);
    const QString base = QFileInfo(saver->casePath()).fileName().chopped(static_cast<int>(qstrlen(".case.json")));
    for (const char* suffix : {".case.json", ".geometry.json", ".info.json"})
        QVERIFY(QFile::copy(QDir(autosaveDir).filePath(base + QLatin1String(suffix)),
                            QDir(crashed).filePath(base + QLatin1String(suffix))));
    const auto sessions = Autosaver::findRecoverable(crashed);
    QCOMPARE(sessions.size(), 1);
    QVERIFY(sessions[0].generated);
    QCOMPARE(sessions[0].title, d.title());
    QVERIFY(sessions[0].projectPath.isEmpty());

    Document r;
    r.recover(sessions[0].casePath, sessions[0].projectPath, sessions[0].generated, sessions[0].title);
    QVERIFY(r.isModified());
    QVERIFY(r.geometryGenerated());
    QCOMPARE(caseText(r.caseFile()), caseText(d.caseFile()));
    QVERIFY(samePoints(r.shape(), d.shape()));
    Autosaver::discard(sessions[0]);
    QVERIFY(Autosaver::findRecoverable(crashed).isEmpty());

    // Saving (a clean document) and a normal end remove the session's files.
    d.saveProject(dir.filePath(QStringLiteral("saved.json")));
    QVERIFY(!QFileInfo::exists(saver->casePath()));
    d.setDesignValue(variable(d, "body.S1.ty"), 0.5);
    QVERIFY(saver->saveNow());
    const QString path = saver->casePath();
    saver.reset();
    QVERIFY(!QFileInfo::exists(path));
}

void DocumentTest::failedLoadKeepsTheDocument() {
    Document d;
    d.newFromSample(true);
    d.setDesignValue(variable(d, "body.S1.ty"), 0.4);
    const std::string before = caseText(d.caseFile());
    QVERIFY_THROWS_EXCEPTION(aero::Error, d.openProject(QStringLiteral("/nonexistent/project.json")));
    QVERIFY_THROWS_EXCEPTION(aero::Error, d.newFromGeometry(QStringLiteral("/nonexistent/geometry.igs")));
    QCOMPARE(caseText(d.caseFile()), before);
    QVERIFY(d.isModified());
    QCOMPARE(d.undoStack()->count(), 1);
}

void DocumentTest::exportsTheDeformedGeometryExactly() {
    QTemporaryDir dir;
    Document d;
    d.newFromSample(true);
    d.setDesignValue(variable(d, "body.S3.ty"), 0.4);
    d.moveLatticePoints(0, {d.lattices()[0].index(1, 1, 1)}, {0.0, 0.0, 0.2});
    const QString iges = dir.filePath(QStringLiteral("deformed.igs"));
    const QString json = dir.filePath(QStringLiteral("deformed.json"));
    const QString vtm = dir.filePath(QStringLiteral("deformed.vtm"));
    d.exportGeometry(iges);
    d.exportGeometry(json);
    d.exportVtk(vtm);
    QVERIFY(samePoints(aero::cad::readIges(iges.toStdString()), d.shape()));  // 17 digits: exact
    QVERIFY(samePoints(aero::io::readPatchSetJson(json.toStdString()), d.shape()));
    QVERIFY(QFileInfo::exists(vtm));
    QVERIFY(QFileInfo(dir.filePath(QStringLiteral("deformed"))).isDir());  // the .vts pieces
    QVERIFY_THROWS_EXCEPTION(aero::InputError, d.exportGeometry(dir.filePath(QStringLiteral("deformed.stl"))));
}

int runDocumentTest(int argc, char** argv) {
    DocumentTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "DocumentTest.moc"
