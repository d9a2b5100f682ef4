// End-to-end run of the relay (issue 18) as separate processes, the way a lecture would use it: a local nats-server
// (LocalNatsServer, stopped by its PID), `shapecast-cli host … --nats`, a `watch` viewer and a `drive` editor. Also
// the watch command's usage and connection errors.
#include "cli_test_support.h"
#include "host_process.h"
#include "session/net/local_nats_server.h"

#include <gtest/gtest.h>
#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QTemporaryDir>
#include <QThread>

#include <cmath>

namespace sc::testing {
namespace {

class RelayCommandsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!session::natsServerAvailable()) GTEST_SKIP() << "nats-server is not installed";
    ASSERT_TRUE(m_dir.isValid());
    m_mesh = m_dir.filePath(QStringLiteral("torus.off"));
    writeOff(m_mesh, torus(60, 24));
    QString error;
    ASSERT_TRUE(m_server.start(&error)) << error.toStdString();
    write(path("host.pw"), m_server.config().hostPassword.toUtf8() + '\n');
    write(path("viewer.pw"), m_server.config().viewerPassword.toUtf8() + '\n');
  }
  QString path(const char* name) const { return m_dir.filePath(QLatin1String(name)); }
  static void write(const QString& file, const QByteArray& bytes) {
    QFile f(file);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    f.write(bytes);
  }
  QStringList relay(const char* user, const char* passwordFile) const {
    return {QStringLiteral("--nats"),
            m_server.url(),
            QStringLiteral("--session"),
            m_server.config().sessionId,
            QStringLiteral("--nats-user"),
            QLatin1String(user),
            QStringLiteral("--nats-password-file"),
            path(passwordFile)};
  }

  QTemporaryDir m_dir;
  QString m_mesh;
  session::LocalNatsServer m_server;
};

TEST_F(RelayCommandsTest, AViewerWatchesWhatTheEditorDragsThroughTheServer) {
  HostProcess host(m_mesh, relay("host", "host.pw"));
  ASSERT_NE(host.port(), 0) << "the host did not print its port";
  QThread::msleep(1000);  // the relay starts right after the port line
  QProcess watch;
  watch.start(QStringLiteral(SHAPECAST_CLI),
              QStringList{QStringLiteral("watch")} + relay("viewer", "viewer.pw") +
                  QStringList{QStringLiteral("--seconds"), QStringLiteral("7"), QStringLiteral("--json")});
  ASSERT_TRUE(watch.waitForStarted());
  QThread::msleep(1500);
  write(path("drag.json"), R"({"handles":[{"sphere":{"vertex":0,"radius_pct":5}}],
                               "anchors":{"farther_than_pct":40,"from_vertex":0},
                               "frames":[{"t":0},{"t":1.5,"translate_pct":[0,10,0]},{"t":3}]})");
  const CliRun drive = runCli({QStringLiteral("drive"), host.address(), QStringLiteral("--script"), path("drag.json")});
  EXPECT_EQ(drive.exitCode, 0) << drive.err.toStdString();
  ASSERT_TRUE(watch.waitForFinished(30000));
  EXPECT_EQ(watch.exitCode(), 0) << watch.readAllStandardError().toStdString();
  const QJsonObject s = QJsonDocument::fromJson(watch.readAllStandardOutput().trimmed()).object();
  // The drag's 91 frames; the host merges drags that arrive less than 8 ms apart on a busy machine: half is the bound.
  EXPECT_GE(s[QStringLiteral("applied")].toInteger(), 45);
  EXPECT_EQ(s[QStringLiteral("lost")].toInteger(), 0);
  EXPECT_EQ(s[QStringLiteral("bad_signature")].toInteger(), 0);
  EXPECT_GT(s[QStringLiteral("latency_p99_ms")].toDouble(), 0.0);
  const QString log = QString::fromUtf8(host.stop());
  EXPECT_TRUE(log.contains(QStringLiteral("relaying session test"))) << log.toStdString();
  EXPECT_TRUE(log.contains(QStringLiteral("relay: "))) << log.toStdString();
}

