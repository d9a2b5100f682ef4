// Issue 18 item 3: a host window that relays through a real nats-server shows its viewers (`shapecast-cli watch`
// processes) in its Peers and Statistics docks as ONE aggregate: a single "N viewers through NATS" row with the
// loss and latency distributions in its tooltip, and a Statistics section, never one row per viewer.

#include "app/gui/peers_dock.h"
#include "app/gui/relay_audience_view.h"
#include "app/gui/session_docks.h"
#include "app/gui/statistics_dock.h"
#include "model/peer_table_model.h"
#include "session/net/local_nats_server.h"
#include "session/net/relay_publisher.h"
#include "session/net/tls_identity.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QFile>
#include <QLabel>
#include <QProcess>
#include <QTest>

#include <memory>
#include <vector>

namespace sc::testing {
namespace {

class RelayDocksTest : public TorusSessionTest {};

TEST_F(RelayDocksTest, TheHostsDocksShowItsViewersAsOneAggregate) {
  if (!session::natsServerAvailable()) GTEST_SKIP() << "no nats-server";
  session::NatsServerConfig config;
  config.sessionId = QStringLiteral("docks");
  session::LocalNatsServer server(config);
  QString error;
  ASSERT_TRUE(server.start(&error)) << error.toStdString();
  const QString secret = m_dir.filePath(QStringLiteral("viewer.pw"));
  {
    QFile file(secret);
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));
    file.write(config.viewerPassword.toUtf8() + '\n');
  }

  app::MainWindow window;
  showSessionWindow(window, {1000, 800});
  app::HostSettings settings = loopbackHostSettings(m_meshPath, 20);
  settings.relay = app::HostRelaySettings{server.url(), config.sessionId, config.hostUser, config.hostPassword, {}};
  app::HostController* host = hostAndWait(window, settings);
  ASSERT_EQ(host->state(), app::SessionController::State::Live) << host->errorText().toStdString();
  // The broker is connected on a thread of its own after the session is live.
  ASSERT_TRUE(QTest::qWaitFor([host] { return host->relay() != nullptr; }, 10000)) << "the relay did not start";
  ASSERT_TRUE(host->relayAudience().has_value());
  EXPECT_EQ(host->relayAudience()->viewers, 0);

  constexpr int kViewers = 3;
  std::vector<std::unique_ptr<QProcess>> viewers;
  for (int i = 0; i < kViewers; ++i) {
    auto viewer = std::make_unique<QProcess>();
    viewer->setProcessChannelMode(QProcess::ForwardedErrorChannel);
    viewer->start(
        QStringLiteral(SHAPECAST_CLI_EXE),
        {QStringLiteral("watch"), QStringLiteral("--nats"), server.url(), QStringLiteral("--session"), config.sessionId,
         QStringLiteral("--nats-user"), config.viewerUser, QStringLiteral("--nats-password-file"), secret,
         QStringLiteral("--pin"), session::formatFingerprint(host->hostFingerprint()), QStringLiteral("--seconds"),
         QStringLiteral("60")});
    ASSERT_TRUE(viewer->waitForStarted());
    viewers.push_back(std::move(viewer));
  }
  model::PeerTableModel* peers = window.docks()->peerModel();
  const auto audienceRow = [peers] { return peers->rowOfPeer(app::kRelayAudienceRowId); };
  // Viewers report every 2 s; the docks refresh once a second.
  const bool counted = QTest::qWaitFor(
      [&] {
        const int row = audienceRow();
        return row >= 0 && peers->peerAt(row).name == QStringLiteral("3 viewers through NATS");
      },
      30000);
  for (const auto& viewer : viewers) {
    viewer->terminate();
    viewer->waitForFinished(5000);
  }
  ASSERT_TRUE(counted) << "audience row: "
                       << (audienceRow() >= 0 ? peers->peerAt(audienceRow()).name.toStdString() : "none");
  EXPECT_EQ(peers->rowCount(), 2) << "the host and ONE row for every viewer";
  const int row = audienceRow();
  const model::PeerRow& aggregate = peers->peerAt(row);
  EXPECT_TRUE(aggregate.hasStats);
  EXPECT_EQ(peers->data(peers->index(row, model::PeerTableModel::Role)).toString(), QStringLiteral("viewers"));
  EXPECT_EQ(peers->data(peers->index(row, model::PeerTableModel::LossPct)).toString(), QStringLiteral("0.0"));
  const QString tip = peers->data(peers->index(row, model::PeerTableModel::LatencyMs), Qt::ToolTipRole).toString();
  EXPECT_TRUE(tip.contains(QStringLiteral("3 viewers"))) << tip.toStdString();
  EXPECT_TRUE(tip.contains(QStringLiteral("loss median 0.00 %"))) << tip.toStdString();
  EXPECT_TRUE(tip.contains(QStringLiteral("latency p99"))) << tip.toStdString();

  QLabel* section = window.docks()->statisticsDock()->relayAudienceLabel();
  EXPECT_TRUE(section->isVisibleTo(window.docks()->statisticsDock()));
  EXPECT_TRUE(section->text().startsWith(QStringLiteral("Relay: 3 viewers through NATS")))
      << section->text().toStdString();
  EXPECT_TRUE(section->text().contains(QStringLiteral("loss median"))) << section->text().toStdString();
}

}  // namespace
}  // namespace sc::testing
