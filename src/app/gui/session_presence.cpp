#include "app/gui/session_presence.h"

#include "app/gui/mesh_viewport.h"
#include "app/gui/peer_colors.h"
#include "app/gui/peers_dock.h"
#include "app/gui/session_controller.h"
#include "model/peer_table_model.h"
#include "session/engine/session_clock.h"

#include <QMenu>
#include <QTableView>

namespace sc::app {
namespace {

session::Presence::Point presencePoint(const QVector3D& v) { return {v.x(), v.y(), v.z()}; }
QVector3D presenceVector(const session::Presence::Point& p) {
  return {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
}

}  // namespace

SessionPresence::SessionPresence(MeshViewport* viewport, PeersDock* peers, QObject* parent)
    : QObject(parent), m_viewport(viewport), m_peers(peers) {
  m_poll.setInterval(kPollMilliseconds);
  connect(&m_poll, &QTimer::timeout, this, &SessionPresence::offer);
  connect(m_viewport, &MeshViewport::cameraMovedByUser, this, [this] { follow(session::kNoPeer); });
  m_peers->view()->setContextMenuPolicy(Qt::CustomContextMenu);
  connect(m_peers->view(), &QWidget::customContextMenuRequested, this, &SessionPresence::showContextMenu);
}

SessionPresence::~SessionPresence() = default;

void SessionPresence::bind(SessionController* controller) {
  if (m_controller) m_controller->disconnect(this);
  m_controller = controller;
  m_board.clear();
  m_schedule.reset();
  follow(session::kNoPeer);
  refreshMarkers();
  if (controller == nullptr) {
    m_poll.stop();
    return;
  }
  connect(controller, &SessionController::presenceReceived, this, &SessionPresence::onPresence);
  connect(controller, &SessionController::peersChanged, this, &SessionPresence::onPeers);
  m_poll.start();
}

void SessionPresence::follow(session::PeerId peer) {
  if (peer == m_following) return;
  m_following = peer;
  if (const session::RemotePresence* entry = m_board.find(peer)) {
    m_viewport->lookFrom(presenceVector(entry->presence.eye), presenceVector(entry->presence.target));
  }
  emit followingChanged(peer);
}

void SessionPresence::onPresence(const session::Presence& presence) {
  if (!m_board.update(presence, session::sessionNow())) return;
  if (presence.author == m_following) {
    m_viewport->lookFrom(presenceVector(presence.eye), presenceVector(presence.target));
  }
  refreshMarkers();
  emit boardChanged();
}

void SessionPresence::onPeers() {
  if (!m_controller) return;
  m_board.setPeers(m_controller->peers(), m_controller->selfId());
  if (m_following != session::kNoPeer && m_board.nameOf(m_following).isEmpty()) follow(session::kNoPeer);
  refreshMarkers();
  emit boardChanged();
}

void SessionPresence::offer() {
  if (!m_controller || m_controller->state() != SessionController::State::Live) return;
  const MeshViewport::LocalView view = m_viewport->localView();
  session::Presence presence{session::kNoPeer,        presencePoint(view.eye),  presencePoint(view.target),
                             presencePoint(view.up),  view.pointer.has_value(), {},
                             m_controller->dragging()};
  if (view.pointer) presence.pointer = presencePoint(*view.pointer);
  presence.handleOn = view.handle.has_value();
  if (view.handle) presence.handle = presencePoint(*view.handle);
  if (m_schedule.offer(presence, session::sessionNow())) m_controller->sendPresence(presence);
}

void SessionPresence::refreshMarkers() {
  std::vector<PresenceMarker> markers;
  for (const auto& [id, entry] : m_board.entries()) {
    const session::Presence& p = entry.presence;
    PresenceMarker marker{
        id,           entry.name, peerColor(id), presenceVector(p.eye), presenceVector(p.target), presenceVector(p.up),
        std::nullopt, p.dragging, std::nullopt};
    if (p.pointerOn) marker.pointer = presenceVector(p.pointer);
    if (p.handleOn) marker.handle = presenceVector(p.handle);
    markers.push_back(std::move(marker));
  }
  m_viewport->setPresenceMarkers(std::move(markers));
}

QMenu* SessionPresence::contextMenu(session::PeerId peer, QWidget* parent) {
  auto* menu = new QMenu(parent);
  const QString name = m_board.nameOf(peer);
  if (!name.isEmpty()) {
    QAction* followAction = menu->addAction(tr("Follow %1").arg(name), this, [this, peer] { follow(peer); });
    followAction->setCheckable(true);
    followAction->setChecked(m_following == peer);
  }
  if (m_following != session::kNoPeer) {
    menu->addAction(tr("Stop following"), this, [this] { follow(session::kNoPeer); });
  }
  return menu;
}

void SessionPresence::showContextMenu(const QPoint& position) {
  const QModelIndex index = m_peers->view()->indexAt(position);
  const quint32 peer = index.isValid() ? index.data(model::PeerTableModel::PeerIdRole).toUInt() : session::kNoPeer;
  QMenu* menu = contextMenu(peer, m_peers->view());
  menu->setAttribute(Qt::WA_DeleteOnClose);
  if (menu->isEmpty()) {
    delete menu;
    return;
  }
  menu->popup(m_peers->view()->viewport()->mapToGlobal(position));
}

}  // namespace sc::app
