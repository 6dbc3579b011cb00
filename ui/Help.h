#pragma once
// The Help menu's texts. GUI thread only.
class QWidget;

namespace aero::ui {

/// How the mouse and keys drive the view, the lattice editor, the mesh preview and the flow.
void showMouseAndKeys(QWidget* parent);
void showAbout(QWidget* parent);

}  // namespace aero::ui
