#pragma once
// Spanwise section profiles (the paper's Figure 6: airfoil cuts every 0.5 units): the wall of
// the flow solution cut at chosen stations y = const, shown in 2D as
//   Profiles   the sections in the x-z plane, to scale, one colour per station;
//   Cp         the pressure coefficient along each cut against x, negative up (the
//              aerodynamicist's convention), in the same colours.
// The stations are typed as a list or generated every `spacing` units across the span. The cuts
// themselves come from the 3D scene (FlowScene::cutWall), which also draws them on the body. GUI
// thread only; no VTK.
#include <QWidget>
#include <vector>

#include "FlowScene.h"

class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPushButton;

namespace aero::ui {

class PlotWidget;

class SectionView : public QWidget {
    Q_OBJECT

  public:
    explicit SectionView(QWidget* parent = nullptr);

    /// The stations typed (sorted, unique); empty when the text does not parse.
    std::vector<double> stations() const;
    void setStations(const std::vector<double>& stations);
    /// Stations every `spacing()` units from `from` up to (not beyond) `to`.
    void fillStations(double from, double to);
    double spacing() const;

    /// The cuts to plot (empty: none; `note` says why).
    void setCuts(const std::vector<SectionCut>& cuts, const QString& note = {});
    const std::vector<SectionCut>& cuts() const { return cuts_; }

    PlotWidget* profilePlot() const { return profiles_; }
    PlotWidget* cpPlot() const { return cp_; }
    QLineEdit* stationEdit() const { return edit_; }

  signals:
    /// The stations changed (typed, or generated): the workspace cuts again.
    void stationsChanged();
    /// The user asked for stations every spacing() units across the span.
    void fillRequested();

  private:
    std::vector<SectionCut> cuts_;
    QLineEdit* edit_ = nullptr;
    QDoubleSpinBox* spacing_ = nullptr;
    QPushButton* fill_ = nullptr;
    QLabel* note_ = nullptr;
    PlotWidget* profiles_ = nullptr;
    PlotWidget* cp_ = nullptr;
};

/// The colour of station `index` of `count` (shared by the 2D plots).
QColor stationColour(int index, int count);

}  // namespace aero::ui
