#pragma once
// "Add FFD Lattice": name, control points and degrees per direction, padding, around all
// patches or the selected ones, and optionally the paper's station design variables
// (translations, section scalings, taper per station). GUI thread only; no VTK.
#include <QDialog>
#include <array>
#include <optional>
#include <vector>

#include "io/CaseFile.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QGroupBox;
class QLineEdit;
class QRadioButton;
class QSpinBox;

namespace aero::ui {

class LatticeDialog : public QDialog {
    Q_OBJECT

  public:
    /// `selectedPatches` (0-based) enables "around the selected patches".
    LatticeDialog(const QString& suggestedName, const std::vector<int>& selectedPatches, QWidget* parent = nullptr);

    io::LatticeCase lattice() const;
    /// The station variables, if requested (lattice index and prefix are set by the document).
    std::optional<ffd::StationSpec> stations() const;

  private:
    QLineEdit* name_ = nullptr;
    std::array<QSpinBox*, 3> counts_{};
    std::array<QSpinBox*, 3> degrees_{};
    std::array<QDoubleSpinBox*, 3> padding_{};
    QRadioButton* allPatches_ = nullptr;
    QRadioButton* selectedPatches_ = nullptr;
    std::vector<int> selection_;
    QGroupBox* stationsBox_ = nullptr;
    QComboBox* direction_ = nullptr;
    std::array<QCheckBox*, 3> translate_{};
    QCheckBox* scaling_ = nullptr;
    QCheckBox* taper_ = nullptr;
    QDoubleSpinBox* bound_ = nullptr;
};

}  // namespace aero::ui
