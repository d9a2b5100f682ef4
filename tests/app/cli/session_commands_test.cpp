// End-to-end runs of the session subcommands as separate processes over real loopback sockets: host, join, drive
// and the loss experiment, the way two terminals on one machine would use them.

#include "cli_test_support.h"
#include "host_process.h"

#include <gtest/gtest.h>
#include <QDir>
#include <QDirIterator>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QProcessEnvironment>
#include <QRegularExpression>
#include <QTemporaryDir>
#include <QThread>

#include <map>
#include <memory>

namespace sc::testing {
namespace {

class SessionCommandsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(m_dir.isValid());
    m_mesh = m_dir.filePath(QStringLiteral("torus.off"));
    writeOff(m_mesh, torus(60, 24));
  }
  QString path(const char* name) const { return m_dir.filePath(QLatin1String(name)); }
  void writeFile(const QString& file, const QByteArray& bytes) const {
    QFile f(file);
    ASSERT_TRUE(f.open(QIODevice::WriteOnly));
    f.write(bytes);
  }

  QTemporaryDir m_dir;
  QString m_mesh;
};

TEST_F(SessionCommandsTest, HostJoinAndDriveInSeparateProcesses) {
  HostProcess host(m_mesh);
  ASSERT_NE(host.port(), 0) << "the host did not print its port";
  const QString stats = path("stats.json");
  QProcess join;
  join.start(QStringLiteral(SHAPECAST_CLI),
             {QStringLiteral("join"), host.address(), QStringLiteral("--name"), QStringLiteral("viewer"),
              QStringLiteral("--level"), QStringLiteral("300"), QStringLiteral("--seconds"), QStringLiteral("7"),
              QStringLiteral("--stats-json"), stats});
  ASSERT_TRUE(join.waitForStarted());
  QThread::msleep(1500);
  const QString script = path("drag.json");
  writeFile(script, R"({"handles":[{"sphere":{"vertex":0,"radius_pct":5}}],
                        "anchors":{"farther_than_pct":40,"from_vertex":0},
                        "frames":[{"t":0},{"t":1.5,"translate_pct":[0,10,0]},{"t":3}]})");
  const CliRun drive =
      runCli({QStringLiteral("drive"), host.address(), QStringLiteral("--script"), script, QStringLiteral("--json")});
  EXPECT_EQ(drive.exitCode, 0) << drive.err.toStdString();
  const QJsonObject driven = QJsonDocument::fromJson(drive.out.trimmed()).object();
  EXPECT_EQ(driven[QStringLiteral("frames_sent")].toInt(), 91);
  EXPECT_TRUE(driven[QStringLiteral("complete")].toBool());

  ASSERT_TRUE(join.waitForFinished(30000));
  EXPECT_EQ(join.exitCode(), 0) << join.readAllStandardError().toStdString();
  QFile file(stats);
  ASSERT_TRUE(file.open(QIODevice::ReadOnly));
  const QJsonObject s = QJsonDocument::fromJson(file.readAll()).object();
  for (const char* key : {"frames_applied", "loss_fraction", "hd_max_pct", "hd_mean_pct", "kbps_in", "latency_p99_ms"})
    EXPECT_TRUE(s.contains(QLatin1String(key))) << key;
  // The drag's 91 frames and slow refreshes; on a busy machine the host merges drags that arrive less than 8 ms
  // apart (see LossExperimentPrintsRowsAndAPlot), so half the drag is the bound.
  EXPECT_GE(s[QStringLiteral("frames_applied")].toInteger(), 45);
  EXPECT_EQ(s[QStringLiteral("loss_fraction")].toDouble(), 0.0);  // loopback, no simulated loss
  EXPECT_GT(s[QStringLiteral("hd_samples")].toInteger(), 0);
  EXPECT_LT(s[QStringLiteral("hd_max_pct")].toDouble(), 0.05);  // quantisation only
  EXPECT_GT(s[QStringLiteral("latency_p99_ms")].toDouble(), 0.0);
  EXPECT_LE(s[QStringLiteral("level_vertices")].toInteger(), 720);  // a decimated level, not the full 1440

  const QString log = QString::fromUtf8(host.stop());
  EXPECT_TRUE(log.contains(QStringLiteral("viewer joined"))) << log.toStdString();
  EXPECT_TRUE(log.contains(QStringLiteral("lock: held by driver"))) << log.toStdString();
  EXPECT_EQ(host.exitCode(), 0);
}

