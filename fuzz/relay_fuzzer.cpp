// Fuzz target "relay": the relay decoders (src/session/wire/relay_message.h, engine/relay_receiver.h and
// engine/relay_audience.h; issue 18), with one identity generated once per process.
//
// Input: one mode byte, then a message. Mode (mod 4):
//   0  the bytes as a frame message from the broker, as is (trailer, signature: almost always refused);
//   1  the bytes as a frame body, signed by the harness's host key, so the fuzzer reaches the post-signature parsing
//      (header, row count, finiteness) and the receiver's rules (latest wins, loss, stale);
//   2  the bytes as a viewer's Stats message to the host's RelayAudience;
//   3  the bytes as a verified Levels body (relay_level_list.h): accepted only when it re-encodes to the same bytes,
//      with ascending indices below `total` and chunkBytes in range.
// Invariants checked: the receiver's Z is m by 3 (m = the facts' m) and finite once a frame applied; its counters
// never go negative; a Stats message is accepted only at exactly kRelayStatsSize bytes.

#include "fuzz_support.h"
#include "session/engine/relay_audience.h"
#include "session/engine/relay_receiver.h"
#include "session/net/tls_identity.h"
#include "session/wire/relay_level_list.h"
#include "session/wire/relay_message.h"

#include <QtCore/QByteArray>

#include <optional>

namespace {

using namespace sc::session;

constexpr int kRows = 20;
const QString kSid = QStringLiteral("fuzz");

const TlsIdentity& identity() {
  static const TlsIdentity id = *generateTlsIdentity(QStringLiteral("fuzz"));
  return id;
}

const RelaySigner& signer() {
  static const RelaySigner s(identity().privateKey.toDer(), kSid);
  return s;
}

/// A receiver that has the facts and a keyframe (frame 100), as a viewer after its join.
RelayReceiver joinedReceiver() {
  RelayReceiver receiver(kSid, identity().fingerprint());
  RelayFacts facts;
  facts.rowCount = kRows;
  facts.vertexCount = 1000;
  facts.certificateDer = identity().certificate.toDer();
  sc::fuzz::check(receiver.onFacts(signer().sign(encodeRelayFactsBody(facts))) == RelayFactsStatus::None, "facts");
  RelayFrame keyframe;
  keyframe.frame = 100;
  keyframe.Z = Eigen::MatrixXd::Zero(kRows, 3);
  sc::fuzz::check(receiver.onKeyframe(signer().sign(encodeRelayFrameBody(keyframe)), Micros{1}), "keyframe");
  return receiver;
}

void fuzzFrame(const QByteArray& message) {
  RelayReceiver receiver = joinedReceiver();
  receiver.onFrame(message, Micros{2});
  const RelayViewerStats stats = receiver.stats(Micros{2});
  sc::fuzz::check(receiver.coefficients().rows() == kRows && receiver.coefficients().cols() == 3, "Z is m by 3");
  sc::fuzz::check(receiver.coefficients().allFinite(), "Z is finite");
  sc::fuzz::check(stats.lost >= 0 && stats.stale >= 0 && stats.applied >= 1, "counters");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sc::fuzz::Input input = sc::fuzz::splitMode(data, size);
  const QByteArray bytes(reinterpret_cast<const char*>(input.rest.data()), static_cast<qsizetype>(input.rest.size()));
  switch (input.mode % 4) {
    case 0:
      fuzzFrame(bytes);
      break;
    case 1:
      fuzzFrame(signer().sign(bytes));
      break;
    case 3: {
      const std::optional<RelayLevelList> list = decodeRelayLevelListBody(bytes);
      if (!list) break;
      sc::fuzz::check(encodeRelayLevelListBody(*list) == bytes, "a level list round-trips");
      sc::fuzz::check(
          list->levels.size() <= list->total && list->chunkBytes >= 1 && list->chunkBytes <= kMaxRelayChunkBytes,
          "level list bounds");
      for (std::size_t i = 1; i < list->levels.size(); ++i) {
        sc::fuzz::check(list->levels[i - 1].index < list->levels[i].index, "ascending");
      }
      break;
    }
    default: {
      RelayAudience audience;
      const bool accepted = audience.onStats(bytes, Micros{1});
      sc::fuzz::check(!accepted || bytes.size() == kRelayStatsSize, "stats size");
      sc::fuzz::check(audience.summary(Micros{1}).viewers == (accepted ? 1 : 0), "one viewer per accepted stats");
      break;
    }
  }
  return 0;
}
