#include "tools/screenshots/demo_screenshots.h"

#include "app/gui/demo.h"
#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/network_conditions_dock.h"
#include "app/gui/peers_dock.h"
#include "app/gui/repaint_batch.h"
#include "app/gui/session_controller.h"
#include "app/gui/session_docks.h"
#include "app/gui/statistics_dock.h"
#include "session/net/session_host.h"

#include <Eigen/Geometry>
#include <QDir>
#include <QImage>
#include <QPixmap>
#include <QTimer>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sc::app {

namespace {

constexpr int kPollMs = 200;
constexpr int kDragStepMs = 33;  // ≈ 30 poses a second, as a mouse drag
constexpr double kSwayHz = 0.4;
constexpr int kRepaintMs = 1200;       // after a resize: layout and a few frames
constexpr int kPeersDockHeight = 200;  // three peers without a scroll bar
constexpr int kNetworkDockHeight = 150;
constexpr double kLiftFraction = 0.08;    // final handle lift, fraction of the bounding-box diagonal
constexpr double kWobbleFraction = 0.03;  // side-to-side motion while dragging
constexpr double kFinalDegrees = 10.0;

/// 0 → 1 with zero slope at both ends.
double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

bool isLive(const MainWindow* window) {
  return window != nullptr && window->session() != nullptr &&
         window->session()->state() == SessionController::State::Live;
}

bool hasFailed(const MainWindow* window) {
  return window != nullptr && window->session() != nullptr &&
         window->session()->state() == SessionController::State::Failed;
}

/// Docks `dockWidth` wide; the peers table high enough for three peers, the network conditions (a client's) at
/// their natural height, the statistics the rest; then the view frames the current (deformed) shape. Call once
/// the window has its new size (a queued call after resize()).
void layOutDocks(MainWindow& window, int dockWidth) {
  window.resizeDocks({window.docks()->peersDock()}, {dockWidth}, Qt::Horizontal);
  QList<QDockWidget*> docks{window.docks()->peersDock(), window.docks()->statisticsDock()};
  const bool network = window.networkConditionsDock()->isVisible();
  // Qt scales the sizes to the column's height: give the statistics what the others leave of it
  const int column = window.centralWidget()->height();
  QList<int> heights{kPeersDockHeight,
                     std::max(kPeersDockHeight, column - kPeersDockHeight - (network ? kNetworkDockHeight : 0))};
  if (network) {
    docks << window.networkConditionsDock();
    heights << kNetworkDockHeight;
  }
  window.resizeDocks(docks, heights, Qt::Vertical);
  window.viewport()->resetView();
}

}  // namespace

DemoScreenshots::DemoScreenshots(Demo& demo, DemoScreenshotOptions options, QObject* parent)
    : QObject(parent), m_demo(demo), m_options(std::move(options)), m_timer(new QTimer(this)) {
  m_options.afterSeconds = std::max(1.0, m_options.afterSeconds);
}

DemoScreenshots::~DemoScreenshots() = default;

QStringList DemoScreenshots::fileNames() {
  return {QStringLiteral("demo-host.png"), QStringLiteral("demo-client-full.png"),
          QStringLiteral("demo-client-low.png"), QStringLiteral("main-window-statistics.png")};
}

void DemoScreenshots::start() {
  if (!QDir().mkpath(m_options.directory)) {
    QTimer::singleShot(0, this, [this] { finish(false, tr("Cannot create %1").arg(m_options.directory)); });
    return;
  }
  m_clock.start();
  connect(m_timer, &QTimer::timeout, this, &DemoScreenshots::poll);
  m_timer->start(kPollMs);
}

void DemoScreenshots::poll() {
  const std::vector<MainWindow*> windows = m_demo.windows();
  for (MainWindow* window : windows) {
    if (hasFailed(window)) {
      finish(false, tr("A demo window failed: %1").arg(window->session()->errorText()));
      return;
    }
  }
  const bool allLive = windows.size() == 3 && std::all_of(windows.begin(), windows.end(), isLive);
  if (allLive && m_demo.hostWindow()->session()->canDrag() && !m_demo.hostWindow()->session()->handle().empty()) {
    m_timer->disconnect(this);
    beginDrag();
    return;
  }
  if (m_clock.elapsed() > 1000LL * m_options.liveTimeoutSeconds) {
    finish(false, tr("The demo windows were not all live after %1 s").arg(m_options.liveTimeoutSeconds));
  }
}

