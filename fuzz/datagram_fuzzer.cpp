// Fuzz target "datagram": the UDP decoders, with the harness's fixed key (fuzz_support.h).
//
// Input: one mode byte, then a datagram. Mode (low 2 bits):
//   0  coefficient datagram as is: the pre-authentication checks (length, tag) of CoefficientDecoder;
//   1  coefficient datagram in clear (header ‖ payload): the harness seals it (AES-128-GCM, nonce from the extended
//      sequence a fresh decoder derives from the header), so the fuzzer reaches the post-authentication
//      parsing (header ranges, exponents, rows), the replay window and FrameAssembler;
//   2  path-open datagram as is (decodePathOpen: length, peer lookup, tag);
//   3  path-open body (26 bytes expected): valid tag appended, so magic/version/type, token and sequence are reached;
//   4  path challenge/response as is (decodePathProbe: length, type, tag), both types;
//   5  path probe body (14 bytes expected): valid tag appended, so magic/version and the value are reached.
// (Mode bits above these select modes 0..3 again: mode mod 6.)
// Invariants checked: an accepted coefficient datagram has one finite row of values per row index, every index
// in [0, m); the same datagram again is Replayed; the assembler's Z stays m by 3 and finite; an accepted path-open
// names the fixed peer.

#include "fuzz_support.h"
#include "session/engine/frame_assembler.h"
#include "session/wire/coefficient_codec.h"
#include "session/wire/path_open.h"

#include <QtCore/QByteArray>
#include <QtCore/QtEndian>

namespace {

using namespace sc::session;

constexpr int kAssemblerRows = 100;  ///< m of the seed frames (fuzz/seed_generator.cpp)

QByteArray key() {
  const auto bytes = sc::fuzz::fixedKey();
  return QByteArray(reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size()));
}

/// The header's 16-bit sequence (offset 6; 0 when shorter): a fresh decoder extends it to itself.
std::uint64_t wireSequence(const QByteArray& datagram) {
  return datagram.size() >= 8 ? qFromBigEndian<std::uint16_t>(datagram.constData() + 6) : 0;
}

QByteArray pathToken() { return QByteArray(kPathTokenSize, '\x5a'); }

void fuzzCoefficientDatagram(const QByteArray& datagram) {
  CoefficientDecoder decoder(key(), sc::fuzz::kFixedPeer);
  DecodedDatagram decoded;
  if (decoder.decode(datagram, decoded) == DecodeError::None) {
    const int m = decoded.header.rowCount;
    sc::fuzz::check(
        decoded.values.rows() == static_cast<Eigen::Index>(decoded.rows.size()) && decoded.values.cols() == 3,
        "one value row per decoded row");
    for (const int row : decoded.rows) sc::fuzz::check(row >= 0 && row < m, "row index in [0, m)");
    sc::fuzz::check(decoded.values.allFinite(), "decoded values finite");
    DecodedDatagram again;
    sc::fuzz::check(decoder.decode(datagram, again) == DecodeError::Replayed, "a repeated datagram is Replayed");
  }
  FrameAssembler assembler(key(), sc::fuzz::kFixedPeer, kAssemblerRows);
  assembler.receive(datagram);
  sc::fuzz::check(assembler.z().rows() == kAssemblerRows && assembler.z().cols() == 3, "assembler Z is m by 3");
  sc::fuzz::check(assembler.z().allFinite(), "assembler Z finite");
}

void fuzzPathOpen(const QByteArray& datagram) {
  static const DatagramMac mac(key());
  const auto lookup = [](PeerId peer) -> std::optional<PathCredentials> {
    if (peer != sc::fuzz::kFixedPeer) return std::nullopt;
    return PathCredentials{&mac, pathToken(), 0};
  };
  const PathOpenResult result = decodePathOpen(datagram, lookup);
  if (result.error == PathOpenError::None)
    sc::fuzz::check(result.peer == sc::fuzz::kFixedPeer && result.sequence >= 1, "accepted path-open is the peer's");
}

void fuzzPathProbe(const QByteArray& datagram) {
  static const DatagramMac mac(key());
  for (const MessageType type : {MessageType::PathChallenge, MessageType::PathResponse}) {
    const PathProbeResult result = decodePathProbe(datagram, type, mac);
    if (result.error == PathOpenError::None) {
      sc::fuzz::check(looksLikePathProbe(datagram, type), "an accepted probe has its length and type");
      sc::fuzz::check(
          encodePathProbe(type, static_cast<std::uint16_t>(pathProbePeer(datagram)), result.challenge, mac) == datagram,
          "an accepted probe re-encodes to itself");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sc::fuzz::Input input = sc::fuzz::splitMode(data, size);
  QByteArray datagram(reinterpret_cast<const char*>(input.rest.data()), static_cast<qsizetype>(input.rest.size()));
  switch (input.mode % 6) {
    case 0:
      fuzzCoefficientDatagram(datagram);
      break;
    case 1:
      fuzzCoefficientDatagram(sealCoefficientDatagram(key(), wireSequence(datagram), datagram));
      break;
    case 2:
      fuzzPathOpen(datagram);
      break;
    case 3:
      fuzzPathOpen(datagram + datagramTag(key(), datagram));
      break;
    case 4:
      fuzzPathProbe(datagram);
      break;
    default:
      fuzzPathProbe(datagram + datagramTag(key(), datagram));
      break;
  }
  return 0;
}
