#pragma once
// Editors for self-describing case options (io/Options.h): a spin box, combo box or check box
// made from an option's spec, with its range, choices and description (tooltip) taken from the
// table the case parser uses, so a panel accepts exactly what a case file accepts. GUI thread
// only; no VTK.
#include <QDoubleSpinBox>
#include <QWidget>
#include <functional>

#include "io/Options.h"

namespace aero::ui {

/// A spin box for doubles that shows and reads numbers in 'g' notation (1e-10 as well as 0.5).
class NumberBox : public QDoubleSpinBox {
    Q_OBJECT

  public:
    explicit NumberBox(QWidget* parent = nullptr);
    QString textFromValue(double value) const override;
    double valueFromText(const QString& text) const override;
    QValidator::State validate(QString& text, int& pos) const override;
    void fixup(QString& text) const override;
    /// As wide as a number in 'g' notation needs (not as the 15 decimals would).
    QSize sizeHint() const override;
    QSize minimumSizeHint() const override;
};

/// One option's editor. `edited` is called with the new value when the user changes it (after
/// editing finished for typed numbers), never for setValue().
class OptionEditor : public QObject {
    Q_OBJECT

  public:
    OptionEditor(const io::OptionSpec& spec, QWidget* parent);

    QWidget* widget() const { return widget_; }
    const io::OptionSpec& spec() const { return spec_; }
    void setValue(const io::OptionValue& v);
    io::OptionValue value() const;
    void setEnabled(bool on);

  signals:
    void edited(const aero::io::OptionValue& value);

  private:
    io::OptionSpec spec_;
    QWidget* widget_ = nullptr;
    bool setting_ = false;
};

}  // namespace aero::ui
