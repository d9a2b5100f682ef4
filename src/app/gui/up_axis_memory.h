#pragma once
// UpAxisMemory: the up axis chosen for each mesh or session file, remembered between runs (QSettings group
// "upAxis", one key per absolute file path, percent-encoded so that a path's slashes do not become groups).

#include "app/gui/orbit_camera.h"

#include <QString>

#include <optional>
#include <utility>

namespace sc::app {

class UpAxisMemory {
 public:
  /// `settingsFile` empty: the application's QSettings; otherwise that INI file (tests).
  explicit UpAxisMemory(QString settingsFile = {}) : m_file(std::move(settingsFile)) {}

  /// The axis remembered for `path` (made absolute), or nullopt when none was. Cost: one QSettings lookup.
  [[nodiscard]] std::optional<UpAxis> recall(const QString& path) const;
  /// Remembers `axis` for `path` (made absolute).
  void remember(const QString& path, UpAxis axis) const;

 private:
  QString m_file;
};

}  // namespace sc::app
