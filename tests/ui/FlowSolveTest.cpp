// Qt Test of Flow > Solve end to end through the GUI, on the half-sphere flow sample at mesh.refine
// 0.3 (a few thousand nodes: seconds): the solve runs as a background job from the tool bar's
// action; the residual plot receives one point per iteration, with the exact and approximate
// phases; the forces shown are the evaluator's; the GUI thread never stalls for more than 100 ms
// while it runs (a timer's ticks are measured); the colour bar follows the chosen field and
// range; contour lines, the slice and the spanwise sections are drawn; Stop ends the run within a
// bounded time and keeps the state, which Continue resumes; one run at a time; a run that does
// not converge says why; quitting mid-run asks, then stops the run and keeps its state.
// Screenshots go to the build tree (tests/ui/screenshots/) and are looked at by eye.
#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QDockWidget>
#include <QScrollArea>
#include <QElapsedTimer>
#include <QFile>
#include <QFileInfo>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QPushButton>
#include <QSlider>
#include <QTemporaryDir>
#include <QTest>
#include <QThread>
#include <QTimer>
#include <QUndoStack>
#include <algorithm>
#include <cmath>
#include <ctime>
#include <array>
#include <memory>
#include <vector>

#include "ActionSet.h"
#include "Document.h"
#include "FlowPanel.h"
#include "FlowRunner.h"
#include "FlowScene.h"
#include "FlowWorkspace.h"
#include "JobRunner.h"
#include "MainWindow.h"
#include "MeshPreviewer.h"
#include "OptionEditor.h"
#include "PatchScene.h"
#include "PlotWidget.h"
#include "ResidualPlot.h"
#include "SectionView.h"
#include "UiTestSupport.h"
#include "VtkViewport.h"
#include "io/CaseFile.h"
#include "io/CaseWriter.h"
#include "study/CaseEvaluator.h"
#include "study/GeometryFiles.h"

using aero::ui::FlowField;
using aero::ui::FlowPart;
using aero::ui::FlowRunner;
using aero::ui::MainWindow;
using State = aero::ui::FlowRunner::State;
using namespace aero::uitest;

namespace {

constexpr int kSolveTimeoutMs = 180000;  // seconds on an idle machine; generous on a busy one
constexpr double kFrameBudgetMs = 100 * aero::uitest::kInstrumentationSlowdown;  // the limit for one frame of the GUI thread

const char* stateName(State s) {
    switch (s) {
        case State::None:
            return "None";
        case State::Running:
            return "Running";
        case State::Converged:
            return "Converged";
        case State::NotConverged:
            return "NotConverged";
        case State::Stopped:
            return "Stopped";
        case State::Failed:
            return "Failed";
    }
    return "?";
}

}  // namespace

class FlowSolveTest : public QObject {
    Q_OBJECT

  public:
    explicit FlowSolveTest(bool canRender) : canRender_(canRender) {}

  private slots:
    void initTestCase();
    void cleanupTestCase();
    void solveFromTheToolBarPlotsEveryIteration();
    void forcesShownAreTheEvaluators();
    void guiStaysResponsiveWhileSolving();
    void colourBarFollowsTheChosenField();
    void contoursSliceAndSections();
    void plotsExportPngSvgAndCsv();
    void screenshotsOfTheSolution();
    void oneRunAtATime();
    void stopEndsTheRunQuicklyAndContinueResumesIt();
    void aRunThatDoesNotConvergeSaysWhy();
    void aRunStoppedByItsTimeLimitSaysSo();
    void caseOptionsAreUndoableEdits();
    void anotherDocumentDropsTheRun();
    void quittingMidRunAsksThenKeepsTheState();

  private:
    FlowRunner& runner() { return window_->flow().runner(); }
    aero::ui::FlowPanel& panel() { return *window_->flow().panel(); }
    aero::ui::FlowScene& scene() { return window_->flowScene(); }
    // Waits until the running solve ends; returns the state.
    State waitForEnd() {
        (void)QTest::qWaitFor([this] { return !runner().running(); }, kSolveTimeoutMs);
        return runner().state();
    }
    State solve() {
        window_->actions().flowSolve->trigger();
        if (runner().state() != State::Running) return runner().state();
        return waitForEnd();
    }

