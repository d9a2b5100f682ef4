#include "app/gui/window_layout.h"

#include "app/gui/settings_store.h"

#include <QEvent>
#include <QMainWindow>

#include <memory>
#include <utility>

namespace sc::app {

namespace {

constexpr int kStateVersion = 1;  // QMainWindow::saveState's version: bump when docks or toolbars change meaning

}  // namespace

WindowLayout::WindowLayout(QMainWindow& window, QString settingsFile)
    : QObject(&window), m_window(window), m_file(std::move(settingsFile)) {
  const std::unique_ptr<QSettings> settings = openSettings(m_file);
  const QByteArray geometry = settings->value(QStringLiteral("window/geometry")).toByteArray();
  const QByteArray state = settings->value(QStringLiteral("window/state")).toByteArray();
  const bool geometryRestored = !geometry.isEmpty() && m_window.restoreGeometry(geometry);
  const bool stateRestored = !state.isEmpty() && m_window.restoreState(state, kStateVersion);
  m_restored = geometryRestored || stateRestored;
  m_window.installEventFilter(this);
}

void WindowLayout::save() const {
  const std::unique_ptr<QSettings> settings = openSettings(m_file);
  settings->setValue(QStringLiteral("window/geometry"), m_window.saveGeometry());
  settings->setValue(QStringLiteral("window/state"), m_window.saveState(kStateVersion));
}

bool WindowLayout::eventFilter(QObject* watched, QEvent* event) {
  if (watched == &m_window && event->type() == QEvent::Close) save();
  return QObject::eventFilter(watched, event);
}

}  // namespace sc::app
