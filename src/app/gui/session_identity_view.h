#pragma once
// How the desktop app shows the host's identity (docs/security.md, "Host authentication"): the SHA-256 fingerprint
// of the host's TLS certificate, grouped for reading aloud, with how a client trusted it. A host shows its own so
// that joiners can compare or pin it; a client shows the one it saw. Views only: the fingerprint and the trust
// decision come from the SessionController (which takes them from the session layer).

#include "app/gui/session_controller.h"

#include <QByteArray>
#include <QDialog>
#include <QPointer>
#include <QString>
#include <QToolButton>

class QLabel;
class QPushButton;

namespace sc::app {

/// The fingerprint as the host shows it (AB:CD:…, session::formatFingerprint), in lines of 16 byte pairs (two
/// lines for SHA-256), easier to compare than one 95-character line. Empty for an empty fingerprint. O(size).
QString groupedFingerprint(const QByteArray& fingerprint);

/// The first 4 byte pairs and an ellipsis ("AB:CD:EF:01…"), for a toolbar; empty for an empty fingerprint.
QString shortFingerprint(const QByteArray& fingerprint);

/// One sentence on what the fingerprint means for `role` and `trust` (host: "compare or pin it"; client: pinned,
/// remembered, or first use "compare it once with the host's"). Empty when there is nothing to say.
QString hostTrustText(SessionController::Role role, HostTrust trust);

/// What the user should do when a join was refused because the host's fingerprint did not match (the failed()
/// text names both fingerprints; this is the advice under it in the error dialog).
QString fingerprintRefusedAdvice();

/// Session ▸ Session info…: role, address, the host's fingerprint (grouped, selectable, objectName
/// "fingerprintLabel") with a Copy button ("copyFingerprintButton") and the trust sentence ("trustLabel").
/// Follows the controller's state while open; shows "Not in a session" when it has none or it is gone.
class SessionInfoDialog : public QDialog {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(SessionInfoDialog)

 public:
  /// `session` may be nullptr; it is observed, not owned.
  explicit SessionInfoDialog(SessionController* session, QWidget* parent = nullptr);
  ~SessionInfoDialog() override;

  /// The fingerprint shown (session::formatFingerprint form, one line; empty when none): what Copy puts on the
  /// clipboard.
  [[nodiscard]] QString fingerprintText() const { return m_fingerprint; }

 private:
  void refresh();

  QPointer<SessionController> m_session;
  QString m_fingerprint;
  QLabel* m_roleLabel = nullptr;
  QLabel* m_fingerprintLabel = nullptr;
  QLabel* m_trustLabel = nullptr;
  QPushButton* m_copyButton = nullptr;
};

/// A toolbar button (objectName "hostIdentityButton") showing shortFingerprint() of the current session's host
/// certificate, its full grouped form and trust sentence as tooltip. Emits clicked() as any button (the window
/// opens SessionInfoDialog) and shownChanged(false) while there is no fingerprint to show (a QToolBar hides a
/// widget through its QAction, which the window owns).
class HostIdentityButton : public QToolButton {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(HostIdentityButton)

 public:
  explicit HostIdentityButton(QWidget* parent = nullptr);
  ~HostIdentityButton() override;

 public slots:
  /// Follows `session` (nullptr: none) from now on.
  void bind(sc::app::SessionController* session);

 signals:
  /// There is (true) or is no longer (false) a fingerprint to show.
  void shownChanged(bool shown);

 private:
  void refresh();

  QPointer<SessionController> m_session;
  bool m_shown = false;
};

}  // namespace sc::app