TEST_F(RelayCommandsTest, AViewerFetchesItsLevelFromTheStreamAndShowsTheDeformedShape) {
  HostProcess host(m_mesh, relay("host", "host.pw"));
  ASSERT_NE(host.port(), 0) << "the host did not print its port";
  QThread::msleep(1000);  // the relay starts right after the port line
  write(path("drag.json"), R"({"handles":[{"sphere":{"vertex":0,"radius_pct":8}}],
                               "anchors":{"farther_than_pct":40,"from_vertex":0},
                               "frames":[{"t":0},{"t":1.0,"translate_pct":[0,15,0]},{"t":1.5,"translate_pct":[0,15,0]}]})");
  const CliRun drive = runCli({QStringLiteral("drive"), host.address(), QStringLiteral("--script"), path("drag.json")});
  EXPECT_EQ(drive.exitCode, 0) << drive.err.toStdString();
  // A late viewer: the drag is over; it starts from the keyframe and fetches the full level (0) from the stream.
  // The host stores the keyframe 200 ms after the last frame: a viewer joining sooner starts from the previous one
  // (every 30 frames) and shows it until the next frame (measured: 2.5 % distortion here). Wait past that.
  QThread::msleep(400);
  const CliRun full = runCli(QStringList{QStringLiteral("watch")} + relay("viewer", "viewer.pw") +
                             QStringList{QStringLiteral("--level"), QStringLiteral("0"), QStringLiteral("--seconds"),
                                         QStringLiteral("4"), QStringLiteral("--json")});
  ASSERT_EQ(full.exitCode, 0) << full.err.toStdString();
  const QJsonObject f = QJsonDocument::fromJson(full.out.trimmed()).object();
  EXPECT_EQ(f[QStringLiteral("level")].toInteger(), 0);
  EXPECT_EQ(f[QStringLiteral("level_vertices")].toInteger(), 60 * 24);
  EXPECT_GE(f[QStringLiteral("level_chunks")].toInteger(), 1);
  EXPECT_GT(f[QStringLiteral("level_bytes")].toInteger(), 0);
  // At rest the torus is symmetric about the origin: its coordinates sum to about 0. The drag moved a cap of
  // vertices by 15% of the diagonal (≈ 0.56) along y: the sum grows by about that times the cap's vertex count.
  EXPECT_GT(std::abs(f[QStringLiteral("shape_checksum")].toDouble()), 1.0) << full.out.toStdString();
  // With its level the viewer reads the stored keyframe back as an exact reference: it shows that very frame, so
  // the distortion is 0 (nothing missed), and nothing was predicted (hold-last).
  EXPECT_EQ(f[QStringLiteral("concealment")].toString(), QStringLiteral("hold-last"));
  EXPECT_GE(f[QStringLiteral("references")].toInteger(), 1) << full.out.toStdString();
  EXPECT_GE(f[QStringLiteral("distortion_count")].toInteger(), 1) << full.out.toStdString();
  EXPECT_EQ(f[QStringLiteral("distortion_max_pct")].toDouble(), 0.0) << full.out.toStdString();
  EXPECT_EQ(f[QStringLiteral("predicted")].toInteger(), 0);
  // A coarser level (the last of the ladder) has fewer vertices; an unlisted one is refused with a reason.
  const CliRun coarse = runCli(QStringList{QStringLiteral("watch")} + relay("viewer", "viewer.pw") +
                               QStringList{QStringLiteral("--level"), QStringLiteral("3"), QStringLiteral("--seconds"),
                                           QStringLiteral("3"), QStringLiteral("--json"),
                                           QStringLiteral("--concealment"), QStringLiteral("extrapolate")});
  ASSERT_EQ(coarse.exitCode, 0) << coarse.err.toStdString();
  const QJsonObject c = QJsonDocument::fromJson(coarse.out.trimmed()).object();
  EXPECT_GT(c[QStringLiteral("level_vertices")].toInteger(), 0);
  EXPECT_LT(c[QStringLiteral("level_vertices")].toInteger(), 60 * 24 / 5);
  EXPECT_EQ(c[QStringLiteral("concealment")].toString(), QStringLiteral("extrapolate"));
  const CliRun unlisted =
      runCli(QStringList{QStringLiteral("watch")} + relay("viewer", "viewer.pw") +
             QStringList{QStringLiteral("--level"), QStringLiteral("9"), QStringLiteral("--seconds"),
                         QStringLiteral("3"), QStringLiteral("--json")});
  EXPECT_EQ(unlisted.exitCode, 4);
  EXPECT_TRUE(unlisted.err.contains("not published")) << unlisted.err.toStdString();
  host.stop();
}

