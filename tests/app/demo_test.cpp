// First start, --demo and the Network conditions dock, with real loopback sockets in one process: the demo opens
// three windows whose two clients reach Live and show the mesh (the low one at ≈5% behind 10% loss); the dock
// changes a client's impairment live; the first start picks a mesh (a generated one when none is fetched), becomes
// Live with a default handle, anchors, the lock and the Drag tool. With SHAPECAST_TEST_SCREENSHOTS=DIR the demo's
// windows are saved to DIR (demo-host.png, demo-client-full.png, demo-client-low.png). DemoScreenshots
// (tools/screenshots/, `shapecast --demo --screenshot-dir`) writes its four PNGs, none blank, after a scripted drag
// that reached the clients.

#include "app/gui/demo.h"
#include "app/gui/client_controller.h"
#include "app/gui/first_start.h"
#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/network_conditions_dock.h"
#include "app_test_support.h"
#include "session_windows.h"
#include "test_meshes.h"
#include "tools/screenshots/demo_screenshots.h"

#include <gtest/gtest.h>

#include <QAction>
#include <QDir>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QImage>
#include <QLabel>
#include <QSpinBox>
#include <QTemporaryDir>
#include <QTest>

namespace sc::app {
namespace {

using State = SessionController::State;
constexpr int kLiveTimeoutMs = 30000;

bool waitLive(MainWindow* window) {
  // A client's join is progressive: it is Live on the host's smallest level, then gets the requested one.
  return QTest::qWaitFor(
             [window] {
               const SessionController* s = window->session();
               const auto* client = qobject_cast<const ClientController*>(s);
               return s != nullptr && ((s->state() == State::Live && (client == nullptr || !client->levelPending())) ||
                                       s->state() == State::Failed);
             },
             kLiveTimeoutMs) &&
         window->session()->state() == State::Live;
}

class DemoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sc::testing::openGlAvailable()) GTEST_SKIP() << "no OpenGL 3.3 context (needs an X server)";
    ASSERT_TRUE(m_dir.isValid());
    const sc::testing::GeneratedMesh mesh = sc::testing::torus(40, 20);
    m_meshPath = m_dir.filePath(QStringLiteral("torus.off"));
    ASSERT_TRUE(sc::testing::writeOff(m_meshPath, mesh.V, mesh.F));
    m_vertices = static_cast<int>(mesh.V.rows());
  }

  QTemporaryDir m_dir;
  QString m_meshPath;
  int m_vertices = 0;
};

