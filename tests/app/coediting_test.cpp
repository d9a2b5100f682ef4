// Several people drag at once (issue 15, item 2), seen from the windows over real loopback sockets: a hosting
// MainWindow and a watching one in this process, and two `shapecast-cli drive` processes that each take a lease and
// drag their own handle of the torus at the same time (one end up, the other down, over the same anchors). The host
// and the watcher must show both ends moved, and the same shape.

#include "app/gui/host_controller.h"
#include "app/gui/main_window.h"
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

  // The torus lies around the z axis: its east end (largest x) goes up, its west end (smallest x) down, while its
  // south side (y below −0.6 of the largest y) is held by both.
  const Eigen::MatrixXd& V = m_mesh.V;
  Eigen::Index east = 0, west = 0;
  V.col(0).maxCoeff(&east);
  V.col(0).minCoeff(&west);
  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  std::vector<int> anchors, eastEnd, westEnd;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if (V(i, 1) < -0.6 * V.col(1).maxCoeff()) anchors.push_back(static_cast<int>(i));
    if ((V.row(i) - V.row(east)).norm() <= 0.08 * diagonal) eastEnd.push_back(static_cast<int>(i));
    if ((V.row(i) - V.row(west)).norm() <= 0.08 * diagonal) westEnd.push_back(static_cast<int>(i));
  }
  const quint16 port = live.host->tcpPort();
  const QByteArray fingerprint = live.host->hostFingerprint();
  const auto up = drive(QStringLiteral("erin"), writeScript(QStringLiteral("up"), static_cast<int>(east), 10, anchors),
                        port, fingerprint);
  const auto down = drive(QStringLiteral("finn"),
                          writeScript(QStringLiteral("down"), static_cast<int>(west), -10, anchors), port, fingerprint);

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

}  // namespace
}  // namespace sc::app
