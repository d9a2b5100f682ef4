#pragma once
// JoinDialog: the Join… form (ui/join_dialog.ui): host address (recent ones), TCP port, password, display name and
// resolution (full, 50 %, 20 %, 5 % of the host's vertices), and the host's certificate fingerprint (optional; empty:
// trust on first use). OK validates (validateJoinSettings, validateFingerprintText) and shows the problem in the
// dialog instead of closing; on success the values (not the password) are remembered. A pinned fingerprint is
// remembered by the session layer's known-hosts store once it matched (session::KnownHosts), not here.

#include "app/gui/session_settings.h"

#include <QDialog>
#include <QString>

namespace Ui {
class JoinDialog;
}

namespace sc::app {

/// Empty when `settings` can be tried; otherwise one readable sentence (empty or malformed host address, port 0,
/// empty or too long name).
QString validateJoinSettings(const JoinSettings& settings);

/// Empty when `text` is empty (no pin) or parses as a SHA-256 fingerprint (64 hex digits, ':' or ' ' between
/// them allowed, either case: session::parseFingerprint); otherwise one readable sentence. O(length).
QString validateFingerprintText(const QString& text);

class JoinDialog : public QDialog {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(JoinDialog)

 public:
  explicit JoinDialog(QWidget* parent = nullptr);
  ~JoinDialog() override;

  /// The form's values; the resolution as JoinSettings::levelFraction (nullopt for full); the fingerprint parsed
  /// (empty when the field is empty or malformed: accept() refuses the latter).
  [[nodiscard]] JoinSettings settings() const;
  /// Fills the form (e.g. from the command line); the password field is left as it is when none is given; the
  /// fingerprint is shown as the host shows it (AB:CD:…), or cleared when none.
  void setSettings(const JoinSettings& settings);
  [[nodiscard]] QString errorText() const;
  /// Shows `problem` (e.g. why the last join failed) above the buttons and puts the cursor in the password field.
  void askForPassword(const QString& problem);

 public slots:
  void accept() override;

 private:
  Ui::JoinDialog* ui;
};

}  // namespace sc::app
