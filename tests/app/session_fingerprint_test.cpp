// The desktop app and the host's TLS fingerprint (docs/security.md), with real sockets on loopback inside one
// process: a hosting MainWindow shows its certificate's fingerprint (Session info, toolbar button); a joining
// MainWindow pins it through the Join dialog's field, or trusts on first use, and refuses a wrong or changed one
// with an error dialog that names both fingerprints, after which the same window still joins. The known-hosts store
// is a temporary INI file (JoinSettings::knownHostsFile), never the user's settings.

#include "app/gui/join_dialog.h"
#include "app/gui/main_window.h"
#include "app/gui/session_controller.h"
#include "app/gui/session_identity_view.h"
#include "app_test_support.h"
#include "session/net/tls_identity.h"
#include "session/net/tls_known_hosts.h"
#include "session_windows.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QClipboard>
#include <QLabel>
#include <QLineEdit>
#include <QMessageBox>
#include <QPushButton>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>

namespace sc::app {
namespace {

using State = SessionController::State;

/// Closes the next error box named `objectName` (the fingerprint refusal by default) once it is shown, keeping its
/// texts and the format its text is shown in.
class RefusalBoxCatcher {
 public:
  explicit RefusalBoxCatcher(QString objectName = QStringLiteral("fingerprintRefusedBox")) {
    m_timer.setInterval(20);
    QObject::connect(&m_timer, &QTimer::timeout, [this, objectName] {
      auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget());
      if (box == nullptr || box->objectName() != objectName) return;
      title = box->windowTitle();
      text = box->text();
      advice = box->informativeText();
      format = box->textFormat();
      box->accept();
      m_timer.stop();
    });
    m_timer.start();
  }
  QString title, text, advice;
  Qt::TextFormat format = Qt::AutoText;

 private:
  QTimer m_timer;
};

class SessionFingerprintTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sc::testing::openGlAvailable()) GTEST_SKIP() << "no OpenGL 3.3 context (needs an X server)";
    ASSERT_TRUE(m_dir.isValid());
    const sc::testing::GeneratedMesh mesh = sc::testing::torus(24, 12);
    m_meshPath = m_dir.filePath(QStringLiteral("torus.off"));
    ASSERT_TRUE(sc::testing::writeOff(m_meshPath, mesh.V, mesh.F));
    m_knownHosts = m_dir.filePath(QStringLiteral("known_hosts.ini"));
    m_hostWindow.setErrorDialogsEnabled(false);
    m_hosting = sc::testing::hostAndWait(m_hostWindow, sc::testing::loopbackHostSettings(m_meshPath, 12));
    ASSERT_EQ(m_hosting->state(), State::Live) << m_hosting->errorText().toStdString();
    m_fingerprint = m_hosting->hostFingerprint();
    ASSERT_EQ(m_fingerprint.size(), session::kFingerprintSize);
  }

  JoinSettings joinSettings(const QByteArray& pinned = {}) const {
    JoinSettings settings = sc::testing::loopbackJoinSettings(m_hosting->tcpPort(), m_knownHosts);
    settings.fingerprint = pinned;
    return settings;
  }

  /// Joins in `window` and waits until live or failed; returns the state reached.
  static State joinAndWait(MainWindow& window, const JoinSettings& settings) {
    return sc::testing::joinAndWait(window, settings)->state();
  }

  [[nodiscard]] std::optional<QByteArray> remembered() const {
    return session::KnownHosts(m_knownHosts).lookup(QStringLiteral("127.0.0.1"), m_hosting->tcpPort());
  }

  [[nodiscard]] QByteArray otherFingerprint() const {
    QByteArray other = m_fingerprint;
    other[0] = static_cast<char>(other[0] ^ 0x5a);
    return other;
  }

  QTemporaryDir m_dir;
  QString m_meshPath;
  QString m_knownHosts;
  MainWindow m_hostWindow;
  SessionController* m_hosting = nullptr;
  QByteArray m_fingerprint;
};

