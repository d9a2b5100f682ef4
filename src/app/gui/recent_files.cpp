#include "app/gui/recent_files.h"

#include "app/gui/recent_sessions.h"

#include <QFileInfo>

namespace sc::app {

RecentFiles RecentFiles::load(QSettings& settings) {
  settings.beginGroup(QStringLiteral("files"));
  RecentFiles recent;
  recent.paths = settings.value(QStringLiteral("recent")).toStringList();
  while (recent.paths.size() > kMaxRecentEntries) recent.paths.removeLast();
  recent.folder = settings.value(QStringLiteral("folder")).toString();
  settings.endGroup();
  return recent;
}

void RecentFiles::save(QSettings& settings) const {
  settings.beginGroup(QStringLiteral("files"));
  settings.setValue(QStringLiteral("recent"), paths);
  settings.setValue(QStringLiteral("folder"), folder);
  settings.endGroup();
}

void RecentFiles::remember(const QString& path) {
  const QFileInfo info(path);
  RecentSessions::remember(paths, info.absoluteFilePath());
  folder = info.absolutePath();
}

QStringList RecentFiles::dropMissing() {
  QStringList missing;
  for (const QString& path : paths) {
    if (!QFileInfo::exists(path)) missing.push_back(path);
  }
  for (const QString& path : missing) paths.removeAll(path);
  return missing;
}

}  // namespace sc::app