    bool canRender_;
    QTemporaryDir dir_;
    QString project_;
    aero::io::CaseFile case_;
    std::unique_ptr<MainWindow> window_;
};

void FlowSolveTest::initTestCase() {
    if (!canRender_)
        QSKIP("test_ui needs an X display: DISPLAY is not set (or QT_QPA_PLATFORM is offscreen). "
              "Run it under xvfb-run -a -s \"-screen 0 1280x800x24\".");
    QVERIFY(dir_.isValid());
    QDir().mkpath(kScreenshotDir);
    // The sample's flow case on a small grid, at an angle of attack (lift), as a project of its
    // own (restart files go next to it).
    aero::io::CaseFile c = aero::io::readCase(std::string(AEROFORM_SAMPLES_DIR) + "/half_sphere_flow.json");
    c.mesh.extrusion.refine = 0.3;
    c.flow.freeStream.alphaDeg = 2.0;
    c.flow.newton.relativeTolerance = 1e-9;
    c.outputFlowVtk.clear();
    c.outputResidualCsv.clear();
    c.outputRestart.clear();
    project_ = dir_.filePath(QStringLiteral("half_sphere_flow_small.json"));
    c.path = project_.toStdString();
    aero::io::writeCase(c, project_.toStdString());
    case_ = aero::io::readCase(project_.toStdString());

    MainWindow::Options options;
    options.autosave = false;
    options.recentFiles = false;
    window_ = std::make_unique<MainWindow>(options);
    window_->resize(1240, 800);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    QString error;
    QVERIFY2(window_->loadFile(project_, &error), qPrintable(error));
    QTRY_VERIFY_WITH_TIMEOUT(window_->viewport()->renderedFrames() > 0, 10000);
}

void FlowSolveTest::cleanupTestCase() {
    window_.reset();
}

void FlowSolveTest::solveFromTheToolBarPlotsEveryIteration() {
    const aero::ui::ActionSet& a = window_->actions();
    QVERIFY(a.flowSolve->isEnabled());
    QVERIFY(!a.flowStop->isEnabled());
    QVERIFY(!a.exportFlow->isEnabled());
    QCOMPARE(runner().state(), State::None);
    // The panel shows the case's options (from the option tables).
    QCOMPARE(std::get<double>(panel().editor("flow", "alpha")->value()), 2.0);
    QCOMPARE(std::get<double>(panel().editor("mesh", "refine")->value()), 0.3);

    a.flowSolve->trigger();
    QCOMPARE(runner().state(), State::Running);
    QVERIFY(a.flowStop->isEnabled());
    QVERIFY(!a.flowSolve->isEnabled());
    QCOMPARE(panel().solveButton()->text(), QStringLiteral("Stop"));
    QVERIFY(window_->findChild<QDockWidget*>(QStringLiteral("residualsDock"))->isVisible());
    QVERIFY(window_->jobs().running(QStringLiteral("flow")) != nullptr);
    const State s = waitForEnd();
    QVERIFY2(s == State::Converged, qPrintable(QStringLiteral("%1: %2").arg(QLatin1String(stateName(s)), runner().stateText())));

    const auto r = runner().result();
    QVERIFY(r && r->flow);
    const auto& history = r->flow->report.history;
    qInfo("small half-sphere: %ld nodes, %zu iterations, %.2f s; CL %.6f CD %.6f", r->nodes(), history.size(), r->seconds,
          r->flow->forces.CL, r->flow->forces.CD);
    QVERIFY(r->nodes() > 1000 && r->nodes() < 11340);
    // One point per accepted iteration, as they arrived; the phases as the solver reports them.
    const aero::ui::ResidualPlot& plot = *window_->flow().residualPlot();
    QCOMPARE(plot.points(), static_cast<int>(history.size()));
    QCOMPARE(runner().acceptedIterations(), static_cast<int>(history.size()));
    const int exact = static_cast<int>(std::count_if(history.begin(), history.end(), [](const auto& it) { return it.exact; }));
    QCOMPARE(plot.exactPoints(), exact);
    QCOMPARE(plot.approximatePoints(), static_cast<int>(history.size()) - exact);
    QVERIFY(plot.yAxis().log);
    // The last point is the converged residual.
    const auto& line = plot.allSeries()[1].points;
    QCOMPARE(line.back().y(), history.back().relativeResidual);
    QVERIFY(plot.yRange().first <= history.back().relativeResidual);

    // What the window says about it.
    QVERIFY2(panel().statusText().startsWith(QStringLiteral("Converged in")), qPrintable(panel().statusText()));
    QVERIFY(a.flowSolve->isEnabled());
    QVERIFY(!a.flowStop->isEnabled());
    QVERIFY(a.exportFlow->isEnabled());
    QVERIFY(!scene().empty());
    QVERIFY(scene().wallShown());
    QVERIFY2(!window_->scene().surfacesVisible(), "the geometry's surfaces make way for the solution's wall");
}

