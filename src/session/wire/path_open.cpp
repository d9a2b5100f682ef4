#include "session/wire/path_open.h"

#include "session/wire/byte_io.h"
#include "session/wire/coefficient_codec.h"

namespace sc::session {
namespace {
constexpr qsizetype kSignedSize = kPathOpenSize - kTagSize;
constexpr qsizetype kProbeSignedSize = kPathProbeSize - kTagSize;
constexpr qsizetype kTypeOffset = 3;
}  // namespace

QByteArray encodePathOpen(std::uint16_t peerId, QByteArrayView token, std::uint32_t sequence, const QByteArray& key) {
  QByteArray out;
  ByteWriter writer(out);
  writer.u16(kMagic);
  writer.u8(kProtocolVersion);
  writer.u8(static_cast<std::uint8_t>(MessageType::PathOpen));
  writer.u16(peerId);
  writer.bytes(token);
  writer.u32(sequence);
  out.append(datagramTag(key, out));
  return out;
}

const char* toString(PathOpenError error) {
  switch (error) {
    case PathOpenError::None:
      return "none";
    case PathOpenError::Truncated:
      return "truncated";
    case PathOpenError::Stranger:
      return "stranger";
    case PathOpenError::BadTag:
      return "bad-tag";
    case PathOpenError::Malformed:
      return "malformed";
    case PathOpenError::Replayed:
      return "replayed";
    case PathOpenError::WrongChallenge:
      return "wrong-challenge";
    case PathOpenError::Count:
      break;
  }
  return "?";
}

PathOpenResult decodePathOpen(QByteArrayView bytes,
                              const std::function<std::optional<PathCredentials>(PeerId)>& lookup) {
  if (bytes.size() != kPathOpenSize) return {PathOpenError::Truncated};
  ByteReader reader(bytes);
  const std::uint16_t magic = reader.u16();
  const std::uint8_t version = reader.u8();
  const std::uint8_t type = reader.u8();
  const PeerId peer = reader.u16();
  const QByteArray token = reader.bytes(kPathTokenSize);
  const std::uint32_t sequence = reader.u32();
  const std::optional<PathCredentials> credentials = peer == kNoPeer ? std::nullopt : lookup(peer);
  if (!credentials) return {PathOpenError::Stranger};
  if (credentials->mac == nullptr || !credentials->mac->verify({bytes.first(kSignedSize)}, bytes.sliced(kSignedSize))) {
    return {PathOpenError::BadTag};
  }
  if (magic != kMagic || version != kProtocolVersion || type != static_cast<std::uint8_t>(MessageType::PathOpen)) {
    return {PathOpenError::Malformed};
  }
  if (!constantTimeEqual(token, credentials->token)) return {PathOpenError::Stranger};
  // Last, after authentication: only an authentic datagram may be judged a replay (RFC 6347 §4.1.2.6 order).
  if (sequence <= credentials->highestSequence) return {PathOpenError::Replayed};
  return {PathOpenError::None, peer, sequence};
}

QByteArray encodePathProbe(MessageType type, std::uint16_t peerId, std::uint64_t challenge, const DatagramMac& mac) {
  QByteArray out;
  ByteWriter writer(out);
  writer.u16(kMagic);
  writer.u8(kProtocolVersion);
  writer.u8(static_cast<std::uint8_t>(type));
  writer.u16(peerId);
  writer.u64(challenge);
  const DatagramTag tag = mac.tag({out});
  out.append(tag.data(), kTagSize);
  return out;
}

bool looksLikePathProbe(QByteArrayView bytes, MessageType type) {
  return bytes.size() == kPathProbeSize &&
         static_cast<std::uint8_t>(bytes[kTypeOffset]) == static_cast<std::uint8_t>(type);
}

PeerId pathProbePeer(QByteArrayView bytes) {
  if (bytes.size() < kPathProbeSize) return kNoPeer;
  ByteReader reader(bytes.sliced(4, 2));
  return reader.u16();
}

PathProbeResult decodePathProbe(QByteArrayView bytes, MessageType type, const DatagramMac& mac) {
  if (!looksLikePathProbe(bytes, type)) return {PathOpenError::Truncated};
  if (!mac.verify({bytes.first(kProbeSignedSize)}, bytes.sliced(kProbeSignedSize))) return {PathOpenError::BadTag};
  ByteReader reader(bytes);
  const std::uint16_t magic = reader.u16();
  const std::uint8_t version = reader.u8();
  reader.u8();   // type, checked above
  reader.u16();  // peer id, the caller's key selection
  const std::uint64_t challenge = reader.u64();
  if (magic != kMagic || version != kProtocolVersion) return {PathOpenError::Malformed};
  return {PathOpenError::None, challenge};
}

}  // namespace sc::session
