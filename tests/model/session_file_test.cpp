// The saved session file (model/session_file.h, version 2; session_file_v1.h, the legacy version 1): round trips
// through bytes and through a file, version-1 files read into the current constraints and Z with their undo
// history counted as dropped, and every kind of broken input — every truncation, every flipped byte, foreign files,
// a newer version, trailing bytes, and files whose checksum is right but whose content is not (ids out of range,
// huge counts, too many edit steps, long or invalid author names, non-finite ΔZ) — gives a readable error instead
// of a crash. Saving never replaces an existing file with a broken one.

#include "model/session_file.h"
#include "model/session_file_v1.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QCryptographicHash>
#include <QFile>
#include <QTemporaryDir>
#include <QtEndian>

#include <Eigen/Geometry>

#include <sys/resource.h>

#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <variant>

namespace sc::model {
namespace {

constexpr qsizetype kHeaderBytes = 20;  // magic, version, payload length

/// ΔZ of `m` rows, distinct per `seed`, with values that are not round in binary (exact equality is meaningful).
Eigen::MatrixXd delta(int m, int seed) {
  Eigen::MatrixXd d(m, 3);
  for (int r = 0; r < m; ++r)
    for (int c = 0; c < 3; ++c) d(r, c) = std::sin(0.37 * seed + 1.3 * r + 0.11 * c) / (1.0 + r);
  return d;
}

/// A small torus session with current constraints, Z and four steps by three authors (one undone, one unnamed,
/// one with a non-ASCII name).
SessionFile sampleSession() {
  const sc::testing::GeneratedMesh mesh = sc::testing::torus(12, 8);
  SessionFile file;
  file.V = mesh.V;
  file.F = mesh.F;
  file.m = 10;
  file.mode = spectral::DeformationMode::Rigid;
  file.Z = Eigen::MatrixXd::Random(file.m, 3);
  file.current = SavedConstraints{{0, 1, 2, 12}, {40, 41, 42, 50, 60, 70}};
  file.steps = {{QStringLiteral("Alice"), delta(file.m, 1), false},
                {QString::fromUtf8("Zoë 🐉"), delta(file.m, 2), false},
                {QString(), delta(file.m, 3), false},
                {QStringLiteral("Alice"), delta(file.m, 4), true}};
  return file;
}

/// The same torus as version 1 wrote it: a current state with a pose (anchors unsorted, one of them also in the
/// handle, as the old app could write them) and three drags, two applied.
v1::LegacySessionFile legacySession() {
  const SessionFile now = sampleSession();
  v1::LegacySessionFile file;
  file.V = now.V;
  file.F = now.F;
  file.m = now.m;
  file.mode = now.mode;
  file.Z = now.Z;
  const auto state = [](std::vector<int> handle, std::vector<int> anchors, double dy, double degrees) {
    v1::SavedDeformation d;
    d.handle = std::move(handle);
    d.anchors = std::move(anchors);
    d.translation = Eigen::Vector3d(0.1, dy, -0.05);
    d.rotation =
        Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    return d;
  };
  const std::vector<int> handle{12, 0, 2, 1};
  const std::vector<int> anchors{70, 40, 41, 42, 12, 50, 60, 41};
  const v1::SavedDeformation rest = state(handle, anchors, 0.0, 0.0);
  const v1::SavedDeformation first = state(handle, anchors, 0.2, 10.0);
  const v1::SavedDeformation second = state(handle, anchors, 0.3, -5.0);
  const v1::SavedDeformation third = state({5, 6}, {80, 81}, -0.1, 30.0);
  file.history = {{rest, first}, {first, second}, {second, third}};
  file.historyIndex = 2;
  file.current = second;
  return file;
}

SessionFileError errorOf(const SessionFileResult& result) {
  if (const auto* error = std::get_if<SessionFileError>(&result)) return *error;
  ADD_FAILURE() << "decoded although it should not";
  return {};
}

SessionFile decoded(const QByteArray& bytes) {
  const SessionFileResult result = decodeSessionFile(bytes);
  if (const auto* error = std::get_if<SessionFileError>(&result)) {
    ADD_FAILURE() << "refused: " << error->message.toStdString();
    return {};
  }
  return std::get<SessionFile>(result);
}

/// `payload` with a fresh header of `version` and a valid checksum (to reach the content checks behind it).
QByteArray sealed(const QByteArray& payload, std::uint32_t version = kSessionFileVersion) {
  QByteArray out(kSessionFileMagic, sizeof(kSessionFileMagic));
  const std::uint32_t le = qToLittleEndian(version);
  const std::uint64_t length = qToLittleEndian(static_cast<std::uint64_t>(payload.size()));
  out.append(reinterpret_cast<const char*>(&le), 4);
  out.append(reinterpret_cast<const char*>(&length), 8);
  out.append(payload);
  out.append(QCryptographicHash::hash(out, QCryptographicHash::Sha256));
  return out;
}

QByteArray payloadOf(const QByteArray& bytes) { return bytes.mid(kHeaderBytes, bytes.size() - kHeaderBytes - 32); }

/// Little-endian payload bytes written by hand (for files encodeSessionFile() would never write, or only from an
/// expanded file too large to build in a test).
class PayloadWriter {
 public:
  explicit PayloadWriter(QByteArray start = {}) : m_bytes(std::move(start)) {}
  void u8(std::uint8_t v) { m_bytes.append(static_cast<char>(v)); }
  void u32(std::uint32_t v) {
    const std::uint32_t le = qToLittleEndian(v);
    m_bytes.append(reinterpret_cast<const char*>(&le), 4);
  }
  void f64(double v) {
    const std::uint64_t le = qToLittleEndian(std::bit_cast<std::uint64_t>(v));
    m_bytes.append(reinterpret_cast<const char*>(&le), 8);
  }
  void raw(const QByteArray& bytes) { m_bytes.append(bytes); }
  void mesh(const sc::testing::GeneratedMesh& mesh) {
    u32(static_cast<std::uint32_t>(mesh.V.rows()));
    u32(static_cast<std::uint32_t>(mesh.F.rows()));
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
      for (int c = 0; c < 3; ++c) f64(mesh.V(i, c));
    for (Eigen::Index i = 0; i < mesh.F.rows(); ++i)
      for (int c = 0; c < 3; ++c) u32(static_cast<std::uint32_t>(mesh.F(i, c)));
  }
  /// A version-1 explicit id list.
  void legacyIds(const std::vector<int>& ids) {
    u8(1);
    u32(static_cast<std::uint32_t>(ids.size()));
    for (int id : ids) u32(static_cast<std::uint32_t>(id));
  }
  /// A version-1 state whose handle and anchors are both "the same as the previous list", the identity pose.
  void sameLegacyState() {
    u8(0);
    u8(0);
    pose();
  }
  void pose() {
    for (int i = 0; i < 3; ++i) f64(0.0);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) f64(r == c ? 1.0 : 0.0);
  }
  /// A version-2 step: author bytes as given, the undone flag, `m` rows of `value`.
  void step(const QByteArray& author, std::uint8_t undone, int m, double value = 0.25) {
    u8(static_cast<std::uint8_t>(author.size()));
    raw(author);
    u8(undone);
    for (int i = 0; i < 3 * m; ++i) f64(value);
  }
  const QByteArray& bytes() const { return m_bytes; }