TEST_F(DemoTest, ThreeWindowsBothClientsLive) {
  DemoOptions options;
  options.meshPath = m_meshPath;
  options.m = 20;
  options.useBasisCache = false;
  options.errorDialogs = false;
  Demo demo(options);
  ASSERT_TRUE(demo.start());
  ASSERT_EQ(demo.windows().size(), 3u);
  for (MainWindow* window : demo.windows()) EXPECT_TRUE(window->isVisible());

  ASSERT_TRUE(waitLive(demo.hostWindow())) << demo.hostWindow()->session()->errorText().toStdString();
  SessionController* host = demo.hostWindow()->session();
  EXPECT_EQ(host->role(), SessionController::Role::Host);
  ASSERT_TRUE(waitLive(demo.fullClientWindow())) << demo.fullClientWindow()->session()->errorText().toStdString();
  ASSERT_TRUE(waitLive(demo.lowClientWindow())) << demo.lowClientWindow()->session()->errorText().toStdString();

  // The host is ready to drag: default handle and anchors, the lock, the Drag tool.
  EXPECT_TRUE(QTest::qWaitFor([host] { return host->canDrag(); }, 5000));
  EXPECT_FALSE(host->handle().empty());
  EXPECT_FALSE(host->anchors().empty());
  EXPECT_EQ(demo.hostWindow()->viewport()->tool(), ViewportTool::Drag);
  EXPECT_FALSE(demo.hostWindow()->viewport()->handles().empty());

  // Both clients show the mesh: full resolution, and a much smaller level behind 10% loss.
  MeshViewport* fullView = demo.fullClientWindow()->viewport();
  MeshViewport* lowView = demo.lowClientWindow()->viewport();
  EXPECT_EQ(fullView->vertexCount(), m_vertices);
  EXPECT_GT(lowView->vertexCount(), 0);
  EXPECT_LT(lowView->vertexCount(), m_vertices / 4);
  auto* low = qobject_cast<ClientController*>(demo.lowClientWindow()->session());
  ASSERT_NE(low, nullptr);
  EXPECT_NEAR(low->networkConditions().loss, 0.10, 1e-12);
  EXPECT_TRUE(QTest::qWaitFor([low] { return low->impairmentInEffect().has_value(); }, 5000));
  auto* full = qobject_cast<ClientController*>(demo.fullClientWindow()->session());
  ASSERT_NE(full, nullptr);
  EXPECT_FALSE(full->impairmentInEffect().has_value());
  // The low client's dock shows its 10% and is enabled; the host's is disabled.
  EXPECT_NEAR(demo.lowClientWindow()->networkConditionsDock()->lossPercent(), 10.0, 1e-9);
  EXPECT_TRUE(demo.lowClientWindow()
                  ->networkConditionsDock()
                  ->widget()
                  ->findChild<QDoubleSpinBox*>(QStringLiteral("lossSpinBox"))
                  ->isEnabled());
  EXPECT_FALSE(demo.hostWindow()
                   ->networkConditionsDock()
                   ->widget()
                   ->findChild<QDoubleSpinBox*>(QStringLiteral("lossSpinBox"))
                   ->isEnabled());

  // A drag on the host reaches both clients.
  ASSERT_TRUE(host->beginDrag());
  ASSERT_TRUE(host->dragTo(Eigen::Vector3d(0.0, 0.3, 0.0), Eigen::Matrix3d::Identity()));
  host->endDrag();
  EXPECT_TRUE(QTest::qWaitFor(
      [full] {
        const Eigen::MatrixXd Z = full->coefficients();
        return Z.size() > 0 && Z.norm() > 1e-6;
      },
      5000));

  const QString shots = qEnvironmentVariable("SHAPECAST_TEST_SCREENSHOTS");
  if (!shots.isEmpty()) {
    QTest::qWait(500);  // a few frames after the drag
    ASSERT_TRUE(QDir().mkpath(shots));
    const std::pair<MainWindow*, const char*> files[] = {{demo.hostWindow(), "demo-host.png"},
                                                         {demo.fullClientWindow(), "demo-client-full.png"},
                                                         {demo.lowClientWindow(), "demo-client-low.png"}};
    for (const auto& [window, file] : files) {
      const QImage image = window->grabWindow();
      EXPECT_FALSE(image.isNull());
      EXPECT_TRUE(image.save(QDir(shots).filePath(QString::fromLatin1(file)), "PNG")) << file;
    }
  }
}

TEST_F(DemoTest, ScreenshotDirWritesFourImagesAfterAScriptedDrag) {
  DemoOptions options;
  options.meshPath = m_meshPath;
  options.m = 20;
  options.useBasisCache = false;
  options.errorDialogs = false;
  Demo demo(options);
  DemoScreenshotOptions shotOptions;
  shotOptions.directory = m_dir.filePath(QStringLiteral("shots"));
  shotOptions.afterSeconds = 1.0;
  shotOptions.windowSize = QSize(640, 480);
  shotOptions.mainWindowSize = QSize(800, 600);
  shotOptions.liveTimeoutSeconds = 60;
  DemoScreenshots screenshots(demo, shotOptions);
  bool done = false;
  bool written = false;
  QString message;
  QObject::connect(&screenshots, &DemoScreenshots::finished, [&](bool ok, const QString& why) {
    done = true;
    written = ok;
    message = why;
  });
  ASSERT_TRUE(demo.start());
  screenshots.start();
  ASSERT_TRUE(QTest::qWaitFor([&] { return done; }, 90000));
  ASSERT_TRUE(written) << message.toStdString();
  // the scripted drag was a real drag of the host: it is a step of the session's edit history and moved the clients
  EXPECT_EQ(demo.hostWindow()->session()->editLog().steps.size(), 1u);
  EXPECT_GT(demo.fullClientWindow()->session()->coefficients().norm(), 1e-6);
  for (const QString& name : DemoScreenshots::fileNames()) {
    const QImage image(QDir(shotOptions.directory).filePath(name));
    ASSERT_FALSE(image.isNull()) << name.toStdString();
    EXPECT_GE(image.width(), 600) << name.toStdString();
    EXPECT_GT(sc::testing::pixelStdDev(image), 5.0) << name.toStdString();
  }
}

