#include "session/wire/relay_message.h"

#include "session/wire/byte_io.h"
#include "session/wire/wire_format.h"

#include <openssl/evp.h>
#include <openssl/x509.h>
#include <QtCore/QCryptographicHash>

#include <algorithm>
#include <cmath>

namespace sc::session {
namespace {

constexpr std::uint16_t kRelayMagic = 0x5343;
constexpr char kSignatureLabel[] = "SC-relay1";

struct KeyDeleter {
  void operator()(EVP_PKEY* key) const { EVP_PKEY_free(key); }
};
struct DigestDeleter {
  void operator()(EVP_MD_CTX* context) const { EVP_MD_CTX_free(context); }
};
using KeyPtr = std::unique_ptr<EVP_PKEY, KeyDeleter>;
using DigestPtr = std::unique_ptr<EVP_MD_CTX, DigestDeleter>;

QByteArray signatureContext(const QString& sessionId) {
  const QByteArray sid = sessionId.toUtf8().left(kMaxSessionIdBytes);
  QByteArray context(kSignatureLabel);
  context.append(static_cast<char>(sid.size()));
  context.append(sid);
  return context;
}

void writeHeader(ByteWriter& out, RelayKind kind) {
  out.u16(kRelayMagic);
  out.u8(kRelayVersion);
  out.u8(static_cast<std::uint8_t>(kind));
}

bool readHeader(ByteReader& in, RelayKind kind) {
  const bool ok = in.u16() == kRelayMagic && in.u8() == kRelayVersion && in.u8() == static_cast<std::uint8_t>(kind);
  return ok && in.ok();
}

}  // namespace

bool isValidSessionId(const QString& sessionId) {
  if (sessionId.isEmpty() || sessionId.size() > kMaxSessionIdBytes) return false;
  for (const QChar c : sessionId) {
    const bool ok =
        (c >= u'a' && c <= u'z') || (c >= u'A' && c <= u'Z') || (c >= u'0' && c <= u'9') || c == u'_' || c == u'-';
    if (!ok) return false;
  }
  return true;
}

struct RelaySigner::Key {
  KeyPtr key;
};

RelaySigner::RelaySigner(QByteArrayView privateKeyDer, const QString& sessionId)
    : m_context(signatureContext(sessionId)) {
  const auto* data = reinterpret_cast<const unsigned char*>(privateKeyDer.data());
  KeyPtr key(d2i_AutoPrivateKey(nullptr, &data, static_cast<long>(privateKeyDer.size())));
  if (key && EVP_PKEY_get_base_id(key.get()) == EVP_PKEY_EC) {
    m_key = std::make_unique<Key>();
    m_key->key = std::move(key);
  }
}

RelaySigner::~RelaySigner() = default;

QByteArray RelaySigner::sign(QByteArrayView body) const {
  if (!m_key) return {};
  const DigestPtr context(EVP_MD_CTX_new());
  if (!context || EVP_DigestSignInit(context.get(), nullptr, EVP_sha256(), nullptr, m_key->key.get()) != 1) return {};
  if (EVP_DigestSignUpdate(context.get(), m_context.constData(), static_cast<size_t>(m_context.size())) != 1 ||
      EVP_DigestSignUpdate(context.get(), body.data(), static_cast<size_t>(body.size())) != 1) {
    return {};
  }
  unsigned char signature[kMaxRelaySignatureBytes + 8];
  size_t size = sizeof signature;
  if (EVP_DigestSignFinal(context.get(), signature, &size) != 1 || size == 0 ||
      size > static_cast<size_t>(kMaxRelaySignatureBytes)) {
    return {};
  }
  QByteArray message;
  message.reserve(body.size() + 1 + static_cast<qsizetype>(size));
  message.append(body.data(), body.size());
  message.append(reinterpret_cast<const char*>(signature), static_cast<qsizetype>(size));
  message.append(static_cast<char>(size));
  return message;
}

struct RelayVerifier::Key {
  KeyPtr key;
};

RelayVerifier::RelayVerifier(QByteArrayView certificateDer, const QString& sessionId)
    : m_context(signatureContext(sessionId)) {
  const auto* data = reinterpret_cast<const unsigned char*>(certificateDer.data());
  X509* certificate = d2i_X509(nullptr, &data, static_cast<long>(certificateDer.size()));
  if (!certificate) return;
  KeyPtr key(X509_get_pubkey(certificate));  // a new reference
  X509_free(certificate);
  if (key && EVP_PKEY_get_base_id(key.get()) == EVP_PKEY_EC) {
    m_key = std::make_unique<Key>();
    m_key->key = std::move(key);
  }
}

RelayVerifier::~RelayVerifier() = default;

std::optional<QByteArrayView> RelayVerifier::verify(QByteArrayView message, RelayError* error) const {
  auto fail = [error](RelayError why) {
    if (error) *error = why;
    return std::nullopt;
  };
  const std::optional<QByteArrayView> body = relayBody(message);
  if (!body) return fail(RelayError::Malformed);
  if (!m_key) return fail(RelayError::BadSignature);
  const QByteArrayView signature = message.sliced(body->size(), message.size() - 1 - body->size());
  const DigestPtr context(EVP_MD_CTX_new());
  const bool ok =
      context && EVP_DigestVerifyInit(context.get(), nullptr, EVP_sha256(), nullptr, m_key->key.get()) == 1 &&
      EVP_DigestVerifyUpdate(context.get(), m_context.constData(), static_cast<size_t>(m_context.size())) == 1 &&
      EVP_DigestVerifyUpdate(context.get(), body->data(), static_cast<size_t>(body->size())) == 1 &&
      EVP_DigestVerifyFinal(context.get(), reinterpret_cast<const unsigned char*>(signature.data()),
                            static_cast<size_t>(signature.size())) == 1;
  if (!ok) return fail(RelayError::BadSignature);
  if (error) *error = RelayError::None;
  return body;
}

QByteArray encodeRelayFrameBody(const RelayFrame& frame) {
  QByteArray out;
  out.reserve(kRelayFrameHeaderSize + 24 * frame.Z.rows());
  ByteWriter w(out);
  writeHeader(w, RelayKind::Frame);
  w.u32(frame.frame);
  w.u64(frame.stampMicros);
  w.u16(static_cast<std::uint16_t>(frame.Z.rows()));
  for (Eigen::Index r = 0; r < frame.Z.rows(); ++r) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      const double v = frame.Z(r, c);
      w.f64(std::isfinite(v) ? v : 0.0);
    }
  }
  return out;
}

