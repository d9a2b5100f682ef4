#include "app/gui/host_dialog.h"

#include "ui_host_dialog.h"

#include "app/gui/host_relay_settings.h"
#include "app/gui/recent_files.h"
#include "app/gui/recent_sessions.h"
#include "session/wire/wire_format.h"

#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QLineEdit>
#include <QPushButton>
#include <QSettings>

#include <optional>

namespace sc::app {

QString validateHostSettings(const HostSettings& settings) {
  const QString path = settings.meshPath.trimmed();
  if (path.isEmpty()) return HostDialog::tr("Choose a mesh file to host.");
  const QFileInfo file(path);
  if (!file.exists()) return HostDialog::tr("The mesh file “%1” does not exist.").arg(path);
  if (!file.isFile() || !file.isReadable()) return HostDialog::tr("The mesh file “%1” cannot be read.").arg(path);
  if (settings.m < 1 || settings.m > session::kMaxRows)
    return HostDialog::tr("The number of frequencies must be between 1 and %1.").arg(session::kMaxRows);
  const QString name = settings.name.trimmed();
  if (name.isEmpty()) return HostDialog::tr("Enter a display name, so the others know who you are.");
  if (name.toUtf8().size() > session::kMaxNameBytes)
    return HostDialog::tr("The display name is too long (at most %1 bytes).").arg(session::kMaxNameBytes);
  return {};
}

HostDialog::HostDialog(QWidget* parent) : QDialog(parent), ui(new Ui::HostDialog) {
  ui->setupUi(this);
  QSettings store;
  const RecentSessions recent = RecentSessions::load(store);
  ui->meshPathCombo->addItems(recent.meshPaths);
  ui->nameCombo->addItems(recent.names);
  if (recent.names.isEmpty()) ui->nameCombo->setEditText(QStringLiteral("host"));
  ui->portSpin->setValue(recent.hostPort);
  ui->frequenciesSpin->setMaximum(session::kMaxRows);
  ui->frequenciesSpin->setValue(recent.frequencies);
  ui->relayGroup->setChecked(recent.relayEnabled);
  ui->natsUrlEdit->setText(recent.relayUrl);
  ui->relaySessionEdit->setText(recent.relaySessionId.isEmpty() ? generateRelaySessionId() : recent.relaySessionId);
  ui->natsUserEdit->setText(recent.relayUser);
  ui->natsCaEdit->setText(recent.relayCaFile);
  connect(ui->browseButton, &QPushButton::clicked, this, &HostDialog::browse);
  connect(ui->natsCaBrowseButton, &QPushButton::clicked, this, &HostDialog::browseCaFile);
  connect(ui->buttonBox, &QDialogButtonBox::accepted, this, &HostDialog::accept);
}

HostDialog::~HostDialog() { delete ui; }

HostSettings HostDialog::settings() const {
  HostSettings s;
  s.meshPath = ui->meshPathCombo->currentText().trimmed();
  s.port = static_cast<quint16>(ui->portSpin->value());
  if (!ui->passwordEdit->text().isEmpty()) s.password = ui->passwordEdit->text();
  s.m = ui->frequenciesSpin->value();
  s.name = ui->nameCombo->currentText().trimmed();
  s.editors = ui->editorsSpin->value();
  if (ui->relayGroup->isChecked()) {
    s.relay = HostRelaySettings{ui->natsUrlEdit->text().trimmed(), ui->relaySessionEdit->text().trimmed(),
                                ui->natsUserEdit->text().trimmed(), ui->natsPasswordEdit->text(),
                                ui->natsCaEdit->text().trimmed()};
  }
  return s;
}

void HostDialog::setSettings(const HostSettings& settings) {
  ui->meshPathCombo->setEditText(settings.meshPath);
  ui->portSpin->setValue(settings.port);
  if (settings.password) ui->passwordEdit->setText(*settings.password);
  ui->frequenciesSpin->setValue(settings.m);
  ui->nameCombo->setEditText(settings.name);
  ui->editorsSpin->setValue(settings.editors);
  ui->relayGroup->setChecked(settings.relay.has_value());
  if (!settings.relay) return;
  ui->natsUrlEdit->setText(settings.relay->url);
  ui->relaySessionEdit->setText(settings.relay->sessionId);
  ui->natsUserEdit->setText(settings.relay->user);
  if (!settings.relay->password.isEmpty()) ui->natsPasswordEdit->setText(settings.relay->password);
  ui->natsCaEdit->setText(settings.relay->caFile);
}

QString HostDialog::errorText() const { return ui->errorLabel->text(); }

QString HostDialog::problem() {
  const HostSettings s = settings();
  const QString error = validateHostSettings(s);
  if (!error.isEmpty() || !s.relay) return error;
  const std::optional<RelayProblem> relay = checkHostRelaySettings(*s.relay);
  if (!relay) return {};
  QLineEdit* const fields[] = {ui->natsUrlEdit, ui->relaySessionEdit, ui->natsUserEdit, ui->natsPasswordEdit,
                               ui->natsCaEdit};
  fields[static_cast<int>(relay->field)]->setFocus();
  return relay->message;
}

void HostDialog::accept() {
  const QString error = problem();
  ui->errorLabel->setText(error);
  if (!error.isEmpty()) return;
  const HostSettings s = settings();
  QSettings store;
  RecentSessions recent = RecentSessions::load(store);
  recent.rememberHost(s);
  recent.save(store);
  QDialog::accept();
}

void HostDialog::browseCaFile() {
  const QString current = ui->natsCaEdit->text();
  const QString path =
      QFileDialog::getOpenFileName(this, tr("Broker's Certificate Authority"), QFileInfo(current).absolutePath(),
                                   tr("PEM certificates (*.pem *.crt);;All files (*)"));
  if (!path.isEmpty()) ui->natsCaEdit->setText(path);
}

void HostDialog::browse() {
  const QString current = ui->meshPathCombo->currentText();
  QSettings store;  // no mesh chosen yet: the folder the window's file dialogs used last
  const QString folder = current.isEmpty() ? RecentFiles::load(store).folder : QFileInfo(current).absolutePath();
  const QString path = QFileDialog::getOpenFileName(
      this, tr("Mesh to Host"), folder,
      tr("Meshes and sessions (*.off *.obj *.ply *.stl *.shapecast *.OFF *.OBJ *.PLY *.STL);;"
         "ShapeCast sessions (*.shapecast);;All files (*)"));
  if (!path.isEmpty()) ui->meshPathCombo->setEditText(path);
}

}  // namespace sc::app
