// Issue 18: the Host… dialog's "Relay viewers through NATS" group. Its values are checked by the command line's rule
// (checkHostRelaySettings) with readable words, remembered in QSettings without the password, and hosting from the
// dialog relays exactly as `shapecast --host … --nats …` does: a real nats-server (LocalNatsServer), the window's
// Session → Host… action filled as a user would, a `shapecast-cli watch` child that receives the frames of a
// `shapecast-cli drive` drag. Wrong credentials leave the editors' session hosting, without the relay, and say why.
#include "app/gui/host_controller.h"
#include "app/gui/host_dialog.h"
#include "app/gui/main_window.h"
#include "session/net/local_nats_server.h"
#include "session/net/relay_publisher.h"
#include "session/net/tls_identity.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QElapsedTimer>
#include <QFile>
#include <QGroupBox>
#include <QLineEdit>
#include <QProcess>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QSpinBox>
#include <QTcpServer>
#include <QTest>
#include <QTimer>

#include <algorithm>
#include <functional>

namespace sc::app {
namespace {

using State = SessionController::State;

/// What a user types into the relay group (the session id is left as the dialog made it when `sessionId` is empty).
struct RelayTyping {
  QString url;
  QString sessionId;
  QString user;
  QString password;
};

template <typename T>
T* field(QWidget& dialog, const char* name) {
  T* widget = dialog.findChild<T*>(QString::fromLatin1(name));
  EXPECT_NE(widget, nullptr) << name;
  return widget;
}

/// Fills the dialog as a user would: the mesh, port 0 (any), m = 20, then checks the relay group and types into it.
void fill(HostDialog& dialog, const QString& meshPath, const RelayTyping& relay) {
  field<QComboBox>(dialog, "meshPathCombo")->setEditText(meshPath);
  field<QSpinBox>(dialog, "portSpin")->setValue(0);
  field<QSpinBox>(dialog, "frequenciesSpin")->setValue(20);
  field<QGroupBox>(dialog, "relayGroup")->setChecked(true);
  const auto type = [&dialog](const char* name, const QString& text) {
    QLineEdit* edit = field<QLineEdit>(dialog, name);
    edit->clear();
    QTest::keyClicks(edit, text);
  };
  type("natsUrlEdit", relay.url);
  if (!relay.sessionId.isEmpty()) type("relaySessionEdit", relay.sessionId);
  type("natsUserEdit", relay.user);
  type("natsPasswordEdit", relay.password);
}

void clickOk(HostDialog& dialog) {
  field<QDialogButtonBox>(dialog, "buttonBox")->button(QDialogButtonBox::Ok)->click();
}

class HostDialogRelay : public testing::TorusSessionTest {
 protected:
  void SetUp() override {
    TorusSessionTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    QSettings().remove(QStringLiteral("sessions"));  // nothing remembered from another test
  }
  void TearDown() override {
    QSettings().remove(QStringLiteral("sessions"));  // no relay left checked for the next test's Host… dialog
    TorusSessionTest::TearDown();
  }

  /// Triggers the window's Session → Host… action, fills the modal dialog with `typing` (and what `also` does) and
  /// clicks OK. Returns the generated session id the dialog showed.
  QString hostFromTheDialog(MainWindow& window, const RelayTyping& typing,
                            const std::function<void(HostDialog&)>& also = {}) {
    QString generated;
    QTimer::singleShot(0, &window, [&] {
      auto* dialog = qobject_cast<HostDialog*>(QApplication::activeModalWidget());
      ASSERT_NE(dialog, nullptr) << "no Host dialog";
      generated = field<QLineEdit>(*dialog, "relaySessionEdit")->text();
      fill(*dialog, m_meshPath, typing);
      if (also) also(*dialog);
      clickOk(*dialog);
      if (dialog->isVisible()) dialog->reject();  // refused: the test fails below
    });
    QAction* host = window.findChild<QAction*>(QStringLiteral("actionHostSession"));
    EXPECT_NE(host, nullptr);
    if (host) host->trigger();
    return generated;
  }

