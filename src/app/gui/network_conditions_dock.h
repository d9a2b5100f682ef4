#pragma once
// NetworkConditionsDock: the client's "Network conditions" panel (issue 5 item 8). Emulated loss % (slider and spin
// box, 0–50), mean burst length (1 = independent Bernoulli loss, more = Gilbert–Elliott bursts) and a fixed delay
// in milliseconds, and the link rate in Mbit/s (issue 17: 0 = unlimited; it throttles the level transfer as well as
// the datagrams), applied live to the bound SessionController (setNetworkConditions), so a user can watch the
// distortion react in the Statistics dock. Enabled only while the bound controller is a client that is connecting
// or live; a host (or no session) shows why it is disabled. Hidden until the window joins a session (shown once per
// joined session; the View menu's toggle shows or hides it any time). Wiring only: the impairment itself is the
// session's.

#include <QDockWidget>
#include <QPointer>

class QDoubleSpinBox;
class QLabel;
class QSlider;
class QSpinBox;

namespace sc::app {

class SessionController;

class NetworkConditionsDock final : public QDockWidget {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(NetworkConditionsDock)

 public:
  /// objectName "networkConditionsDock"; children "lossSlider", "lossSpinBox", "burstSpinBox", "delaySpinBox",
  /// "rateSpinBox" (Mbit/s, 0 = unlimited), "networkConditionsLabel".
  explicit NetworkConditionsDock(QWidget* parent = nullptr);
  ~NetworkConditionsDock() override;

  /// Follows `controller` from now on (nullptr: none): shows its current conditions, enables the controls when it
  /// is a client, and applies every change to it.
  void bind(SessionController* controller);

  /// Sets the controls (and, when bound to a client, applies them): loss in percent (0–50), burst length (≥ 1),
  /// delay in ms (≥ 0), rate in Mbit/s (0 = unlimited). Values are clamped to the controls' ranges.
  void setConditions(double lossPercent, double burstLength, int delayMs, double rateMbit = 0.0);
  [[nodiscard]] double lossPercent() const;
  [[nodiscard]] double burstLength() const;
  [[nodiscard]] int delayMs() const;
  [[nodiscard]] double rateMbit() const;

 private:
  void apply();
  void updateEnabled();
  void showControllerConditions();

  QPointer<SessionController> m_controller;
  QPointer<SessionController> m_shownFor;  ///< the client session the dock was shown for
  QSlider* m_lossSlider = nullptr;
  QDoubleSpinBox* m_lossSpin = nullptr;
  QDoubleSpinBox* m_burstSpin = nullptr;
  QSpinBox* m_delaySpin = nullptr;
  QDoubleSpinBox* m_rateSpin = nullptr;
  QLabel* m_label = nullptr;
  QWidget* m_controls = nullptr;
  bool m_updating = false;  ///< setting the controls from code: do not apply
  bool m_applying = false;  ///< inside apply(): the controller's change notification is ours
};

}  // namespace sc::app
