// Several people drag at once (issue 15, item 2), seen from the windows over real loopback sockets: a hosting
// MainWindow and a watching one in this process, and two `shapecast-cli drive` processes that each take a lease and
// drag their own handle of the torus at the same time (one end up, the other down, over the same anchors). The host
// and the watcher must show both ends moved, and the same shape.

#include "app/gui/host_controller.h"
#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/repaint_batch.h"
#include "app/gui/session_docks.h"
#include "app/gui/session_presence.h"
#include "app/gui/vertex_id_lists.h"
#include "app_test_support.h"
#include "session/engine/host_engine.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QElapsedTimer>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QStatusBar>
#include <QTest>

#include <algorithm>
#include <memory>
#include <vector>

namespace sc::app {
namespace {

using State = SessionController::State;

class CoeditingTest : public sc::testing::TorusSessionTest {
 protected:
  /// A drag script moving a sphere of `radiusPct` around `vertex` by `dzPct` % of the diagonal along z in the first
  /// second, then holding it still until t = 3 s (so that both drivers hold their leases while both poses stand),
  /// over the shared anchors.
  QString writeScript(const QString& name, int vertex, double dzPct, const std::vector<int>& anchors) {
    QJsonArray anchorIds;
    for (const int a : anchors) anchorIds.append(a);
    const QJsonObject script{
        {QStringLiteral("handles"),
         QJsonArray{QJsonObject{{QStringLiteral("sphere"),
                                 QJsonObject{{QStringLiteral("vertex"), vertex}, {QStringLiteral("radius_pct"), 8}}}}}},
        {QStringLiteral("anchors"), QJsonObject{{QStringLiteral("vertices"), anchorIds}}},
        {QStringLiteral("fps"), 30},
        {QStringLiteral("frames"),
         QJsonArray{
             QJsonObject{{QStringLiteral("t"), 0}},
             QJsonObject{{QStringLiteral("t"), 1}, {QStringLiteral("translate_pct"), QJsonArray{0, 0, dzPct}}},
             QJsonObject{{QStringLiteral("t"), 3}, {QStringLiteral("translate_pct"), QJsonArray{0, 0, dzPct}}}}}};
    const QString path = m_dir.filePath(name + QStringLiteral(".json"));
    QFile file(path);
    EXPECT_TRUE(file.open(QIODevice::WriteOnly));
    file.write(QJsonDocument(script).toJson());
    return path;
  }

  /// Starts `shapecast-cli drive` as `name` against the host, trusting its fingerprint.
  std::unique_ptr<QProcess> drive(const QString& name, const QString& script, quint16 port,
                                  const QByteArray& fingerprint) {
    auto process = std::make_unique<QProcess>();
    QProcessEnvironment environment = QProcessEnvironment::systemEnvironment();
    environment.insert(QStringLiteral("XDG_CONFIG_HOME"), m_dir.filePath(QStringLiteral("config-") + name));
    process->setProcessEnvironment(environment);
    process->start(QStringLiteral(SHAPECAST_CLI_EXE),
                   {QStringLiteral("drive"), QStringLiteral("127.0.0.1:%1").arg(port), QStringLiteral("--name"), name,
                    QStringLiteral("--fingerprint"), QString::fromLatin1(fingerprint.toHex()),
                    QStringLiteral("--script"), script, QStringLiteral("--json")});
    return process;
  }

  /// The torus (around the z axis): its east end (largest x, within 8 % of the diagonal), its west end, and its
  /// south side (y below −0.6 of the largest y), which both drivers hold.
  struct Ends {
    std::vector<int> east, west, anchors;
    int eastVertex = 0, westVertex = 0;
    double diagonal = 0.0;
  };
  Ends ends() const {
    const Eigen::MatrixXd& V = m_mesh.V;
    Ends out;
    Eigen::Index east = 0, west = 0;
    V.col(0).maxCoeff(&east);
    V.col(0).minCoeff(&west);
    out.eastVertex = static_cast<int>(east);
    out.westVertex = static_cast<int>(west);
    out.diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      if (V(i, 1) < -0.6 * V.col(1).maxCoeff()) out.anchors.push_back(static_cast<int>(i));
      if ((V.row(i) - V.row(east)).norm() <= 0.08 * out.diagonal) out.east.push_back(static_cast<int>(i));
      if ((V.row(i) - V.row(west)).norm() <= 0.08 * out.diagonal) out.west.push_back(static_cast<int>(i));
    }
    return out;
  }

