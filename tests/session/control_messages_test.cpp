// Tests for the control (TCP) message codecs (src/session/wire/control_messages.cpp), the stream frame reader
// (control_frame.cpp) and the password challenge-response (password_auth.cpp). No sockets.
#include "session/wire/control_messages.h"

#include <gtest/gtest.h>

#include <QtCore/QtEndian>

#include <cmath>
#include <limits>
#include <random>

#include "session/wire/control_frame.h"
#include "session/wire/password_auth.h"

namespace sc::session {
namespace {

QByteArray filled(int size, char seed) {
  QByteArray bytes(size, '\0');
  for (int i = 0; i < size; ++i) bytes[i] = static_cast<char>(seed + 7 * i);
  return bytes;
}

/// One message of every type, with non-trivial contents (index i has wire type 0x40 + i). The defaults give the
/// largest chunk; the split-point test uses small ones so that it can try every split point.
std::vector<ControlMessage> sampleMessages(int chunkBytes = static_cast<int>(kMaxChunkBytes), int keyframeRows = 100) {
  HandleTransform handle{7, {1, 0, 0, 0.25, 0, 1, 0, -0.5, 0, 0, 1, 1e-300}};
  Keyframe keyframe{123456, {}};
  for (int i = 0; i < 3 * keyframeRows; ++i) keyframe.z.push_back(std::sin(i) * 1e-3);
  return {
      Hello{kProtocolVersion, QString::fromUtf8("Zoë 🦆")},
      Refused{RefuseReason::VersionMismatch, kProtocolVersion, QStringLiteral("host speaks version 1, you 2")},
      Challenge{filled(kNonceSize, 1), filled(kSaltSize, 2), 100000},
      ChallengeResponse{filled(kMacSize, 3)},
      Welcome{65535, filled(kDatagramKeySize, 4), filled(kPathTokenSize, 5), 100, 22982, 40000},
      ModelBegin{9, TransferKind::Level, 5000, 3000000, filled(kChecksumSize, 6)},
      ModelChunk{9, 65536, 3000000, filled(chunkBytes, 8)},
      ResolutionRequest{5000},
      PeerList{{{1, 22982, QStringLiteral("host")}, {2, 5000, QString()}, {3, 0, QString(64, QChar('n'))}}},
      LockMessage{LockRequestKind::Renew, 42},
      LockNotice{LockNoticeKind::Released, 3, 42, 0, LockReleaseReason::LeaseExpired},
      Drag{42, {handle, HandleTransform{}}},
      keyframe,
      Leave{LeaveReason::Kicked, QStringLiteral("please stop")},
      Heartbeat{0xfffffffe},
      Constraints{42, {{1, 2, 3}, {22981}}, {7, 8}},
      StatsReport{5000, 90, 180, 20, 3, 1, 0.1, 0.5, 24.2, 30.1, 30.0, 0.2, 1.5, 0.12, 0.01, 0.0},
      LevelList{4, {{0, 22982, 45960, 9654321}, {2, 5231, 10458, 2200000}, {3, 1719, 3434, kMaxTransferSize}}},
      StrokeEnd{42},
      EditRequest{EditAction::Redo},
      EditLog{
          {{1, 1, 0, false, QStringLiteral("host")}, {7, 2, 1, true, QString::fromUtf8("Zoë")}, {9, 0, 0, false, {}}}},
      Presence{3, {1.5, -2.0, 1e9}, {0, 0, 0}, {0, 1, 0}, true, {0.25, -0.125, 1e-300}, true},
  };
}

/// A Hello body of this version: magic, kProtocolVersion, then `restHex` (name length and bytes).
QByteArray helloBody(const char* restHex) {
  return QByteArray::fromHex("5343") + static_cast<char>(kProtocolVersion) + QByteArray::fromHex(restHex);
}

QByteArray concatenated(const std::vector<ControlMessage>& messages) {
  QByteArray stream;
  for (const ControlMessage& message : messages) stream += encodeControlMessage(message);
  return stream;
}

/// Drains every available result from the reader into `out`.
void drain(ControlFrameReader& reader, std::vector<ControlDecodeResult>& out) {
  while (auto result = reader.next()) out.push_back(std::move(*result));
}

QByteArray frame(std::uint32_t length, std::uint8_t type, const QByteArray& body) {
  QByteArray bytes(4, '\0');
  qToBigEndian(length, bytes.data());
  bytes.append(static_cast<char>(type));
  return bytes + body;
}

TEST(ControlMessages, EveryMessageRoundTrips) {
  const auto messages = sampleMessages();
  ASSERT_EQ(messages.size(), std::variant_size_v<ControlMessage>);
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const QByteArray bytes = encodeControlMessage(messages[i]);
    ASSERT_FALSE(bytes.isEmpty()) << "type index " << i;
    EXPECT_EQ(qFromBigEndian<std::uint32_t>(bytes.constData()), static_cast<std::uint32_t>(bytes.size() - 4));
    EXPECT_EQ(static_cast<std::uint8_t>(bytes[4]), 0x40 + i);
    const ControlDecodeResult decoded = decodeControlMessage(static_cast<std::uint8_t>(bytes[4]), bytes.sliced(5));
    ASSERT_EQ(decoded.error, ControlError::None) << "type index " << i;
    EXPECT_TRUE(decoded.message == messages[i]) << "type index " << i;
  }
}

TEST(ControlMessages, DocumentedSizes) {
  EXPECT_EQ(encodeControlMessage(Welcome{1, filled(32, 0), filled(16, 0), 1, 1, 1}).size(), 5 + 60);
  EXPECT_EQ(encodeControlMessage(LockNotice{}).size(), 5 + 15);
  EXPECT_EQ(encodeControlMessage(LockNotice{LockNoticeKind::Waiting, 0, 0, 0, {}, {2, 3}}).size(), 5 + 15 + 8);
  EXPECT_EQ(encodeControlMessage(Leave{}).size(), 5 + 3);
  EXPECT_EQ(encodeControlMessage(Leave{LeaveReason::HostEnded, QStringLiteral("bye")}).toHex(),
            QByteArray("000000074d0100036279"
                       "65"));
  EXPECT_EQ(encodeControlMessage(Keyframe{1, std::vector<double>(3 * kMaxRows, 0.5)}).size(), 5 + 6 + 24 * kMaxRows);
  const QByteArray hello = encodeControlMessage(Hello{kProtocolVersion, QStringLiteral("ab")});
  EXPECT_EQ(hello.toHex(), QByteArray("0000000740534306026162"));  // frozen: length, type, magic, version (6), name
}

TEST(ControlMessages, LeaveReasonsAndTheLockQueueAreBounded) {
  for (const LeaveReason reason : {LeaveReason::ClientLeft, LeaveReason::HostEnded, LeaveReason::Kicked}) {
    const Leave leave{reason, QStringLiteral("why")};
    const QByteArray bytes = encodeControlMessage(leave);
    ASSERT_FALSE(bytes.isEmpty());
    EXPECT_TRUE(decodeControlMessage(0x4d, bytes.sliced(5)).message == ControlMessage{leave});
  }
  EXPECT_TRUE(encodeControlMessage(Leave{static_cast<LeaveReason>(kLeaveReasonLast + 1), {}}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Leave{LeaveReason::HostEnded, QString(kMaxTextBytes + 1, QChar('x'))}).isEmpty());
  EXPECT_EQ(decodeControlMessage(0x4d, QByteArray::fromHex("030000")).error, ControlError::Malformed)
      << "an unknown reason";
  EXPECT_EQ(decodeControlMessage(0x4d, QByteArray()).error, ControlError::Malformed) << "v3's empty Leave";

  LockNotice waiting{LockNoticeKind::Waiting, 0, 0, 0, {}, {}};
  for (PeerId id = 2; id < 2 + kMaxPeers; ++id) waiting.waiting.push_back(id);
  EXPECT_FALSE(encodeControlMessage(waiting).isEmpty()) << "kMaxPeers waiting";
  waiting.waiting.push_back(500);
  EXPECT_TRUE(encodeControlMessage(waiting).isEmpty()) << "more than kMaxPeers";
  EXPECT_TRUE(encodeControlMessage(LockNotice{LockNoticeKind::Waiting, 0, 0, 0, {}, {0}}).isEmpty()) << "peer 0";
  EXPECT_TRUE(encodeControlMessage(LockNotice{LockNoticeKind::Granted, 2, 1, 0, {}, {3}}).isEmpty())
      << "a queue on another kind";
  EXPECT_TRUE(
      encodeControlMessage(LockNotice{LockNoticeKind::Released, 2, 1, 0, LockReleaseReason::RevokedByHost, {}}).size() >
      0);
  EXPECT_TRUE(encodeControlMessage(LockNotice{LockNoticeKind::Released, 2, 1, 0, static_cast<LockReleaseReason>(4), {}})
                  .isEmpty());
  // A hostile count: 255 entries announced, 1 present.
  EXPECT_EQ(decodeControlMessage(0x4a, QByteArray::fromHex("05000000000000000000000000"
                                                           "00ff00000002"))
                .error,
            ControlError::Malformed);
}

TEST(ControlMessages, ValuesBreakingLimitsDoNotEncode) {
  EXPECT_TRUE(encodeControlMessage(Hello{kProtocolVersion, QString(65, QChar('x'))}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Refused{static_cast<RefuseReason>(0), 1, {}}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Challenge{filled(31, 0), filled(16, 0), 1}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Challenge{filled(32, 0), filled(16, 0), kMaxPbkdf2Iterations + 1}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Welcome{0, filled(32, 0), filled(16, 0), 1, 1, 1}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Welcome{1, filled(32, 0), filled(16, 0), 1, 1, 0}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Constraints{1, {{}}, {}}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Constraints{0, {{1}}, {}}).isEmpty());
  EXPECT_TRUE(
      encodeControlMessage(Constraints{1, {}, std::vector<std::uint32_t>(kMaxConstraintVertices + 1, 0)}).isEmpty());
  EXPECT_EQ(encodeControlMessage(StatsReport{}).size(), 5 + kStatsReportSize);
  StatsReport negative;
  negative.jitterMs = -1.0;
  EXPECT_TRUE(encodeControlMessage(negative).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Welcome{65536, filled(32, 0), filled(16, 0), 1, 1, 1}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(ModelChunk{1, 10, 10, filled(1, 0)}).isEmpty());  // past totalSize
  EXPECT_TRUE(encodeControlMessage(ModelChunk{1, 0, 10, {}}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(PeerList{std::vector<PeerInfo>(kMaxPeers + 1, PeerInfo{1, 1, {}})}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Drag{kNoEpoch, {}}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Drag{1, std::vector<HandleTransform>(kMaxHandles + 1)}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Keyframe{1, {1.0, std::nan(""), 0.0}}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(Keyframe{1, {1.0, 2.0}}).isEmpty());  // not m×3
  EXPECT_TRUE(encodeControlMessage(Keyframe{1, std::vector<double>(3 * (kMaxRows + 1), 0.0)}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(LockMessage{static_cast<LockRequestKind>(4), 1}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(StrokeEnd{kNoEpoch}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(EditRequest{static_cast<EditAction>(3)}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(EditLog{{{2, 1, 0, false, {}}, {2, 1, 0, false, {}}}}).isEmpty());  // not ascending
  EXPECT_TRUE(encodeControlMessage(EditLog{{{0, 1, 0, false, {}}}}).isEmpty());                        // step 0
  EXPECT_TRUE(encodeControlMessage(EditLog{{{1, 1, 0, true, {}}}}).isEmpty());  // redoable but applied
  EXPECT_TRUE(encodeControlMessage(EditLog{{{1, 0x10000, 0, false, {}}}}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(EditLog{{{1, 1, 0, false, QString(65, QChar('n'))}}}).isEmpty());
  std::vector<EditLogEntry> tooMany;
  for (std::uint32_t i = 1; i <= kMaxEditLogSteps + 1; ++i) tooMany.push_back({i, 1, 0, false, {}});
  EXPECT_TRUE(encodeControlMessage(EditLog{tooMany}).isEmpty());
  tooMany.pop_back();
  EXPECT_FALSE(encodeControlMessage(EditLog{tooMany}).isEmpty());
}

TEST(ControlMessages, LevelListLayoutAndLimits) {
  // total, count, then per level: id, vertices, faces, payload bytes (wire_format.h, 0x51).
  const QByteArray bytes = encodeControlMessage(LevelList{3, {{0, 22982, 45960, 9654321}, {2, 1719, 3434, 700}}});
  ASSERT_EQ(bytes.size(), 5 + 2 + 2 * kLevelEntrySize);
  EXPECT_EQ(bytes.toHex(), QByteArray("0000001d51"
                                      "0302"
                                      "00000059c60000b38800935031"
                                      "02000006b700000d6a000002bc"));
  EXPECT_EQ(encodeControlMessage(LevelList{1, {}}).size(), 5 + 2);  // nothing built yet
  EXPECT_TRUE(encodeControlMessage(LevelList{}).isEmpty());         // total 0
  EXPECT_TRUE(encodeControlMessage(LevelList{kMaxLevels + 1, {}}).isEmpty());
  EXPECT_TRUE(encodeControlMessage(LevelList{1, {{0, 1, 1, 1}, {1, 1, 1, 1}}}).isEmpty());  // count > total
  EXPECT_TRUE(encodeControlMessage(LevelList{3, {{3, 1, 1, 1}}}).isEmpty());                // id ≥ total
  EXPECT_TRUE(encodeControlMessage(LevelList{3, {{1, 5, 5, 5}, {1, 4, 4, 4}}}).isEmpty());  // ids not ascending
  EXPECT_TRUE(encodeControlMessage(LevelList{3, {{0, 0, 1, 1}}}).isEmpty());                // no vertices
  EXPECT_TRUE(encodeControlMessage(LevelList{3, {{0, 1, 0, 1}}}).isEmpty());                // no faces
  EXPECT_TRUE(encodeControlMessage(LevelList{3, {{0, 1, 1, 0}}}).isEmpty());                // empty payload
  EXPECT_TRUE(encodeControlMessage(LevelList{3, {{0, 1, 1, kMaxTransferSize + 1}}}).isEmpty());
  // A count larger than the entries that follow (truncated) and more entries than the count (trailing bytes).
  EXPECT_EQ(decodeControlMessage(0x51, QByteArray::fromHex("0302") + bytes.sliced(7, kLevelEntrySize)).error,
            ControlError::Malformed);
  EXPECT_EQ(decodeControlMessage(0x51, QByteArray::fromHex("0301") + bytes.sliced(7)).error, ControlError::Malformed);
  EXPECT_EQ(decodeControlMessage(0x51, QByteArray::fromHex("ffff")).error, ControlError::Malformed);  // oversized
  EXPECT_EQ(decodeControlMessage(0x51, bytes.sliced(5)).error, ControlError::None);
}

TEST(ControlMessages, ClosestLevelByExactCount) {
  const LevelList list{4, {{0, 22982, 1, 1}, {1, 11491, 1, 1}, {2, 5231, 1, 1}, {3, 1719, 1, 1}}};
  EXPECT_EQ(closestLevel(LevelList{}, 5000), nullptr);
  EXPECT_EQ(closestLevel(list, 0)->vertexCount, 22982u);  // 0 = full
  EXPECT_EQ(closestLevel(list, 5000)->vertexCount, 5231u);
  EXPECT_EQ(closestLevel(list, 1149)->vertexCount, 1719u);  // 5% of n: the 5% level, whatever its exact count
  EXPECT_EQ(closestLevel(list, 3475)->vertexCount, 5231u);  // tie (1756 each way): the larger
  EXPECT_EQ(closestLevel(list, 100000)->vertexCount, 22982u);
  EXPECT_TRUE(list.complete());
  EXPECT_FALSE((LevelList{4, {{0, 22982, 1, 1}}}).complete());
}

TEST(ControlMessages, HelloOfAnotherVersionDecodesForARefusal) {
  // A later version's Hello may be longer: only magic and version are read, so the host can refuse it by version.
  QByteArray body = QByteArray::fromHex("534307") + filled(300, 9);
  const ControlDecodeResult decoded = decodeControlMessage(0x40, body);
  ASSERT_EQ(decoded.error, ControlError::None);
  EXPECT_EQ(std::get<Hello>(decoded.message).version, 7);
  EXPECT_EQ(decodeControlMessage(0x40, QByteArray::fromHex("000001")).error, ControlError::Malformed);  // magic
  EXPECT_EQ(decodeControlMessage(0x40, helloBody("00ff")).error, ControlError::Malformed);
}

TEST(ControlMessages, InvalidUtf8IsMalformed) {
  EXPECT_EQ(decodeControlMessage(0x40, helloBody("02c328")).error, ControlError::Malformed);
  EXPECT_EQ(decodeControlMessage(0x40, helloBody("02c3a9")).error, ControlError::None);  // "é"
}

TEST(ControlMessages, EveryTruncationIsIncompleteOrMalformed) {
  for (const ControlMessage& message : sampleMessages()) {
    const QByteArray bytes = encodeControlMessage(message);
    const auto type = static_cast<std::uint8_t>(bytes[4]);
    for (qsizetype size = 0; size < bytes.size(); ++size) {
      ControlFrameReader reader;
      reader.append(bytes.first(size));
      EXPECT_FALSE(reader.next().has_value()) << "type " << int(type) << " size " << size;
      if (size >= 5) {
        EXPECT_EQ(decodeControlMessage(type, bytes.sliced(5, size - 5)).error, ControlError::Malformed)
            << "type " << int(type) << " body " << size - 5;
      }
    }
    // One byte too many inside the frame is malformed too.
    EXPECT_EQ(decodeControlMessage(type, bytes.sliced(5) + 'x').error, ControlError::Malformed);
  }
}

TEST(ControlFrameReader, EverySplitPointOfAStreamYieldsTheSameMessages) {
  const auto messages = sampleMessages(300, 10);
  const QByteArray stream = concatenated(messages);
  ASSERT_LT(stream.size(), 3000);
  for (qsizetype split = 0; split <= stream.size(); ++split) {
    ControlFrameReader reader;
    std::vector<ControlDecodeResult> results;
    reader.append(stream.first(split));
    drain(reader, results);
    reader.append(stream.sliced(split));
    drain(reader, results);
    ASSERT_EQ(results.size(), messages.size()) << "split " << split;
    for (std::size_t i = 0; i < messages.size(); ++i) {
      ASSERT_EQ(results[i].error, ControlError::None);
      EXPECT_TRUE(results[i].message == messages[i]) << "split " << split << " message " << i;
    }
    EXPECT_EQ(reader.buffered(), 0);
  }
}

TEST(ControlFrameReader, ByteByByte) {
  const auto messages = sampleMessages();
  const QByteArray stream = concatenated(messages);
  ControlFrameReader reader;
  std::vector<ControlDecodeResult> results;
  for (char byte : stream) {
    reader.append(QByteArrayView(&byte, 1));
    drain(reader, results);
  }
  ASSERT_EQ(results.size(), messages.size());
  for (std::size_t i = 0; i < messages.size(); ++i) EXPECT_TRUE(results[i].message == messages[i]);
}

TEST(ControlFrameReader, OversizeFailsAtOnceAndForGood) {
  for (std::uint32_t length : {0u, kMaxControlMessageSize + 1, 0xffffffffu}) {
    ControlFrameReader reader;
    QByteArray header(4, '\0');
    qToBigEndian(length, header.data());
    reader.append(header);  // only the length: the error comes before any body is buffered
    const auto result = reader.next();
    ASSERT_TRUE(result.has_value());
    EXPECT_EQ(result->error, ControlError::Oversize);
    EXPECT_TRUE(reader.failed());
    reader.append(encodeControlMessage(Leave{}));
    EXPECT_FALSE(reader.next().has_value());
    EXPECT_EQ(reader.buffered(), 0);
  }
  ControlFrameReader reader;  // exactly the maximum is not oversize (here: a Hello with trailing bytes)
  reader.append(frame(kMaxControlMessageSize, 0x40, helloBody("00") + QByteArray(kMaxControlMessageSize - 5, 'x')));
  const auto result = reader.next();
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->error, ControlError::Malformed);
  EXPECT_FALSE(reader.failed());
}

TEST(ControlFrameReader, UnknownTypesAreReportedAndSkipped) {
  for (int type : {0x00, 0x01, 0x02, 0x3f, static_cast<int>(MessageType::ControlEnd), 0x7f, 0x80, 0xc0, 0xff}) {
    ControlFrameReader reader;
    reader.append(frame(3, static_cast<std::uint8_t>(type), "ab") + encodeControlMessage(Heartbeat{5}));
    std::vector<ControlDecodeResult> results;
    drain(reader, results);
    ASSERT_EQ(results.size(), 2u) << type;
    EXPECT_EQ(results[0].error, ControlError::UnknownType) << type;
    EXPECT_EQ(results[1].error, ControlError::None);
    EXPECT_TRUE(results[1].message == ControlMessage{Heartbeat{5}});
  }
  EXPECT_STREQ(toString(ControlError::UnknownType), "unknown-type");
}

/// Whatever decodes must re-encode, and the re-encoding must decode to the same value.
void expectReencodes(const ControlDecodeResult& result) {
  if (result.error != ControlError::None) return;
  const QByteArray again = encodeControlMessage(result.message);
  ASSERT_FALSE(again.isEmpty());
  const ControlDecodeResult twice = decodeControlMessage(static_cast<std::uint8_t>(again[4]), again.sliced(5));
  ASSERT_EQ(twice.error, ControlError::None);
  EXPECT_TRUE(twice.message == result.message);
}

TEST(ControlFuzz, RandomAndMutatedBodiesNeverCrashAndReencode) {
  std::mt19937 rng(20240611);
  const auto messages = sampleMessages();
  int accepted = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    QByteArray body;
    auto type = static_cast<std::uint8_t>(0x40 + rng() % 17);
    if (trial % 2 == 0) {  // random bytes of a random length
      body.resize(static_cast<qsizetype>(rng() % 80));
      for (char& byte : body) byte = static_cast<char>(rng());
      if (trial % 10 == 0) type = static_cast<std::uint8_t>(rng());
    } else {  // a valid body with a few bytes overwritten, sometimes cut or extended
      const QByteArray bytes = encodeControlMessage(messages[type - 0x40]);
      body = bytes.sliced(5);
      for (int flips = 1 + static_cast<int>(rng() % 3); flips > 0 && !body.isEmpty(); --flips) {
        body[static_cast<qsizetype>(rng() % body.size())] = static_cast<char>(rng());
      }
      if (rng() % 4 == 0) body.truncate(static_cast<qsizetype>(rng() % (body.size() + 1)));
      if (rng() % 8 == 0) body.append(static_cast<char>(rng()));
    }
    const ControlDecodeResult result = decodeControlMessage(type, body);
    accepted += result.error == ControlError::None;
    expectReencodes(result);
  }
  EXPECT_GT(accepted, 1000);  // the mutations reach the accepting paths, not only the rejecting ones
}

TEST(ControlFuzz, RandomStreamsThroughTheReader) {
  std::mt19937 rng(7);
  const QByteArray valid = concatenated(sampleMessages());
  for (int trial = 0; trial < 3000; ++trial) {
    QByteArray stream = valid.first(static_cast<qsizetype>(rng() % 400));
    for (int i = static_cast<int>(rng() % 64); i > 0; --i) stream.append(static_cast<char>(rng() % 4 == 0 ? 0 : rng()));
    if (stream.size() > 4 && rng() % 2 == 0) qToBigEndian<std::uint32_t>(rng() % 96, stream.data());
    ControlFrameReader reader;
    std::vector<ControlDecodeResult> results;
    for (qsizetype at = 0; at < stream.size();) {
      const qsizetype piece = std::min<qsizetype>(1 + rng() % 16, stream.size() - at);
      reader.append(stream.sliced(at, piece));
      at += piece;
      drain(reader, results);
    }
    for (const ControlDecodeResult& result : results) expectReencodes(result);
    EXPECT_LE(reader.buffered(), stream.size());
  }
}

TEST(PasswordAuth, RightPasswordIsAcceptedWrongOneRejected) {
  const QByteArray salt = secureRandomBytes(kSaltSize);
  constexpr std::uint32_t kIterations = 1000;  // fast for the test; the host uses kDefaultPbkdf2Iterations
  const QByteArray hostKey = derivePasswordKey(QStringLiteral("correct horse"), salt, kIterations);
  ASSERT_EQ(hostKey.size(), kMacSize);
  const Challenge challenge = makeChallenge(salt, kIterations);

  // The challenge crosses the wire; the client derives the key from what it received.
  const QByteArray wire = encodeControlMessage(challenge);
  const Challenge received = std::get<Challenge>(decodeControlMessage(0x42, wire.sliced(5)).message);
  // Channel bindings: the host's certificate hash, and the one a man in the middle would show the client.
  const QByteArray hostCertificate = secureRandomBytes(32);
  const QByteArray relayCertificate = secureRandomBytes(32);
  const auto respond = [&](const QString& password, const QByteArray& binding) {
    return answerChallenge(derivePasswordKey(password, received.salt, received.iterations), received, binding);
  };
  const ChallengeResponse right = respond(QStringLiteral("correct horse"), hostCertificate);
  EXPECT_FALSE(right.mac.contains("correct horse"));
  EXPECT_TRUE(verifyChallengeResponse(hostKey, challenge, hostCertificate, right));
  EXPECT_FALSE(verifyChallengeResponse(hostKey, challenge, hostCertificate,
                                       respond(QStringLiteral("correct hors"), hostCertificate)));
  EXPECT_FALSE(verifyChallengeResponse(hostKey, challenge, hostCertificate, respond(QString(), hostCertificate)));
  EXPECT_FALSE(verifyChallengeResponse(hostKey, challenge, hostCertificate, ChallengeResponse{}));
  // The right password over another TLS channel (bound to another certificate) is refused: no relaying.
  EXPECT_FALSE(verifyChallengeResponse(hostKey, challenge, hostCertificate,
                                       respond(QStringLiteral("correct horse"), relayCertificate)));
  // A recorded response does not answer a fresh nonce (replay).
  EXPECT_FALSE(verifyChallengeResponse(hostKey, makeChallenge(salt, kIterations), hostCertificate, right));
  // Another session's salt gives another key.
  EXPECT_NE(derivePasswordKey(QStringLiteral("correct horse"), secureRandomBytes(kSaltSize), kIterations), hostKey);
}

TEST(PasswordAuth, ConstantTimeEquals) {
  EXPECT_TRUE(constantTimeEquals("", ""));
  EXPECT_TRUE(constantTimeEquals("abc", "abc"));
  EXPECT_FALSE(constantTimeEquals("abc", "abd"));
  EXPECT_FALSE(constantTimeEquals("abc", "ab"));
  EXPECT_EQ(secureRandomBytes(kNonceSize).size(), kNonceSize);
  EXPECT_NE(secureRandomBytes(kNonceSize), secureRandomBytes(kNonceSize));
}

}  // namespace
}  // namespace sc::session
