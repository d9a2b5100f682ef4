// Fuzz target "control": the TCP control channel, from bytes to state machines.
//
// Input: one mode byte, then a byte stream as a peer would send it. The stream is appended to a
// ControlFrameReader in chunks of `mode` bytes (mode 0: all at once), so arbitrary split points are covered, and
// next() is drained after every append. Every frame the reader yields goes where the real adapters send it:
//   - a decoded message must re-encode to a frame that decodes to an equal value (control_messages.h contract);
//   - both handshakes get it (a password host with PBKDF2 iterations 1, an open host, and a client with a
//     password; a Challenge of more than kClientIterationLimit iterations is not handed to the client, only
//     because its PBKDF2 would slow the fuzzer to a crawl, not because it is unsafe);
//   - ModelBegin/ModelChunk drive a ModelReceiver (unchecked, so a completed payload is reached) and a completed
//     Level payload is decoded with decodeResolutionLevel (the model transfer's level payload);
//   - decode errors go to the handshakes' handleDecodeError.
// Invariants checked: the round trip above; after Oversize the reader is failed() and yields nothing more; the
// receiver never holds more bytes than its transfer announced.

#include "fuzz_support.h"
#include "session/engine/handshake_client.h"
#include "session/engine/handshake_host.h"
#include "session/wire/control_frame.h"
#include "session/wire/control_messages.h"
#include "session/wire/model_transfer.h"
#include "session/wire/password_auth.h"
#include "spectral/resolution_level.h"

#include <QtCore/QtEndian>

#include <algorithm>

namespace {

using namespace sc::session;

constexpr std::uint32_t kClientIterationLimit = 64;

QByteArray fixedRandom(int count) { return QByteArray(count, '\x3c'); }

HostHandshakeConfig hostConfig(bool withPassword) {
  HostHandshakeConfig config;
  if (withPassword) config.secret = makeSessionSecret(QStringLiteral("fuzz"), 1, fixedRandom);
  config.rowCount = 100;
  config.vertexCount = 1000;
  config.udpPort = 4000;
  config.peerId = 3;
  config.random = fixedRandom;
  return config;
}

ClientHandshakeConfig clientConfig() {
  ClientHandshakeConfig config;
  config.displayName = QStringLiteral("fuzz");
  config.password = QStringLiteral("fuzz");
  return config;
}

void checkRoundTrip(const ControlMessage& message) {
  const QByteArray frame = encodeControlMessage(message);
  sc::fuzz::check(frame.size() >= kControlHeaderSize, "an accepted message re-encodes");
  sc::fuzz::check(qFromBigEndian<std::uint32_t>(frame.constData()) == static_cast<std::uint32_t>(frame.size() - 4),
                  "length field is type + body");
  const auto type = static_cast<std::uint8_t>(frame.at(4));
  sc::fuzz::check(type == static_cast<std::uint8_t>(messageType(message)), "frame type is the message's type");
  const ControlDecodeResult again = decodeControlMessage(type, QByteArrayView(frame).sliced(kControlHeaderSize));
  sc::fuzz::check(again.error == ControlError::None && again.message == message, "re-encoded message decodes equal");
}

/// Everything one connection's stream reaches.
class Receivers {
 public:
  Receivers() : m_passwordHost(hostConfig(true), Millis{0}), m_openHost(hostConfig(false), Millis{0}) {
    m_client.start();
  }

  void deliver(const ControlDecodeResult& result) {
    if (result.error != ControlError::None) {
      m_passwordHost.handleDecodeError(result.error);
      m_openHost.handleDecodeError(result.error);
      m_client.handleDecodeError(result.error);
      return;
    }
    checkRoundTrip(result.message);
    m_passwordHost.handleMessage(result.message);
    m_openHost.handleMessage(result.message);
    const auto* challenge = std::get_if<Challenge>(&result.message);
    if (challenge == nullptr || challenge->iterations <= kClientIterationLimit) {
      const HandshakeOutput out = m_client.handleMessage(result.message);
      if (out.deriveKey) {  // what the adapter's worker does, then the proof
        const PasswordKeyRequest& r = *out.deriveKey;
        m_client.keyDerived(derivePasswordKey(r.password, r.salt, r.iterations));
      }
    }
    if (const auto* begin = std::get_if<ModelBegin>(&result.message)) m_receiver.begin(*begin);
    if (const auto* chunk = std::get_if<ModelChunk>(&result.message)) receiveChunk(*chunk);
  }

 private:
  void receiveChunk(const ModelChunk& chunk) {
    const bool isLevel = m_receiver.current() && m_receiver.current()->kind == TransferKind::Level;
    const ModelReceiver::Status status = m_receiver.addUnchecked(chunk);
    sc::fuzz::check(m_receiver.receivedBytes() <= m_receiver.totalBytes(), "receiver holds ≤ the announced bytes");
    if (status != ModelReceiver::Status::Complete) return;
    const QByteArray payload = m_receiver.take();
    if (isLevel) sc::spectral::decodeResolutionLevel(std::as_bytes(std::span(payload.constData(), payload.size())));
  }

  HostHandshake m_passwordHost;
  HostHandshake m_openHost;
  ClientHandshake m_client{clientConfig()};
  ModelReceiver m_receiver;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sc::fuzz::Input input = sc::fuzz::splitMode(data, size);
  const std::size_t chunk = input.mode == 0 ? std::max<std::size_t>(input.rest.size(), 1) : input.mode;
  ControlFrameReader reader;
  Receivers receivers;
  bool oversize = false;
  for (std::size_t offset = 0; offset < input.rest.size(); offset += chunk) {
    const std::size_t length = std::min(chunk, input.rest.size() - offset);
    reader.append(QByteArrayView(input.rest.data() + offset, static_cast<qsizetype>(length)));
    while (const std::optional<ControlDecodeResult> result = reader.next()) {
      sc::fuzz::check(!oversize, "nothing after Oversize");
      oversize = result->error == ControlError::Oversize;
      receivers.deliver(*result);
    }
    sc::fuzz::check(reader.failed() == oversize, "failed() exactly after Oversize");
  }
  return 0;
}