QByteArray encodeRelayFactsBody(const RelayFacts& facts) {
  QByteArray out;
  ByteWriter w(out);
  writeHeader(w, RelayKind::Facts);
  w.u16(static_cast<std::uint16_t>(facts.rowCount));
  w.u32(facts.vertexCount);
  w.u16(static_cast<std::uint16_t>(facts.certificateDer.size()));
  w.bytes(facts.certificateDer);
  return out;
}

namespace {
constexpr double kMaxReportedMs = 1e6;
double clampMs(double ms) { return std::isfinite(ms) ? std::clamp(ms, 0.0, kMaxReportedMs) : 0.0; }
}  // namespace

QByteArray encodeRelayStats(const RelayStats& stats) {
  QByteArray out;
  out.reserve(kRelayStatsSize);
  ByteWriter w(out);
  writeHeader(w, RelayKind::Stats);
  w.u64(stats.viewer);
  w.u64(stats.applied);
  w.u64(stats.lost);
  w.u64(stats.badSignature);
  w.u64(stats.dropped);
  w.f64(clampMs(stats.latencyP50Ms));
  w.f64(clampMs(stats.latencyP99Ms));
  w.u64(stats.concealed);
  w.u64(stats.distortions);
  w.f64(clampMs(stats.distortionMeanPct));
  w.f64(clampMs(stats.distortionMaxPct));
  return out;
}

