// aeroform: the desktop application (and `--batch`, its headless entry point).
//
//   aeroform [FILE]                      open FILE (project .json, patch set .json, .igs,
//                                        .iges), or the sample
//   aeroform --sample                    open the half-sphere sample with the paper's FFD
//   aeroform --screenshot OUT.png [--solve | --optimize] [--window] [--sections] [FILE]
//                                        open, (solve the flow, or run the optimization,)
//                                        render, save the viewport (or the whole window), exit
//   aeroform --batch FILE                headless run (no Qt application, no window)
//
// Exit codes: 0 success, 1 failure of the work (bad input, cannot write), 2 usage error.
#include <QApplication>
#include <QDockWidget>
#include <QElapsedTimer>
#include <QSurfaceFormat>
#include <QWindow>
#include <cstdio>
#include <cstring>
#include <string>

#include "FlowRunner.h"
#include "FlowWorkspace.h"
#include "MainWindow.h"
#include "OptimizationRunner.h"
#include "OptimizationWorkspace.h"
#include "VtkViewport.h"
#include "cli/Commands.h"

namespace {

constexpr const char* kUsage =
    "Usage: aeroform [FILE]\n"
    "       aeroform --sample\n"
    "       aeroform --screenshot OUT.png [--solve | --optimize] [--window] [--sections]\n"
    "                [FILE | --sample]\n"
    "       aeroform --batch FILE\n"
    "\n"
    "Aeroform: NURBS / free-form deformation aerodynamic shape design.\n"
    "\n"
    "  FILE               project (a case file, .json), patch set (.json) or IGES (.igs,\n"
    "                     .iges) to open; without FILE the half-sphere sample is shown\n"
    "  --sample           open the half-sphere sample (20 bicubic patches) with the paper's\n"
    "                     6x6x2 FFD lattice and 89 design variables\n"
    "  --screenshot OUT   open FILE (or the sample), render it, save the viewport as OUT\n"
    "                     (PNG or JPEG by suffix) and exit; needs a display (e.g. xvfb-run)\n"
    "  --solve            with --screenshot: solve the case's flow first (Flow > Solve) and\n"
    "                     show the solution; exit 1 if it does not converge\n"
    "  --optimize         with --screenshot: run the case's optimization (Optimize > Start,\n"
    "                     or Resume when its history exists) and show its workspace with\n"
    "                     the last evaluation; exit 1 if it fails or is stopped\n"
    "  --window           with --screenshot: save the whole window, panels and plots included\n"
    "  --sections         with --solve: show the spanwise sections below the view instead of\n"
    "                     the residual history\n"
    "  --batch FILE       run FILE headless, without any window (see aeroform-cli)\n"
    "  -h, --help         show this help\n"
    "\n"
    "Qt options (e.g. -platform, -style) are accepted as well.\n";

int usageError(const std::string& message) {
    std::fprintf(stderr, "aeroform: %s\n\n%s", message.c_str(), kUsage);
    return 2;
}

struct GuiOptions {
    QString file;
    QString screenshot;
    bool sample = false;
    bool solve = false;
    bool optimize = false;
    bool window = false;
    bool sections = false;
};

// Parses the arguments left after QApplication removed its own. Returns -1 to go on, or an
// exit code.
int parseGuiOptions(const QStringList& args, GuiOptions& o) {
    for (qsizetype i = 1; i < args.size(); ++i) {
        const QString& a = args[i];
        if (a == QLatin1String("--sample")) {
            o.sample = true;
        } else if (a == QLatin1String("--solve")) {
            o.solve = true;
        } else if (a == QLatin1String("--optimize")) {
            o.optimize = true;
        } else if (a == QLatin1String("--window")) {
            o.window = true;
        } else if (a == QLatin1String("--sections")) {
            o.sections = true;
        } else if (a == QLatin1String("--screenshot")) {
            if (i + 1 >= args.size()) return usageError("--screenshot needs an output file");
            o.screenshot = args[++i];
        } else if (a.startsWith(QLatin1Char('-')) && a != QLatin1String("-")) {
            return usageError("unknown option '" + a.toStdString() + "'");
        } else if (o.file.isEmpty()) {
            o.file = a;
        } else {
            return usageError("more than one FILE given");
        }
    }
    if (o.sample && !o.file.isEmpty()) return usageError("give either FILE or --sample");
    if ((o.solve || o.optimize || o.window) && o.screenshot.isEmpty())
        return usageError("--solve, --optimize and --window go with --screenshot");
    if (o.solve && o.optimize) return usageError("give either --solve or --optimize");
    if (o.sections && !o.solve) return usageError("--sections goes with --solve");
    return -1;
}

// Shows the window, loads, waits until the window is exposed and has rendered, saves the
// viewport. Loading after show() lets the camera fit the final viewport size.
int runScreenshot(QApplication& app, aero::ui::MainWindow& window, const GuiOptions& o) {
    window.show();
    QElapsedTimer timer;
    timer.start();
    auto waitUntil = [&](auto done) {
        while (!done() && timer.elapsed() < 10000) app.processEvents(QEventLoop::AllEvents, 50);
    };
    waitUntil([&] { return window.windowHandle() && window.windowHandle()->isExposed(); });
    QString error;
    const bool loaded =
        o.file.isEmpty() ? window.loadSample(&error) : window.loadFile(o.file, &error);
    if (!loaded) {
        std::fprintf(stderr, "aeroform: %s\n", qPrintable(error));
        return 1;
    }
    waitUntil([&] { return window.viewport()->renderedFrames() > 0; });
    int code = 0;
    if (o.solve) {
        aero::ui::FlowRunner& runner = window.flow().runner();
        window.flow().solve();
        while (runner.running()) app.processEvents(QEventLoop::AllEvents, 50);
        std::fprintf(stderr, "aeroform: %s\n", qPrintable(runner.stateText()));
        if (runner.state() != aero::ui::FlowRunner::State::Converged) code = 1;
        if (o.sections) {
            if (auto* dock = window.findChild<QDockWidget*>(QStringLiteral("sectionsDock"))) {
                dock->show();
                dock->raise();
            }
        }
        const int frames = window.viewport()->renderedFrames();
        timer.restart();
        waitUntil([&] { return window.viewport()->renderedFrames() > frames; });
    }
    if (o.optimize) {
        aero::ui::OptimizationRunner& runner = window.optimization().runner();
        while (runner.loading())
            app.processEvents(QEventLoop::AllEvents, 50);  // a history read back
        using Start = aero::ui::OptimizationRunner::Start;
        if (!runner.start(runner.historyExists() ? Start::Resume : Start::New, &error)) {
            std::fprintf(stderr, "aeroform: %s\n", qPrintable(error));
            return 1;
        }
        while (runner.running()) app.processEvents(QEventLoop::AllEvents, 50);
        std::fprintf(stderr, "aeroform: %s\n", qPrintable(runner.stateText()));
        if (runner.state() != aero::ui::OptimizationRunner::State::Finished) code = 1;
        window.resetCamera();
        const int frames = window.viewport()->renderedFrames();
        timer.restart();
        waitUntil([&] { return window.viewport()->renderedFrames() > frames; });
    }
    if (o.window) {
        app.processEvents();
        if (!window.grab().save(o.screenshot)) {
            std::fprintf(stderr, "aeroform: cannot write %s\n", qPrintable(o.screenshot));
            return 1;
        }
    } else if (!window.saveScreenshot(o.screenshot, &error)) {
        std::fprintf(stderr, "aeroform: %s\n", qPrintable(error));
        return 1;
    }
    std::fprintf(stderr, "aeroform: wrote %s\n", qPrintable(o.screenshot));
    return code;
}

}  // namespace