  /// Shows `window`, hosts the torus from its Host… dialog relaying through `server` as its host user with
  /// `password`, and waits until the preparation has ended. Returns the host; nullptr (a test failure) when the
  /// dialog did not host. A QSignalSpy on `window` made before the call sees every failure it reports.
  HostController* hostThroughTheDialog(MainWindow& window, const session::LocalNatsServer& server,
                                       const QString& password) {
    testing::showSessionWindow(window, {900, 700});
    window.setErrorDialogsEnabled(false);
    hostFromTheDialog(window, {server.url(), server.config().sessionId, server.config().hostUser, password});
    auto* host = qobject_cast<HostController*>(window.session());
    EXPECT_NE(host, nullptr) << "the dialog did not host";
    if (host == nullptr) return nullptr;
    EXPECT_TRUE(QTest::qWaitFor([host] { return host->state() != State::Preparing; }, 60000));
    return host;
  }
};

TEST_F(HostDialogRelay, RefusesABadUrlOrSessionIdReadablyAndRemembersAllButThePassword) {
  HostDialog dialog;
  const QString generated = field<QLineEdit>(dialog, "relaySessionEdit")->text();
  EXPECT_EQ(generated.size(), 10) << generated.toStdString();  // a fresh id by default
  EXPECT_FALSE(dialog.settings().relay) << "the group starts unchecked";

  fill(dialog, m_meshPath, {QStringLiteral("127.0.0.1:4222"), {}, QStringLiteral("host"), QStringLiteral("pw")});
  dialog.show();
  clickOk(dialog);
  EXPECT_TRUE(dialog.isVisible()) << "a bad URL closed the dialog";
  EXPECT_TRUE(dialog.errorText().contains(QStringLiteral("must start with nats:// or tls://")))
      << dialog.errorText().toStdString();

  fill(dialog, m_meshPath,
       {QStringLiteral("nats://127.0.0.1:99999"), {}, QStringLiteral("host"), QStringLiteral("pw")});
  clickOk(dialog);
  EXPECT_TRUE(dialog.errorText().contains(QStringLiteral("port from 1 to 65535"))) << dialog.errorText().toStdString();

  fill(dialog, m_meshPath,
       {QStringLiteral("nats://127.0.0.1:4222"), QStringLiteral("a.b"), QStringLiteral("host"), QStringLiteral("pw")});
  clickOk(dialog);
  EXPECT_TRUE(dialog.errorText().contains(QStringLiteral("session id"))) << dialog.errorText().toStdString();

  fill(dialog, m_meshPath,
       {QStringLiteral("nats://127.0.0.1:4222"), QStringLiteral("lecture-1"), QStringLiteral("host"), QString()});
  clickOk(dialog);
  EXPECT_TRUE(dialog.errorText().contains(QStringLiteral("password of user “host”")))
      << dialog.errorText().toStdString();

  fill(dialog, m_meshPath,
       {QStringLiteral("tls://broker.example.org:4222"), QStringLiteral("lecture-1"), QStringLiteral("host"),
        QStringLiteral("s3cret")});
  field<QLineEdit>(dialog, "natsCaEdit")->setText(m_dir.filePath(QStringLiteral("missing-ca.pem")));
  clickOk(dialog);
  EXPECT_TRUE(dialog.errorText().contains(QStringLiteral("missing-ca.pem"))) << dialog.errorText().toStdString();

  field<QLineEdit>(dialog, "natsCaEdit")->clear();
  clickOk(dialog);
  EXPECT_TRUE(dialog.errorText().isEmpty()) << dialog.errorText().toStdString();
  EXPECT_EQ(dialog.result(), QDialog::Accepted);
  const std::optional<HostRelaySettings> relay = dialog.settings().relay;
  ASSERT_TRUE(relay);
  EXPECT_EQ(relay->url, QStringLiteral("tls://broker.example.org:4222"));
  EXPECT_EQ(relay->sessionId, QStringLiteral("lecture-1"));
  EXPECT_EQ(relay->user, QStringLiteral("host"));
  EXPECT_EQ(relay->password, QStringLiteral("s3cret"));

  // Remembered: everything but the password, which is nowhere in the settings.
  HostDialog again;
  EXPECT_TRUE(field<QGroupBox>(again, "relayGroup")->isChecked());
  EXPECT_EQ(field<QLineEdit>(again, "natsUrlEdit")->text(), QStringLiteral("tls://broker.example.org:4222"));
  EXPECT_EQ(field<QLineEdit>(again, "relaySessionEdit")->text(), QStringLiteral("lecture-1"));
  EXPECT_EQ(field<QLineEdit>(again, "natsUserEdit")->text(), QStringLiteral("host"));
  EXPECT_TRUE(field<QLineEdit>(again, "natsPasswordEdit")->text().isEmpty());
  QSettings store;
  store.sync();
  QFile file(store.fileName());
  ASSERT_TRUE(file.open(QIODevice::ReadOnly)) << store.fileName().toStdString();
  EXPECT_FALSE(file.readAll().contains("s3cret"));
}

TEST_F(HostDialogRelay, HostingFromTheDialogRelaysTheFramesToAWatchProcess) {
  if (!session::natsServerAvailable()) GTEST_SKIP() << "nats-server is not installed";
  session::LocalNatsServer server;  // session "test"
  QString error;
  ASSERT_TRUE(server.start(&error)) << error.toStdString();
  MainWindow window;
  QSignalSpy failures(&window, &MainWindow::sessionFailed);
  HostController* host = hostThroughTheDialog(window, server, server.config().hostPassword);
  ASSERT_NE(host, nullptr);
  ASSERT_EQ(host->state(), State::Live) << host->errorText().toStdString();
  // The broker is connected on a thread of its own after the session is live.
  (void)QTest::qWaitFor([&] { return host->relay() != nullptr || !failures.isEmpty(); }, 10000);
  ASSERT_NE(host->relay(), nullptr) << (failures.isEmpty() ? std::string("no failure reported")
                                                           : failures.first().first().toString().toStdString());
  ASSERT_TRUE(host->settings().relay);
  EXPECT_EQ(host->settings().relay->sessionId, server.config().sessionId);
  EXPECT_TRUE(host->settings().relay->password.isEmpty()) << "the controller forgets the NATS password";

  const QString secret = m_dir.filePath(QStringLiteral("viewer.pw"));
  {
    QFile file(secret);
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));
    file.write(server.config().viewerPassword.toUtf8() + '\n');
  }
  QProcess watch;
  watch.start(QStringLiteral(SHAPECAST_CLI_EXE),
              {QStringLiteral("watch"), QStringLiteral("--nats"), server.url(), QStringLiteral("--session"),
               server.config().sessionId, QStringLiteral("--nats-user"), server.config().viewerUser,
               QStringLiteral("--nats-password-file"), secret, QStringLiteral("--pin"),
               session::formatFingerprint(host->hostFingerprint()), QStringLiteral("--frames"), QStringLiteral("5"),
               QStringLiteral("--seconds"), QStringLiteral("60")});
  ASSERT_TRUE(watch.waitForStarted());
  ASSERT_TRUE(QTest::qWaitFor([&watch] { return watch.canReadLine() || watch.state() != QProcess::Running; }, 30000));
  const QByteArray first = watch.readLine();
  ASSERT_TRUE(first.startsWith("watching session test"))
      << first.toStdString() << watch.readAllStandardError().toStdString();

