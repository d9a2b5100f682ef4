#include "app/gui/session_identity_view.h"

#include "session/net/tls_identity.h"

#include <QClipboard>
#include <QDialogButtonBox>
#include <QFontDatabase>
#include <QGuiApplication>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QStringList>
#include <QVBoxLayout>

namespace sc::app {

namespace {
constexpr int kPairsPerLine = 16;  ///< byte pairs per line of groupedFingerprint()
constexpr int kShortPairs = 4;     ///< byte pairs in shortFingerprint()
}  // namespace

QString groupedFingerprint(const QByteArray& fingerprint) {
  QStringList lines;
  for (qsizetype at = 0; at < fingerprint.size(); at += kPairsPerLine) {
    lines << session::formatFingerprint(fingerprint.mid(at, kPairsPerLine));
  }
  return lines.join(QLatin1Char('\n'));
}

QString shortFingerprint(const QByteArray& fingerprint) {
  if (fingerprint.isEmpty()) return {};
  return session::formatFingerprint(fingerprint.left(kShortPairs)) + QStringLiteral("…");
}

QString hostTrustText(SessionController::Role role, HostTrust trust) {
  if (role == SessionController::Role::Host) {
    return SessionInfoDialog::tr(
        "This is your certificate's fingerprint. People who join can compare it with the "
        "one their Session info shows, or enter it in the Join dialog to pin it.");
  }
  switch (trust) {
    case HostTrust::Pinned:
      return SessionInfoDialog::tr("Matches the fingerprint you entered when joining.");
    case HostTrust::Known:
      return SessionInfoDialog::tr("Matches the fingerprint remembered from your first join of this address.");
    case HostTrust::FirstUse:
      return SessionInfoDialog::tr(
          "First join of this address: the fingerprint is remembered from now on. Compare "
          "it once with the one the host's Session info shows (by voice or chat).");
    case HostTrust::None:
      break;
  }
  return {};
}

QString fingerprintRefusedAdvice() {
  return SessionInfoDialog::tr(
      "Ask the host for the fingerprint its Session ▸ Session info… shows (or the one shapecast-cli host prints). "
      "If it is the one this host shows now, join again with it in the Join dialog's “Host fingerprint” field; "
      "that also replaces the remembered one. If it is not, do not join: someone may be intercepting the "
      "connection.");
}

// ---------------------------------------------------------------------------------------------------- dialog

SessionInfoDialog::SessionInfoDialog(SessionController* session, QWidget* parent)
    : QDialog(parent), m_session(session) {
  setWindowTitle(tr("Session Info"));
  m_roleLabel = new QLabel(this);
  m_roleLabel->setObjectName(QStringLiteral("roleLabel"));
  auto* caption = new QLabel(tr("Host certificate fingerprint (SHA-256):"), this);
  m_fingerprintLabel = new QLabel(this);
  m_fingerprintLabel->setObjectName(QStringLiteral("fingerprintLabel"));
  m_fingerprintLabel->setFont(QFontDatabase::systemFont(QFontDatabase::FixedFont));
  m_fingerprintLabel->setTextInteractionFlags(Qt::TextSelectableByMouse | Qt::TextSelectableByKeyboard);
  m_copyButton = new QPushButton(tr("&Copy"), this);
  m_copyButton->setObjectName(QStringLiteral("copyFingerprintButton"));
  m_copyButton->setToolTip(tr("Copy the fingerprint (one line) to the clipboard"));
  m_trustLabel = new QLabel(this);
  m_trustLabel->setObjectName(QStringLiteral("trustLabel"));
  m_trustLabel->setWordWrap(true);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close, this);

  auto* fingerprintRow = new QHBoxLayout;
  fingerprintRow->addWidget(m_fingerprintLabel, 1);
  fingerprintRow->addWidget(m_copyButton, 0, Qt::AlignTop);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(m_roleLabel);
  layout->addWidget(caption);
  layout->addLayout(fingerprintRow);
  layout->addWidget(m_trustLabel);
  layout->addStretch(1);
  layout->addWidget(buttons);

  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  connect(m_copyButton, &QPushButton::clicked, this, [this] { QGuiApplication::clipboard()->setText(m_fingerprint); });
  if (session != nullptr) {
    connect(session, &SessionController::stateChanged, this, &SessionInfoDialog::refresh);
    connect(session, &QObject::destroyed, this, &SessionInfoDialog::refresh, Qt::QueuedConnection);
  }
  refresh();
}

SessionInfoDialog::~SessionInfoDialog() = default;

void SessionInfoDialog::refresh() {
  const SessionController* s = m_session.data();
  const QByteArray fingerprint = s != nullptr ? s->hostFingerprint() : QByteArray();
  m_fingerprint = session::formatFingerprint(fingerprint);
  if (s == nullptr || s->role() == SessionController::Role::None) {
    m_roleLabel->setText(tr("Not in a session."));
  } else if (s->role() == SessionController::Role::Host) {
    m_roleLabel->setText(tr("Hosting on TCP port %1 (%2).").arg(s->tcpPort()).arg(toString(s->state())));
  } else {
    m_roleLabel->setText(tr("Joined a session (%1).").arg(toString(s->state())));
  }
  m_fingerprintLabel->setText(fingerprint.isEmpty() ? tr("(none yet)") : groupedFingerprint(fingerprint));
  m_copyButton->setEnabled(!fingerprint.isEmpty());
  m_trustLabel->setText(s != nullptr && !fingerprint.isEmpty() ? hostTrustText(s->role(), s->hostTrust()) : QString());
}

// ---------------------------------------------------------------------------------------------------- button

HostIdentityButton::HostIdentityButton(QWidget* parent) : QToolButton(parent) {
  setObjectName(QStringLiteral("hostIdentityButton"));
  setAutoRaise(true);
  setFont(QFontDatabase::systemFont(QFontDatabase::FixedFont));
}

HostIdentityButton::~HostIdentityButton() = default;

void HostIdentityButton::bind(SessionController* session) {
  if (m_session != nullptr) m_session->disconnect(this);
  m_session = session;
  if (session != nullptr) {
    connect(session, &SessionController::stateChanged, this, &HostIdentityButton::refresh);
    connect(session, &QObject::destroyed, this, &HostIdentityButton::refresh, Qt::QueuedConnection);
  }
  refresh();
}

void HostIdentityButton::refresh() {
  const SessionController* s = m_session.data();
  const QByteArray fingerprint = s != nullptr ? s->hostFingerprint() : QByteArray();
  // A client shows the certificate only once it was accepted (a refused one is in the error dialog).
  const bool shown =
      !fingerprint.isEmpty() && (s->role() == SessionController::Role::Host || s->hostTrust() != HostTrust::None);
  setText(shown ? tr("Host %1").arg(shortFingerprint(fingerprint)) : QString());
  setToolTip(shown ? tr("Host certificate fingerprint (SHA-256):\n%1\n%2\nClick for Session info.")
                         .arg(groupedFingerprint(fingerprint), hostTrustText(s->role(), s->hostTrust()))
                   : QString());
  if (shown != m_shown) {
    m_shown = shown;
    emit shownChanged(shown);
  }
}

}  // namespace sc::app
