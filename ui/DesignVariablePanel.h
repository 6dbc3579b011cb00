#pragma once
// The design variables of the project as a list: name, a slider and a spin box limited to
// the variable's bounds (a slider drag is one undo step), a filter, "Reset All", and the
// switch for the sensitivity arrows of the current variable. After a gradient (Flow > Compute
// Sensitivities) each row shows dJ/dv as a signed bar (sortable by a click on its header: largest
// first, smallest first, the variables' order), greyed with a note once the design changed, and
// below the list the first-order prediction of J for the design as shown with a button that
// confirms it by a flow solve. GUI thread only; no VTK.
#include <QString>
#include <QWidget>
#include <vector>

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QSlider;
class QTableWidget;

namespace aero::ui {

class Document;

class DesignVariablePanel : public QWidget {
    Q_OBJECT

  public:
    explicit DesignVariablePanel(Document* document, QWidget* parent = nullptr);

    /// The variable of the current row, or -1.
    int currentVariable() const;
    void setCurrentVariable(int var);
    bool sensitivityShown() const;
    void setSensitivityShown(bool on);
    /// Tells the user how the arrows are scaled (empty: hide the note).
    void setSensitivityNote(const QString& text);

    /// dJ/dv per variable (model order) of `objective`, drawn as signed bars scaled to the largest;
    /// `current`: false greys them (the design changed since), `note` says what they are.
    void setGradient(const std::vector<double>& dJdv, const QString& objective, bool current, const QString& note);
    /// No gradient: the column is empty, `note` (may be empty) says why.
    void clearGradient(const QString& note = {});
    /// The dJ/dv shown for `var` (NaN when none).
    double gradient(int var) const;
    bool gradientCurrent() const { return gradientCurrent_; }
    /// Row order by dJ/dv: 0 the variables' order, 1 largest first, 2 smallest first.
    void sortByGradient(int mode);
    int gradientSort() const { return sortMode_; }
    /// Variables in the order shown (top to bottom).
    std::vector<int> shownOrder() const;
    /// The prediction line (empty: hidden) and whether the confirming solve can start.
    void setPrediction(const QString& text, bool canConfirm);
    QString predictionText() const;
    /// Whether Compute Sensitivities can start now (no computation running).
    void setCanComputeGradient(bool on);
    /// The objectives to choose from for the gradient (e.g. the case's, CL/CD, CL, CD) and the
    /// chosen one; no signal.
    void setObjectiveChoices(const QStringList& items, int current);
    QComboBox* objectiveBox() const { return objective_; }

    static constexpr int kGradientColumn = 3;

    QTableWidget* table() const { return table_; }
    QSlider* slider(int var) const;
    QDoubleSpinBox* spinBox(int var) const;

    static constexpr int kSliderSteps = 1000;

  signals:
    void currentVariableChanged(int var);
    void sensitivityToggled(bool on);
    /// The panel's "Compute dJ/dv" button.
    void computeGradientRequested();
    /// The panel's "Confirm with a Flow Solve" button.
    void confirmRequested();
    /// The user chose objective `index` of setObjectiveChoices's items.
    void objectiveChosen(int index);

  protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

  private:
    void rebuild();
    void updateValues();
    void applyFilter();
    void sliderMoved(int var, int position);
    void fillGradientColumn();

    Document* document_;
    QLineEdit* filter_ = nullptr;
    QTableWidget* table_ = nullptr;
    QCheckBox* sensitivity_ = nullptr;
    QLabel* note_ = nullptr;
    QLabel* empty_ = nullptr;
    QPushButton* reset_ = nullptr;
    QLabel* gradientNote_ = nullptr;
    QPushButton* compute_ = nullptr;
    QComboBox* objective_ = nullptr;
    QLabel* prediction_ = nullptr;
    QPushButton* confirm_ = nullptr;
    std::vector<double> gradient_;
    bool gradientCurrent_ = false;
    int sortMode_ = 0;
    std::vector<QSlider*> sliders_;
    std::vector<QDoubleSpinBox*> spins_;
    int gesture_ = 0;        // non-zero while a slider is held down
    int nextGesture_ = 1;
    bool updating_ = false;
};

}  // namespace aero::ui