  const QString script = writeLiftScript();
  QProcess drive;
  drive.start(QStringLiteral(SHAPECAST_CLI_EXE),
              {QStringLiteral("drive"), QStringLiteral("127.0.0.1:%1").arg(host->tcpPort()), QStringLiteral("--script"),
               script, QStringLiteral("--fingerprint"), session::formatFingerprint(host->hostFingerprint())});
  ASSERT_TRUE(drive.waitForStarted());
  ASSERT_TRUE(QTest::qWaitFor([&watch] { return watch.state() == QProcess::NotRunning; }, 60000));
  // The host runs in this process: wait with the event loop running.
  ASSERT_TRUE(QTest::qWaitFor([&drive] { return drive.state() == QProcess::NotRunning; }, 60000));
  EXPECT_EQ(drive.exitCode(), 0) << drive.readAllStandardError().toStdString();
  const QByteArray output = watch.readAll();
  EXPECT_EQ(watch.exitCode(), 0) << output.toStdString();
  EXPECT_TRUE(output.contains("watch ended: frame")) << output.toStdString();
  EXPECT_FALSE(output.contains(" 0 applied")) << output.toStdString();
  EXPECT_GE(host->relay()->counters().frames, 5);
  EXPECT_TRUE(failures.isEmpty());
}

