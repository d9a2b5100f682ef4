#pragma once
// SessionPresence: presence in a session window (issue 15), wiring only. It sends this user's view (camera, pointer,
// dragging) through the bound SessionController, paced by session::PresenceSchedule (polled every
// kPollMilliseconds: ≤ 30/s while it changes, 2/s idle), keeps the others' latest presence (session::PresenceBoard,
// pruned by every PeerList) and shows it: markers in the MeshViewport (PresenceOverlay, in each user's peerColor())
// and "Follow NAME" in the Peers dock's context menu. While following, the local camera copies that user's camera
// on every update; any orbit, pan or zoom of the local user stops following (as does the user leaving).

#include "session/engine/presence_board.h"
#include "session/engine/presence_schedule.h"

#include <QObject>
#include <QPointer>
#include <QTimer>

class QAction;
class QMenu;

namespace sc::app {

class MeshViewport;
class PeersDock;
class SessionController;

class SessionPresence final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(SessionPresence)

 public:
  static constexpr int kPollMilliseconds = 33;

  /// @param viewport, peers  this window's view and Peers dock (outlive this object: both are the window's).
  SessionPresence(MeshViewport* viewport, PeersDock* peers, QObject* parent);
  ~SessionPresence() override;

  /// Observes `controller` from now on (nullptr: none); the board starts empty, following stops.
  void bind(SessionController* controller);

  /// The others' latest presence.
  [[nodiscard]] const session::PresenceBoard& board() const { return m_board; }
  /// Follows `peer`'s camera (kNoPeer: stop). A peer not on the board is followed from its next presence.
  void follow(session::PeerId peer);
  [[nodiscard]] session::PeerId following() const { return m_following; }
  /// The Peers dock's context menu for `peer`: "Follow NAME" (not for this user) and, while following, "Stop
  /// following". Owned by `parent`.
  QMenu* contextMenu(session::PeerId peer, QWidget* parent);

 signals:
  /// The board changed (a presence arrived or a peer left).
  void boardChanged();
  void followingChanged(quint32 peer);

 private:
  void onPresence(const session::Presence& presence);
  void onPeers();
  void offer();
  void refreshMarkers();
  void showContextMenu(const QPoint& position);

  QPointer<SessionController> m_controller;
  MeshViewport* m_viewport = nullptr;
  PeersDock* m_peers = nullptr;
  session::PresenceBoard m_board;
  session::PresenceSchedule m_schedule;
  QTimer m_poll;
  session::PeerId m_following = session::kNoPeer;
};

}  // namespace sc::app
