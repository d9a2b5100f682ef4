#pragma once
// HostDialog: the Host… form (ui/host_dialog.ui): mesh file (recent ones, Browse…), TCP port, password, number of
// frequencies m and display name, and the optional "Relay viewers through NATS" group (issue 18: server URL, relay
// session id — a generated one by default —, NATS user and password, the broker's CA file for TLS). OK validates
// (validateHostSettings, and checkHostRelaySettings: the command line's rule) and shows the problem in the dialog
// instead of closing; on success the values (no password) are remembered in QSettings (RecentSessions).

#include "app/gui/session_settings.h"

#include <QDialog>
#include <QString>

namespace Ui {
class HostDialog;
}

namespace sc::app {

/// Empty when `settings` can be tried; otherwise one readable sentence naming the field and the problem
/// (missing or unreadable mesh file, m out of 1..4096, empty or too long name). The port needs no check (0 = any).
QString validateHostSettings(const HostSettings& settings);

class HostDialog : public QDialog {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(HostDialog)

 public:
  /// Fills the form from the remembered values.
  explicit HostDialog(QWidget* parent = nullptr);
  ~HostDialog() override;

  /// The form's values (password nullopt when empty; relay nullopt unless the relay group is checked).
  [[nodiscard]] HostSettings settings() const;
  /// Fills the form (e.g. from the command line); the password fields are left as they are when none is given, the
  /// relay group is checked and filled only when `settings.relay` is set.
  void setSettings(const HostSettings& settings);
  /// The current validation message (empty: valid).
  [[nodiscard]] QString errorText() const;

 public slots:
  /// Validates; stays open with the message shown when invalid, otherwise remembers the values and closes.
  void accept() override;

 private:
  void browse();
  void browseCaFile();
  /// The problem of the current values (host, then relay): its message, with the faulty relay field focused.
  [[nodiscard]] QString problem();

  Ui::HostDialog* ui;
};

}  // namespace sc::app