TEST_F(RelayCommandsTest, WatchErrorsHaveExitCodesAndMessages) {
  const CliRun noServer = runCli({QStringLiteral("watch"), QStringLiteral("--session"), QStringLiteral("x")});
  EXPECT_EQ(noServer.exitCode, 2);
  EXPECT_TRUE(noServer.err.contains("--nats")) << noServer.err.toStdString();
  const CliRun badSession = runCli({QStringLiteral("watch"), QStringLiteral("--nats"), m_server.url(),
                                    QStringLiteral("--session"), QStringLiteral("a.b")});
  EXPECT_EQ(badSession.exitCode, 2);
  const CliRun badConcealment =
      runCli({QStringLiteral("watch"), QStringLiteral("--nats"), m_server.url(), QStringLiteral("--session"),
              QStringLiteral("x"), QStringLiteral("--concealment"), QStringLiteral("zero-fill")});
  EXPECT_EQ(badConcealment.exitCode, 2);
  EXPECT_TRUE(badConcealment.err.contains("--concealment")) << badConcealment.err.toStdString();
  write(path("wrong.pw"), "not-the-password\n");
  const CliRun wrongPassword = runCli(QStringList{QStringLiteral("watch")} + relay("viewer", "wrong.pw"));
  EXPECT_EQ(wrongPassword.exitCode, 4);
  EXPECT_TRUE(wrongPassword.err.contains("NATS")) << wrongPassword.err.toStdString();
  const CliRun noSession = runCli(QStringList{QStringLiteral("watch")} + relay("viewer", "viewer.pw"));
  EXPECT_EQ(noSession.exitCode, 4);  // no host published this session yet
  EXPECT_TRUE(noSession.err.contains("no session")) << noSession.err.toStdString();
  const CliRun badUrl = runCli({QStringLiteral("watch"), QStringLiteral("--nats"), QStringLiteral("127.0.0.1:4222"),
                                QStringLiteral("--session"), QStringLiteral("x")});
  EXPECT_EQ(badUrl.exitCode, 2);
  EXPECT_TRUE(badUrl.err.contains("--nats: The NATS URL")) << badUrl.err.toStdString();
}

TEST_F(RelayCommandsTest, HostAndWatchRelayOverTlsTrustingTheBrokersCa) {
  // TLS to the broker: a server that requires TLS, its certificate signed by a generated CA; --nats-ca trusts it.
  session::LocalNatsServer tls;
  tls.setTls(session::NatsServerTls::CaSigned);
  QString error;
  ASSERT_TRUE(tls.start(&error)) << error.toStdString();
  const auto relayTls = [&](const char* user, const char* passwordFile) {
    return QStringList{QStringLiteral("--nats"),
                       tls.url(),
                       QStringLiteral("--session"),
                       tls.config().sessionId,
                       QStringLiteral("--nats-user"),
                       QLatin1String(user),
                       QStringLiteral("--nats-password-file"),
                       path(passwordFile)};
  };
  const QStringList ca{QStringLiteral("--nats-ca"), tls.caFile()};
  HostProcess host(m_mesh, relayTls("host", "host.pw") + ca);
  ASSERT_NE(host.port(), 0) << "the host did not print its port";
  QThread::msleep(1000);  // the relay starts right after the port line
  write(path("drag.json"), R"({"handles":[{"sphere":{"vertex":0,"radius_pct":5}}],
                               "anchors":{"farther_than_pct":40,"from_vertex":0},
                               "frames":[{"t":0},{"t":2,"translate_pct":[0,10,0]},{"t":3}]})");
  QProcess watch;
  watch.start(QStringLiteral(SHAPECAST_CLI),
              QStringList{QStringLiteral("watch")} + relayTls("viewer", "viewer.pw") + ca +
                  QStringList{QStringLiteral("--frames"), QStringLiteral("5"), QStringLiteral("--seconds"),
                              QStringLiteral("30"), QStringLiteral("--json")});
  ASSERT_TRUE(watch.waitForStarted());
  QThread::msleep(1000);
  const CliRun drive = runCli({QStringLiteral("drive"), host.address(), QStringLiteral("--script"), path("drag.json")});
  EXPECT_EQ(drive.exitCode, 0) << drive.err.toStdString();
  ASSERT_TRUE(watch.waitForFinished(30000));
  EXPECT_EQ(watch.exitCode(), 0) << watch.readAllStandardError().toStdString();
  const QJsonObject s = QJsonDocument::fromJson(watch.readAllStandardOutput().trimmed()).object();
  EXPECT_GE(s[QStringLiteral("applied")].toInteger(), 5);
  EXPECT_EQ(s[QStringLiteral("bad_signature")].toInteger(), 0);

  // Without --nats-ca the system's CAs do not know the broker's: refused, and the message says TLS.
  const CliRun untrusted = runCli(QStringList{QStringLiteral("watch")} + relayTls("viewer", "viewer.pw"));
  EXPECT_EQ(untrusted.exitCode, 4);
  EXPECT_TRUE(untrusted.err.contains("TLS to the NATS server")) << untrusted.err.toStdString();
  const CliRun missingCa = runCli(QStringList{QStringLiteral("watch")} + relayTls("viewer", "viewer.pw") +
                                  QStringList{QStringLiteral("--nats-ca"), path("none.pem")});
  EXPECT_EQ(missingCa.exitCode, 2);
  EXPECT_TRUE(missingCa.err.contains("--nats-ca")) << missingCa.err.toStdString();
  host.stop();
}