TEST_F(SessionCommandsTest, WrongPasswordIsRefusedWithItsReason) {
  writeFile(path("secret"), "correct horse\n");
  writeFile(path("wrong"), "battery staple\n");
  HostProcess host(m_mesh, {QStringLiteral("--password-file"), path("secret")});
  ASSERT_NE(host.port(), 0);
  const CliRun wrong = runCli({QStringLiteral("join"), host.address(), QStringLiteral("--password-file"), path("wrong"),
                               QStringLiteral("--seconds"), QStringLiteral("1")});
  EXPECT_EQ(wrong.exitCode, 4);
  EXPECT_TRUE(wrong.err.contains("password")) << wrong.err.toStdString();
  const CliRun right = runCli({QStringLiteral("join"), host.address(), QStringLiteral("--password-file"),
                               path("secret"), QStringLiteral("--seconds"), QStringLiteral("1")});
  EXPECT_EQ(right.exitCode, 0) << right.err.toStdString();
}

// Issue 14, item 4: `drive` trusts the host the way `join` does. A known-hosts entry (written by a first `join`
// with the same home folder) that names another certificate makes `drive` refuse before its password proof: the
// host never sees the driver, neither joined nor refused for a wrong password.
TEST_F(SessionCommandsTest, DriveRefusesAChangedCertificateAndSendsNoProof) {
  writeFile(path("secret"), "correct horse\n");
  HostProcess host(m_mesh, {QStringLiteral("--password-file"), path("secret")});
  ASSERT_NE(host.port(), 0);
  QProcessEnvironment home = QProcessEnvironment::systemEnvironment();
  home.insert(QStringLiteral("XDG_CONFIG_HOME"), path("config"));
  const CliRun first = runCli({QStringLiteral("join"), host.address(), QStringLiteral("--password-file"),
                               path("secret"), QStringLiteral("--seconds"), QStringLiteral("1")},
                              {}, home);
  ASSERT_EQ(first.exitCode, 0) << first.err.toStdString();
  // The entry the first join remembered, changed to another fingerprint (an impostor's certificate).
  QDirIterator files(path("config"), {QStringLiteral("*.conf")}, QDir::Files, QDirIterator::Subdirectories);
  ASSERT_TRUE(files.hasNext()) << "join remembered no fingerprint";
  const QString store = files.next();
  QFile in(store);
  ASSERT_TRUE(in.open(QIODevice::ReadOnly));
  const QByteArray known = in.readAll();
  in.close();
  const QRegularExpression entry(QStringLiteral("=([0-9A-F]{2}(:[0-9A-F]{2}){31})"));
  const QRegularExpressionMatch match = entry.match(QString::fromLatin1(known));
  ASSERT_TRUE(match.hasMatch()) << known.toStdString();
  const QString impostor = QStringLiteral("AB:").repeated(31) + QStringLiteral("AB");
  ASSERT_NE(match.captured(1), impostor);
  writeFile(store, QString::fromLatin1(known).replace(match.captured(1), impostor).toLatin1());

  const QString script = path("drag.json");
  writeFile(script, R"({"handles":[{"sphere":{"vertex":0,"radius_pct":5}}],
                        "anchors":{"farther_than_pct":40,"from_vertex":0},
                        "frames":[{"t":0},{"t":0.1,"translate_pct":[0,10,0]}]})");
  const CliRun drive =
      runCli({QStringLiteral("drive"), host.address(), QStringLiteral("--script"), script, QStringLiteral("--name"),
              QStringLiteral("intruded"), QStringLiteral("--password-file"), path("secret")},
             {}, home);
  EXPECT_EQ(drive.exitCode, 4) << drive.err.toStdString();
  EXPECT_TRUE(drive.err.contains("fingerprint changed")) << drive.err.toStdString();
  const QString log = QString::fromUtf8(host.stop());
  EXPECT_FALSE(log.contains(QStringLiteral("intruded"))) << log.toStdString();  // no proof reached the host
  EXPECT_FALSE(log.contains(QStringLiteral("lock: held"))) << log.toStdString();
}

