#pragma once
// `shapecast-screenshots --demo [MESH] --screenshot-dir DIR [--after SECONDS]` (also `shapecast --demo
// --screenshot-dir …`, which runs it): README screenshots of the real demo. Not part of the application: this tool
// drives the GUI library's public API only. Once the demo's three windows are live, the host plays a scripted drag
// of its default handle through the calls a mouse drag ends in (MainWindow::session()'s beginDrag(), dragTo() and
// endDrag(), as the window does for its viewport's drag gestures: the session solves and streams every step, and the
// drag's end makes it a step of the session's edit history) for the given time, so that the shape,
// the clients' displays and every Statistics chart (distortion, loss, bandwidth, frame rate) are live; then, with the
// drag still going, each window is resized to a sensible size, its view framed on the deformed shape and grabbed with
// QWidget::grab (which includes the OpenGL viewport) into
//   DIR/demo-host.png, DIR/demo-client-full.png, DIR/demo-client-low.png   (the three windows, docks as they are)
//   DIR/main-window-statistics.png   (the host window, larger, its Statistics dock showing the lossy client)
// and finished() reports the result.

#include <QObject>
#include <QSize>
#include <QString>
#include <QStringList>

#include <Eigen/Core>

#include <QElapsedTimer>

class QTimer;

namespace sc::app {

class Demo;
class MainWindow;

struct DemoScreenshotOptions {
  QString directory;                ///< created if missing
  double afterSeconds = 20.0;       ///< how long the scripted drag plays before the grabs (≥ 1)
  QSize windowSize{1000, 680};      ///< each demo window when grabbed
  QSize mainWindowSize{1120, 840};  ///< the host window for main-window-statistics.png
  int liveTimeoutSeconds = 600;     ///< give up when the windows are not all live by then (basis of a big mesh)
};

class DemoScreenshots final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(DemoScreenshots)

 public:
  /// Watches `demo` (which must outlive this object; start it before or after this).
  DemoScreenshots(Demo& demo, DemoScreenshotOptions options, QObject* parent = nullptr);
  ~DemoScreenshots() override;

  /// Starts waiting for the three windows to be live; finished() comes exactly once, at the latest after
  /// liveTimeoutSeconds + afterSeconds + a few seconds.
  void start();

  /// The files written into the directory, in the order above.
  [[nodiscard]] static QStringList fileNames();

 signals:
  /// ok: every file was written; else `message` says what failed (a window not live, a session failure, a file).
  void finished(bool ok, const QString& message);

 private:
  void poll();
  void beginDrag();
  void dragStep();
  void endDrag();
  void grabDemoWindows();
  void grabMainWindow();
  void finish(bool ok, const QString& message);
  void save(MainWindow* window, const QString& name);  ///< failures go to m_failures

  Demo& m_demo;
  DemoScreenshotOptions m_options;
  QTimer* m_timer = nullptr;
  QElapsedTimer m_clock;
  Eigen::Vector3d m_finalTranslation = Eigen::Vector3d::Zero();
  Eigen::Vector3d m_wobble = Eigen::Vector3d::Zero();
  bool m_done = false;
  bool m_grabbing = false;  ///< the drag time is over: grabs under way (the drag goes on until they are done)
  QStringList m_failures;
};

}  // namespace sc::app