void DemoScreenshots::beginDrag() {
  SessionController* session = m_demo.hostWindow()->session();
  const Eigen::MatrixXd& V = session->displayRestPositions();
  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  m_finalTranslation = Eigen::Vector3d(0.3, 1.0, 0.2).normalized() * kLiftFraction * diagonal;
  m_wobble = Eigen::Vector3d(1.0, 0.0, -0.5).normalized() * kWobbleFraction * diagonal;
  session->beginDrag();
  m_clock.restart();
  connect(m_timer, &QTimer::timeout, this, &DemoScreenshots::dragStep);
  m_timer->start(kDragStepMs);
}

void DemoScreenshots::dragStep() {
  const double duration = 1000.0 * m_options.afterSeconds;
  const double p = std::min(1.0, static_cast<double>(m_clock.elapsed()) / duration);
  // lift to the final pose in the first third, then sway around it until the grabs are done
  const double lift = smoothstep(3.0 * p);
  const double seconds = static_cast<double>(m_clock.elapsed()) / 1000.0;
  const double sway = lift * std::sin(2.0 * std::numbers::pi * kSwayHz * seconds);
  const Eigen::Vector3d translation = lift * m_finalTranslation + sway * m_wobble;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(lift * kFinalDegrees * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  m_demo.hostWindow()->session()->dragTo(translation, rotation);
  if (p >= 1.0 && !m_grabbing) {
    m_grabbing = true;  // the drag goes on while the windows are resized and grabbed: the figures stay live
    grabDemoWindows();
  }
}

void DemoScreenshots::endDrag() {
  m_timer->stop();
  m_timer->disconnect(this);
  MainWindow* host = m_demo.hostWindow();
  host->session()->endDrag();
}

void DemoScreenshots::grabDemoWindows() {
  for (MainWindow* window : m_demo.windows()) window->resize(m_options.windowSize);
  QTimer::singleShot(kRepaintMs / 2, this, [this] {
    // the 3D view keeps about 60% of the width; then it frames the deformed shape
    for (MainWindow* window : m_demo.windows()) layOutDocks(*window, m_options.windowSize.width() * 2 / 5);
  });
  QTimer::singleShot(kRepaintMs, this, [this] {
    const QStringList names = fileNames();
    const std::vector<MainWindow*> windows = m_demo.windows();
    for (std::size_t i = 0; i < windows.size() && i < 3; ++i) save(windows[i], names[static_cast<qsizetype>(i)]);
    grabMainWindow();
  });
}

void DemoScreenshots::grabMainWindow() {
  MainWindow* host = m_demo.hostWindow();
  // the host shows the lossy client's statistics (its loss and distortion are the interesting ones)
  for (const session::PeerInfo& peer : host->session()->peers().peers) {
    if (peer.peerId != session::kHostPeer &&
        peer.vertexCount < static_cast<std::uint32_t>(host->viewport()->vertexCount())) {
      host->docks()->peersDock()->selectPeer(peer.peerId);
    }
  }
  host->resize(m_options.mainWindowSize);
  QTimer::singleShot(kRepaintMs / 2, this,
                     [this, host] { layOutDocks(*host, m_options.mainWindowSize.width() * 9 / 20); });
  QTimer::singleShot(kRepaintMs, this, [this, host] {
    save(host, fileNames().last());
    endDrag();
    finish(m_failures.isEmpty(), m_failures.join(QStringLiteral("; ")));
  });
}

void DemoScreenshots::save(MainWindow* window, const QString& name) {
  const QString path = QDir(m_options.directory).filePath(name);
  if (window->docks() != nullptr) window->docks()->repaintBatch()->releaseNow();  // grab() skips held widgets
  const QImage image = window->grabWindow();
  if (image.isNull() || !image.save(path, "PNG")) m_failures << tr("could not write %1").arg(path);
}

void DemoScreenshots::finish(bool ok, const QString& message) {
  if (m_done) return;
  m_done = true;
  if (m_grabbing) endDrag();
  m_timer->stop();
  emit finished(ok, message);
}

}  // namespace sc::app