TEST_F(SessionCommandsTest, BadAddressesAreUsageErrors) {
  EXPECT_EQ(runCli({QStringLiteral("join"), QStringLiteral("localhost")}).exitCode, 2);
  EXPECT_EQ(runCli({QStringLiteral("join"), QStringLiteral("localhost:99999")}).exitCode, 2);
  EXPECT_EQ(runCli({QStringLiteral("drive"), QStringLiteral("127.0.0.1:1")}).exitCode, 2);  // no --script
  const CliRun nobody =
      runCli({QStringLiteral("join"), QStringLiteral("127.0.0.1:1"), QStringLiteral("--seconds"), QStringLiteral("1")});
  EXPECT_EQ(nobody.exitCode, 4) << nobody.err.toStdString();  // connection refused: a network error, not a crash
}

TEST_F(SessionCommandsTest, JoinExperimentWaitsForTheLinkRate) {
  // Issue 17: a host process and a client over a 2 Mbit/s emulated link. The level (about 90 kB compressed) cannot
  // arrive sooner than the bytes beyond the bucket's 32 KiB burst take at 2 Mbit/s.
  const CliRun run =
      runCli({QStringLiteral("experiment"), QStringLiteral("join"), QStringLiteral("--mesh"), m_mesh,
              QStringLiteral("--rate-mbit"), QStringLiteral("2"), QStringLiteral("--delay-ms"), QStringLiteral("20"),
              QStringLiteral("--json"), QStringLiteral("--no-cache"), QStringLiteral("--m"), QStringLiteral("30")});
  ASSERT_EQ(run.exitCode, 0) << run.err.toStdString();
  const QJsonObject r = QJsonDocument::fromJson(run.out.trimmed()).object();
  for (const char* key : {"bytes_received", "first_frame_s", "level_ready_s", "peak_rss_mb", "stream_bytes"})
    EXPECT_TRUE(r.contains(QLatin1String(key))) << key;
  EXPECT_EQ(r[QStringLiteral("level_vertices")].toInt(), 1440);
  const double stream = r[QStringLiteral("stream_bytes")].toDouble();
  EXPECT_GT(stream, 2 * 32768.0);  // well past the bucket's burst: the rate, not the burst, decides the time
  EXPECT_GE(r[QStringLiteral("bytes_received")].toDouble(), stream);
  EXPECT_GE(r[QStringLiteral("level_ready_s")].toDouble(), (stream - 32768.0) * 8.0 / 2e6);
  // Progressive join (issue 17 item 4): the host's smallest level first, the deformed frames on it, then the
  // requested full level.
  EXPECT_TRUE(r[QStringLiteral("progressive")].toBool());
  EXPECT_LT(r[QStringLiteral("first_level_vertices")].toInt(), 1440);
  EXPECT_GT(r[QStringLiteral("first_level_vertices")].toInt(), 0);
  EXPECT_GE(r[QStringLiteral("first_frame_s")].toDouble(), r[QStringLiteral("first_level_s")].toDouble());
  EXPECT_LT(r[QStringLiteral("first_level_s")].toDouble(), r[QStringLiteral("level_ready_s")].toDouble());
  EXPECT_GT(r[QStringLiteral("peak_rss_mb")].toDouble(), 0.0);
}

TEST_F(SessionCommandsTest, JoinPlotDrawsOneLinePerMeshFromJoinResults) {
  // Issue 17 item 5: the join figures against the link rate, from `join --json` objects (one per file).
  const auto result = [](const char* mesh, double rate, double first, double ready) {
    return QJsonDocument(QJsonObject{{QStringLiteral("mesh"), QLatin1String(mesh)},
                                     {QStringLiteral("rate_mbit"), rate},
                                     {QStringLiteral("first_frame_s"), first},
                                     {QStringLiteral("level_ready_s"), ready},
                                     {QStringLiteral("bytes_received"), 3e6}})
        .toJson();
  };
  writeFile(path("a.json"), result("/m/small.ply", 1.0, 1.6, 29.4));
  writeFile(path("b.json"), result("/m/small.ply", 20.0, 0.15, 2.1));
  writeFile(path("c.json"), result("/m/large.ply", 20.0, 0.33, 7.1));
  const QString plot = path("join.png");
  const CliRun run = runLab({QStringLiteral("join-plot"), plot, path("a.json"), path("b.json"), path("c.json")});
  ASSERT_EQ(run.exitCode, 0) << run.err.toStdString();
  EXPECT_TRUE(run.out.contains("plotted 3 results of 2 meshes")) << run.out.toStdString();
  QFile png(plot);
  ASSERT_TRUE(png.open(QIODevice::ReadOnly));
  const QByteArray header = png.read(24);  // the signature, then IHDR: width and height, big-endian
  ASSERT_EQ(header.size(), 24);
  ASSERT_TRUE(header.startsWith("\x89PNG"));
  const auto bigEndian = [&header](int at) {
    return (static_cast<quint32>(static_cast<quint8>(header[at])) << 24) |
           (static_cast<quint32>(static_cast<quint8>(header[at + 1])) << 16) |
           (static_cast<quint32>(static_cast<quint8>(header[at + 2])) << 8) |
           static_cast<quint32>(static_cast<quint8>(header[at + 3]));
  };
  EXPECT_EQ(bigEndian(16), 3u * 420u);  // three panels: first frame, level ready, bytes
  EXPECT_EQ(bigEndian(20), 360u);
  writeFile(path("bad.json"), "[1, 2]");
  EXPECT_EQ(runLab({QStringLiteral("join-plot"), plot, path("bad.json")}).exitCode, 2);
  EXPECT_EQ(runLab({QStringLiteral("join-plot"), plot, path("missing.json")}).exitCode, 2);
}