 private:
  QByteArray m_bytes;
};

/// The sample session's payload up to (not including) its step count: steps are appended by hand after it.
QByteArray payloadBeforeSteps() {
  SessionFile file = sampleSession();
  file.steps.clear();
  return payloadOf(encodeSessionFile(file)).chopped(4);
}

/// The sample session with `count` written as its step count followed by `steps` (hand-written step bytes).
QByteArray withSteps(std::uint32_t count, const QByteArray& steps) {
  PayloadWriter w(payloadBeforeSteps());
  w.u32(count);
  w.raw(steps);
  return sealed(w.bytes());
}

/// A valid-looking version-1 session of `mesh` whose current state has `handle` and `anchors` written once,
/// followed by `drags` drags whose states all say "the same lists as before": small on disk, each drag expanding to
/// two copies of both lists in memory.
QByteArray expandingLegacySession(const sc::testing::GeneratedMesh& mesh, const std::vector<int>& handle,
                                  const std::vector<int>& anchors, std::uint32_t drags) {
  PayloadWriter w;
  w.mesh(mesh);
  w.u32(10);  // m
  w.u8(0);    // linear
  w.u8(1);    // has a current state
  w.legacyIds(handle);
  w.legacyIds(anchors);
  w.pose();
  w.u32(10);
  w.u32(3);
  for (int i = 0; i < 30; ++i) w.f64(0.0);
  w.u32(drags);
  w.u32(0);  // history index
  for (std::uint32_t i = 0; i < drags; ++i) {
    w.sameLegacyState();
    w.sameLegacyState();
  }
  return sealed(w.bytes(), v1::kVersion);
}

/// The process's peak resident set so far, in KiB (Linux: ru_maxrss).
long peakKiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

TEST(SessionFileTest, RoundTripWithStepsThroughBytesAndAFile) {
  const SessionFile file = sampleSession();
  ASSERT_TRUE(validateSessionFile(file).isEmpty()) << validateSessionFile(file).toStdString();
  const QByteArray bytes = encodeSessionFile(file);
  EXPECT_EQ(qFromLittleEndian<std::uint32_t>(bytes.constData() + 8), 2u);  // always written as version 2
  const SessionFile back = decoded(bytes);
  EXPECT_TRUE(sameSessionFile(back, file));
  ASSERT_EQ(back.steps.size(), 4u);
  EXPECT_EQ(back.steps[1].author, QString::fromUtf8("Zoë 🐉"));
  EXPECT_TRUE(back.steps[3].undone);
  EXPECT_EQ(back.steps[2].delta, file.steps[2].delta);
  EXPECT_EQ(back.droppedLegacyDrags, 0);

  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  const QString path = dir.filePath(QStringLiteral("a.shapecast"));
  ASSERT_FALSE(writeSessionFile(path, file).has_value());
  EXPECT_TRUE(isSessionFile(path));
  const SessionFileResult read = readSessionFile(path);
  ASSERT_TRUE(std::holds_alternative<SessionFile>(read)) << std::get<SessionFileError>(read).message.toStdString();
  EXPECT_TRUE(sameSessionFile(std::get<SessionFile>(read), file));
  // a different session is not "the same"
  SessionFile other = file;
  other.steps[1].delta(3, 2) += 1e-12;
  EXPECT_FALSE(sameSessionFile(other, file));
  other = file;
  other.steps[0].undone = true;
  EXPECT_FALSE(sameSessionFile(other, file));
  other = file;
  other.steps[0].author = QStringLiteral("Alicia");
  EXPECT_FALSE(sameSessionFile(other, file));
}

TEST(SessionFileTest, RoundTripWithoutCurrentConstraintsStepsOrCoefficients) {
  SessionFile file = sampleSession();
  file.current.reset();
  file.steps.clear();
  file.mode = spectral::DeformationMode::Linear;
  EXPECT_TRUE(sameSessionFile(decoded(encodeSessionFile(file)), file));
  file.Z.resize(0, 0);  // the rest shape
  ASSERT_TRUE(validateSessionFile(file).isEmpty()) << validateSessionFile(file).toStdString();
  EXPECT_TRUE(sameSessionFile(decoded(encodeSessionFile(file)), file));
  // the most steps a file holds, each at the longest author name
  file = sampleSession();
  file.steps.clear();
  for (int i = 0; i < kMaxSavedEditSteps; ++i)
    file.steps.push_back({QString(kMaxStepAuthorBytes, QLatin1Char('a' + i % 26)), delta(file.m, i), i % 3 == 0});
  EXPECT_TRUE(sameSessionFile(decoded(encodeSessionFile(file)), file));
}

TEST(SessionFileTest, Version1FileReadsIntoCurrentConstraintsAndZWithItsHistoryDropped) {
  const v1::LegacySessionFile legacy = legacySession();
  const QByteArray bytes = v1::encodeLegacySessionFile(legacy);
  EXPECT_EQ(qFromLittleEndian<std::uint32_t>(bytes.constData() + 8), 1u);
  const SessionFile file = decoded(bytes);
  EXPECT_EQ(file.V, legacy.V);
  EXPECT_EQ(file.F, legacy.F);
  EXPECT_EQ(file.m, legacy.m);
  EXPECT_EQ(file.mode, legacy.mode);
  EXPECT_TRUE(file.Z.rows() == legacy.Z.rows() && file.Z.cols() == 3 && file.Z == legacy.Z);
  // the handle and anchors of v1's current state, sorted, repeats and handle ids gone from the anchors; no pose
  ASSERT_TRUE(file.current.has_value());
  EXPECT_EQ(file.current->handle, (std::vector<int>{0, 1, 2, 12}));
  EXPECT_EQ(file.current->anchors, (std::vector<int>{40, 41, 42, 50, 60, 70}));
  EXPECT_TRUE(file.steps.empty());
  EXPECT_EQ(file.droppedLegacyDrags, 3);
  EXPECT_TRUE(validateSessionFile(file).isEmpty());
  // saved again, it is a version-2 file (the dropped count is not written)
  SessionFile again = decoded(encodeSessionFile(file));
  EXPECT_EQ(again.droppedLegacyDrags, 0);
  again.droppedLegacyDrags = file.droppedLegacyDrags;
  EXPECT_TRUE(sameSessionFile(again, file));

  v1::LegacySessionFile plain = legacy;
  plain.current.reset();
  plain.history.clear();
  plain.historyIndex = 0;
  const SessionFile bare = decoded(v1::encodeLegacySessionFile(plain));
  EXPECT_FALSE(bare.current.has_value());
  EXPECT_EQ(bare.droppedLegacyDrags, 0);
}

TEST(SessionFileTest, Version1GuardsStillRefuseBadLegacyContent) {
  const v1::LegacySessionFile good = legacySession();
  const auto contentError = [](const v1::LegacySessionFile& file) {
    return errorOf(decodeSessionFile(v1::encodeLegacySessionFile(file))).message;
  };
  v1::LegacySessionFile file = good;
  file.history[2].after.anchors.push_back(static_cast<int>(file.V.rows()) + 7);
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("drag 3 (after)"))) << contentError(file).toStdString();
  file = good;
  file.current->handle.clear();
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("empty handle")));
  file = good;
  file.historyIndex = 4;
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("history index")));
  file = good;
  file.current->rotation(0, 0) = 2.0;
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("rotation")));
  file = good;
  file.history[0].before.translation.x() = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("non-finite pose")));
  file = good;
  file.Z.resize(0, 0);  // version 1 always held m × 3
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("Z is")));
  file = good;
  file.F(3, 1) = static_cast<int>(file.V.rows());
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("face")));
}