TEST_F(SessionFingerprintTest, HostShowsItsFingerprintAndAClientPinnedToItJoinsAndSeesTheSame) {
  const QString formatted = session::formatFingerprint(m_fingerprint);

  // Host side: Session ▸ Session info… shows the fingerprint grouped, selectable, and Copy copies it.
  auto* infoAction = m_hostWindow.findChild<QAction*>(QStringLiteral("actionSessionInfo"));
  ASSERT_NE(infoAction, nullptr);
  infoAction->trigger();
  auto* hostInfo = m_hostWindow.findChild<SessionInfoDialog*>();
  ASSERT_NE(hostInfo, nullptr);
  EXPECT_EQ(hostInfo->fingerprintText(), formatted);
  auto* label = hostInfo->findChild<QLabel*>(QStringLiteral("fingerprintLabel"));
  ASSERT_NE(label, nullptr);
  EXPECT_EQ(label->text(), groupedFingerprint(m_fingerprint));
  EXPECT_EQ(label->text().count(QLatin1Char('\n')), 1);  // two lines of 16 pairs
  EXPECT_TRUE(label->textInteractionFlags().testFlag(Qt::TextSelectableByMouse));
  auto* copy = hostInfo->findChild<QPushButton*>(QStringLiteral("copyFingerprintButton"));
  ASSERT_NE(copy, nullptr);
  QApplication::clipboard()->clear();
  copy->click();
  EXPECT_EQ(QApplication::clipboard()->text(), formatted);
  hostInfo->close();
  auto* hostButton = m_hostWindow.findChild<HostIdentityButton*>(QStringLiteral("hostIdentityButton"));
  ASSERT_NE(hostButton, nullptr);
  EXPECT_TRUE(hostButton->text().contains(shortFingerprint(m_fingerprint)));

  // Client side: the Join dialog's field takes the fingerprint as a user may type it (lower case, spaces).
  JoinDialog dialog;
  dialog.setSettings(joinSettings());
  auto* field = dialog.findChild<QLineEdit*>(QStringLiteral("fingerprintEdit"));
  ASSERT_NE(field, nullptr);
  field->setText(QString::fromLatin1(m_fingerprint.toHex(' ')));
  JoinSettings settings = dialog.settings();
  EXPECT_EQ(settings.fingerprint, m_fingerprint);
  settings.knownHostsFile = m_knownHosts;

  MainWindow clientWindow;
  clientWindow.setErrorDialogsEnabled(false);
  ASSERT_EQ(joinAndWait(clientWindow, settings), State::Live) << clientWindow.session()->errorText().toStdString();
  SessionController* joined = clientWindow.session();
  EXPECT_EQ(joined->hostFingerprint(), m_hostWindow.session()->hostFingerprint());  // the host shows what we saw
  EXPECT_EQ(joined->hostTrust(), HostTrust::Pinned);
  EXPECT_FALSE(joined->fingerprintRefused());
  EXPECT_EQ(remembered(), std::optional<QByteArray>(m_fingerprint));  // a matching pin is remembered

  // The client's window shows the fingerprint it saw, the same text as the host's.
  clientWindow.findChild<QAction*>(QStringLiteral("actionSessionInfo"))->trigger();
  auto* clientInfo = clientWindow.findChild<SessionInfoDialog*>();
  ASSERT_NE(clientInfo, nullptr);
  EXPECT_EQ(clientInfo->fingerprintText(), formatted);
  EXPECT_EQ(clientInfo->findChild<QLabel*>(QStringLiteral("trustLabel"))->text(),
            hostTrustText(SessionController::Role::Client, HostTrust::Pinned));
  auto* clientButton = clientWindow.findChild<HostIdentityButton*>(QStringLiteral("hostIdentityButton"));
  ASSERT_NE(clientButton, nullptr);
  EXPECT_EQ(clientButton->text(), hostButton->text());
}

