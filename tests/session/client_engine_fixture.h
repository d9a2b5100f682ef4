#pragma once
// Shared helpers of the ClientEngine suites (client_engine_*_test.cpp): a fake host that drives the engine through
// its events with an injected clock (no sockets, no timers, no threads), and readers of the actions it returns.

#include "session/engine/client_engine.h"
#include "session/wire/control_frame.h"
#include "session/wire/model_transfer.h"
#include "spectral/display_level.h"
#include "spectral/resolution_level.h"

#include <gtest/gtest.h>

#include <vector>

namespace sc::session::test {

inline constexpr Micros kT0{5'000'000};        ///< the fake clock's time of the join
inline constexpr std::uint16_t kRows = 2;      ///< m of the fake session
inline constexpr std::uint32_t kVertices = 3;  ///< n of the fake session
inline constexpr PeerId kSelf = 3;

inline Welcome fakeWelcome() {
  return Welcome{kSelf, QByteArray(kDatagramKeySize, 'k'), QByteArray(kPathTokenSize, 't'), kRows, kVertices, 4000};
}

inline ClientEngineConfig config(const char* name, std::uint32_t level = 0, std::optional<double> fraction = {},
                                 Millis hostTimeout = Millis{10000}) {
  return ClientEngineConfig{QString::fromUtf8(name), std::nullopt, level, fraction, hostTimeout, kMinPbkdf2Iterations};
}

inline ControlDecodeResult message(ControlMessage m) { return ControlDecodeResult{ControlError::None, std::move(m)}; }

/// Every action of type A in `actions`, in order.
template <class A>
std::vector<A> actionsOf(const ClientActions& actions) {
  std::vector<A> out;
  for (const ClientAction& action : actions) {
    if (const A* a = std::get_if<A>(&action)) out.push_back(*a);
  }
  return out;
}

/// The control messages the Send actions carry, decoded as the host would.
inline std::vector<ControlMessage> sentMessages(const ClientActions& actions) {
  ControlFrameReader reader;
  for (const client_action::Send& send : actionsOf<client_action::Send>(actions)) reader.append(send.frame);
  std::vector<ControlMessage> out;
  while (std::optional<ControlDecodeResult> result = reader.next()) {
    EXPECT_EQ(result->error, ControlError::None);
    out.push_back(std::move(result->message));
  }
  return out;
}

/// The messages of type M among the Send actions.
template <class M>
std::vector<M> sent(const ClientActions& actions) {
  std::vector<M> out;
  for (const ControlMessage& m : sentMessages(actions)) {
    if (const M* typed = std::get_if<M>(&m)) out.push_back(*typed);
  }
  return out;
}

/// The states announced by `actions`, in order.
inline std::vector<ClientState> statesOf(const ClientActions& actions) {
  std::vector<ClientState> out;
  for (const client_action::StateChanged& s : actionsOf<client_action::StateChanged>(actions)) out.push_back(s.state);
  return out;
}

/// Drives `engine` from Idle to Loading at `now` (connect, secure, Hello, Welcome, datagrams opened); returns the
/// actions of the last step (the ResolutionRequest among them).
inline ClientActions joinSession(ClientEngine& engine, Micros now = kT0) {
  engine.start();
  engine.onSecured(QByteArray(32, 'c'), now);
  engine.onMessage(message(fakeWelcome()), now);
  return engine.onDatagramsOpened(now);
}

/// A level of the fake session (n' = 3 = n, P = identity, K n' by m), wrapped for display.
inline spectral::ResolutionLevel tinyLevel(float kScale = 1.0f) {
  spectral::ResolutionLevel level;
  level.restV = Eigen::MatrixXd::Identity(3, 3);
  level.F = Eigen::MatrixXi(1, 3);
  level.F << 0, 1, 2;
  level.P.resize(3, kVertices);
  level.P.setIdentity();
  level.K = spectral::quantizeBasis(Eigen::MatrixXd::Constant(3, kRows, kScale));
  return level;
}

/// tinyLevel() encoded: an honest payload of the fake session.
inline QByteArray encoded(const spectral::ResolutionLevel& level) {
  const std::vector<std::byte> bytes = spectral::encodeResolutionLevel(level);
  return QByteArray(reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size()));
}

/// A payload of exactly the size of an encoded tinyLevel() (what a LevelList of the fake session may announce),
/// starting with `tag` so that tests can tell transfers apart.
inline QByteArray tinyPayload(const char* tag) {
  QByteArray payload = encoded(tinyLevel());
  payload.replace(0, static_cast<qsizetype>(qstrlen(tag)), tag);
  return payload;
}

/// The fake host's LevelList: one level (the full model, n' = n = 3, one face) of `payloadBytes`.
inline LevelList tinyLevelList(std::uint32_t payloadBytes) {
  return LevelList{1, {LevelInfo{0, kVertices, 1, payloadBytes}}};
}

inline DecodedLevel decodedLevel(float kScale = 1.0f) {
  return DecodedLevel{QByteArray("payload"), spectral::makeDisplayLevel(tinyLevel(kScale)), {}};
}

/// Lists a level of payload.size() bytes (tinyLevelList), then sends `payload` as transfer `id` in chunks of
/// `chunkBytes`; returns the actions of the last chunk.
inline ClientActions deliverTransfer(ClientEngine& engine, const QByteArray& payload, std::uint32_t id, Micros now,
                                     std::uint32_t chunkBytes = kMaxChunkBytes) {
  engine.onMessage(message(tinyLevelList(static_cast<std::uint32_t>(payload.size()))), now);
  ModelSender sender(id, TransferKind::Level, kVertices, payload, chunkBytes);
  ClientActions last = engine.onMessage(message(sender.begin()), now);
  while (std::optional<ModelChunk> chunk = sender.nextChunk()) last = engine.onMessage(message(*chunk), now);
  return last;
}

}  // namespace sc::session::test