TEST_F(DemoTest, NetworkConditionsDockChangesTheClientsImpairment) {
  MainWindow hostWindow;
  hostWindow.setErrorDialogsEnabled(false);
  hostWindow.hostSession(sc::testing::loopbackHostSettings(m_meshPath, 20));
  NetworkConditionsDock* hostDock = hostWindow.networkConditionsDock();
  ASSERT_NE(hostDock, nullptr);
  EXPECT_EQ(hostDock->objectName(), QStringLiteral("networkConditionsDock"));
  ASSERT_TRUE(waitLive(&hostWindow)) << hostWindow.session()->errorText().toStdString();
  EXPECT_FALSE(hostDock->widget()->findChild<QSpinBox*>(QStringLiteral("delaySpinBox"))->isEnabled());
  EXPECT_TRUE(hostDock->isHidden());
  // The View menu toggles the dock.
  EXPECT_TRUE(hostWindow.findChildren<QAction*>().contains(hostDock->toggleViewAction()));

  MainWindow clientWindow;
  clientWindow.setErrorDialogsEnabled(false);
  clientWindow.joinSession(sc::testing::loopbackJoinSettings(hostWindow.session()->tcpPort(),
                                                             m_dir.filePath(QStringLiteral("known_hosts.ini"))));
  ASSERT_TRUE(waitLive(&clientWindow)) << clientWindow.session()->errorText().toStdString();
  NetworkConditionsDock* dock = clientWindow.networkConditionsDock();
  auto* loss = dock->widget()->findChild<QDoubleSpinBox*>(QStringLiteral("lossSpinBox"));
  auto* burst = dock->widget()->findChild<QDoubleSpinBox*>(QStringLiteral("burstSpinBox"));
  auto* delay = dock->widget()->findChild<QSpinBox*>(QStringLiteral("delaySpinBox"));
  ASSERT_TRUE(loss && burst && delay);
  EXPECT_TRUE(loss->isEnabled());
  const auto* client = qobject_cast<const ClientController*>(clientWindow.session());
  ASSERT_NE(client, nullptr);
  EXPECT_FALSE(client->impairmentInEffect().has_value());

  loss->setValue(25.0);  // as the user typing it: applied at once
  ASSERT_TRUE(client->impairmentInEffect().has_value());
  EXPECT_NEAR(client->impairmentInEffect()->loss, 0.25, 1e-12);
  EXPECT_FALSE(client->impairmentInEffect()->burst);
  burst->setValue(4.0);
  delay->setValue(40);
  ASSERT_TRUE(client->impairmentInEffect().has_value());
  EXPECT_TRUE(client->impairmentInEffect()->burst);
  EXPECT_DOUBLE_EQ(client->impairmentInEffect()->burstLength, 4.0);
  EXPECT_EQ(client->impairmentInEffect()->delay.count(), 40);
  const NetworkConditions conditions = clientWindow.session()->networkConditions();
  EXPECT_NEAR(conditions.loss, 0.25, 1e-12);
  EXPECT_EQ(conditions.delayMs, 40);

  loss->setValue(0.0);
  delay->setValue(0);
  EXPECT_FALSE(client->impairmentInEffect().has_value());
  EXPECT_DOUBLE_EQ(burst->value(), 4.0);  // kept as the user left it

  // A link rate alone is an impairment too (issue 17): it reaches the datagram channel and the label says so.
  auto* rate = dock->widget()->findChild<QDoubleSpinBox*>(QStringLiteral("rateSpinBox"));
  ASSERT_NE(rate, nullptr);
  rate->setValue(5.0);
  ASSERT_TRUE(client->impairmentInEffect().has_value());
  EXPECT_DOUBLE_EQ(client->impairmentInEffect()->rate.bitsPerSecond, 5e6);
  EXPECT_EQ(client->impairmentInEffect()->loss, 0.0);
  EXPECT_DOUBLE_EQ(clientWindow.session()->networkConditions().rateMbit, 5.0);
  EXPECT_TRUE(dock->widget()
                  ->findChild<QLabel*>(QStringLiteral("networkConditionsLabel"))
                  ->text()
                  .contains(QStringLiteral("5.0 Mbit/s")));
  rate->setValue(0.0);
  EXPECT_FALSE(client->impairmentInEffect().has_value());
  EXPECT_FALSE(hostWindow.session()->setNetworkConditions(0.1, 1.0, 0, 0.0));  // a host has none
}