TEST_F(SessionCommandsTest, JoinRefusesABadRateOrDelay) {
  EXPECT_EQ(runCli({QStringLiteral("join"), QStringLiteral("127.0.0.1:1"), QStringLiteral("--rate-mbit"),
                    QStringLiteral("-1")})
                .exitCode,
            2);
  EXPECT_EQ(runCli({QStringLiteral("join"), QStringLiteral("127.0.0.1:1"), QStringLiteral("--delay-ms"),
                    QStringLiteral("soon")})
                .exitCode,
            2);
}

TEST_F(SessionCommandsTest, LossExperimentPrintsRowsAndAPlot) {
  const QString plot = path("loss.png");
  const CliRun run = runCli({QStringLiteral("experiment"), QStringLiteral("loss"), QStringLiteral("--mesh"), m_mesh,
                             QStringLiteral("--loss"), QStringLiteral("0,0.3"), QStringLiteral("--json"),
                             QStringLiteral("--markdown"), QString(), QStringLiteral("--plot"), plot,
                             QStringLiteral("--no-cache"), QStringLiteral("--m"), QStringLiteral("30")});
  ASSERT_EQ(run.exitCode, 0) << run.err.toStdString();
  const QJsonArray rows = QJsonDocument::fromJson(run.out.trimmed()).object()[QStringLiteral("rows")].toArray();
  ASSERT_EQ(rows.size(), 12);  // 2 ratios × {full, low} × {hold-last, zero-fill, extrapolate}
  std::map<QString, double> meanByConcealment;
  for (const QJsonValue& value : rows) {
    const QJsonObject row = value.toObject();
    for (const char* key : {"loss", "concealment", "level", "measured_loss", "hd_max_pct", "hd_max_frame",
                            "hd_mean_pct", "payload_bytes_per_frame", "latency_p99_ms"})
      EXPECT_TRUE(row.contains(QLatin1String(key))) << key;
    // The drag has 181 frames at 30 fps. When the machine is busy the driver's timer fires late and then sends the
    // overdue poses at once; the host merges drags less than 8 ms apart into one frame (SessionHostOptions::coalesce),
    // so a loaded run measures fewer frames (182-240 seen with two runs side by side, including still frames). Half
    // the drag is still a measured drag, not an empty row.
    EXPECT_GE(row[QStringLiteral("frames")].toInt(), 90) << row[QStringLiteral("concealment")].toString().toStdString();
    EXPECT_LE(row[QStringLiteral("payload_bytes_per_frame")].toDouble(), 800.0);
    if (row[QStringLiteral("loss")].toDouble() == 0.0) {
      EXPECT_EQ(row[QStringLiteral("measured_loss")].toDouble(), 0.0);
    } else {
      EXPECT_NEAR(row[QStringLiteral("measured_loss")].toDouble(), 0.3, 0.1);
      meanByConcealment[row[QStringLiteral("concealment")].toString()] += row[QStringLiteral("hd_mean_pct")].toDouble();
    }
  }
  ASSERT_EQ(meanByConcealment.size(), 3u);
  EXPECT_TRUE(meanByConcealment.contains(QStringLiteral("extrapolate")));
  EXPECT_LT(meanByConcealment[QStringLiteral("hold-last")], meanByConcealment[QStringLiteral("zero-fill")]);
  EXPECT_TRUE(QFile::exists(plot));
}

}  // namespace
}  // namespace sc::testing
