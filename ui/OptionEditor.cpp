#include "OptionEditor.h"

#include <QCheckBox>
#include <QFontMetrics>
#include <QComboBox>
#include <QSignalBlocker>
#include <QSpinBox>
#include <algorithm>
#include <cmath>
#include <limits>

namespace aero::ui {

// ---- NumberBox ------------------------------------------------------------------------------------

NumberBox::NumberBox(QWidget* parent) : QDoubleSpinBox(parent) {
    setDecimals(15);
    setStepType(QAbstractSpinBox::AdaptiveDecimalStepType);
    setKeyboardTracking(false);
}

QString NumberBox::textFromValue(double value) const {
    return QString::number(value, 'g', 6);
}

double NumberBox::valueFromText(const QString& text) const {
    bool ok = false;
    const double v = text.trimmed().toDouble(&ok);
    return ok ? v : value();
}

QValidator::State NumberBox::validate(QString& text, int&) const {
    const QString t = text.trimmed();
    if (t.isEmpty() || t == QLatin1String("-") || t == QLatin1String("+") || t.endsWith(QLatin1Char('e'), Qt::CaseInsensitive) ||
        t.endsWith(QLatin1String("e-"), Qt::CaseInsensitive) || t.endsWith(QLatin1String("e+"), Qt::CaseInsensitive))
        return QValidator::Intermediate;
    bool ok = false;
    const double v = t.toDouble(&ok);
    if (!ok) return QValidator::Invalid;
    return v >= minimum() && v <= maximum() ? QValidator::Acceptable : QValidator::Intermediate;
}

void NumberBox::fixup(QString& text) const {
    bool ok = false;
    const double v = text.trimmed().toDouble(&ok);
    text = textFromValue(ok ? std::clamp(v, minimum(), maximum()) : value());
}

QSize NumberBox::sizeHint() const {
    QSize s = QDoubleSpinBox::sizeHint();
    const int text = fontMetrics().horizontalAdvance(QStringLiteral("-0.000000e-00") + suffix());
    s.setWidth(std::min(s.width(), text + 40));
    return s;
}

QSize NumberBox::minimumSizeHint() const {
    QSize s = QDoubleSpinBox::minimumSizeHint();
    s.setWidth(std::min(s.width(), fontMetrics().horizontalAdvance(QStringLiteral("0.000000")) + 30));
    return s;
}

// ---- OptionEditor -----------------------------------------------------------------------------------

namespace {

// The spin box limits of a range with open ends: just inside.
double inside(double bound, bool closed, bool lower) {
    if (closed) return bound;
    const double step = bound == 0 ? 1e-15 : 1e-9 * std::abs(bound);
    return lower ? bound + step : bound - step;
}

}  // namespace

OptionEditor::OptionEditor(const io::OptionSpec& spec, QWidget* parent) : QObject(parent), spec_(spec) {
    const QString tip = QStringLiteral("<p><b>%1</b> (%2)</p><p>%3</p>")
                            .arg(QString::fromStdString(spec.key), QString::fromStdString(spec.rangeWithUnit()).toHtmlEscaped(),
                                 QString::fromStdString(spec.description).toHtmlEscaped());
    switch (spec.kind) {
        case io::OptionKind::Number: {
            auto* box = new NumberBox(parent);
            box->setRange(inside(spec.lower, spec.lowerClosed, true), inside(spec.upper, spec.upperClosed, false));
            if (!spec.unit.empty()) box->setSuffix(QLatin1Char(' ') + QString::fromStdString(spec.unit == "degrees" ? "\u00b0" : spec.unit));
            connect(box, &QDoubleSpinBox::valueChanged, this, [this](double v) {
                if (!setting_) emit edited(io::OptionValue(v));
            });
            widget_ = box;
            break;
        }
        case io::OptionKind::Integer: {
            auto* box = new QSpinBox(parent);
            box->setRange(static_cast<int>(std::max<double>(spec.lower, std::numeric_limits<int>::min())),
                          static_cast<int>(std::min<double>(spec.upper, std::numeric_limits<int>::max())));
            box->setKeyboardTracking(false);
            connect(box, &QSpinBox::valueChanged, this, [this](int v) {
                if (!setting_) emit edited(io::OptionValue(static_cast<long>(v)));
            });
            widget_ = box;
            break;
        }
        case io::OptionKind::Boolean: {
            auto* box = new QCheckBox(parent);
            connect(box, &QCheckBox::toggled, this, [this](bool on) {
                if (!setting_) emit edited(io::OptionValue(on));
            });
            widget_ = box;
            break;
        }
        case io::OptionKind::Choice: {
            auto* box = new QComboBox(parent);
            for (const std::string& c : spec.choices) {
                QString label = QString::fromStdString(c);
                if (c == "slsqp") {
                    label = QStringLiteral("SLSQP");  // a name, spelled as its authors do
                } else {
                    label.replace(QLatin1Char('_'), QLatin1Char(' '));
                    if (!label.isEmpty()) label[0] = label[0].toUpper();
                }
                box->addItem(label, QString::fromStdString(c));
            }
            connect(box, &QComboBox::activated, this, [this, box](int) {
                if (!setting_) emit edited(io::OptionValue(box->currentData().toString().toStdString()));
            });
            widget_ = box;
            break;
        }
        case io::OptionKind::Point:
            widget_ = new QWidget(parent);  // not edited in panels (yet)
            widget_->setEnabled(false);
            break;
    }
    widget_->setToolTip(tip);
    widget_->setObjectName(QStringLiteral("option_") + QString::fromStdString(spec.key));
}

void OptionEditor::setValue(const io::OptionValue& v) {
    setting_ = true;
    const QSignalBlocker block(widget_);
    if (auto* n = qobject_cast<QDoubleSpinBox*>(widget_)) {
        if (const auto* d = std::get_if<double>(&v)) n->setValue(*d);
    } else if (auto* i = qobject_cast<QSpinBox*>(widget_)) {
        if (const auto* l = std::get_if<long>(&v)) i->setValue(static_cast<int>(*l));
    } else if (auto* b = qobject_cast<QCheckBox*>(widget_)) {
        if (const auto* on = std::get_if<bool>(&v)) b->setChecked(*on);
    } else if (auto* c = qobject_cast<QComboBox*>(widget_)) {
        if (const auto* s = std::get_if<std::string>(&v)) {
            const int at = c->findData(QString::fromStdString(*s));
            c->setCurrentIndex(std::max(0, at));
        }
    }
    setting_ = false;
}

io::OptionValue OptionEditor::value() const {
    if (auto* n = qobject_cast<QDoubleSpinBox*>(widget_)) return n->value();
    if (auto* i = qobject_cast<QSpinBox*>(widget_)) return static_cast<long>(i->value());
    if (auto* b = qobject_cast<QCheckBox*>(widget_)) return b->isChecked();
    if (auto* c = qobject_cast<QComboBox*>(widget_)) return c->currentData().toString().toStdString();
    return std::array<double, 3>{0, 0, 0};
}

void OptionEditor::setEnabled(bool on) {
    widget_->setEnabled(on && spec_.kind != io::OptionKind::Point);
}

}  // namespace aero::ui