std::optional<RelayStats> decodeRelayStats(QByteArrayView message) {
  if (message.size() != kRelayStatsSize) return std::nullopt;
  ByteReader in(message);
  if (!readHeader(in, RelayKind::Stats)) return std::nullopt;
  RelayStats stats;
  stats.viewer = in.u64();
  stats.applied = in.u64();
  stats.lost = in.u64();
  stats.badSignature = in.u64();
  stats.dropped = in.u64();
  stats.latencyP50Ms = in.f64();
  stats.latencyP99Ms = in.f64();
  stats.concealed = in.u64();
  stats.distortions = in.u64();
  stats.distortionMeanPct = in.f64();
  stats.distortionMaxPct = in.f64();
  const auto valid = [](double ms) { return std::isfinite(ms) && ms >= 0.0 && ms <= kMaxReportedMs; };
  if (!in.finished() || !valid(stats.latencyP50Ms) || !valid(stats.latencyP99Ms) || !valid(stats.distortionMeanPct) ||
      !valid(stats.distortionMaxPct)) {
    return std::nullopt;
  }
  return stats;
}

std::optional<RelayKind> relayKind(QByteArrayView message) {
  ByteReader in(message);
  const bool ok = in.u16() == kRelayMagic && in.u8() == kRelayVersion;
  const std::uint8_t kind = in.u8();
  if (!ok || !in.ok()) return std::nullopt;
  if (kind == static_cast<std::uint8_t>(RelayKind::Frame)) return RelayKind::Frame;
  if (kind == static_cast<std::uint8_t>(RelayKind::Facts)) return RelayKind::Facts;
  if (kind == static_cast<std::uint8_t>(RelayKind::Stats)) return RelayKind::Stats;
  if (kind == static_cast<std::uint8_t>(RelayKind::Levels)) return RelayKind::Levels;
  return std::nullopt;
}

std::optional<RelayFrame> decodeRelayFrameBody(QByteArrayView body) {
  ByteReader in(body);
  if (!readHeader(in, RelayKind::Frame)) return std::nullopt;
  RelayFrame frame;
  frame.frame = in.u32();
  frame.stampMicros = in.u64();
  const int m = in.u16();
  if (!in.ok() || m < 1 || m > kMaxRows || in.remaining() != 24 * static_cast<qsizetype>(m)) return std::nullopt;
  frame.Z.resize(m, 3);
  for (int r = 0; r < m; ++r) {
    for (int c = 0; c < 3; ++c) {
      const double v = in.f64();
      if (!std::isfinite(v)) return std::nullopt;
      frame.Z(r, c) = v;
    }
  }
  if (!in.finished()) return std::nullopt;
  return frame;
}

std::optional<RelayFacts> decodeRelayFactsBody(QByteArrayView body) {
  ByteReader in(body);
  if (!readHeader(in, RelayKind::Facts)) return std::nullopt;
  RelayFacts facts;
  facts.rowCount = in.u16();
  facts.vertexCount = in.u32();
  const int size = in.u16();
  if (!in.ok() || facts.rowCount < 1 || facts.rowCount > kMaxRows || facts.vertexCount < 1 || size < 1 ||
      size > kMaxRelayCertificateBytes) {
    return std::nullopt;
  }
  facts.certificateDer = in.bytes(size);
  if (!in.finished()) return std::nullopt;
  return facts;
}

std::optional<QByteArrayView> relayBody(QByteArrayView message) {
  // The last byte is the signature's size; a body is at least a 4-byte header.
  if (message.size() < 4 + 1 + 1) return std::nullopt;
  const int s = static_cast<unsigned char>(message.back());
  if (s < 1 || s > kMaxRelaySignatureBytes || message.size() - 1 - s < 4) return std::nullopt;
  return message.first(message.size() - 1 - s);
}

QByteArray relayCertificateFingerprint(QByteArrayView certificateDer) {
  return QCryptographicHash::hash(certificateDer, QCryptographicHash::Sha256);
}

}  // namespace sc::session