TEST(SessionFileTest, RepeatedVersion1ListsAreWrittenOnce) {
  v1::LegacySessionFile file = legacySession();
  const qsizetype shared = v1::encodeLegacySessionFile(file).size();
  // give every state its own (equal-sized) anchor list: each must now be written in full
  int shift = 1;
  for (v1::SavedDrag& drag : file.history) {
    for (v1::SavedDeformation* d : {&drag.before, &drag.after}) {
      for (int& id : d->anchors) id = (id + shift) % static_cast<int>(file.V.rows());
      ++shift;
    }
  }
  EXPECT_LT(shared, v1::encodeLegacySessionFile(file).size());
}

TEST(SessionFileTest, EveryTruncationIsAnError) {
  for (const QByteArray& bytes : {encodeSessionFile(sampleSession()), v1::encodeLegacySessionFile(legacySession())}) {
    for (qsizetype n = 0; n < bytes.size(); ++n) {
      const SessionFileError error = errorOf(decodeSessionFile(bytes.first(n)));
      EXPECT_FALSE(error.message.isEmpty()) << n;
      if (n >= kHeaderBytes + 32) {
        EXPECT_TRUE(error.message.contains(QStringLiteral("truncated"))) << n;
      }
    }
  }
  // truncated payloads with a valid checksum: the parser itself meets the end of the data at every length
  for (const QByteArray& bytes : {encodeSessionFile(sampleSession()), v1::encodeLegacySessionFile(legacySession())}) {
    const QByteArray payload = payloadOf(bytes);
    const std::uint32_t version = qFromLittleEndian<std::uint32_t>(bytes.constData() + 8);
    for (qsizetype n = 0; n < payload.size(); ++n) {
      const SessionFileError error = errorOf(decodeSessionFile(sealed(payload.first(n), version)));
      EXPECT_FALSE(error.message.isEmpty()) << version << " " << n;
    }
  }
}

