#pragma once
// What File → Open Recent and the file dialogs remember between runs (QSettings, group "files"): the meshes and
// session files opened, most recent first (at most kMaxRecentEntries), and the folder last used in a file dialog.

#include <QSettings>
#include <QString>
#include <QStringList>

namespace sc::app {

struct RecentFiles {
  QStringList paths;  ///< absolute paths, most recent first
  QString folder;     ///< the folder a file dialog starts in (empty: the current folder)

  /// Reads them from `settings` (empty when missing).
  static RecentFiles load(QSettings& settings);
  void save(QSettings& settings) const;
  /// Moves `path` (made absolute) to the front and remembers its folder.
  void remember(const QString& path);
  /// Removes the paths whose files are gone; returns them (for a message), in list order.
  QStringList dropMissing();
};

}  // namespace sc::app
