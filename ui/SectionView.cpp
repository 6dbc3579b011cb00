#include "SectionView.h"

#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QLocale>
#include <QPushButton>
#include <QRegularExpression>
#include <QSplitter>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "PlotWidget.h"
#include "Resources.h"

namespace aero::ui {

QColor stationColour(int index, int count) {
    // From the root (dark blue) to the tip (orange-red) through the field scale's hues.
    const double t = count > 1 ? static_cast<double>(index) / (count - 1) : 0.0;
    const auto c = fieldColour(0.05 + 0.9 * t);
    return QColor::fromRgbF(static_cast<float>(0.85 * c[0]), static_cast<float>(0.85 * c[1]), static_cast<float>(0.85 * c[2]));
}

SectionView::SectionView(QWidget* parent) : QWidget(parent) {
    setObjectName(QStringLiteral("sectionView"));
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(4, 4, 4, 4);
    auto* row = new QHBoxLayout;
    auto* label = new QLabel(tr("&Stations y ="), this);
    edit_ = new QLineEdit(this);
    edit_->setObjectName(QStringLiteral("sectionStations"));
    edit_->setPlaceholderText(tr("e.g. 0, 0.5, 1, 1.5"));
    edit_->setToolTip(tr("Spanwise stations (y) of the cuts, separated by commas or spaces"));
    label->setBuddy(edit_);
    spacing_ = new QDoubleSpinBox(this);
    spacing_->setRange(0.01, 100);
    spacing_->setDecimals(2);
    spacing_->setSingleStep(0.1);
    const double spacing = setting(QStringLiteral("sections/spacing")).toDouble();
    spacing_->setValue(spacing > 0 ? spacing : 0.5);
    spacing_->setPrefix(tr("every "));
    spacing_->setToolTip(tr("Spacing of the generated stations (the paper's Figure 6: 0.5 units)"));
    fill_ = new QPushButton(tr("Across the Span"), this);
    fill_->setToolTip(tr("Stations every spacing units from the root to the tip"));
    row->addWidget(label);
    row->addWidget(edit_, 1);
    row->addWidget(spacing_);
    row->addWidget(fill_);
    layout->addLayout(row);
    note_ = new QLabel(this);
    note_->setStyleSheet(QStringLiteral("QLabel { color: #606878; }"));
    note_->hide();
    layout->addWidget(note_);

    auto* split = new QSplitter(Qt::Horizontal, this);
    profiles_ = new PlotWidget(split);
    profiles_->setObjectName(QStringLiteral("sectionProfiles"));
    profiles_->setTitle(tr("Sections"));
    profiles_->xAxis().label = tr("x");
    profiles_->yAxis().label = tr("z");
    profiles_->setEqualAspect(true);
    profiles_->setPlaceholder(tr("Solve the flow to cut its wall"));
    cp_ = new PlotWidget(split);
    cp_->setObjectName(QStringLiteral("sectionCp"));
    cp_->setTitle(tr("Pressure along the cuts"));
    cp_->xAxis().label = tr("x");
    cp_->yAxis().label = tr("Cp");
    cp_->yAxis().reversed = true;
    cp_->setPlaceholder(tr("Solve the flow to see Cp along the cuts"));
    split->addWidget(profiles_);
    split->addWidget(cp_);
    layout->addWidget(split, 1);

    connect(edit_, &QLineEdit::editingFinished, this, &SectionView::stationsChanged);
    connect(fill_, &QPushButton::clicked, this, &SectionView::fillRequested);
}

std::vector<double> SectionView::stations() const {
    std::vector<double> out;
    for (const QString& part : edit_->text().split(QRegularExpression(QStringLiteral("[,;\\s]+")), Qt::SkipEmptyParts)) {
        bool ok = false;
        const double v = QLocale::c().toDouble(part, &ok);
        if (!ok || !std::isfinite(v)) return {};
        out.push_back(v);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

void SectionView::setStations(const std::vector<double>& stations) {
    QStringList parts;
    for (double s : stations) parts << QString::number(s, 'g', 6);
    edit_->setText(parts.join(QStringLiteral(", ")));
}

void SectionView::fillStations(double from, double to) {
    std::vector<double> s;
    const double h = spacing();
    for (int k = 0; k < 1000; ++k) {
        const double y = from + k * h;
        if (y > to - 1e-9 * std::max(1.0, std::abs(to))) break;
        s.push_back(std::round(y * 1e9) / 1e9);
    }
    setStations(s);
}

double SectionView::spacing() const {
    return spacing_->value();
}

void SectionView::setCuts(const std::vector<SectionCut>& cuts, const QString& note) {
    cuts_ = cuts;
    note_->setText(note);
    note_->setVisible(!note.isEmpty());
    profiles_->clearSeries();
    cp_->clearSeries();
    const int n = static_cast<int>(cuts.size());
    for (int i = 0; i < n; ++i) {
        const SectionCut& c = cuts[static_cast<std::size_t>(i)];
        PlotSeries shape, cp;
        shape.name = cp.name = QStringLiteral("y = %1").arg(QString::number(c.station, 'g', 4));
        shape.colour = cp.colour = stationColour(i, n);
        shape.lineWidth = 1.8;
        cp.lineWidth = 1.6;
        for (const auto& piece : c.pieces) {
            for (const auto& p : piece) {
                shape.points.push_back({p[0], p[1]});
                cp.points.push_back({p[0], p[2]});
            }
            shape.points.push_back({0, std::nan("")});  // breaks between pieces
            cp.points.push_back({0, std::nan("")});
        }
        if (c.pieces.empty()) {
            shape.name += tr(" (no cut)");
            cp.legend = false;
        }
        profiles_->addSeries(shape);
        cp_->addSeries(cp);
    }
}

}  // namespace aero::ui