TEST(SessionFileTest, EveryFlippedByteIsAnError) {
  const QByteArray bytes = encodeSessionFile(sampleSession());
  for (qsizetype i = 0; i < bytes.size(); ++i) {
    QByteArray broken = bytes;
    broken[i] = static_cast<char>(broken[i] ^ 0x20);
    EXPECT_FALSE(errorOf(decodeSessionFile(broken)).message.isEmpty()) << i;
  }
  QByteArray broken = bytes;
  broken[kHeaderBytes + 100] = static_cast<char>(broken[kHeaderBytes + 100] ^ 1);
  EXPECT_TRUE(errorOf(decodeSessionFile(broken)).message.contains(QStringLiteral("checksum")));
}

TEST(SessionFileTest, ForeignNewerAndPaddedFilesAreErrors) {
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  const QString off = dir.filePath(QStringLiteral("mesh.off"));
  QFile text(off);
  ASSERT_TRUE(text.open(QIODevice::WriteOnly));
  text.write("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  text.close();
  EXPECT_FALSE(isSessionFile(off));
  EXPECT_TRUE(errorOf(readSessionFile(off)).message.contains(QStringLiteral("signature")));
  EXPECT_TRUE(errorOf(readSessionFile(dir.filePath(QStringLiteral("missing.shapecast"))))
                  .message.contains(QStringLiteral("Cannot read")));

  const QByteArray bytes = encodeSessionFile(sampleSession());
  QByteArray newer = bytes;
  newer[8] = 3;  // version 3
  EXPECT_TRUE(errorOf(decodeSessionFile(newer)).message.contains(QStringLiteral("version 3")));
  QByteArray zero = bytes;
  zero[8] = 0;
  EXPECT_TRUE(errorOf(decodeSessionFile(zero)).message.contains(QStringLiteral("version 0")));
  EXPECT_TRUE(errorOf(decodeSessionFile(bytes + QByteArray(5, '\0'))).message.contains(QStringLiteral("unexpected")));
  // a version-2 payload under a version-1 header is not read as version 1
  EXPECT_FALSE(errorOf(decodeSessionFile(sealed(payloadOf(bytes), v1::kVersion))).message.isEmpty());
}

TEST(SessionFileTest, ValidChecksumButBadContentIsAnError) {
  const SessionFile good = sampleSession();
  const auto contentError = [](const SessionFile& file) {
    return errorOf(decodeSessionFile(encodeSessionFile(file))).message;
  };
  SessionFile file = good;
  file.F(3, 1) = static_cast<int>(file.V.rows());
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("face"))) << contentError(file).toStdString();
  file = good;
  file.current->anchors.push_back(static_cast<int>(file.V.rows()) + 7);
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("anchor vertex id"))) << contentError(file).toStdString();
  file = good;
  file.current->handle.clear();
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("empty handle")));
  file = good;
  file.current->anchors = {41, 40};
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("out of order or repeated")))
      << contentError(file).toStdString();
  file = good;
  file.current->handle = {3, 3};
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("out of order or repeated")));
  file = good;
  file.current->anchors = {2, 40};
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("vertex 2 in both"))) << contentError(file).toStdString();
  file = good;
  file.m = static_cast<int>(file.V.rows());
  file.Z = Eigen::MatrixXd::Zero(file.m, 3);
  for (SavedEditStep& step : file.steps) step.delta = Eigen::MatrixXd::Zero(file.m, 3);
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("m = ")));
  file = good;
  file.Z = Eigen::MatrixXd::Zero(file.m + 1, 3);
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("Z is")));
  file = good;
  file.Z(2, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("coefficient is not finite")));
  file = good;
  file.V(0, 0) = std::nan("");
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("finite")));

  // counts far beyond the data: refused before anything is allocated
  const QByteArray payload = payloadOf(encodeSessionFile(good));
  for (const qsizetype at : {qsizetype{0}, qsizetype{4}}) {  // #V, #F
    QByteArray huge = payload;
    const std::uint32_t count = qToLittleEndian(std::uint32_t{0xFFFFFFFFu});
    huge.replace(at, 4, reinterpret_cast<const char*>(&count), 4);
    EXPECT_TRUE(errorOf(decodeSessionFile(sealed(huge))).message.contains(QStringLiteral("do not fit"))) << at;
  }
  // the unchanged payload, sealed again, still reads (sealed() is right)
  EXPECT_TRUE(std::holds_alternative<SessionFile>(decodeSessionFile(sealed(payload))));
  EXPECT_FALSE(errorOf(decodeSessionFile(sealed(payload + QByteArray(1, '\0')))).message.isEmpty());
}

