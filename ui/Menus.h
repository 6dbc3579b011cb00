#pragma once
// Where the main window's commands (ActionSet) appear: the menu bar (File, Edit, View, FFD,
// Mesh, Flow, Optimize, Help) and the tool bar. Layout only: what an action does is connected
// elsewhere. GUI thread only.
class QMainWindow;
class QMenu;
class QToolBar;

namespace aero::ui {

struct ActionSet;

/// Menus whose items the window fills later.
struct MenuRefs {
    QMenu* recent = nullptr;  // File > Open Recent (filled when shown)
    QMenu* panels = nullptr;  // View > Panels (the docks' toggles)
    QMenu* mesh = nullptr;    // Mesh (gets the quality panel's toggle)
    QMenu* flow = nullptr;    // Flow (gets the flow panels' toggles)
    QMenu* optimize = nullptr;  // Optimize (gets the optimization panels' toggles)
};

/// Builds the menu bar of `window` from `actions`.
MenuRefs buildMenus(QMainWindow* window, const ActionSet& actions);
/// Builds the main tool bar ("mainToolBar").
QToolBar* buildToolBar(QMainWindow* window, const ActionSet& actions);

}  // namespace aero::ui
