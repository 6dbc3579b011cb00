#pragma once
// The "Flow" panel:
//   Case      Mach, angle of attack, grid level and refinement, dissipation (kappa2, kappa4),
//             iterations and tolerance: edits of the case (undoable), with the ranges and
//             descriptions of the case file's option tables (io/Options.h);
//   Run       Solve / Stop, Continue (a stopped run, from its restart file), the run's state
//             (running, converged, not converged or failed with the reason, stopped) and the
//             latest iteration;
//   Forces    CL, CD, CM, L/D and the checks of the answer (largest Mach number and entropy);
//   Display   the field on the wall, symmetry plane and slice (entropy as the paper's Figure 6,
//             Cp, Mach, pressure), its colour range (automatic or chosen), contour lines, the
//             parts shown and the slice's plane and position.
// The panel only shows and asks: FlowRunner runs, FlowScene draws, the workspace wires them.
// GUI thread only; no VTK.
#include <QString>
#include <QWidget>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "FlowRun.h"
#include "FlowScene.h"  // FlowPart (the header has no VTK)
#include "io/Options.h"

class QCheckBox;
class QComboBox;
class QGroupBox;
class QLabel;
class QPushButton;
class QSlider;
class QSpinBox;

namespace aero::ui {

class NumberBox;
class OptionEditor;

class FlowPanel : public QWidget {
    Q_OBJECT

  public:
    explicit FlowPanel(QWidget* parent = nullptr);

    /// Shows the case's options (no signals).
    void setCase(const io::CaseFile& c);
    /// The editor of option `key` of section "flow" or "mesh" (null if not shown).
    OptionEditor* editor(const std::string& section, const std::string& key) const;

    /// While running, Solve reads Stop and the case options are locked.
    void setRunning(bool running);
    bool running() const { return running_; }
    void setCanContinue(bool can);
    enum class Tone { Neutral, Busy, Good, Warning, Bad };
    void setStatus(const QString& text, Tone tone = Tone::Neutral);
    QString statusText() const;
    /// The latest iteration's line under the state.
    void setProgress(const QString& text);

    /// The solution to describe (null: none); `outdated` greys the forces and display.
    void setResult(std::shared_ptr<const FlowRunResult> result, bool outdated);

    FlowField field() const;
    void setField(FlowField field);
    /// The range shown in the boxes while "automatic" is checked.
    void setAutomaticRange(std::pair<double, double> range);
    bool automaticRange() const;
    std::pair<double, double> chosenRange() const;
    void setChosenRange(std::pair<double, double> range);  // unchecks "automatic"
    bool partShown(FlowPart part) const;
    void setPartShown(FlowPart part, bool shown);
    int contourCount() const;
    /// The slice's axis (0 x, 1 y, 2 z) and position; `bounds` of the grid for the slider.
    int sliceAxis() const;
    double slicePosition() const;
    void setSliceBounds(const std::array<double, 6>& bounds);
    void setSlice(int axis, double position);

    QPushButton* solveButton() const { return solve_; }
    QPushButton* continueButton() const { return continue_; }
    QComboBox* fieldBox() const { return field_; }
    QCheckBox* automaticBox() const { return automatic_; }
    QSlider* sliceSlider() const { return slicePosition_; }
    /// The forces' value labels by name: "CL", "CD", "CM", "L/D", "maxMach", "maxEntropy".
    QLabel* forceLabel(const QString& name) const;

  signals:
    void solveRequested();
    void stopRequested();
    void continueRequested();
    /// The user changed a case option (section "flow" or "mesh").
    void optionEdited(const std::string& section, const std::string& key, const aero::io::OptionValue& value);
    void fieldChanged(aero::ui::FlowField field);
    /// automatic: the field's own range; else [lo, hi].
    void rangeChanged(bool automatic, double lo, double hi);
    void contourCountChanged(int count);  // 0: no contour lines
    void partToggled(aero::ui::FlowPart part, bool shown);
    void sliceChanged(int axis, double position);

  private:
    void emitRange();
    void emitSlice();
    void updateSliceLabel();

    struct Row {
        std::string section, key;
        OptionEditor* editor = nullptr;
    };
    std::vector<Row> rows_;
    bool running_ = false;
    bool canContinue_ = false;
    std::shared_ptr<const FlowRunResult> result_;
    std::array<double, 6> bounds_{0, 1, 0, 1, 0, 1};
    QPushButton* solve_ = nullptr;
    QPushButton* continue_ = nullptr;
    QLabel* status_ = nullptr;
    QString statusText_;  // as set (the label shows one clause per line)
    QLabel* progress_ = nullptr;
    QGroupBox* forces_ = nullptr;
    std::vector<std::pair<QString, QLabel*>> forceLabels_;
    QGroupBox* display_ = nullptr;
    QComboBox* field_ = nullptr;
    QCheckBox* automatic_ = nullptr;
    NumberBox* lo_ = nullptr;
    NumberBox* hi_ = nullptr;
    QCheckBox* contours_ = nullptr;
    QSpinBox* contourCount_ = nullptr;
    std::vector<std::pair<int, QCheckBox*>> parts_;
    QComboBox* sliceAxis_ = nullptr;
    QSlider* slicePosition_ = nullptr;
    QLabel* sliceLabel_ = nullptr;
};

}  // namespace aero::ui