void FlowSolveTest::forcesShownAreTheEvaluators() {
    const auto r = runner().result();
    QVERIFY(r && r->flow);
    // The same case through the one pipeline, here on the test's thread.
    aero::io::CaseFile c = case_;
    c.flow.present = true;
    aero::study::CaseEvaluator ev(c, aero::study::loadGeometry(c.geometry));
    const aero::study::Evaluation e = ev.evaluate(ev.caseValues());
    QVERIFY2(e.ok(), e.message.c_str());
    const auto& f = r->flow->forces;
    const auto& g = e.flow->forces;
    qInfo("GUI CL %.12f CD %.12f CM %.12f; evaluator CL %.12f CD %.12f CM %.12f", f.CL, f.CD, f.CM, g.CL, g.CD, g.CM);
    QVERIFY(f.CD > 0);  // numerical drag on the coarse grid (a sphere has no lift at any angle)
    for (auto [x, y] : {std::pair{f.CL, g.CL}, std::pair{f.CD, g.CD}, std::pair{f.CM, g.CM}})
        QVERIFY2(std::abs(x - y) <= 1e-10 * std::max(1.0, std::abs(y)), qPrintable(QStringLiteral("%1 vs %2").arg(x).arg(y)));
    QCOMPARE(r->flow->report.iterations, e.flow->report.iterations);
    // The panel shows them.
    QCOMPARE(panel().forceLabel(QStringLiteral("CL"))->text(), QLocale().toString(f.CL, 'g', 6));
    QCOMPARE(panel().forceLabel(QStringLiteral("CD"))->text(), QLocale().toString(f.CD, 'g', 6));
    QCOMPARE(panel().forceLabel(QStringLiteral("CM"))->text(), QLocale().toString(f.CM, 'g', 6));
    QCOMPARE(panel().forceLabel(QStringLiteral("L/D"))->text(), QLocale().toString(f.CL / f.CD, 'g', 4));
}

