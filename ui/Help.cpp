#include "Help.h"

#include <QApplication>
#include <QMessageBox>

namespace aero::ui {

void showMouseAndKeys(QWidget* parent) {
    QMessageBox::information(
        parent, QObject::tr("Mouse and Keys"),
        QObject::tr(
            "<p><b>View</b>: left drag rotates, middle drag (or Shift+left) pans, the wheel zooms; Ctrl+R resets the "
            "camera, Ctrl+1/2/3 look from the front, side and top.</p>"
            "<p><b>Lattice points</b>: click to select, Ctrl+click to add or remove, drag to move in the view plane, "
            "Shift+drag to move along X, Y or Z, Esc cancels a drag; Delete resets the selected points. Exact "
            "coordinates go in the Properties panel.</p>"
            "<p><b>Design variables</b>: sliders and spin boxes in the Design Variables panel; a slider drag is one "
            "undo step.</p>"
            "<p><b>Mesh preview</b>: Ctrl+M generates the grid (level and increments in the Mesh Quality panel); the "
            "model tree's Grid blocks toggle the control grid, wall, symmetry plane and slice; click a worst cell to "
            "fly the camera to it.</p>"
            "<p><b>Flow</b>: F5 solves the case's flow in the background (Mach, angle of attack, grid and "
            "dissipation in the Flow panel), Shift+F5 stops it (the state reached is kept; Continue resumes it). The "
            "Residuals panel plots every iteration; the Flow panel chooses the field (entropy, Cp, Mach, pressure), "
            "its range, contour lines and a slice; the Sections panel cuts the wall at spanwise stations. Right-click "
            "a plot to export it (PNG, SVG) or its data (CSV).</p>"
            "<p><b>Sensitivities</b>: F6 solves the design's flow and its adjoint in the background: dJ/dv of the "
            "objective next to every slider (click the column to sort), green arrows at the lattice points towards a "
            "better objective, View \u25b8 Surface Sensitivity colours the wall by dJ/dA\u00b7n. While you move a "
            "slider or drag a lattice point, the first-order change of J shows in the status bar; Confirm with a Flow "
            "Solve compares it with the actual change.</p>"));
}

void showAbout(QWidget* parent) {
    QMessageBox::about(parent, QObject::tr("About Aeroform"),
                       QObject::tr("<p><b>Aeroform</b> %1</p><p>Aerodynamic shape design with the two-level free-form "
                                   "deformation of Gagnon &amp; Zingg.</p>")
                           .arg(QApplication::applicationVersion()));
}

}  // namespace aero::ui