TEST_F(SessionFingerprintTest, WrongPinnedFingerprintIsRefusedWithBothInTheDialogAndTheWindowStillJoins) {
  const QByteArray wrong = otherFingerprint();
  MainWindow clientWindow;  // error dialogs on: the refusal box is caught and closed
  QSignalSpy failures(&clientWindow, &MainWindow::sessionFailed);
  {
    RefusalBoxCatcher box;
    ASSERT_EQ(joinAndWait(clientWindow, joinSettings(wrong)), State::Failed);
    ASSERT_TRUE(QTest::qWaitFor([&box] { return !box.text.isEmpty(); }, 10000));
    EXPECT_TRUE(clientWindow.session()->fingerprintRefused());
    EXPECT_EQ(clientWindow.session()->hostTrust(), HostTrust::None);
    EXPECT_EQ(clientWindow.session()->hostFingerprint(), m_fingerprint);  // what was seen
    ASSERT_EQ(failures.count(), 1);
    const QString message = failures.first().first().toString();
    EXPECT_EQ(box.text, message);
    EXPECT_TRUE(message.contains(session::formatFingerprint(m_fingerprint))) << message.toStdString();
    EXPECT_TRUE(message.contains(session::formatFingerprint(wrong))) << message.toStdString();
    EXPECT_EQ(box.title, QStringLiteral("Host fingerprint does not match"));
    EXPECT_EQ(box.advice, fingerprintRefusedAdvice());
    EXPECT_EQ(box.format, Qt::PlainText);  // the message quotes what the host sent
    EXPECT_TRUE(box.advice.contains(QStringLiteral("Host fingerprint")));
  }
  EXPECT_FALSE(remembered().has_value());          // a refused certificate is not remembered
  EXPECT_EQ(m_hosting->peers().peers.size(), 1u);  // the host never saw a Hello
  auto* button = clientWindow.findChild<HostIdentityButton*>(QStringLiteral("hostIdentityButton"));
  ASSERT_NE(button, nullptr);
  EXPECT_TRUE(button->text().isEmpty());  // a refused certificate is not shown as the session's host

  // The same window joins with the right fingerprint.
  clientWindow.setErrorDialogsEnabled(false);
  ASSERT_EQ(joinAndWait(clientWindow, joinSettings(m_fingerprint)), State::Live)
      << clientWindow.session()->errorText().toStdString();
  EXPECT_EQ(clientWindow.session()->hostFingerprint(), m_fingerprint);
  ASSERT_TRUE(QTest::qWaitFor([this] { return m_hosting->peers().peers.size() == 2; }, 10000));
}

TEST_F(SessionFingerprintTest, TheHostsRefusalIsShownAsPlainTextNeverRichText) {
  // The failure box showed the host's Refused text in Qt's AutoText: a hostile host's "<a href=…>" or "<img>" would
  // have been rendered. A name the host already has is refused with a text of the host's.
  MainWindow clientWindow;
  JoinSettings settings = joinSettings(m_fingerprint);
  settings.name = QStringLiteral("alice");  // the host's own name
  RefusalBoxCatcher box(QStringLiteral("sessionFailedBox"));
  ASSERT_EQ(joinAndWait(clientWindow, settings), State::Failed);
  ASSERT_TRUE(QTest::qWaitFor([&box] { return !box.text.isEmpty(); }, 10000));
  EXPECT_EQ(box.format, Qt::PlainText);
  EXPECT_EQ(box.text, clientWindow.session()->errorText());
}

