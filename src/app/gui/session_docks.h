#pragma once
// The Peers and Statistics docks of a session window, and what feeds their models: on every peersChanged /
// lockChanged / statsChanged of the bound SessionController it rebuilds the PeerTableModel rows and appends one
// sample per reporting peer to that peer's StatisticsModel (the last 60 s). The once-a-second refresh repaints both
// docks in one pass (RepaintBatch). Wiring only: the figures come from the
// controller (a host sees every client's reports; a client its own), the views from the docks.

#include <QElapsedTimer>
#include <QObject>
#include <QPointer>

#include <map>
#include <memory>

class QMainWindow;

namespace sc::model {
class PeerTableModel;
class StatisticsModel;
}  // namespace sc::model

namespace sc::app {

class PeersDock;
class RepaintBatch;
class SessionController;
class StatisticsDock;

class SessionDocks final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(SessionDocks)

 public:
  /// Creates both docks (right dock area of `window`) with empty models.
  explicit SessionDocks(QMainWindow* window);
  ~SessionDocks() override;

  /// Observes `controller` from now on (nullptr: none); the models start empty.
  void bind(SessionController* controller);

  [[nodiscard]] PeersDock* peersDock() const { return m_peersDock; }
  [[nodiscard]] StatisticsDock* statisticsDock() const { return m_statisticsDock; }
  [[nodiscard]] model::PeerTableModel* peerModel() const { return m_peerModel; }
  /// The statistics of one peer (nullptr before its first figures).
  [[nodiscard]] model::StatisticsModel* statisticsOf(quint32 peer) const;
  /// Both docks' once-a-second repaint (RepaintBatch): held while the figures settle, then one pass.
  [[nodiscard]] RepaintBatch* repaintBatch() const { return m_repaint; }

 private:
  void refreshPeers();
  void appendStatistics();
  void showStatisticsOf(quint32 peer);

  QPointer<SessionController> m_controller;
  PeersDock* m_peersDock = nullptr;
  StatisticsDock* m_statisticsDock = nullptr;
  model::PeerTableModel* m_peerModel = nullptr;
  RepaintBatch* m_repaint = nullptr;                        ///< child of this
  std::map<quint32, model::StatisticsModel*> m_statistics;  ///< children of this
  quint32 m_shownPeer = 0;
  QElapsedTimer m_clock;  ///< sample times: seconds since bind()
};

}  // namespace sc::app
