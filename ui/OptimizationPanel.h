#pragma once
// The "Optimization" panel, top to bottom (what is watched while a run works comes first):
//   Run          Start (Start Over when a history exists), Pause (after the evaluation being
//                computed), Stop, Resume (from the history file, also after a restart of the
//                application); the run's state and the optimizer's log;
//   Evaluation   the history slider: any evaluation's numbers, why it failed, its shape and
//                flow in the 3D view (follow the run, or stay on one), a second evaluation to
//                compare with (side by side or overlaid), Use This Design (the document takes its
//                design values), Solve Its Flow (when its solution is not kept), Export Shape;
//   Problem      the case's optimization section: objective and sense, optimizer, limits
//                (evaluations, iterations), tolerances, the constraints (enclosed volume, lift,
//                grid validity; the linear ones the case has), the angle of attack as a
//                variable; edits of the case (undoable) with the ranges and descriptions of the
//                case file's option table (io::optimizationOptions());
//   Files        the history file, Export History, Export Plots;
//   Sensitivities dJ/dv of every design variable at the last gradient, as signed bars, sortable.
// The panel only shows and asks: OptimizationRunner runs, the workspace wires. GUI thread only;
// no VTK.
#include <QString>
#include <QWidget>
#include <optional>
#include <string>
#include <vector>

#include "FlowRun.h"
#include "OptimizationScene.h"  // CompareMode (the header has no VTK)
#include "io/Options.h"

class QCheckBox;
class QComboBox;
class QLabel;
class QPlainTextEdit;
class QPushButton;
class QSlider;
class QSpinBox;
class QTreeWidget;

namespace aero::ui {

class NumberBox;
class OptionEditor;
struct EvaluationSnapshot;

class OptimizationPanel : public QWidget {
    Q_OBJECT

  public:
    explicit OptimizationPanel(QWidget* parent = nullptr);

    /// Shows the case's optimization options (no signals).
    void setCase(const io::CaseFile& c, const QString& historyPath);
    OptionEditor* editor(const std::string& key) const;
    QComboBox* volumeBox() const { return volume_; }

    enum class Tone { Neutral, Busy, Good, Warning, Bad };
    /// The run's buttons: what can be done now.
    struct Actions {
        bool start = false, startOver = false, pause = false, stop = false, resume = false;
    };
    void setRunState(const QString& text, Tone tone, const Actions& can, bool running);
    QString statusText() const;
    void setProgress(const QString& text);
    void appendLog(const QString& line);
    void clearLog();

    /// The history slider's range (0: empty) and position; the evaluation's description.
    void setEvaluationCount(int count);
    int evaluationCount() const;
    void setCurrentEvaluation(int index);  // no signal
    int currentEvaluation() const;
    void setEvaluationText(const QString& text, bool failed);
    QString evaluationText() const;
    void setEvaluationActions(bool canUse, bool canSolveFlow, bool canExport);
    bool follow() const;
    void setFollow(bool on);  // no signal
    bool viewShown() const;
    void setViewShown(bool on);             // no signal
    int comparedEvaluation() const;         // 0: none
    void setComparedEvaluation(int index);  // emits compareChanged
    CompareMode compareMode() const;
    void setCompareMode(CompareMode mode);  // emits compareChanged
    FlowField field() const;

    /// The sensitivities at the last gradient: variable names and dJ/dv (J the case's objective,
    /// as the optimizer sees it: signs flipped when maximizing are undone). Empty: none yet.
    void setSensitivities(const std::vector<std::string>& names, const std::vector<double>& dJdv,
                          const QString& note);
    QTreeWidget* sensitivityList() const { return sensitivities_; }

    QLabel* startDesignLabel() const { return startDesign_; }
    QPushButton* clearStartButton() const { return clearStart_; }
    QPushButton* startButton() const { return start_; }
    QPushButton* pauseButton() const { return pause_; }
    QPushButton* stopButton() const { return stop_; }
    QPushButton* resumeButton() const { return resume_; }
    QSlider* historySlider() const { return slider_; }
    QPushButton* useDesignButton() const { return use_; }
    QPushButton* solveFlowButton() const { return solveFlow_; }

  signals:
    void optionEdited(const std::string& key, const aero::io::OptionValue& value);
    /// The volume constraint: none, the start's volume (NaN), or a value.
    void volumeEdited(std::optional<double> minimum);
    /// optimization.start_design: a case file's path, or empty for the case's own design.
    void startDesignEdited(const QString& path);
    void startDesignChooseRequested();  // the workspace asks for the file
    void startRequested();
    void startOverRequested();
    void pauseRequested();
    void stopRequested();
    void resumeRequested();
    /// The slider moved to evaluation `index` (by the user).
    void evaluationChosen(int index);
    void followToggled(bool on);
    void viewToggled(bool on);
    void compareChanged(int index, aero::ui::CompareMode mode);
    void fieldChanged(aero::ui::FlowField field);
    void useDesignRequested();
    void solveFlowRequested();
    void exportShapeRequested();
    void exportHistoryRequested();
    void exportPlotsRequested();

  private:
    void emitVolume();

    struct Row {
        std::string key;
        OptionEditor* editor = nullptr;
    };
    std::vector<Row> rows_;
    QLabel* note_ = nullptr;
    QComboBox* volume_ = nullptr;
    NumberBox* volumeValue_ = nullptr;
    QLabel* linear_ = nullptr;
    QLabel* startDesign_ = nullptr;
    QPushButton* chooseStart_ = nullptr;
    QPushButton* clearStart_ = nullptr;
    QLabel* history_ = nullptr;
    QPushButton* start_ = nullptr;
    QPushButton* pause_ = nullptr;
    QPushButton* stop_ = nullptr;
    QPushButton* resume_ = nullptr;
    bool startIsStartOver_ = false;
    QLabel* status_ = nullptr;
    QLabel* progress_ = nullptr;
    QPlainTextEdit* log_ = nullptr;
    QSlider* slider_ = nullptr;
    QLabel* sliderLabel_ = nullptr;
    QCheckBox* follow_ = nullptr;
    QCheckBox* view_ = nullptr;
    QLabel* evaluation_ = nullptr;
    QSpinBox* compare_ = nullptr;
    QComboBox* compareMode_ = nullptr;
    QComboBox* field_ = nullptr;
    QPushButton* use_ = nullptr;
    QPushButton* solveFlow_ = nullptr;
    QPushButton* exportShape_ = nullptr;
    QTreeWidget* sensitivities_ = nullptr;
    QLabel* sensitivityNote_ = nullptr;
};

}  // namespace aero::ui