TEST_F(SessionFingerprintTest, TrustOnFirstUseRemembersAndRefusesAChangedFingerprintUntilPinned) {
  MainWindow clientWindow;
  clientWindow.setErrorDialogsEnabled(false);
  ASSERT_EQ(joinAndWait(clientWindow, joinSettings()), State::Live)
      << clientWindow.session()->errorText().toStdString();
  EXPECT_EQ(clientWindow.session()->hostTrust(), HostTrust::FirstUse);
  EXPECT_EQ(remembered(), std::optional<QByteArray>(m_fingerprint));
  clientWindow.leaveSession();

  ASSERT_EQ(joinAndWait(clientWindow, joinSettings()), State::Live)
      << clientWindow.session()->errorText().toStdString();
  EXPECT_EQ(clientWindow.session()->hostTrust(), HostTrust::Known);
  clientWindow.leaveSession();

  // The remembered fingerprint differs from the host's now (as after an impostor took the address): refused.
  const QByteArray previous = otherFingerprint();
  session::KnownHosts(m_knownHosts).remember(QStringLiteral("127.0.0.1"), m_hosting->tcpPort(), previous);
  clientWindow.setErrorDialogsEnabled(true);
  {
    RefusalBoxCatcher box;
    ASSERT_EQ(joinAndWait(clientWindow, joinSettings()), State::Failed);
    ASSERT_TRUE(QTest::qWaitFor([&box] { return !box.text.isEmpty(); }, 10000));
    EXPECT_TRUE(clientWindow.session()->fingerprintRefused());
    EXPECT_TRUE(box.text.contains(QStringLiteral("changed"))) << box.text.toStdString();
    EXPECT_TRUE(box.text.contains(session::formatFingerprint(m_fingerprint))) << box.text.toStdString();
    EXPECT_TRUE(box.text.contains(session::formatFingerprint(previous))) << box.text.toStdString();
  }
  EXPECT_EQ(remembered(), std::optional<QByteArray>(previous));  // a refusal changes nothing

  // Pinning the host's fingerprint joins and replaces the remembered one.
  clientWindow.setErrorDialogsEnabled(false);
  ASSERT_EQ(joinAndWait(clientWindow, joinSettings(m_fingerprint)), State::Live)
      << clientWindow.session()->errorText().toStdString();
  EXPECT_EQ(remembered(), std::optional<QByteArray>(m_fingerprint));
}

TEST(JoinDialogFingerprint, FieldAcceptsHexWithOrWithoutSeparatorsAndRefusesAnythingElse) {
  EXPECT_TRUE(validateFingerprintText(QString()).isEmpty());
  EXPECT_TRUE(validateFingerprintText(QStringLiteral("  ")).isEmpty());
  const QByteArray bytes = QByteArray::fromHex("00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff");
  const QString forms[] = {QString::fromLatin1(bytes.toHex()), QString::fromLatin1(bytes.toHex(':').toUpper()),
                           QString::fromLatin1(bytes.toHex(' '))};
  for (const QString& form : forms) EXPECT_TRUE(validateFingerprintText(form).isEmpty()) << form.toStdString();
  const QString bad[] = {QString::fromLatin1(bytes.toHex()).chopped(1),
                         QString::fromLatin1(bytes.toHex()) + QStringLiteral("00"),
                         QString::fromLatin1(bytes.toHex()).replace(0, 1, QStringLiteral("g"))};
  for (const QString& form : bad) EXPECT_FALSE(validateFingerprintText(form).isEmpty()) << form.toStdString();

  JoinDialog dialog;
  JoinSettings settings;
  settings.name = QStringLiteral("bob");
  settings.fingerprint = bytes;
  dialog.setSettings(settings);
  auto* field = dialog.findChild<QLineEdit*>(QStringLiteral("fingerprintEdit"));
  ASSERT_NE(field, nullptr);
  EXPECT_EQ(field->text(), session::formatFingerprint(bytes));
  EXPECT_EQ(dialog.settings().fingerprint, bytes);
  field->setText(QStringLiteral("AB:CD"));
  EXPECT_TRUE(dialog.settings().fingerprint.isEmpty());
  dialog.accept();  // refused before anything is remembered
  EXPECT_NE(dialog.result(), QDialog::Accepted);
  EXPECT_EQ(dialog.errorText(), validateFingerprintText(QStringLiteral("AB:CD")));
}

}  // namespace
}  // namespace sc::app