void FlowSolveTest::guiStaysResponsiveWhileSolving() {
    const double loadBefore = loadPerCore();
    // One solve with the window in use, measured; returns how it ended.
    auto solveWhileUsing = [this](FrameProbe& probe) {
        probe.start();
        window_->actions().flowSolve->trigger();
        if (runner().state() != State::Running) return runner().state();
        // Use the window meanwhile, as a user would: hover over the plot, turn the view now and then.
        QTimer user;
        int moves = 0;
        connect(&user, &QTimer::timeout, this, [&] {
            window_->flow().residualPlot()->hoverAt(QPointF(60 + 7 * (moves % 40), 120));
            if (moves % 5 == 0) window_->viewport()->requestRender();
            ++moves;
        });
        user.start(40);
        const State s = waitForEnd();
        QTest::qWait(300);  // the result is shown and the view renders it
        user.stop();
        probe.stop();
        qInfo("GUI thread while solving: %ld ticks of a 5 ms timer, mean gap %.1f ms; longest gap %.1f ms, without the "
              "3D view's rendering %.1f ms; the GUI thread's own CPU in one gap at most %.1f ms; %d frames of the 3D "
              "view, the longest %.1f ms; load average %s on %d cores",
              probe.ticks(), probe.meanMs(), probe.worstMs(), probe.worstWithoutRenderingMs(), probe.worstOwnCpuMs(),
              probe.frames(), probe.longestFrameMs(), qPrintable(loadAverage()), QThread::idealThreadCount());
        for (const auto& g : probe.slowGaps()) qInfo("  %s", qPrintable(describe(g)));
        return s;
    };
    FrameProbe probe(window_->viewport());
    QCOMPARE(solveWhileUsing(probe), State::Converged);
    // Enough gaps were measured to mean something. Not a fixed count per second: with a software
    // OpenGL (llvmpipe under Xvfb) a gap may hold a 30-100 ms frame of the 3D view, and a fast
    // machine converges this coarse case in a second or two.
    QVERIFY2(probe.ticks() >= 20, qPrintable(QStringLiteral("%1 ticks").arg(probe.ticks())));
    QVERIFY(probe.frames() > 3);
    // Our work on the GUI thread (reports, plot, panels, the result's surfaces) never takes a
    // frame's budget, whatever the machine runs besides (a breach is measured again, see
    // confirmedOwnCpuMs).
    const double ownCpu = confirmedOwnCpuMs(probe.worstOwnCpuMs(), kFrameBudgetMs, [&] {
        FrameProbe second(window_->viewport());
        return solveWhileUsing(second) == State::Converged ? second.worstOwnCpuMs() : kFrameBudgetMs;
    });
    QVERIFY2(ownCpu < kFrameBudgetMs, qPrintable(QStringLiteral("the GUI thread worked %1 ms in one go").arg(ownCpu)));
    // The wall clock holds the budget too, unless other work oversubscribed the machine's cores
    // before the solve started (a shared CI box): then a waiting GUI thread is not scheduled for
    // tens of milliseconds, whoever runs, and the numbers above are the record.
    if (loadBefore <= 1.0)
        QVERIFY2(probe.worstWithoutRenderingMs() < kFrameBudgetMs,
                 qPrintable(QStringLiteral("the GUI thread stalled for %1 ms").arg(probe.worstWithoutRenderingMs())));
    else
        qInfo("the wall-clock gaps are not checked: %.1f runnable threads per core before the solve", loadBefore);
}

void FlowSolveTest::colourBarFollowsTheChosenField() {
    QVERIFY(!scene().empty());
    QVERIFY(panel().automaticRange());
    std::vector<std::pair<double, double>> ranges;
    for (int f = 0; f < aero::ui::kFlowFields; ++f) {
        const auto field = static_cast<FlowField>(f);
        panel().fieldBox()->setCurrentIndex(f);
        QCOMPARE(scene().field(), field);
        const auto range = scene().range();
        QCOMPARE(range, scene().autoRange(field));
        ranges.push_back(range);
        // The bar names the field; the panel's boxes show its range.
        const std::string title = scene().barTitle();
        const char* expected[] = {"Entropy", "Cp", "Mach", "Pressure"};  // short: the bar is narrow
        QVERIFY2(title.find(expected[f]) != std::string::npos, title.c_str());
        QCOMPARE(panel().chosenRange().first, range.first);
        QCOMPARE(panel().chosenRange().second, range.second);
        qInfo("%s: [%g, %g]", title.c_str(), range.first, range.second);
    }
    // Different fields, different ranges: Mach below 1 and above 0, Cp up to about 1 at the nose.
    QVERIFY(ranges[2].first >= 0 && ranges[2].second < 1.0 && ranges[2].second > 0.5);
    QVERIFY(ranges[1].second > 0.8 && ranges[1].second < 1.1);
    QVERIFY(ranges[1] != ranges[2]);
    // The entropy's automatic range is its bulk on the wall and symmetry plane (percentiles),
    // inside the field's extremes.
    const auto& extremes = runner().result()->range[static_cast<std::size_t>(FlowField::Entropy)];
    QVERIFY(ranges[0].first >= extremes[0] && ranges[0].second <= extremes[1]);
    // A chosen range holds whatever the data; unchecking returns to the data's.
    panel().setField(FlowField::PressureCoefficient);
    panel().setChosenRange({-1.5, 1.0});
    QCOMPARE(scene().range(), (std::pair<double, double>{-1.5, 1.0}));
    panel().setField(FlowField::Mach);
    QCOMPARE(scene().range(), (std::pair<double, double>{-1.5, 1.0}));
    panel().automaticBox()->setChecked(true);
    QCOMPARE(scene().range(), scene().autoRange(FlowField::Mach));
    panel().setField(FlowField::Entropy);
}