TEST(FanoutExperiment, EveryViewerSharingProcessesGetsFramesAndTheHostCountsWhatItPublished) {
  // Issue 18 item 5, a short run: a host child relaying a 2 s drag through its own local nats-server to 4 viewers in
  // 2 processes (2 each, one NATS connection per viewer).
  if (!session::natsServerAvailable()) GTEST_SKIP() << "nats-server is not installed";
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  const QString mesh = dir.filePath(QStringLiteral("torus.off"));
  writeOff(mesh, torus(60, 24));
  const CliRun run = runLab({QStringLiteral("fanout"), QStringLiteral("--mesh"), mesh, QStringLiteral("--viewers"),
                             QStringLiteral("4"), QStringLiteral("--viewers-per-process"), QStringLiteral("2"),
                             QStringLiteral("--seconds"), QStringLiteral("2"), QStringLiteral("--json"),
                             QStringLiteral("--no-cache"), QStringLiteral("--m"), QStringLiteral("30")});
  ASSERT_EQ(run.exitCode, 0) << run.err.toStdString();
  const QJsonObject r = QJsonDocument::fromJson(run.out.trimmed()).object();
  for (const char* key : {"viewers", "processes", "min_delivered_fraction", "latency_p50_ms", "latency_p99_ms",
                          "host_cpu_pct", "host_upload_bytes_per_frame", "server_cpu_pct", "frames_published",
                          "viewer_threads", "load_average", "machine"})
    EXPECT_TRUE(r.contains(QLatin1String(key))) << key;
  EXPECT_EQ(r[QStringLiteral("viewers")].toInt(), 4);
  EXPECT_EQ(r[QStringLiteral("processes")].toInt(), 2);
  EXPECT_GT(r[QStringLiteral("frames_published")].toInt(), 20);  // 2 s at 30 fps, a loaded machine's timer aside
  EXPECT_GT(r[QStringLiteral("min_delivered_fraction")].toDouble(), 0.0) << "a viewer got no frame";
  EXPECT_LE(r[QStringLiteral("min_delivered_fraction")].toDouble(), 1.0);
  EXPECT_EQ(r[QStringLiteral("bad_signature")].toInt(), 0);
  // One signed frame carries 30 × 3 doubles: what the host published per frame is at least that, whatever N.
  EXPECT_GE(r[QStringLiteral("host_payload_bytes_per_frame")].toDouble(), 30 * 3 * 8.0);
  EXPECT_GE(r[QStringLiteral("host_upload_bytes_per_frame")].toDouble(),
            r[QStringLiteral("host_payload_bytes_per_frame")].toDouble());
  EXPECT_GT(r[QStringLiteral("latency_p99_ms")].toDouble(), 0.0);
  EXPECT_GE(r[QStringLiteral("latency_p99_ms")].toDouble(), r[QStringLiteral("latency_p50_ms")].toDouble());
  EXPECT_GT(r[QStringLiteral("host_cpu_pct")].toDouble(), 0.0);
  EXPECT_GT(r[QStringLiteral("viewer_threads")].toInt(), 2);
}

}  // namespace
}  // namespace sc::testing
