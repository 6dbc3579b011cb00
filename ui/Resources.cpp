#include "Resources.h"

#include <QSettings>

// Q_INIT_RESOURCE must be used outside any namespace.
static void registerAeroformResources() {
    Q_INIT_RESOURCE(aeroform);
}

namespace aero::ui {

void initResources() {
    static const bool done = [] {
        registerAeroformResources();
        return true;
    }();
    (void)done;
}

QVariant setting(const QString& key) {
    initResources();
    const QSettings user;
    if (user.contains(key)) return user.value(key);
    static const QSettings defaults(QStringLiteral(":/settings/defaults.ini"), QSettings::IniFormat);
    return defaults.value(key);
}

}  // namespace aero::ui