void FlowSolveTest::contoursSliceAndSections() {
    QCOMPARE(scene().contourSegments(), 0L);
    panel().setPartShown(FlowPart::Contours, true);
    QVERIFY(scene().partVisible(FlowPart::Contours));
    QVERIFY2(scene().contourSegments() > 50, qPrintable(QString::number(scene().contourSegments())));
    // The slice: moving the slider shows it, at the chosen plane.
    QCOMPARE(scene().sliceCells(), 0L);
    panel().sliceSlider()->setValue(300);
    QVERIFY(scene().partVisible(FlowPart::Slice));
    QVERIFY(scene().sliceCells() > 100);
    const double x = panel().slicePosition();
    QCOMPARE(scene().slicePosition(), x);
    QCOMPARE(scene().sliceAxis(), 0);
    // Sections: filled across the span every 0.5 at the first solution; cut again when typed.
    aero::ui::SectionView& sections = *window_->flow().sections();
    const std::vector<double> filled = sections.stations();
    QCOMPARE(filled, (std::vector<double>{0.0, 0.5}));  // radius 1: 0 and 0.5 (1 is the tip)
    sections.stationEdit()->setText(QStringLiteral("0.2, 0.5, 0.8"));
    emit sections.stationEdit()->editingFinished();
    const auto& cuts = sections.cuts();
    QCOMPARE(static_cast<int>(cuts.size()), 3);
    const auto cpRange = scene().autoRange(FlowField::PressureCoefficient);
    for (const aero::ui::SectionCut& c : cuts) {
        QVERIFY(!c.pieces.empty());
        // A circle of radius sqrt(1 - y^2) on the half-sphere; x spans its chord.
        const double r = std::sqrt(1 - c.station * c.station);
        const auto xr = c.xRange();
        QVERIFY2(std::abs(xr[1] - xr[0] - 2 * r) < 0.05 * r, qPrintable(QStringLiteral("%1: %2 .. %3").arg(c.station).arg(xr[0]).arg(xr[1])));
        for (const auto& piece : c.pieces)
            for (const auto& p : piece) QVERIFY(p[2] >= cpRange.first - 1e-9 && p[2] <= cpRange.second + 1e-9);
    }
    QCOMPARE(static_cast<int>(sections.profilePlot()->allSeries().size()), 3);
    QCOMPARE(static_cast<int>(sections.cpPlot()->allSeries().size()), 3);
    QVERIFY(sections.cpPlot()->yAxis().reversed);
}

void FlowSolveTest::plotsExportPngSvgAndCsv() {
    aero::ui::ResidualPlot& plot = *window_->flow().residualPlot();
    QTemporaryDir out;
    const QString png = out.filePath(QStringLiteral("residuals.png")), svg = out.filePath(QStringLiteral("residuals.svg")),
                  csv = out.filePath(QStringLiteral("residuals.csv"));
    QVERIFY(plot.exportPng(png));
    QVERIFY(plot.exportSvg(svg));
    QVERIFY(plot.exportCsv(csv));
    QImage image(png);
    QCOMPARE(image.size(), plot.size() * 2);
    QVERIFY(distinctColours(image) > 20);
    QFile s(svg);
    QVERIFY(s.open(QIODevice::ReadOnly));
    const QString text = QString::fromUtf8(s.readAll());
    QVERIFY(text.startsWith(QStringLiteral("<?xml")));
    QVERIFY(text.contains(QStringLiteral("<svg")) && text.contains(QStringLiteral("</svg>")));
    QVERIFY(text.contains(QStringLiteral("<polyline")));
    QVERIFY(text.contains(QStringLiteral("Nonlinear iteration")));
    QFile c(csv);
    QVERIFY(c.open(QIODevice::ReadOnly));
    const QStringList lines = QString::fromUtf8(c.readAll()).split(QLatin1Char('\n'), Qt::SkipEmptyParts);
    QVERIFY(lines.front().startsWith(QStringLiteral("iteration,residual,relative_residual")));
    QCOMPARE(lines.size() - 1, static_cast<int>(runner().reports().size() -
                                                 std::count_if(runner().reports().begin(), runner().reports().end(),
                                                               [](const auto& p) { return !p.hasIteration; })));
    // Hovering a point names its values.
    const QPointF last = plot.allSeries()[1].points.back();
    plot.hoverAt(plot.toWidget(last));
    QVERIFY2(plot.hoverText().contains(QStringLiteral("Relative residual")), qPrintable(plot.hoverText()));
    QVERIFY(QTest::qWaitForWindowExposed(&plot) || true);
    QVERIFY(plot.toImage(1.0).save(kScreenshotDir + QStringLiteral("/flow_residuals.png")));
    QVERIFY(plot.exportSvg(kScreenshotDir + QStringLiteral("/flow_residuals.svg")));
    plot.hoverAt({-1, -1});
    // The section plots export too (shown first: a hidden dock's plot has no size yet).
    auto* sectionsDock = window_->findChild<QDockWidget*>(QStringLiteral("sectionsDock"));
    sectionsDock->show();
    sectionsDock->raise();
    QTRY_VERIFY(window_->flow().sections()->cpPlot()->width() > 200);
    const QImage cpPlot = window_->flow().sections()->cpPlot()->toImage(1.0);
    QVERIFY(distinctColours(cpPlot) > 20);
    QVERIFY(cpPlot.save(kScreenshotDir + QStringLiteral("/flow_sections_cp.png")));
    window_->findChild<QDockWidget*>(QStringLiteral("residualsDock"))->raise();
}

