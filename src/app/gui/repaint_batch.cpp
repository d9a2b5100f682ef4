#include "app/gui/repaint_batch.h"

namespace sc::app {

RepaintBatch::RepaintBatch(QObject* parent) : QObject(parent) {
  m_timer.setSingleShot(true);
  m_timer.setInterval(kSettle);
  connect(&m_timer, &QTimer::timeout, this, &RepaintBatch::release);
}

RepaintBatch::~RepaintBatch() = default;

void RepaintBatch::add(QWidget* widget) { m_widgets.emplace_back(widget); }

void RepaintBatch::hold() {
  for (const QPointer<QWidget>& widget : m_widgets) {
    if (widget) widget->setUpdatesEnabled(false);
  }
  m_timer.start();
}

void RepaintBatch::releaseNow() {
  if (!m_timer.isActive()) return;
  m_timer.stop();
  release();
}

void RepaintBatch::release() {
  for (const QPointer<QWidget>& widget : m_widgets) {
    if (widget) widget->setUpdatesEnabled(true);  // schedules one full repaint of the widget and its children
  }
}

}  // namespace sc::app
