#pragma once
// RepaintBatch: lets a group of widgets change over a few event-loop passes and repaints them together once (issue
// 16, idle CPU). With a QOpenGLWidget in the window every repaint of any widget composes the whole window again
// (about 15 ms on a software rasteriser); the docks' once-a-second figures used to cost four such compositions (each
// chart settles in its own pass), now one.
//
// hold() turns updates off on the widgets (their children too) and (re)starts a short single-shot timer; when it
// fires, updates come back on and Qt repaints each widget in full, in one pass. Text, models and layouts change as
// usual meanwhile: only painting waits. Widgets destroyed meanwhile are skipped. GUI thread.

#include <QObject>
#include <QPointer>
#include <QTimer>
#include <QWidget>

#include <chrono>
#include <vector>

namespace sc::app {

class RepaintBatch final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(RepaintBatch)

 public:
  /// How long painting waits after the last hold(): long enough for a chart's layout passes to settle.
  static constexpr std::chrono::milliseconds kSettle{50};

  explicit RepaintBatch(QObject* parent = nullptr);
  ~RepaintBatch() override;

  /// Adds a widget to the batch (kept by QPointer).
  void add(QWidget* widget);
  /// Holds the batch's painting until kSettle after this call.
  void hold();
  /// Ends a hold at once (before grabbing a widget: QWidget::grab() draws nothing of a widget whose updates are off).
  void releaseNow();
  /// Whether painting is held now.
  [[nodiscard]] bool holding() const { return m_timer.isActive(); }

 private:
  void release();

  std::vector<QPointer<QWidget>> m_widgets;
  QTimer m_timer;
};

}  // namespace sc::app
