#include "Menus.h"

#include <QAction>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QToolBar>

#include "ActionSet.h"

namespace aero::ui {

MenuRefs buildMenus(QMainWindow* window, const ActionSet& a) {
    MenuRefs menus;
    QMenuBar* bar = window->menuBar();

    QMenu* file = bar->addMenu(QObject::tr("&File"));
    file->setToolTipsVisible(true);
    file->addAction(a.open);
    menus.recent = file->addMenu(QObject::tr("Open &Recent"));
    menus.recent->setObjectName(QStringLiteral("menuRecent"));
    QMenu* samples = file->addMenu(QObject::tr("Open &Sample"));
    samples->addAction(a.openSample);
    samples->addAction(a.openSampleGeometry);
    file->addSeparator();
    file->addAction(a.save);
    file->addAction(a.saveAs);
    QMenu* exports = file->addMenu(QObject::tr("&Export"));
    exports->setToolTipsVisible(true);
    exports->addAction(a.exportGeometry);
    exports->addAction(a.exportVtk);
    exports->addAction(a.exportGrid);
    exports->addAction(a.exportFlow);
    exports->addAction(a.screenshot);
    file->addSeparator();
    file->addAction(a.quit);

    QMenu* edit = bar->addMenu(QObject::tr("&Edit"));
    edit->addAction(a.undo);
    edit->addAction(a.redo);
    edit->addSeparator();
    edit->addAction(a.selectAllPoints);
    edit->addAction(a.resetPoints);
    edit->addAction(a.resetVariables);

    QMenu* view = bar->addMenu(QObject::tr("&View"));
    for (QAction* t : {a.surfaces, a.patchEdges, a.controlNets, a.lattices, a.sensitivity, a.gradientArrows, a.surfaceSensitivity,
                       a.orientationAxes})
        view->addAction(t);
    view->addSeparator();
    for (QAction* t : {a.resetCamera, a.viewFront, a.viewSide, a.viewTop}) view->addAction(t);
    view->addSeparator();
    menus.panels = view->addMenu(QObject::tr("&Panels"));

    QMenu* ffd = bar->addMenu(QObject::tr("F&FD"));
    ffd->addAction(a.addLattice);
    ffd->addAction(a.removeLattice);

    menus.mesh = bar->addMenu(QObject::tr("&Mesh"));
    menus.mesh->setToolTipsVisible(true);
    menus.mesh->addAction(a.meshPreview);
    menus.mesh->addAction(a.meshCancel);
    menus.mesh->addAction(a.meshClear);
    menus.mesh->addSeparator();
    menus.mesh->addAction(a.exportGrid);

    menus.flow = bar->addMenu(QObject::tr("Flo&w"));
    menus.flow->setToolTipsVisible(true);
    menus.flow->addAction(a.flowSolve);
    menus.flow->addAction(a.flowStop);
    menus.flow->addAction(a.flowContinue);
    menus.flow->addSeparator();
    menus.flow->addAction(a.computeSensitivities);
    menus.flow->addAction(a.cancelSensitivities);
    menus.flow->addAction(a.confirmPrediction);
    menus.flow->addSeparator();
    menus.flow->addAction(a.exportFlow);
    menus.flow->addSeparator();

    menus.optimize = bar->addMenu(QObject::tr("&Optimize"));
    menus.optimize->setToolTipsVisible(true);
    menus.optimize->addAction(a.optimizeStart);
    menus.optimize->addAction(a.optimizePause);
    menus.optimize->addAction(a.optimizeStop);
    menus.optimize->addAction(a.optimizeResume);
    menus.optimize->addSeparator();
    menus.optimize->addAction(a.optimizeExportShape);
    menus.optimize->addAction(a.optimizeExportHistory);
    menus.optimize->addSeparator();

    QMenu* help = bar->addMenu(QObject::tr("&Help"));
    help->addAction(a.mouseAndKeys);
    help->addAction(a.about);
    return menus;
}

QToolBar* buildToolBar(QMainWindow* window, const ActionSet& a) {
    QToolBar* bar = window->addToolBar(QObject::tr("Main"));
    bar->setObjectName(QStringLiteral("mainToolBar"));
    bar->setMovable(false);
    bar->setToolButtonStyle(Qt::ToolButtonTextBesideIcon);
    bar->addAction(a.open);
    bar->addAction(a.save);
    bar->addSeparator();
    bar->addAction(a.undoTool);
    bar->addAction(a.redoTool);
    bar->addSeparator();
    bar->addAction(a.addLattice);
    bar->addAction(a.lattices);
    bar->addAction(a.sensitivity);
    bar->addAction(a.meshPreview);
    bar->addSeparator();
    bar->addAction(a.flowSolve);
    bar->addAction(a.flowStop);
    bar->addSeparator();
    bar->addAction(a.optimizeStart);
    bar->addAction(a.optimizePause);
    bar->addAction(a.optimizeResume);
    bar->addSeparator();
    bar->addAction(a.resetCamera);
    return bar;
}

}  // namespace aero::ui
