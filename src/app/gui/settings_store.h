#pragma once
// The settings a window remembers: the application's QSettings, or an INI file that tests give instead.

#include <QSettings>
#include <QString>

#include <memory>

namespace sc::app {

/// `file` empty: the application's QSettings (organisation and application names); otherwise that INI file.
[[nodiscard]] inline std::unique_ptr<QSettings> openSettings(const QString& file) {
  return file.isEmpty() ? std::make_unique<QSettings>() : std::make_unique<QSettings>(file, QSettings::IniFormat);
}

}  // namespace sc::app
