#include "app/gui/up_axis_memory.h"

#include "app/gui/settings_store.h"

#include <QFileInfo>
#include <QUrl>

#include <memory>

namespace sc::app {

namespace {

QString keyOf(const QString& path) {
  return QStringLiteral("upAxis/") + QString::fromLatin1(QUrl::toPercentEncoding(QFileInfo(path).absoluteFilePath()));
}

}  // namespace

std::optional<UpAxis> UpAxisMemory::recall(const QString& path) const {
  const QString value = openSettings(m_file)->value(keyOf(path)).toString();
  if (value == QStringLiteral("z")) return UpAxis::Z;
  if (value == QStringLiteral("y")) return UpAxis::Y;
  return std::nullopt;
}

void UpAxisMemory::remember(const QString& path, UpAxis axis) const {
  openSettings(m_file)->setValue(keyOf(path), axis == UpAxis::Z ? QStringLiteral("z") : QStringLiteral("y"));
}

}  // namespace sc::app