TEST_F(HostDialogRelay, AWrongPasswordHostsWithoutTheRelayAndSaysWhy) {
  if (!session::natsServerAvailable()) GTEST_SKIP() << "nats-server is not installed";
  session::LocalNatsServer server;
  QString error;
  ASSERT_TRUE(server.start(&error)) << error.toStdString();
  MainWindow window;
  QSignalSpy failures(&window, &MainWindow::sessionFailed);
  HostController* host = hostThroughTheDialog(window, server, QStringLiteral("wrong"));
  ASSERT_NE(host, nullptr);
  ASSERT_TRUE(QTest::qWaitFor([&failures] { return !failures.isEmpty(); }, 10000));
  EXPECT_EQ(host->state(), State::Live) << "the editors' session goes on";
  EXPECT_EQ(host->relay(), nullptr);
  const QString message = failures.first().first().toString();
  EXPECT_TRUE(message.startsWith(QStringLiteral("Hosting without the relay through NATS"))) << message.toStdString();
  EXPECT_TRUE(message.contains(QStringLiteral("refused the user “host” or its password"))) << message.toStdString();
}

TEST_F(HostDialogRelay, ABrokerThatNeverAnswersLeavesTheWindowLiveWhileItIsTried) {
  // A TCP server that accepts and says nothing: cnats waits for its INFO until the 2 s connect timeout.
  QTcpServer silent;
  ASSERT_TRUE(silent.listen(QHostAddress::LocalHost));
  MainWindow window;
  sc::testing::showSessionWindow(window, {800, 600});
  QSignalSpy failures(&window, &MainWindow::sessionFailed);
  HostSettings settings = sc::testing::loopbackHostSettings(m_meshPath, 20);
  settings.relay = HostRelaySettings{QStringLiteral("nats://127.0.0.1:%1").arg(silent.serverPort()),
                                     QStringLiteral("silent"),
                                     QStringLiteral("host"),
                                     QStringLiteral("pw"),
                                     {}};
  HostController* host = sc::testing::hostAndWait(window, settings);
  ASSERT_EQ(host->state(), State::Live) << host->errorText().toStdString();

  QElapsedTimer clock;
  clock.start();
  qint64 lastTick = 0;
  qint64 longestGapMs = 0;
  QTimer ticker;  // the window's event loop, seen from inside
  QObject::connect(&ticker, &QTimer::timeout, [&] {
    longestGapMs = std::max(longestGapMs, clock.elapsed() - lastTick);
    lastTick = clock.elapsed();
  });
  ticker.start(20);
  ASSERT_TRUE(QTest::qWaitFor([&failures] { return !failures.isEmpty(); }, 15000));
  const qint64 triedMs = clock.elapsed();
  EXPECT_GE(triedMs, 1000) << "the connect gave up before its timeout: the broker did answer";
  EXPECT_LT(longestGapMs, 500) << "the window stood still while the broker was tried";
  EXPECT_EQ(host->state(), State::Live) << "the editors' session goes on";
  EXPECT_EQ(host->relay(), nullptr);
  EXPECT_TRUE(failures.first().first().toString().startsWith(QStringLiteral("Hosting without the relay through NATS")))
      << failures.first().first().toString().toStdString();
}

}  // namespace
}  // namespace sc::app