  /// The mean displacement along z of `ids` in interleaved positions `xyz` against rest `V`.
  static double meanLift(const std::vector<float>& xyz, const Eigen::MatrixXd& V, const std::vector<int>& ids) {
    double sum = 0.0;
    for (const int v : ids) sum += xyz[static_cast<std::size_t>(3 * v + 2)] - V(v, 2);
    return sum / static_cast<double>(ids.size());
  }
};

TEST_F(CoeditingTest, TwoCliClientsDragTwoHandlesAtOnceAndTheHostAndAThirdClientShowBoth) {
  MainWindow hostWindow, watcherWindow;
  const LiveSession live = hostAndJoin(hostWindow, watcherWindow);
  ASSERT_EQ(live.host->state(), State::Live) << live.host->errorText().toStdString();
  ASSERT_NE(live.client, nullptr);
  ASSERT_EQ(live.client->state(), State::Live) << live.client->errorText().toStdString();

  const Eigen::MatrixXd& V = m_mesh.V;
  const Ends torus = ends();
  const std::vector<int>& anchors = torus.anchors;
  const std::vector<int>& eastEnd = torus.east;
  const std::vector<int>& westEnd = torus.west;
  const double diagonal = torus.diagonal;
  const quint16 port = live.host->tcpPort();
  const QByteArray fingerprint = live.host->hostFingerprint();
  const auto up = drive(QStringLiteral("erin"), writeScript(QStringLiteral("up"), torus.eastVertex, 10, anchors), port,
                        fingerprint);
  const auto down = drive(QStringLiteral("finn"), writeScript(QStringLiteral("down"), torus.westVertex, -10, anchors),
                          port, fingerprint);

  // While they drag, both hold a lease at once; the host's window keeps running its event loop meanwhile.
  std::size_t mostHolders = 0;
  QElapsedTimer waited;
  waited.start();
  while ((up->state() != QProcess::NotRunning || down->state() != QProcess::NotRunning) && waited.elapsed() < 90000) {
    mostHolders = std::max(mostHolders, live.host->lockHolders().size());
    QTest::qWait(20);
  }
  ASSERT_EQ(up->state(), QProcess::NotRunning);
  ASSERT_EQ(down->state(), QProcess::NotRunning);
  EXPECT_EQ(up->exitCode(), 0) << up->readAllStandardError().toStdString();
  EXPECT_EQ(down->exitCode(), 0) << down->readAllStandardError().toStdString();
  EXPECT_EQ(mostHolders, 2u) << "the two drivers held their leases at the same time";
  EXPECT_EQ(live.host->counters().constraintsOverlapping, 0u) << "their handles and shared anchors do not overlap";

  // Both ends moved, on the host and on the watcher, and the two show the same shape.
  ASSERT_TRUE(QTest::qWaitFor([&] { return live.client->reception().received == live.host->currentFrame(); }, 10000));
  const double target = 0.1 * diagonal;
  for (SessionController* screen :
       {static_cast<SessionController*>(live.host), static_cast<SessionController*>(live.client)}) {
    const std::vector<float> shown = screen->positions();
    ASSERT_EQ(shown.size(), static_cast<std::size_t>(3 * V.rows()));
    EXPECT_GT(meanLift(shown, V, eastEnd), 0.7 * target) << "the east end went up";
    EXPECT_LT(meanLift(shown, V, westEnd), -0.7 * target) << "the west end went down";
    EXPECT_LT(std::abs(meanLift(shown, V, anchors)), 0.05 * target) << "the shared anchors held";
  }
  const std::vector<float> hostShape = live.host->positions();
  const std::vector<float> watcherShape = live.client->positions();
  float worst = 0.0F;
  for (std::size_t i = 0; i < hostShape.size(); ++i) worst = std::max(worst, std::abs(hostShape[i] - watcherShape[i]));
  EXPECT_LT(worst, 1e-3 * diagonal) << "the watcher shows the host's shape (up to the frames' quantisation)";
  // Each driver's drag is its own step of the shared history.
  ASSERT_EQ(live.host->editLog().steps.size(), 2u);
  QStringList authors{live.host->editLog().steps[0].authorName, live.host->editLog().steps[1].authorName};
  authors.sort();
  EXPECT_EQ(authors, (QStringList{QStringLiteral("erin"), QStringLiteral("finn")}));
}

TEST_F(CoeditingTest, TwoWindowsDragAtOnceAndTheHostSeesBothShapesAndBothPeople) {
  MainWindow hostWindow, bobWindow, carolWindow;
  const LiveSession live = hostAndJoin(hostWindow, bobWindow, QSize(1000, 700), QSize(560, 420));
  ASSERT_EQ(live.host->state(), State::Live) << live.host->errorText().toStdString();
  ASSERT_NE(live.client, nullptr);
  ASSERT_EQ(live.client->state(), State::Live) << live.client->errorText().toStdString();
  ClientController* bob = live.client;
  sc::testing::showSessionWindow(carolWindow, QSize(560, 420));
  JoinSettings carolSettings = sc::testing::loopbackJoinSettings(live.host->tcpPort(), knownHostsFile());
  carolSettings.name = QStringLiteral("carol");
  ClientController* carol = sc::testing::joinAndWait(carolWindow, carolSettings);
  ASSERT_EQ(carol->state(), State::Live) << carol->errorText().toStdString();

  // Bob asks first and is granted first (two clients' requests, each sent from its own connection's thread, reach
  // the host in no fixed order otherwise).
  ASSERT_TRUE(bob->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return bob->canDrag(); }, 5000)) << bob->lockText().toStdString();
  ASSERT_TRUE(carol->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return bob->canDrag() && carol->canDrag(); }, 5000))
      << bob->lockText().toStdString() << " / " << carol->lockText().toStdString();
  EXPECT_EQ(live.host->lockText(), QStringLiteral("Locks held by bob and carol"));

  // Each paints its own end over the shared south side, looks at it, and drags it: bob up, carol down, together.
  const Ends torus = ends();
  const auto paint = [&torus](MainWindow& window, ClientController* who, const std::vector<int>& end) {
    window.viewport()->setSelection(end, torus.anchors);
    return who->setSelection(typedIds<spectral::DisplayVertexId>(end),
                             typedIds<spectral::DisplayVertexId>(torus.anchors));
  };
  ASSERT_TRUE(paint(bobWindow, bob, torus.east));
  // carol first paints over bob's handle: refused, and her status bar says whose it is
  ASSERT_TRUE(QTest::qWaitFor([&] { return live.host->counters().constraintsAccepted >= 1; }, 5000));
  ASSERT_TRUE(paint(carolWindow, carol, torus.east));
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return carolWindow.statusBar()->currentMessage().contains(QStringLiteral("overlap bob's")); }, 5000))
      << carolWindow.statusBar()->currentMessage().toStdString();
  EXPECT_EQ(live.host->counters().constraintsOverlapping, 1u);
  ASSERT_TRUE(paint(carolWindow, carol, torus.west));
  bobWindow.viewport()->lookFrom(QVector3D(3.0f, -1.5f, 2.0f), QVector3D(1.2f, 0.0f, 0.0f));
  carolWindow.viewport()->lookFrom(QVector3D(-3.0f, -1.5f, 2.0f), QVector3D(-1.2f, 0.0f, 0.0f));
  for (MainWindow* window : {&bobWindow, &carolWindow}) {
    MeshViewport* view = window->viewport();
    view->setPointer(QPointF(view->width() / 2.0, view->height() / 2.0));
  }
  ASSERT_TRUE(bob->beginDrag());
  ASSERT_TRUE(carol->beginDrag());
  const double target = 0.1 * torus.diagonal;
  for (int step = 1; step <= 10; ++step) {
    ASSERT_TRUE(bob->dragTo(Eigen::Vector3d(0.0, 0.0, target * step / 10.0), Eigen::Matrix3d::Identity()));
    ASSERT_TRUE(carol->dragTo(Eigen::Vector3d(0.0, 0.0, -target * step / 10.0), Eigen::Matrix3d::Identity()));
    QTest::qWait(30);
  }

  // While both still drag: the host shows both ends moved, and both people (markers, "is dragging").
  const Eigen::MatrixXd& V = m_mesh.V;
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        const std::vector<float> shown = live.host->positions();
        return meanLift(shown, V, torus.east) > 0.7 * target && meanLift(shown, V, torus.west) < -0.7 * target;
      },
      5000));
  SessionPresence& atHost = *hostWindow.presence();
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        const session::RemotePresence* b = atHost.board().find(bob->selfId());
        const session::RemotePresence* c = atHost.board().find(carol->selfId());
        return b != nullptr && c != nullptr && b->presence.dragging && c->presence.dragging;
      },
      3000))
      << "both are seen dragging";
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        const std::vector<PresenceMarker>& markers = hostWindow.viewport()->presenceMarkers();
        return markers.size() == 2u && markers[0].handle && markers[1].handle;
      },
      3000))
      << "each one's handle is shown where it is";
  // Each dragger sees the other's end move too.
  ASSERT_TRUE(QTest::qWaitFor([&] { return meanLift(bob->positions(), V, torus.west) < -0.7 * target; }, 5000));
  ASSERT_TRUE(QTest::qWaitFor([&] { return meanLift(carol->positions(), V, torus.east) > 0.7 * target; }, 5000));

  if (const QByteArray path = qgetenv("SHAPECAST_COEDITING_SCREENSHOT"); !path.isEmpty()) {
    hostWindow.viewport()->lookFrom(QVector3D(0.0f, -5.5f, 3.2f), QVector3D(0.0f, 0.0f, 0.0f));
    QTest::qWait(300);
    // The window with the viewport's own frame in it (MainWindow::grabWindow()).
    hostWindow.docks()->repaintBatch()->releaseNow();  // grab() draws nothing of widgets whose painting is held
    const QImage shot = hostWindow.grabWindow();
    EXPECT_TRUE(shot.save(QString::fromLocal8Bit(path)));
  }

  bob->endDrag();
  carol->endDrag();
  ASSERT_TRUE(QTest::qWaitFor([&] { return live.host->editLog().steps.size() == 2u; }, 5000))
      << "each drag is its author's own step";
}

}  // namespace
}  // namespace sc::app