TEST(FirstStartName, GivenElseTheRememberedNameElseHost) {
  // The first start named itself "host" even when the dialogs remembered the user's name.
  sc::app::RecentSessions recent;
  EXPECT_EQ(sc::app::firstStartName({}, recent).toStdString(), "host");
  recent.names = {QStringLiteral("ada"), QStringLiteral("bob")};
  EXPECT_EQ(sc::app::firstStartName({}, recent).toStdString(), "ada");
  EXPECT_EQ(sc::app::firstStartName(QStringLiteral(" eve "), recent).toStdString(), "eve");
}

TEST_F(DemoTest, FirstStartPicksAMeshAndIsReadyToDrag) {
  // No fetched mesh in an empty folder: a generated torus; a folder with meshes: the dragon first, else by name.
  QTemporaryDir empty;
  ASSERT_TRUE(empty.isValid());
  EXPECT_TRUE(findDefaultMesh({empty.path()}).isEmpty());
  QTemporaryDir meshes;
  ASSERT_TRUE(QFile::copy(m_meshPath, meshes.filePath(QStringLiteral("b.off"))));
  ASSERT_TRUE(QFile::copy(m_meshPath, meshes.filePath(QStringLiteral("a.off"))));
  EXPECT_EQ(QFileInfo(findDefaultMesh({empty.path(), meshes.path()})).fileName(), QStringLiteral("a.off"));
  ASSERT_TRUE(QFile::copy(m_meshPath, meshes.filePath(QString::fromLatin1(kDefaultMeshName))));
  EXPECT_EQ(QFileInfo(findDefaultMesh({meshes.path()})).fileName(), QString::fromLatin1(kDefaultMeshName));

  QString error;
  const QString mesh = defaultMeshOrGenerated({empty.path()}, &error);
  ASSERT_FALSE(mesh.isEmpty()) << error.toStdString();
  EXPECT_TRUE(QFileInfo(mesh).isFile());

  MainWindow window;
  window.setErrorDialogsEnabled(false);
  window.show();
  HostSettings settings;
  settings.meshPath = mesh;
  settings.port = availablePort(0);
  settings.m = 30;
  settings.useBasisCache = false;
  hostReadyToDrag(window, settings);
  ASSERT_TRUE(waitLive(&window)) << window.session()->errorText().toStdString();
  SessionController* session = window.session();
  EXPECT_GT(window.viewport()->vertexCount(), 1000);  // the generated torus
  EXPECT_TRUE(QTest::qWaitFor([session] { return session->canDrag(); }, 5000));
  EXPECT_FALSE(session->handle().empty());
  EXPECT_GT(session->anchors().size(), session->handle().size());
  EXPECT_EQ(window.viewport()->tool(), ViewportTool::Drag);
  auto* dragAction = window.findChild<QAction*>(QStringLiteral("actionToolDrag"));
  ASSERT_NE(dragAction, nullptr);
  EXPECT_TRUE(dragAction->isChecked());
  // The handle is at the top (largest y).
  const Eigen::MatrixXd& V = session->displayRestPositions();
  EXPECT_GT(V(static_cast<Eigen::Index>(session->handle().front().index()), 1), 0.5 * V.col(1).maxCoeff());
  // and the drag works at once
  ASSERT_TRUE(session->beginDrag());
  EXPECT_TRUE(session->dragTo(Eigen::Vector3d(0.0, 0.2, 0.0), Eigen::Matrix3d::Identity()));
  session->endDrag();
}

}  // namespace
}  // namespace sc::app