void FlowSolveTest::screenshotsOfTheSolution() {
    panel().setField(FlowField::Entropy);
    panel().setPartShown(FlowPart::Contours, false);
    panel().setPartShown(FlowPart::Slice, false);
    window_->resetCamera();
    const QImage entropy = window_->viewport()->grabImage();
    QVERIFY(entropy.save(kScreenshotDir + QStringLiteral("/flow_entropy.png")));
    QVERIFY2(distinctColours(entropy) > 200, "the entropy view looks blank");
    panel().setField(FlowField::PressureCoefficient);
    panel().setPartShown(FlowPart::Contours, true);
    const QImage cp = window_->viewport()->grabImage();
    QVERIFY(cp.save(kScreenshotDir + QStringLiteral("/flow_cp.png")));
    QVERIFY2(compare(cp, entropy).differingShare > 0.02, "Cp looks like the entropy");
    // The whole window, with the residual history and the sections below.
    window_->findChild<QDockWidget*>(QStringLiteral("sectionsDock"))->show();
    window_->findChild<QDockWidget*>(QStringLiteral("residualsDock"))->raise();
    QTest::qWait(100);
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/flow_window.png")));
    window_->findChild<QDockWidget*>(QStringLiteral("sectionsDock"))->raise();
    QTest::qWait(100);
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/flow_window_sections.png")));
    window_->findChild<QDockWidget*>(QStringLiteral("residualsDock"))->raise();
    panel().setPartShown(FlowPart::Contours, false);
    panel().setField(FlowField::Entropy);
}

void FlowSolveTest::oneRunAtATime() {
    window_->actions().flowSolve->trigger();
    QCOMPARE(runner().state(), State::Running);
    QString error;
    QVERIFY(!runner().start(&error));
    QVERIFY2(error.contains(QStringLiteral("one at a time")), qPrintable(error));
    QCOMPARE(window_->jobs().jobs().size(), 1);
    // A mesh preview may run beside it (the runner holds several jobs, each with its own
    // progress and Cancel in the status bar).
    window_->actions().meshPreview->trigger();
    QCOMPARE(window_->jobs().jobs().size(), 2);
    QVERIFY(window_->jobs().running(QStringLiteral("mesh-preview")) != nullptr);
    QVERIFY(window_->jobs().running(QStringLiteral("flow")) != nullptr);
    runner().stop();
    QCOMPARE(waitForEnd(), State::Stopped);
    QVERIFY(QTest::qWaitFor([this] { return !window_->jobs().busy(); }, kSolveTimeoutMs));
    window_->meshPreviewer().clear();
}