TEST(SessionFileTest, MalformedEditStepsAreRefused) {
  const int m = sampleSession().m;
  PayloadWriter one;
  one.step("Bob", 0, m);
  // the hand-written steps are right: one valid step reads
  const SessionFile ok = decoded(withSteps(1, one.bytes()));
  ASSERT_EQ(ok.steps.size(), 1u);
  EXPECT_EQ(ok.steps[0].author, QStringLiteral("Bob"));
  EXPECT_EQ(ok.steps[0].delta, Eigen::MatrixXd::Constant(m, 3, 0.25));

  const auto refusal = [](const QByteArray& bytes) { return errorOf(decodeSessionFile(bytes)).message; };
  // more steps than a file may hold: refused on the count, before the steps (or their space) are looked at
  for (const std::uint32_t count : {std::uint32_t(kMaxSavedEditSteps + 1), std::uint32_t{0xFFFFFFFFu}}) {
    const QString why = refusal(withSteps(count, one.bytes()));
    EXPECT_TRUE(why.contains(QStringLiteral("%1 edit steps (at most 256)").arg(count))) << why.toStdString();
  }
  // a count within the bound but beyond the data
  EXPECT_TRUE(refusal(withSteps(kMaxSavedEditSteps, one.bytes())).contains(QStringLiteral("do not fit")));
  // an author name one byte too long
  PayloadWriter longName;
  longName.step(QByteArray(kMaxStepAuthorBytes + 1, 'x'), 0, m);
  EXPECT_TRUE(refusal(withSteps(1, longName.bytes())).contains(QStringLiteral("author has 65 bytes (at most 64)")))
      << refusal(withSteps(1, longName.bytes())).toStdString();
  PayloadWriter longestName;
  longestName.step(QByteArray(kMaxStepAuthorBytes, 'x'), 0, m);
  EXPECT_EQ(decoded(withSteps(1, longestName.bytes())).steps.at(0).author.size(), kMaxStepAuthorBytes);
  // invalid UTF-8: a stray continuation, a cut sequence, an overlong encoding, a UTF-16 surrogate
  for (const QByteArray& name : {QByteArray("a\x80"
                                            "b"),
                                 QByteArray("Zo\xC3"), QByteArray("\xC0\xAF"), QByteArray("\xED\xA0\x80")}) {
    PayloadWriter bad;
    bad.step(name, 0, m);
    const QString why = refusal(withSteps(2, one.bytes() + bad.bytes()));
    EXPECT_TRUE(why.contains(QStringLiteral("edit step 2's author is not valid UTF-8"))) << why.toStdString();
  }
  // an undone flag other than 0 or 1
  PayloadWriter flag;
  flag.step("Bob", 2, m);
  EXPECT_TRUE(refusal(withSteps(1, flag.bytes())).contains(QStringLiteral("undone flag is 2")));
  // non-finite ΔZ values
  for (const double value : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    PayloadWriter nonFinite;
    nonFinite.step("Bob", 0, m, value);
    const QString why = refusal(withSteps(1, nonFinite.bytes()));
    EXPECT_TRUE(why.contains(QStringLiteral("edit step 1's ΔZ is not finite"))) << why.toStdString();
  }
  // a step cut short: its ΔZ holds m − 1 rows, the file ends
  PayloadWriter shortStep;
  shortStep.step("Bob", 0, m - 1);
  EXPECT_TRUE(refusal(withSteps(1, shortStep.bytes())).contains(QStringLiteral("do not fit")));
}

