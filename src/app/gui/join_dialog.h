#pragma once
// JoinDialog: the Join… form (ui/join_dialog.ui): host address (recent ones), TCP port, password, display name and
// resolution (full, 50 %, 20 %, 5 % of the host's vertices). OK validates (validateJoinSettings) and shows the
// problem in the dialog instead of closing; on success the values (not the password) are remembered.

#include "app/gui/session_controller.h"

#include <QDialog>
#include <QString>

namespace Ui {
class JoinDialog;
}

namespace sc::app {

/// Empty when `settings` can be tried; otherwise one readable sentence (empty or malformed host address, port 0,
/// empty or too long name).
QString validateJoinSettings(const JoinSettings& settings);

class JoinDialog : public QDialog {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(JoinDialog)

 public:
  explicit JoinDialog(QWidget* parent = nullptr);
  ~JoinDialog() override;

  /// The form's values; the resolution as JoinSettings::levelFraction (nullopt for full).
  [[nodiscard]] JoinSettings settings() const;
  /// Fills the form (e.g. from the command line); the password field is left as it is when none is given.
  void setSettings(const JoinSettings& settings);
  [[nodiscard]] QString errorText() const;

 public slots:
  void accept() override;

 private:
  Ui::JoinDialog* ui;
};

}  // namespace sc::app
