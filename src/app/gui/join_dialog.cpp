#include "app/gui/join_dialog.h"

#include "ui_join_dialog.h"

#include "app/gui/recent_sessions.h"
#include "session/net/tls_identity.h"
#include "session/wire/wire_format.h"

#include <QDialogButtonBox>
#include <QRegularExpression>
#include <QSettings>

#include <algorithm>
#include <array>
#include <cmath>

namespace sc::app {

namespace {
/// The Join dialog's resolutions: fraction of the host's vertex count (1 = full).
constexpr std::array<double, 4> kResolutionFractions = {1.0, 0.5, 0.2, 0.05};
}  // namespace

QString validateJoinSettings(const JoinSettings& settings) {
  const QString host = settings.host.trimmed();
  if (host.isEmpty()) return JoinDialog::tr("Enter the host's name or IP address.");
  static const QRegularExpression allowed(QStringLiteral("^[A-Za-z0-9._:%\\-\\[\\]]+$"));
  if (!allowed.match(host).hasMatch()) return JoinDialog::tr("“%1” is not a host name or IP address.").arg(host);
  if (settings.port == 0) return JoinDialog::tr("The port must be between 1 and 65535.");
  const QString name = settings.name.trimmed();
  if (name.isEmpty()) return JoinDialog::tr("Enter a display name, so the others know who you are.");
  if (name.toUtf8().size() > session::kMaxNameBytes)
    return JoinDialog::tr("The display name is too long (at most %1 bytes).").arg(session::kMaxNameBytes);
  return {};
}

QString validateFingerprintText(const QString& text) {
  if (text.trimmed().isEmpty() || session::parseFingerprint(text)) return {};
  return JoinDialog::tr(
      "The host fingerprint must be 64 hexadecimal digits (colons or spaces between them are "
      "fine), as the host's Session info shows it; or leave it empty.");
}

JoinDialog::JoinDialog(QWidget* parent) : QDialog(parent), ui(new Ui::JoinDialog) {
  ui->setupUi(this);
  ui->errorLabel->setTextFormat(Qt::PlainText);  // it may quote the host's refusal: never rich text
  ui->resolutionCombo->addItem(tr("Full resolution"));
  ui->resolutionCombo->addItem(tr("50 % of the vertices"));
  ui->resolutionCombo->addItem(tr("20 % of the vertices"));
  ui->resolutionCombo->addItem(tr("5 % of the vertices"));
  QSettings store;
  const RecentSessions recent = RecentSessions::load(store);
  ui->hostCombo->addItems(recent.hosts);
  if (recent.hosts.isEmpty()) ui->hostCombo->setEditText(QStringLiteral("127.0.0.1"));
  ui->nameCombo->addItems(recent.names);
  ui->portSpin->setValue(recent.joinPort);
  ui->resolutionCombo->setCurrentIndex(std::min(recent.joinResolution, ui->resolutionCombo->count() - 1));
  connect(ui->buttonBox, &QDialogButtonBox::accepted, this, &JoinDialog::accept);
}

JoinDialog::~JoinDialog() { delete ui; }

JoinSettings JoinDialog::settings() const {
  JoinSettings s;
  s.host = ui->hostCombo->currentText().trimmed();
  s.port = static_cast<quint16>(ui->portSpin->value());
  if (!ui->passwordEdit->text().isEmpty()) s.password = ui->passwordEdit->text();
  s.name = ui->nameCombo->currentText().trimmed();
  const int index = std::max(0, ui->resolutionCombo->currentIndex());
  const double fraction = kResolutionFractions[static_cast<std::size_t>(index) % kResolutionFractions.size()];
  if (fraction < 1.0) s.levelFraction = fraction;
  s.fingerprint = session::parseFingerprint(ui->fingerprintEdit->text()).value_or(QByteArray());
  return s;
}

void JoinDialog::setSettings(const JoinSettings& settings) {
  ui->hostCombo->setEditText(settings.host);
  ui->portSpin->setValue(settings.port);
  if (settings.password) ui->passwordEdit->setText(*settings.password);
  ui->nameCombo->setEditText(settings.name);
  int index = 0;
  if (settings.levelFraction) {
    for (std::size_t i = 0; i < kResolutionFractions.size(); ++i) {
      if (std::abs(kResolutionFractions[i] - *settings.levelFraction) < 1e-9) index = static_cast<int>(i);
    }
  }
  ui->resolutionCombo->setCurrentIndex(index);
  ui->fingerprintEdit->setText(settings.fingerprint.isEmpty() ? QString()
                                                              : session::formatFingerprint(settings.fingerprint));
}

QString JoinDialog::errorText() const { return ui->errorLabel->text(); }

void JoinDialog::askForPassword(const QString& problem) {
  ui->errorLabel->setText(problem);
  ui->passwordEdit->setFocus();
}

void JoinDialog::accept() {
  const JoinSettings s = settings();
  QString error = validateJoinSettings(s);
  if (error.isEmpty()) error = validateFingerprintText(ui->fingerprintEdit->text());
  ui->errorLabel->setText(error);
  if (!error.isEmpty()) return;
  QSettings store;
  RecentSessions recent = RecentSessions::load(store);
  recent.rememberJoin(s);
  recent.joinResolution = ui->resolutionCombo->currentIndex();
  recent.save(store);
  QDialog::accept();
}

}  // namespace sc::app