void FlowSolveTest::stopEndsTheRunQuicklyAndContinueResumesIt() {
    const QString restart = runner().restartPath();
    QCOMPARE(restart, dir_.filePath(QStringLiteral("half_sphere_flow_small.restart")));
    QFile::remove(restart);
    window_->actions().flowSolve->trigger();
    QVERIFY(QTest::qWaitFor([this] { return runner().acceptedIterations() >= 3; }, kSolveTimeoutMs));
    QElapsedTimer clock;
    clock.start();
    window_->actions().flowStop->trigger();
    const State s = waitForEnd();
    const qint64 ms = clock.elapsed();
    qInfo("stopped %lld ms after Stop, at iteration %d", ms, runner().acceptedIterations());
    QCOMPARE(s, State::Stopped);
    QVERIFY2(ms < 10000, qPrintable(QStringLiteral("%1 ms").arg(ms)));  // one iteration at most
    const auto stopped = runner().result();
    QVERIFY(stopped && stopped->flow);
    QCOMPARE(QString::fromStdString(stopped->restartWritten), restart);
    QVERIFY(QFileInfo::exists(restart));
    QVERIFY2(panel().statusText().contains(QStringLiteral("Stopped at iteration")), qPrintable(panel().statusText()));
    QVERIFY(!scene().empty());  // the state reached is shown
    QVERIFY(window_->actions().flowContinue->isEnabled());
    QVERIFY(panel().continueButton()->isEnabled());
    const int before = stopped->flow->report.iterations;

    // Continue: the iterations go on from where they stopped, to convergence.
    window_->actions().flowContinue->trigger();
    QCOMPARE(runner().state(), State::Running);
    const State again = waitForEnd();
    QVERIFY2(again == State::Converged, qPrintable(runner().stateText()));
    const auto r = runner().result();
    QVERIFY(r->flow->restartContinued);
    QCOMPARE(r->flow->previousIterations, before);
    const auto& line = window_->flow().residualPlot()->allSeries()[1].points;
    QCOMPARE(static_cast<int>(line.front().x()), before + 1);
    // Converged: no stale state is left to continue.
    QVERIFY(!QFileInfo::exists(restart));
    QVERIFY(!window_->actions().flowContinue->isEnabled());
}

void FlowSolveTest::aRunThatDoesNotConvergeSaysWhy() {
    aero::ui::Document& doc = window_->document();
    const int undoBefore = doc.undoStack()->count();
    doc.setOption(aero::ui::Document::Section::Flow, "max_iterations", aero::io::OptionValue(3L));
    QCOMPARE(std::get<long>(panel().editor("flow", "max_iterations")->value()), 3L);
    QVERIFY(runner().outdated());
    QVERIFY2(scene().empty(), "an outdated solution leaves the view");
    const State s = solve();
    QCOMPARE(s, State::NotConverged);
    QVERIFY2(panel().statusText().startsWith(QStringLiteral("Not converged: ")), qPrintable(panel().statusText()));
    QVERIFY2(runner().reason().contains(QStringLiteral("iterations")), qPrintable(runner().reason()));
    // The pipeline's mode analysis (flow.stall_modes) ran in the background job and its verdict
    // is in the reason: a mode that grows, or none.
    QVERIFY2(runner().reason().contains(QStringLiteral("grows")), qPrintable(runner().reason()));
    QTest::qWait(100);
    QVERIFY(window_->grab().save(kScreenshotDir + QStringLiteral("/flow_not_converged.png")));
    // The whole reason is there to read: the status scrolls (a plain label was cut after four
    // lines).
    auto* area = window_->findChild<QScrollArea*>(QStringLiteral("flowStatusArea"));
    QVERIFY(area);
    QVERIFY2(area->widget()->height() >= area->widget()->heightForWidth(area->widget()->width()),
             "the status label is shorter than its text");
    QCOMPARE(runner().acceptedIterations(), 3);
    doc.undoStack()->undo();
    QCOMPARE(doc.undoStack()->count(), undoBefore + 1);
    QCOMPARE(doc.caseFile().flow.newton.maxIterations, case_.flow.newton.maxIterations);
}

// flow.max_seconds is on the panel; a run that spends it stops with that reason, and no retry or
// mode search follows in the background job.
void FlowSolveTest::aRunStoppedByItsTimeLimitSaysSo() {
    aero::ui::Document& doc = window_->document();
    QVERIFY(panel().editor("flow", "max_seconds"));
    doc.setOption(aero::ui::Document::Section::Flow, "max_seconds", aero::io::OptionValue(1e-6));
    QCOMPARE(std::get<double>(panel().editor("flow", "max_seconds")->value()), 1e-6);
    const State s = solve();
    QCOMPARE(s, State::NotConverged);
    QVERIFY2(runner().reason().contains(QStringLiteral("flow.max_seconds")), qPrintable(runner().reason()));
    QVERIFY2(!runner().reason().contains(QStringLiteral("grows")), qPrintable(runner().reason()));
    doc.undoStack()->undo();
    QCOMPARE(doc.caseFile().flow.maxSeconds, 0.0);
}