TEST(SessionFileTest, InvalidEditStepsAreNeitherSavedNorRead) {
  const SessionFile good = sampleSession();
  const auto problem = [](const SessionFile& file) {
    const QString why = validateSessionFile(file);
    // written as it is, the file is refused when read too
    EXPECT_FALSE(errorOf(decodeSessionFile(encodeSessionFile(file))).message.isEmpty()) << why.toStdString();
    return why;
  };
  SessionFile file = good;
  file.steps[1].delta = Eigen::MatrixXd::Zero(file.m + 1, 3);  // wrong rows
  EXPECT_TRUE(problem(file).contains(QStringLiteral("edit step 2's ΔZ is 11 × 3, not m × 3 = 10 × 3")))
      << problem(file).toStdString();
  file = good;
  file.steps[0].delta = Eigen::MatrixXd::Zero(file.m, 2);  // wrong columns
  EXPECT_TRUE(problem(file).contains(QStringLiteral("edit step 1's ΔZ is 10 × 2")));
  file = good;
  file.steps[3].delta(0, 0) = std::nan("");
  EXPECT_TRUE(problem(file).contains(QStringLiteral("edit step 4's ΔZ is not finite")));
  file = good;
  file.steps[2].author = QString(kMaxStepAuthorBytes / 2 + 1, QChar(0x00E9));  // 2 UTF-8 bytes each: 66
  EXPECT_TRUE(problem(file).contains(QStringLiteral("edit step 3's author has 66 UTF-8 bytes")));
  file = good;
  file.steps[2].author = QString(300, QLatin1Char('x'));  // over the u8 length: cut when written, still refused
  EXPECT_TRUE(problem(file).contains(QStringLiteral("author has 300 UTF-8 bytes")));
  file = good;
  file.steps[0].author = QString(QChar(0xD800));  // a lone surrogate, not text UTF-8 can carry
  EXPECT_TRUE(problem(file).contains(QStringLiteral("not valid UTF-8")));
  file = good;
  while (file.steps.size() <= static_cast<std::size_t>(kMaxSavedEditSteps))
    file.steps.push_back({QString(), delta(file.m, 9), false});
  EXPECT_TRUE(problem(file).contains(QStringLiteral("257 edit steps (at most 256)")));
  file = good;
  file.droppedLegacyDrags = -1;
  EXPECT_FALSE(validateSessionFile(file).isEmpty());
}

