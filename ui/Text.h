#pragma once
// Small text helpers for user-facing messages.
#include <QString>

namespace aero::ui {

/// "1 patch", "3 patches": the number with the singular or plural noun. (The application loads
/// no translations, so Qt's "%n ...(s)" plural forms would show their "(s)".)
inline QString counted(long long n, const QString& one, const QString& many) {
    return QStringLiteral("%1 %2").arg(n).arg(n == 1 ? one : many);
}

}  // namespace aero::ui