void FlowSolveTest::caseOptionsAreUndoableEdits() {
    aero::ui::Document& doc = window_->document();
    QUndoStack* stack = doc.undoStack();
    const int index = stack->index();
    auto* alpha = qobject_cast<QDoubleSpinBox*>(panel().editor("flow", "alpha")->widget());
    QVERIFY(alpha);
    alpha->setValue(3.5);
    QCOMPARE(doc.caseFile().flow.freeStream.alphaDeg, 3.5);
    QCOMPARE(stack->index(), index + 1);
    QVERIFY(stack->undoText().contains(QStringLiteral("flow.alpha")));
    // The table's range: the panel cannot go beyond what the case parser accepts.
    QVERIFY(alpha->maximum() < 90.0 && alpha->maximum() > 89.99);
    stack->undo();
    QCOMPARE(doc.caseFile().flow.freeStream.alphaDeg, 2.0);
    QCOMPARE(std::get<double>(panel().editor("flow", "alpha")->value()), 2.0);
    // The grid level resets the grid options, as in a case file (undone again).
    auto* level = qobject_cast<QComboBox*>(panel().editor("mesh", "level")->widget());
    QVERIFY(level);
    QCOMPARE(level->currentData().toString(), QStringLiteral("coarse"));
    level->setCurrentIndex(level->findData(QStringLiteral("medium")));
    emit level->activated(level->currentIndex());
    QCOMPARE(doc.caseFile().mesh.level, std::string("medium"));
    QCOMPARE(doc.caseFile().mesh.extrusion.refine, 1.0);
    stack->undo();
    QCOMPARE(doc.caseFile().mesh.extrusion.refine, 0.3);
}

void FlowSolveTest::anotherDocumentDropsTheRun() {
    window_->actions().flowSolve->trigger();
    QVERIFY(QTest::qWaitFor([this] { return runner().acceptedIterations() >= 1; }, kSolveTimeoutMs));
    QString error;
    QVERIFY2(window_->loadFile(project_, &error), qPrintable(error));  // the project again: a new document
    QCOMPARE(runner().state(), State::None);
    QVERIFY(QTest::qWaitFor([this] { return !window_->jobs().busy(); }, kSolveTimeoutMs));
    QCOMPARE(runner().state(), State::None);  // the old run's end is not this document's result
    QVERIFY(runner().result() == nullptr);
    QVERIFY(scene().empty());
    QVERIFY(window_->actions().flowSolve->isEnabled());
    QVERIFY(!window_->actions().exportFlow->isEnabled());
}

void FlowSolveTest::quittingMidRunAsksThenKeepsTheState() {
    window_->document().undoStack()->setClean();  // no question about saving: this is about the run
    const QString restart = runner().restartPath();
    QFile::remove(restart);
    window_->actions().flowSolve->trigger();
    QVERIFY(QTest::qWaitFor([this] { return runner().acceptedIterations() >= 2; }, kSolveTimeoutMs));
    // "Keep Working": the window stays and the run goes on.
    bool answered = false;
    answerNextMessageBox(QStringLiteral("Keep Working"), &answered);
    QVERIFY(!window_->close());
    QVERIFY(answered);
    QVERIFY(window_->isVisible());
    QCOMPARE(runner().state(), State::Running);
    // "Stop and Quit": the run stops, keeps its state, the window closes.
    answered = false;
    answerNextMessageBox(QStringLiteral("stopAndQuit"), &answered);
    QVERIFY(window_->close());
    QVERIFY(answered);
    QVERIFY(!window_->jobs().busy() || window_->jobs().jobs().front()->wait(0));
    QTRY_COMPARE_WITH_TIMEOUT(runner().state(), State::Stopped, 5000);
    QVERIFY(QFileInfo::exists(restart));
}

int runFlowSolveTest(int argc, char** argv, bool canRender) {
    FlowSolveTest test(canRender);
    return QTest::qExec(&test, argc, argv);
}

#include "FlowSolveTest.moc"