// Issue 14, item 9: a (version-1) id list is checked where it is written (ids in range, no more ids than
// vertices), before any "same as previous" copies it.
TEST(SessionFileTest, AnIdListLongerThanTheMeshIsRefusedBeforeItIsCopied) {
  const sc::testing::GeneratedMesh mesh = sc::testing::torus(12, 8);
  const auto n = static_cast<int>(mesh.V.rows());
  std::vector<int> anchors;
  for (int i = 0; i < 4 * n; ++i) anchors.push_back(1 + i % (n - 1));  // every id valid, each four times
  const QString why = errorOf(decodeSessionFile(expandingLegacySession(mesh, {0}, anchors, 3))).message;
  EXPECT_TRUE(why.contains(QStringLiteral("anchor list has %1 ids").arg(anchors.size()))) << why.toStdString();
  EXPECT_TRUE(why.contains(QStringLiteral("%1 vertices").arg(n))) << why.toStdString();
  // the same in version 2 (no "same as previous" there, but the bound holds)
  PayloadWriter w;
  w.mesh(mesh);
  w.u32(10);
  w.u8(0);
  w.u8(1);  // has current constraints
  w.u32(1);
  w.u32(0);
  w.u32(static_cast<std::uint32_t>(anchors.size()));
  for (int id : anchors) w.u32(static_cast<std::uint32_t>(id));
  w.u32(0);  // Z: empty
  w.u32(0);
  w.u32(0);  // no steps
  const QString v2 = errorOf(decodeSessionFile(sealed(w.bytes()))).message;
  EXPECT_TRUE(v2.contains(QStringLiteral("anchor list has %1 ids").arg(anchors.size()))) << v2.toStdString();
}

