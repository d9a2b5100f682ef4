// Tests src/session/wire/coefficient_codec.cpp, wire_format.cpp and replay_window.cpp.
#include "session/wire/coefficient_codec.h"

#include "spectral/harmonic_basis.h"
#include "spectral/laplace_operators.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QtCore/QtEndian>

#include <cstdio>
#include <random>

namespace {

using namespace sc::session;

const QByteArray kKey = QByteArrayLiteral("per-client-key-0123456789abcdef");
constexpr std::uint16_t kPeer = 7;

Eigen::MatrixXd randomZ(int m, unsigned seed, double scale = 1.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd Z(m, 3);
  for (int k = 0; k < m; ++k)
    for (int c = 0; c < 3; ++c) Z(k, c) = scale * normal(rng) / (1.0 + k);  // decaying spectrum
  return Z;
}

/// Decodes every part of a frame into an m by 3 matrix; fails the test on any error.
Eigen::MatrixXd decodeAll(CoefficientDecoder& decoder, const std::vector<QByteArray>& parts, int m) {
  Eigen::MatrixXd Z = Eigen::MatrixXd::Constant(m, 3, std::nan(""));
  for (const QByteArray& part : parts) {
    DecodedDatagram d;
    EXPECT_EQ(decoder.decode(part, d), DecodeError::None);
    for (std::size_t i = 0; i < d.rows.size(); ++i) Z.row(d.rows[i]) = d.values.row(static_cast<Eigen::Index>(i));
  }
  return Z;
}

/// Decrypts `datagram`, lets `edit` change its clear form (header ‖ payload), and seals it again: an authentic but
/// otherwise bad datagram.
template <typename Edit>
QByteArray resigned(const QByteArray& datagram, Edit edit) {
  // A fresh decoder extends the 16-bit sequence (offset 6) to itself: the nonce holds it as a 64-bit number.
  const std::optional<QByteArray> opened =
      openCoefficientDatagram(kKey, qFromBigEndian<std::uint16_t>(datagram.constData() + 6), datagram);
  EXPECT_TRUE(opened.has_value());
  QByteArray clear = opened.value_or(QByteArray());
  edit(clear);
  return sealCoefficientDatagram(kKey, qFromBigEndian<std::uint16_t>(clear.constData() + 6), clear);
}

DecodeError decodeOnce(const QByteArray& bytes) {
  CoefficientDecoder decoder(kKey, kPeer);
  DecodedDatagram d;
  return decoder.decode(bytes, d);
}

TEST(CoefficientCodec, RoundTripWithinQuantisationBound) {
  const int m = 100;
  const Eigen::MatrixXd Z = randomZ(m, 1);
  CoefficientEncoder encoder(kKey, kPeer);
  CoefficientDecoder decoder(kKey, kPeer);
  const Eigen::MatrixXd decoded = decodeAll(decoder, encoder.encodeFrame(0, Z), m);
  for (int b = 0; b < m / 10; ++b) {
    const double bound = Z.middleRows(b * 10, 10).cwiseAbs().maxCoeff() / 32767.0;
    EXPECT_LE((decoded - Z).middleRows(b * 10, 10).cwiseAbs().maxCoeff(), bound) << "band " << b;
  }
}

TEST(CoefficientCodec, RealisticZReconstructsWithin1e4OfDiagonal) {
  // === a real basis on a 642-vertex sphere and a smooth drag of 15% of the diagonal
  const auto mesh = sc::testing::icosphere(3);
  const auto ops = sc::spectral::laplaceOperators(mesh.V, mesh.F);
  const auto result = sc::spectral::manifoldHarmonicBasis(ops, {});
  ASSERT_TRUE(result.ok()) << result.message;
  const Eigen::MatrixXd& H = result.basis.vectors;
  const double diag = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
  Eigen::MatrixXd D(mesh.V.rows(), 3);
  const Eigen::RowVector3d handle = mesh.V.row(0), pull(0.1, 0.05, 0.08);
  for (Eigen::Index i = 0; i < D.rows(); ++i)
    D.row(i) = 0.15 * diag / pull.norm() * pull * std::exp(-(mesh.V.row(i) - handle).squaredNorm() / 0.5);
  const Eigen::MatrixXd Z = H.transpose() * ops.mass.asDiagonal() * D;

  CoefficientEncoder encoder(kKey, kPeer);
  CoefficientDecoder decoder(kKey, kPeer);
  const Eigen::MatrixXd decoded = decodeAll(decoder, encoder.encodeFrame(0, Z), 100);
  const double maxVertexError = (H * (decoded - Z)).rowwise().norm().maxCoeff();
  std::printf("quantisation: max vertex error %.3g of the bbox diagonal\n", maxVertexError / diag);
  EXPECT_LE(maxVertexError, 1e-4 * diag);
}

TEST(CoefficientCodec, DatagramSizesForM100AndLarger) {
  CoefficientEncoder encoder(kKey, kPeer);
  const auto parts = encoder.encodeFrame(0, randomZ(100, 2));
  qsizetype total = 0;
  for (const QByteArray& p : parts) {
    EXPECT_LE(p.size(), kMaxDatagramSize);
    total += p.size();
  }
  std::printf("m = 100: %zu datagrams, %lld bytes of UDP payload per frame\n", parts.size(),
              static_cast<long long>(total));
  EXPECT_EQ(parts.size(), 2u);
  EXPECT_LE(total, 800);
  for (int m : {1, 10, 11, 500, 1000, 4096}) {
    for (const QByteArray& p : encoder.encodeFrame(1, randomZ(m, 3))) EXPECT_LE(p.size(), kMaxDatagramSize) << m;
  }
}

TEST(CoefficientCodec, WrongKeyAndAnyFlippedByteFailTheTag) {
  CoefficientEncoder encoder(kKey, kPeer);
  const QByteArray datagram = encoder.encodeFrame(0, randomZ(100, 4)).front();
  CoefficientDecoder stranger(QByteArrayLiteral("another-client-key"), kPeer);
  DecodedDatagram d;
  EXPECT_EQ(stranger.decode(datagram, d), DecodeError::BadTag);
  for (qsizetype i = 0; i < datagram.size(); ++i) {
    QByteArray tampered = datagram;
    tampered[i] = static_cast<char>(tampered[i] ^ 0x01);
    EXPECT_EQ(decodeOnce(tampered), DecodeError::BadTag) << "byte " << i;
  }
}

TEST(CoefficientCodec, TruncatedAtEveryLength) {
  CoefficientEncoder encoder(kKey, kPeer);
  const QByteArray datagram = encoder.encodeFrame(0, randomZ(100, 5)).front();
  for (qsizetype n = 0; n < datagram.size(); ++n) {
    // Below header + tag nothing can be authenticated; above it the tag moved, so the tag fails first.
    const DecodeError expected = n < kDatagramMinSize ? DecodeError::Truncated : DecodeError::BadTag;
    EXPECT_EQ(decodeOnce(datagram.left(n)), expected) << "length " << n;
  }
  // Authenticated but shorter / longer than its header says.
  EXPECT_EQ(decodeOnce(resigned(datagram, [](QByteArray& b) { b.chop(1); })), DecodeError::Truncated);
  EXPECT_EQ(decodeOnce(resigned(datagram, [](QByteArray& b) { b.append('\0'); })), DecodeError::Malformed);
}

TEST(CoefficientCodec, RandomBytesAreRejected) {
  std::mt19937 rng(20240601);
  std::uniform_int_distribution<int> length(0, 1300), byte(0, 255);
  CoefficientDecoder decoder(kKey, kPeer);
  for (int trial = 0; trial < 5000; ++trial) {
    QByteArray bytes(length(rng), '\0');
    for (char& c : bytes) c = static_cast<char>(byte(rng));
    if (trial % 2 == 0 && bytes.size() >= 4) qToBigEndian<std::uint16_t>(kMagic, bytes.data());  // plausible start
    DecodedDatagram d;
    const DecodeError e = decoder.decode(bytes, d);
    EXPECT_TRUE(e == DecodeError::Truncated || e == DecodeError::BadTag) << toString(e);
  }
  EXPECT_TRUE(decoder.replayWindow().empty()) << "forged datagrams must not move the window";
}

TEST(CoefficientCodec, AuthenticatedButInvalidFieldsAreRejected) {
  CoefficientEncoder encoder(kKey, kPeer);
  const QByteArray datagram = encoder.encodeFrame(0, randomZ(100, 6)).front();
  const auto setByte = [&](int offset, char value) {
    return resigned(datagram, [=](QByteArray& b) { b[offset] = value; });
  };
  EXPECT_EQ(decodeOnce(setByte(0, 'X')), DecodeError::BadMagic);
  EXPECT_EQ(decodeOnce(setByte(2, kProtocolVersion + 1)), DecodeError::BadVersion);
  EXPECT_EQ(decodeOnce(setByte(3, static_cast<char>(MessageType::Count))), DecodeError::Malformed);
  EXPECT_EQ(decodeOnce(setByte(5, kPeer + 1)), DecodeError::Malformed) << "addressed to another peer";
  EXPECT_EQ(decodeOnce(setByte(12, 2)), DecodeError::Malformed) << "part index >= part count";
  EXPECT_EQ(decodeOnce(setByte(13, 0)), DecodeError::Malformed) << "zero parts";
  EXPECT_EQ(decodeOnce(setByte(17, 0)), DecodeError::Malformed) << "zero band rows";
  EXPECT_EQ(decodeOnce(setByte(16, 101)), DecodeError::Malformed) << "more protected rows than m";
  EXPECT_EQ(decodeOnce(setByte(15, 98)), DecodeError::Malformed) << "m changed: longer than its header says";
  EXPECT_EQ(decodeOnce(setByte(15, 0)), DecodeError::Malformed) << "m = 0";
}

TEST(CoefficientCodec, ReplayedAndStaleSequenceNumbers) {
  CoefficientEncoder encoder(kKey, kPeer);
  CoefficientDecoder decoder(kKey, kPeer);
  DecodedDatagram d;
  std::vector<QByteArray> sent;
  for (std::uint32_t f = 0; f < 40; ++f)
    for (QByteArray& p : encoder.encodeFrame(f, randomZ(20, f))) sent.push_back(std::move(p));
  ASSERT_EQ(sent.size(), 80u);  // sequence numbers 0..79
  EXPECT_EQ(decoder.decode(sent[79], d), DecodeError::None);
  EXPECT_EQ(decoder.decode(sent[79], d), DecodeError::Replayed);
  EXPECT_EQ(decoder.decode(sent[79 - 64], d), DecodeError::Stale) << "64 behind: outside the window";
  EXPECT_EQ(decoder.decode(sent[79 - 63], d), DecodeError::None) << "63 behind: inside, not seen";
  EXPECT_EQ(decoder.decode(sent[79 - 63], d), DecodeError::Replayed);
  EXPECT_EQ(decoder.decode(sent[0], d), DecodeError::Stale);
}

TEST(CoefficientCodec, SequenceWrapsAt65535) {
  CoefficientEncoder encoder(kKey, kPeer);
  encoder.setNextSequence(65531);
  CoefficientDecoder decoder(kKey, kPeer);
  DecodedDatagram d;
  std::vector<QByteArray> sent;
  for (std::uint32_t f = 0; f < 5; ++f) {
    for (QByteArray& p : encoder.encodeFrame(f, randomZ(30, f))) {
      EXPECT_EQ(decoder.decode(p, d), DecodeError::None) << "sequence " << d.header.sequence;
      sent.push_back(std::move(p));
    }
  }
  EXPECT_EQ(decoder.replayWindow().newest(), 65540u) << "sequences 65531..65540: extended past the 16-bit wrap";
  EXPECT_EQ(d.header.sequence, 4) << "the wire carries the low 16 bits";
  EXPECT_EQ(decoder.decode(sent[3], d), DecodeError::Replayed) << "65534 replayed after the wrap";
  EXPECT_EQ(decoder.decode(sent[5], d), DecodeError::Replayed) << "0 replayed";
}

TEST(CoefficientCodec, ReplayAfterSequenceWrapDoesNotFreezeTheStream) {
  // Issue 14 item 5: a genuine stream runs past 65535 (its 16-bit wire sequence wraps); an attacker then replays a
  // datagram recorded before the wrap whose 16-bit number reads as ~190 ahead of the newest. It must be dropped and
  // must not move the replay window, so the genuine datagrams after it are still accepted.
  CoefficientEncoder encoder(kKey, kPeer);
  CoefficientDecoder decoder(kKey, kPeer);
  DecodedDatagram d;
  const Eigen::MatrixXd Z = randomZ(1, 8);
  QByteArray recorded;  // sequence 200 of the first cycle (frame 100)
  std::uint32_t frame = 0;
  std::uint64_t accepted = 0;
  while (accepted < 65536 + 10) {  // every datagram decoded, as a client would: the wrap is genuine
    for (const QByteArray& p : encoder.encodeFrame(frame, Z)) {
      ASSERT_EQ(decoder.decode(p, d), DecodeError::None) << "datagram " << accepted;
      if (accepted == 200) recorded = p;
      ++accepted;
    }
    ++frame;
  }
  ASSERT_EQ(decoder.replayWindow().newest() & 0xffffu, 9u) << "65536 + 10 datagrams: the 16-bit number wrapped";
  EXPECT_NE(decoder.decode(recorded, d), DecodeError::None) << "the replayed pre-wrap datagram is dropped";
  for (int k = 0; k < 100; ++k, ++frame) {
    for (const QByteArray& p : encoder.encodeFrame(frame, Z)) {
      EXPECT_EQ(decoder.decode(p, d), DecodeError::None) << "genuine datagram " << k << " after the replay";
    }
  }
}

TEST(CoefficientCodec, PayloadIsCiphertextUnderANoncePerSequence) {
  // Datagram confidentiality (Issue 14): the same frame sent at two sequence numbers must not show the same
  // payload bytes (in clear, the quantised rows were identical), and no 6-byte quantised row appears as is.
  const Eigen::MatrixXd Z = randomZ(100, 9);
  CoefficientEncoder first(kKey, kPeer), second(kKey, kPeer);
  second.setNextSequence(2);
  const QByteArray a = first.encodeFrame(5, Z).front(), b = second.encodeFrame(5, Z).front();
  ASSERT_EQ(a.size(), b.size());
  const qsizetype payload = kDatagramHeaderSize, end = a.size() - kTagSize;
  EXPECT_EQ(a.first(kDatagramHeaderSize).sliced(8), b.first(kDatagramHeaderSize).sliced(8)) << "header: clear";
  int equal = 0;
  for (qsizetype i = payload; i < end; ++i) equal += a[i] == b[i];
  EXPECT_LT(equal, (end - payload) / 16) << "payload bytes equal at two sequence numbers";
  CoefficientDecoder decoder(kKey, kPeer);
  DecodedDatagram d;
  ASSERT_EQ(decoder.decode(a, d), DecodeError::None);
  EXPECT_LE((d.values.row(0) - Z.row(0)).cwiseAbs().maxCoeff(), 1e-3) << "and it still decodes";
}

TEST(ReplayWindow, JumpsAndOutOfOrder) {
  ReplayWindow w;
  w.accept(65000);
  EXPECT_EQ(w.check(64990), ReplayVerdict::Fresh) << "late but inside the window";
  w.accept(64990);
  EXPECT_EQ(w.check(64990), ReplayVerdict::Replayed);
  w.accept(65000 + 1000);  // past the 16-bit wrap: a big jump clears the bitmap
  EXPECT_EQ(w.check(65000), ReplayVerdict::Stale);
  EXPECT_EQ(w.check(65000 + 1000 - 63), ReplayVerdict::Fresh);
  EXPECT_EQ(w.check(65000 + 1000 - 64), ReplayVerdict::Stale);
  EXPECT_EQ(w.check(65000 + 1000 + 40000), ReplayVerdict::Fresh) << "64-bit numbers never read as old";
}

TEST(ReplayWindow, ExtendsThe16BitNumberToTheClosest64BitOne) {
  ReplayWindow w;
  EXPECT_EQ(w.extend(5), 5u) << "before any accept: the first cycle";
  w.accept(65530);
  EXPECT_EQ(w.extend(3), 65539u) << "just past the wrap: the next cycle";
  EXPECT_EQ(w.extend(65000), 65000u) << "a little behind: this cycle";
  w.accept(65539);
  EXPECT_EQ(w.extend(65535), 65535u) << "reordered from before the wrap: the previous cycle";
  EXPECT_EQ(w.extend(100), 65636u);
  EXPECT_EQ(w.extend(static_cast<std::uint16_t>(3 + 32768)), 65536u + 3 + 32768) << "32768 ahead: still ahead";
  EXPECT_EQ(w.extend(static_cast<std::uint16_t>(3 + 32769)), 3u + 32769) << "32767 behind: behind";
}

TEST(CoefficientCodec, BandExponentIsTheSmallestSufficientStep) {
  for (double maxAbs : {1e-9, 1e-3, 0.5, 1.0, 32767.0, 32768.0, 1e6}) {
    const int e = bandExponent(maxAbs);
    EXPECT_LE(maxAbs / std::ldexp(1.0, e), 32767.0) << maxAbs;
    EXPECT_GT(maxAbs / std::ldexp(1.0, e - 1), 32767.0) << maxAbs;
  }
  EXPECT_EQ(bandExponent(0.0), -127);
}

}  // namespace
