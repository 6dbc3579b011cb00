#pragma once
// The design variables of the project as a list: name, a slider and a spin box limited to
// the variable's bounds (a slider drag is one undo step), a filter, "Reset All", and the
// switch for the sensitivity arrows of the current variable. GUI thread only; no VTK.
#include <QWidget>
#include <vector>

class QCheckBox;
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

    QTableWidget* table() const { return table_; }
    QSlider* slider(int var) const;
    QDoubleSpinBox* spinBox(int var) const;

    static constexpr int kSliderSteps = 1000;

  signals:
    void currentVariableChanged(int var);
    void sensitivityToggled(bool on);

  protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

  private:
    void rebuild();
    void updateValues();
    void applyFilter();
    void sliderMoved(int var, int position);

    Document* document_;
    QLineEdit* filter_ = nullptr;
    QTableWidget* table_ = nullptr;
    QCheckBox* sensitivity_ = nullptr;
    QLabel* note_ = nullptr;
    QLabel* empty_ = nullptr;
    QPushButton* reset_ = nullptr;
    std::vector<QSlider*> sliders_;
    std::vector<QDoubleSpinBox*> spins_;
    int gesture_ = 0;        // non-zero while a slider is held down
    int nextGesture_ = 1;
    bool updating_ = false;
};

}  // namespace aero::ui
