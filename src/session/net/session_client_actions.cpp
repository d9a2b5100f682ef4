// SessionClient: the translation of the engine's actions into socket calls and signals, one line of work each.

#include "session/net/session_client.h"

#include "session/engine/session_clock.h"

#include "session/net/tls_stream.h"

#include <QtNetwork/QHostAddress>

#include <utility>
#include <variant>

namespace sc::session {
namespace {

SessionClient::State toState(ClientState state) {
  using S = SessionClient::State;
  static_assert(static_cast<int>(S::Idle) == static_cast<int>(ClientState::Idle) &&
                    static_cast<int>(S::Connecting) == static_cast<int>(ClientState::Connecting) &&
                    static_cast<int>(S::Handshaking) == static_cast<int>(ClientState::Handshaking) &&
                    static_cast<int>(S::Loading) == static_cast<int>(ClientState::Loading) &&
                    static_cast<int>(S::Ready) == static_cast<int>(ClientState::Ready) &&
                    static_cast<int>(S::Left) == static_cast<int>(ClientState::Left) &&
                    static_cast<int>(S::Failed) == static_cast<int>(ClientState::Failed),
                "SessionClient::State mirrors ClientState");
  return static_cast<S>(state);
}

}  // namespace

void SessionClient::apply(ClientActions actions) {
  for (ClientAction& action : actions) std::visit([this](auto& a) { execute(a); }, action);
  armTimer();
}

void SessionClient::execute(client_action::Connect) {
  m_stream->connectToHostEncrypted(m_options.host, m_options.port);
}

void SessionClient::execute(client_action::Send& send) {
  m_stream->write(send.frame);  // dropped unless connected
}

void SessionClient::execute(client_action::StateChanged changed) {
  m_state = toState(changed.state);
  emit stateChanged(m_state);
}

void SessionClient::execute(client_action::OpenDatagrams& open) {
  QHostAddress host = m_stream->peerAddress();
  bool ipv4 = false;
  const quint32 v4 = host.toIPv4Address(&ipv4);
  if (ipv4) host = QHostAddress(v4);
  QString error;
  if (!m_channel->bind(QHostAddress(ipv4 ? QHostAddress::AnyIPv4 : QHostAddress::AnyIPv6), &error)) {
    apply(m_engine.fail(QStringLiteral("UDP bind failed: %1").arg(error)));
    return;
  }
  const Welcome& s = open.session;
  m_channel->open(host, s.udpPort, s.peerId, s.datagramKey, s.pathToken, s.rowCount);
  apply(m_engine.onDatagramsOpened(sessionNow()));
}

void SessionClient::execute(client_action::CloseDatagrams) { m_channel->close(); }

void SessionClient::execute(client_action::Disconnect disconnect) {
  if (disconnect.flush) {
    m_stream->disconnectFromHost();  // writes what was sent first (our Leave)
  } else {
    m_stream->abort();
  }
}

void SessionClient::execute(client_action::Failed& failure) { emit failed(failure.reason); }

void SessionClient::execute(client_action::Notify notify) {
  switch (notify.notice) {
    case ClientNotice::PeersChanged:
      emit peersChanged();
      return;
    case ClientNotice::LevelsChanged:
      emit levelsChanged();
      return;
    case ClientNotice::LockChanged:
      emit lockChanged();
      return;
    case ClientNotice::EditLogChanged:
      emit editLogChanged();
      return;
    case ClientNotice::LevelChoiceKept:
      return;  // sent once the preview is in
    case ClientNotice::LevelInstalled:
      m_positions.assign(displayLevel()->rest.size(), 0.0f);
      emit displayLevelChanged(displayLevel());
      return;
  }
}

void SessionClient::execute(client_action::ModelProgress progress) {
  // An accepted transfer may be read ahead of this thread (its size is checked against the LevelList first).
  if (progress.received == 0) grantReadAhead(progress.total);
  if (progress.received == progress.total) grantReadAhead(0);
  emit modelProgress(progress.received, progress.total);
}

void SessionClient::execute(client_action::SeedKeyframe& keyframe) {
  m_channel->seed(keyframe.frame, keyframe.Z);  // ignored once datagram frames flow; emits frameUpdated if applied
  emit keyframeReceived(keyframe.frame, keyframe.Z);
}

void SessionClient::execute(client_action::LevelFailed& failure) { emit levelFailed(failure.reason); }

void SessionClient::execute(client_action::LevelReady ready) { emit levelReady(ready.vertexCount); }

}  // namespace sc::session
