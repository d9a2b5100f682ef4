#include "app/gui/network_conditions_dock.h"

#include "app/gui/session_controller.h"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QSpinBox>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>

namespace sc::app {

namespace {
constexpr int kMaxLossPercent = 50;
constexpr double kMaxBurst = 20.0;
constexpr int kMaxDelayMs = 2000;
constexpr double kMaxRateMbit = 10000.0;
}  // namespace

NetworkConditionsDock::NetworkConditionsDock(QWidget* parent) : QDockWidget(tr("Network conditions"), parent) {
  setObjectName(QStringLiteral("networkConditionsDock"));
  auto* body = new QWidget(this);
  auto* layout = new QVBoxLayout(body);
  m_controls = new QWidget(body);
  auto* form = new QFormLayout(m_controls);
  form->setContentsMargins(0, 0, 0, 0);

  m_lossSlider = new QSlider(Qt::Horizontal, m_controls);
  m_lossSlider->setObjectName(QStringLiteral("lossSlider"));
  m_lossSlider->setRange(0, kMaxLossPercent);
  m_lossSpin = new QDoubleSpinBox(m_controls);
  m_lossSpin->setObjectName(QStringLiteral("lossSpinBox"));
  m_lossSpin->setRange(0.0, kMaxLossPercent);
  m_lossSpin->setDecimals(1);
  m_lossSpin->setSuffix(QStringLiteral(" %"));
  m_lossSpin->setToolTip(tr("Share of the coefficient datagrams dropped on receive"));
  auto* lossRow = new QHBoxLayout;
  lossRow->addWidget(m_lossSlider, 1);
  lossRow->addWidget(m_lossSpin);
  form->addRow(tr("Loss"), lossRow);

  m_burstSpin = new QDoubleSpinBox(m_controls);
  m_burstSpin->setObjectName(QStringLiteral("burstSpinBox"));
  m_burstSpin->setRange(1.0, kMaxBurst);
  m_burstSpin->setSingleStep(0.5);
  m_burstSpin->setDecimals(1);
  m_burstSpin->setToolTip(tr("Mean number of datagrams lost in a row: 1 = independent losses, more = bursts"));
  form->addRow(tr("Burst length"), m_burstSpin);

  m_delaySpin = new QSpinBox(m_controls);
  m_delaySpin->setObjectName(QStringLiteral("delaySpinBox"));
  m_delaySpin->setRange(0, kMaxDelayMs);
  m_delaySpin->setSingleStep(10);
  m_delaySpin->setSuffix(QStringLiteral(" ms"));
  m_delaySpin->setToolTip(tr("Fixed delay added to every datagram received"));
  form->addRow(tr("Delay"), m_delaySpin);

  m_rateSpin = new QDoubleSpinBox(m_controls);
  m_rateSpin->setObjectName(QStringLiteral("rateSpinBox"));
  m_rateSpin->setRange(0.0, kMaxRateMbit);
  m_rateSpin->setDecimals(1);
  m_rateSpin->setSingleStep(1.0);
  m_rateSpin->setSuffix(QStringLiteral(" Mbit/s"));
  m_rateSpin->setSpecialValueText(tr("unlimited"));
  m_rateSpin->setToolTip(
      tr("Bandwidth of the emulated link for everything received: the model transfer and the "
         "datagrams (0 = unlimited)"));
  form->addRow(tr("Rate"), m_rateSpin);

  layout->addWidget(m_controls);
  m_label = new QLabel(body);
  m_label->setObjectName(QStringLiteral("networkConditionsLabel"));
  m_label->setWordWrap(true);
  layout->addWidget(m_label);
  layout->addStretch(1);
  setWidget(body);

  connect(m_lossSlider, &QSlider::valueChanged, this, [this](int value) {
    if (m_updating) return;
    const QSignalBlocker blocker(m_lossSpin);
    m_lossSpin->setValue(value);
    apply();
  });
  connect(m_lossSpin, &QDoubleSpinBox::valueChanged, this, [this](double value) {
    if (m_updating) return;
    const QSignalBlocker blocker(m_lossSlider);
    m_lossSlider->setValue(static_cast<int>(std::lround(value)));
    apply();
  });
  connect(m_burstSpin, &QDoubleSpinBox::valueChanged, this, [this] {
    if (!m_updating) apply();
  });
  connect(m_delaySpin, &QSpinBox::valueChanged, this, [this] {
    if (!m_updating) apply();
  });
  connect(m_rateSpin, &QDoubleSpinBox::valueChanged, this, [this] {
    if (!m_updating) apply();
  });
  updateEnabled();
  hide();  // shown when a session turns out to be a client's
}

NetworkConditionsDock::~NetworkConditionsDock() = default;

void NetworkConditionsDock::bind(SessionController* controller) {
  if (m_controller) m_controller->disconnect(this);
  m_controller = controller;
  if (controller != nullptr) {
    // join() creates the client (with JoinSettings::impairment) after sessionStarted(): re-read on state changes.
    connect(controller, &SessionController::stateChanged, this, &NetworkConditionsDock::showControllerConditions);
    connect(controller, &SessionController::networkConditionsChanged, this,
            &NetworkConditionsDock::showControllerConditions);
  }
  hide();  // until the controller turns out to be a client (join() runs after sessionStarted())
  showControllerConditions();
}

void NetworkConditionsDock::setConditions(double lossPercent, double burstLength, int delayMs, double rateMbit) {
  {
    m_updating = true;
    m_lossSpin->setValue(lossPercent);
    m_lossSlider->setValue(static_cast<int>(std::lround(m_lossSpin->value())));
    m_burstSpin->setValue(burstLength);
    m_delaySpin->setValue(delayMs);
    m_rateSpin->setValue(rateMbit);
    m_updating = false;
  }
  apply();
}

double NetworkConditionsDock::lossPercent() const { return m_lossSpin->value(); }
double NetworkConditionsDock::burstLength() const { return m_burstSpin->value(); }
int NetworkConditionsDock::delayMs() const { return m_delaySpin->value(); }
double NetworkConditionsDock::rateMbit() const { return m_rateSpin->value(); }

void NetworkConditionsDock::apply() {
  if (m_controller && m_controller->role() == SessionController::Role::Client) {
    m_applying = true;  // keep the controls as the user left them (e.g. a burst length while loss is 0)
    m_controller->setNetworkConditions(lossPercent() / 100.0, burstLength(), delayMs(), rateMbit());
    m_applying = false;
  }
  updateEnabled();
}

void NetworkConditionsDock::showControllerConditions() {
  if (m_applying) return;
  const NetworkConditions conditions = m_controller ? m_controller->networkConditions() : NetworkConditions{};
  m_updating = true;
  m_lossSpin->setValue(100.0 * conditions.loss);
  m_lossSlider->setValue(static_cast<int>(std::lround(m_lossSpin->value())));
  m_burstSpin->setValue(conditions.burstLength);
  m_delaySpin->setValue(conditions.delayMs);
  m_rateSpin->setValue(conditions.rateMbit);
  m_updating = false;
  updateEnabled();
  // Shown where it applies, once per client session; elsewhere View → Network conditions shows it (disabled).
  if (m_controller && m_controller->role() == SessionController::Role::Client && m_shownFor != m_controller) {
    m_shownFor = m_controller;
    show();
  }
}

void NetworkConditionsDock::updateEnabled() {
  const bool client = m_controller && m_controller->role() == SessionController::Role::Client;
  const SessionController::State state = m_controller ? m_controller->state() : SessionController::State::Idle;
  const bool active =
      client && (state == SessionController::State::Connecting || state == SessionController::State::Live);
  m_controls->setEnabled(active);
  if (!client) {
    m_label->setText(tr("Join a session to emulate loss and delay on what this window receives."));
  } else if (!active) {
    m_label->setText(tr("Not connected."));
  } else if (lossPercent() == 0.0 && delayMs() == 0 && rateMbit() == 0.0) {
    m_label->setText(tr("No emulated impairment: datagrams arrive as the network delivers them."));
  } else {
    const QString rate = rateMbit() > 0.0 ? tr(", a %1 Mbit/s link").arg(rateMbit(), 0, 'f', 1) : QString();
    m_label->setText(
        tr("Emulating %1 % loss (%2), %3 ms delay%4 on receive.")
            .arg(lossPercent(), 0, 'f', 1)
            .arg(burstLength() > 1.0 ? tr("bursts of %1").arg(burstLength(), 0, 'f', 1) : tr("independent"))
            .arg(delayMs())
            .arg(rate));
  }
}

}  // namespace sc::app
