#pragma once
// The application's resources (the design card's resources/: icons, the Qt resource file,
// default settings, the desktop entry) as the code sees them: the compiled-in resource file
// and the settings, where the user's own value (QSettings) wins over the default that ships in
// resources/settings/defaults.ini. GUI thread only.
#include <QString>
#include <QVariant>

namespace aero::ui {

/// Registers resources/aeroform.qrc (compiled into the static aeroform_ui library, whose
/// initializer the linker would otherwise drop). Idempotent; MainWindow calls it.
void initResources();

/// The setting `key` ("flow/field", "autosave/intervalSeconds", ...): the user's value if set,
/// else the shipped default (an invalid QVariant for an unknown key).
QVariant setting(const QString& key);

}  // namespace aero::ui