// Issue 14, item 9: a small valid version-1 file whose "same as previous" lists would expand to more ids than
// kMaxSessionFileIds is refused while counting, before the copies are made: peak memory stays near the file's size.
TEST(SessionFileTest, SameAsPreviousListsCannotExpandPastTheBound) {
  const sc::testing::GeneratedMesh mesh = sc::testing::torus(256, 256);  // 65536 vertices
  const auto n = static_cast<int>(mesh.V.rows());
  std::vector<int> anchors(static_cast<std::size_t>(n - 1));
  std::iota(anchors.begin(), anchors.end(), 1);
  // each drag repeats the anchors twice: (1 + 2·drags)·(n − 1) ids, just past the bound
  const auto drags = static_cast<std::uint32_t>(kMaxSessionFileIds / (2 * (n - 1)) + 10);
  const QByteArray bytes = expandingLegacySession(mesh, {0}, anchors, drags);
  const double expandedMiB = (1.0 + 2.0 * drags) * (n - 1) * sizeof(int) / (1 << 20);
  ASSERT_LT(bytes.size(), 4 << 20);  // ≈ 3.5 MB on disk (the mesh is most of it) …
  ASSERT_GT(expandedMiB, 256.0);     // … more than 256 MiB of ids once expanded
  const long before = peakKiB();
  const QString why = errorOf(decodeSessionFile(bytes)).message;
  const long grownKiB = peakKiB() - before;
  EXPECT_TRUE(why.contains(QStringLiteral("more than %1 vertex ids").arg(kMaxSessionFileIds))) << why.toStdString();
  EXPECT_LT(grownKiB, 64 * 1024) << "peak memory grew by " << grownKiB / 1024 << " MiB for a " << bytes.size()
                                 << "-byte file (expanded: " << expandedMiB << " MiB)";
}

// Issue 14, item 9: a file over the size bound is refused before it is read.
TEST(SessionFileTest, FilesOverTheSizeBoundAreRefusedUnread) {
  QTemporaryDir dir;
  const QString path = dir.filePath(QStringLiteral("huge.shapecast"));
  QFile out(path);
  ASSERT_TRUE(out.open(QIODevice::WriteOnly));
  out.write(kSessionFileMagic, sizeof(kSessionFileMagic));
  ASSERT_TRUE(out.resize(kMaxSessionFileBytes + 1));  // sparse: no disk space used
  out.close();
  const QString why = errorOf(readSessionFile(path)).message;
  EXPECT_TRUE(why.contains(QStringLiteral("too large"))) << why.toStdString();
}

TEST(SessionFileTest, SavingNeverLeavesABrokenFile) {
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  const QString path = dir.filePath(QStringLiteral("keep.shapecast"));
  const SessionFile good = sampleSession();
  ASSERT_FALSE(writeSessionFile(path, good).has_value());
  SessionFile bad = good;
  bad.steps[0].author = QString(kMaxStepAuthorBytes + 1, QLatin1Char('x'));
  const std::optional<QString> refused = writeSessionFile(path, bad);
  ASSERT_TRUE(refused.has_value());
  EXPECT_TRUE(refused->contains(QStringLiteral("author has 65 UTF-8 bytes"))) << refused->toStdString();
  const SessionFileResult kept = readSessionFile(path);
  ASSERT_TRUE(std::holds_alternative<SessionFile>(kept));
  EXPECT_TRUE(sameSessionFile(std::get<SessionFile>(kept), good));
  // an unwritable place is an error too
  EXPECT_TRUE(writeSessionFile(dir.filePath(QStringLiteral("no/such/folder/x.shapecast")), good).has_value());
}

}  // namespace
}  // namespace sc::model