int main(int argc, char** argv) {
    // Background flow runs (and --batch) use OpenMP: never let its threads spin.
    aero::app::ensurePassiveOpenMpWaiting(argv);
    // Options that must not create a Qt application are handled before it exists.
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
            std::fputs(kUsage, stdout);
            return 0;
        }
    }
    if (argc >= 2 && std::strcmp(argv[1], "--batch") == 0) {
        if (argc != 3) return usageError("--batch takes exactly one FILE and no other option");
        return aero::app::runBatch(argv[2]);
    }
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--batch") == 0)
            return usageError("--batch must come first and alone: aeroform --batch FILE");

    // VTK needs an OpenGL 3.2 core context: the default format must be set before the
    // QApplication (and with it the first context) exists.
    QSurfaceFormat::setDefaultFormat(aero::ui::VtkViewport::defaultFormat());
    QApplication app(argc, argv);
    QApplication::setApplicationName(QStringLiteral("Aeroform"));
    QApplication::setOrganizationName(QStringLiteral("Aeroform"));
    QApplication::setApplicationVersion(QStringLiteral("0.1.0"));

    GuiOptions options;
    if (const int code = parseGuiOptions(QApplication::arguments(), options); code >= 0)
        return code;

    if (!options.screenshot.isEmpty()) {
        // A one-shot picture: no autosave session, no recent-files entry.
        aero::ui::MainWindow::Options o;
        o.autosave = false;
        o.recentFiles = false;
        aero::ui::MainWindow window(o);
        window.resize(1200, 800);
        return runScreenshot(app, window, options);
    }
    aero::ui::MainWindow window;
    window.resize(1240, 780);

    window.show();
    if (options.file.isEmpty())
        window.openSample();
    else
        window.openFile(options.file);
    // After the window is up: offer work a crashed session autosaved (asks before replacing
    // what was just opened, which is unmodified).
    QMetaObject::invokeMethod(&window, [&window] { window.offerRecovery(); }, Qt::QueuedConnection);
    return QApplication::exec();
}
