// The saved session file (model/session_file.h): round trips through bytes and through a file, and every kind of
// broken input — every truncation, every flipped byte, foreign files, a newer version, trailing bytes, and files
// whose checksum is right but whose content is not (ids out of range, huge counts, a bad history index) — gives a
// readable error instead of a crash. Saving never replaces an existing file with a broken one.

#include "model/session_file.h"

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
#include <numbers>
#include <numeric>
#include <variant>

namespace sc::model {
namespace {

constexpr qsizetype kHeaderBytes = 20;  // magic, version, payload length

SavedDeformation deformation(std::vector<int> handle, std::vector<int> anchors, double dy, double degrees) {
  SavedDeformation d;
  d.handle = std::move(handle);
  d.anchors = std::move(anchors);
  d.translation = Eigen::Vector3d(0.1, dy, -0.05);
  d.rotation =
      Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  return d;
}

/// A small torus session with a current state, Z and three drags (two sharing their anchors), two applied.
SessionFile sampleSession() {
  const sc::testing::GeneratedMesh mesh = sc::testing::torus(12, 8);
  SessionFile file;
  file.V = mesh.V;
  file.F = mesh.F;
  file.m = 10;
  file.mode = spectral::DeformationMode::Rigid;
  file.Z = Eigen::MatrixXd::Random(file.m, 3);
  const std::vector<int> handle{0, 1, 2, 12};
  const std::vector<int> anchors{40, 41, 42, 50, 60, 70};
  const SavedDeformation rest = deformation(handle, anchors, 0.0, 0.0);
  const SavedDeformation first = deformation(handle, anchors, 0.2, 10.0);
  const SavedDeformation second = deformation(handle, anchors, 0.3, -5.0);
  const SavedDeformation third = deformation({5, 6}, {80, 81}, -0.1, 30.0);
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

/// `payload` with a fresh header and a valid checksum (to reach the content checks behind the checksum).
QByteArray sealed(const QByteArray& payload) {
  QByteArray out(kSessionFileMagic, sizeof(kSessionFileMagic));
  const std::uint32_t version = qToLittleEndian(kSessionFileVersion);
  const std::uint64_t length = qToLittleEndian(static_cast<std::uint64_t>(payload.size()));
  out.append(reinterpret_cast<const char*>(&version), 4);
  out.append(reinterpret_cast<const char*>(&length), 8);
  out.append(payload);
  out.append(QCryptographicHash::hash(out, QCryptographicHash::Sha256));
  return out;
}

QByteArray payloadOf(const QByteArray& bytes) { return bytes.mid(kHeaderBytes, bytes.size() - kHeaderBytes - 32); }

/// Little-endian payload bytes written by hand (for files encodeSessionFile() would never write, or only from an
/// expanded SessionFile too large to build in a test).
class PayloadWriter {
 public:
  void u8(std::uint8_t v) { m_bytes.append(static_cast<char>(v)); }
  void u32(std::uint32_t v) {
    const std::uint32_t le = qToLittleEndian(v);
    m_bytes.append(reinterpret_cast<const char*>(&le), 4);
  }
  void f64(double v) {
    const std::uint64_t le = qToLittleEndian(std::bit_cast<std::uint64_t>(v));
    m_bytes.append(reinterpret_cast<const char*>(&le), 8);
  }
  void mesh(const sc::testing::GeneratedMesh& mesh) {
    u32(static_cast<std::uint32_t>(mesh.V.rows()));
    u32(static_cast<std::uint32_t>(mesh.F.rows()));
    for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
      for (int c = 0; c < 3; ++c) f64(mesh.V(i, c));
    for (Eigen::Index i = 0; i < mesh.F.rows(); ++i)
      for (int c = 0; c < 3; ++c) u32(static_cast<std::uint32_t>(mesh.F(i, c)));
  }
  /// An explicit id list.
  void ids(const std::vector<int>& ids) {
    u8(1);
    u32(static_cast<std::uint32_t>(ids.size()));
    for (int id : ids) u32(static_cast<std::uint32_t>(id));
  }
  /// Handle and anchors both "the same as the previous list", the identity pose.
  void sameDeformation() {
    u8(0);
    u8(0);
    pose();
  }
  void pose() {
    for (int i = 0; i < 3; ++i) f64(0.0);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) f64(r == c ? 1.0 : 0.0);
  }
  /// m, linear mode, Z = 0 (m × 3).
  void modeAndZ(std::uint32_t m) {
    u8(0);
    u32(m);
    u32(3);
    for (std::uint32_t i = 0; i < 3 * m; ++i) f64(0.0);
  }
  const QByteArray& bytes() const { return m_bytes; }

 private:
  QByteArray m_bytes;
};

/// A valid-looking session of `mesh` whose current state has `handle` and `anchors` written once, followed by
/// `drags` drags whose states all say "the same lists as before": small on disk, each drag expanding to two
/// copies of both lists in memory.
QByteArray expandingSession(const sc::testing::GeneratedMesh& mesh, const std::vector<int>& handle,
                            const std::vector<int>& anchors, std::uint32_t drags) {
  PayloadWriter w;
  w.mesh(mesh);
  w.u32(10);  // m
  w.u8(0);    // linear
  w.u8(1);    // has a current state
  w.ids(handle);
  w.ids(anchors);
  w.pose();
  w.u32(10);
  w.u32(3);
  for (int i = 0; i < 30; ++i) w.f64(0.0);
  w.u32(drags);
  w.u32(0);  // history index
  for (std::uint32_t i = 0; i < drags; ++i) {
    w.sameDeformation();
    w.sameDeformation();
  }
  return sealed(w.bytes());
}

/// The process's peak resident set so far, in KiB (Linux: ru_maxrss).
long peakKiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

TEST(SessionFileTest, RoundTripThroughBytesAndAFile) {
  const SessionFile file = sampleSession();
  ASSERT_TRUE(validateSessionFile(file).isEmpty()) << validateSessionFile(file).toStdString();
  const QByteArray bytes = encodeSessionFile(file);
  const SessionFileResult decoded = decodeSessionFile(bytes);
  ASSERT_TRUE(std::holds_alternative<SessionFile>(decoded))
      << std::get<SessionFileError>(decoded).message.toStdString();
  EXPECT_TRUE(sameSessionFile(std::get<SessionFile>(decoded), file));

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
  other.history[1].after.translation.x() += 1e-12;
  EXPECT_FALSE(sameSessionFile(other, file));
}

TEST(SessionFileTest, RoundTripWithoutCurrentStateOrHistory) {
  SessionFile file = sampleSession();
  file.current.reset();
  file.history.clear();
  file.historyIndex = 0;
  file.mode = spectral::DeformationMode::Linear;
  const SessionFileResult decoded = decodeSessionFile(encodeSessionFile(file));
  ASSERT_TRUE(std::holds_alternative<SessionFile>(decoded));
  EXPECT_TRUE(sameSessionFile(std::get<SessionFile>(decoded), file));
}

TEST(SessionFileTest, RepeatedConstraintListsAreWrittenOnce) {
  SessionFile file = sampleSession();
  const qsizetype shared = encodeSessionFile(file).size();
  // give every state its own (equal-sized) anchor list: each must now be written in full
  int shift = 1;
  for (SavedDrag& drag : file.history) {
    for (SavedDeformation* d : {&drag.before, &drag.after}) {
      for (int& id : d->anchors) id = (id + shift) % static_cast<int>(file.V.rows());
      ++shift;
    }
  }
  EXPECT_LT(shared, encodeSessionFile(file).size());
}

TEST(SessionFileTest, EveryTruncationIsAnError) {
  const QByteArray bytes = encodeSessionFile(sampleSession());
  for (qsizetype n = 0; n < bytes.size(); ++n) {
    const SessionFileError error = errorOf(decodeSessionFile(bytes.first(n)));
    EXPECT_FALSE(error.message.isEmpty()) << n;
    if (n >= kHeaderBytes + 32) {
      EXPECT_TRUE(error.message.contains(QStringLiteral("truncated"))) << n;
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
  newer[8] = 2;  // version 2
  EXPECT_TRUE(errorOf(decodeSessionFile(newer)).message.contains(QStringLiteral("version 2")));
  EXPECT_TRUE(errorOf(decodeSessionFile(bytes + QByteArray(5, '\0'))).message.contains(QStringLiteral("unexpected")));
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
  file.history[2].after.anchors.push_back(static_cast<int>(file.V.rows()) + 7);
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("drag 3 (after)"))) << contentError(file).toStdString();
  file = good;
  file.current->handle.clear();
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("empty handle")));
  file = good;
  file.historyIndex = 4;
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("history index")));
  file = good;
  file.m = static_cast<int>(file.V.rows());
  file.Z = Eigen::MatrixXd::Zero(file.m, 3);
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("m = ")));
  file = good;
  file.Z = Eigen::MatrixXd::Zero(file.m + 1, 3);
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("Z is")));
  file = good;
  file.current->rotation(0, 0) = 2.0;
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("rotation")));
  file = good;
  file.V(0, 0) = std::nan("");
  EXPECT_TRUE(contentError(file).contains(QStringLiteral("finite")));

  // counts far beyond the data: refused before anything is allocated
  QByteArray payload = payloadOf(encodeSessionFile(good));
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

// Issue 14, item 9: an id list is checked where it is written (ids in range, no more ids than vertices), before
// any "same as previous" copies it.
TEST(SessionFileTest, AnIdListLongerThanTheMeshIsRefusedBeforeItIsCopied) {
  const sc::testing::GeneratedMesh mesh = sc::testing::torus(12, 8);
  const auto n = static_cast<int>(mesh.V.rows());
  std::vector<int> anchors;
  for (int i = 0; i < 4 * n; ++i) anchors.push_back(1 + i % (n - 1));  // every id valid, each four times
  const QString why = errorOf(decodeSessionFile(expandingSession(mesh, {0}, anchors, 3))).message;
  EXPECT_TRUE(why.contains(QStringLiteral("anchor list has %1 ids").arg(anchors.size()))) << why.toStdString();
  EXPECT_TRUE(why.contains(QStringLiteral("%1 vertices").arg(n))) << why.toStdString();
}

// Issue 14, item 9: a small valid file whose "same as previous" lists would expand to more ids than
// kMaxSessionFileIds is refused while counting, before the copies are made: peak memory stays near the file's size.
TEST(SessionFileTest, SameAsPreviousListsCannotExpandPastTheBound) {
  const sc::testing::GeneratedMesh mesh = sc::testing::torus(256, 256);  // 65536 vertices
  const auto n = static_cast<int>(mesh.V.rows());
  std::vector<int> anchors(static_cast<std::size_t>(n - 1));
  std::iota(anchors.begin(), anchors.end(), 1);
  // each drag repeats the anchors twice: (1 + 2·drags)·(n − 1) ids, just past the bound
  const auto drags = static_cast<std::uint32_t>(kMaxSessionFileIds / (2 * (n - 1)) + 10);
  const QByteArray bytes = expandingSession(mesh, {0}, anchors, drags);
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
  bad.historyIndex = -1;
  const std::optional<QString> refused = writeSessionFile(path, bad);
  ASSERT_TRUE(refused.has_value());
  EXPECT_TRUE(refused->contains(QStringLiteral("history index")));
  const SessionFileResult kept = readSessionFile(path);
  ASSERT_TRUE(std::holds_alternative<SessionFile>(kept));
  EXPECT_TRUE(sameSessionFile(std::get<SessionFile>(kept), good));
  // an unwritable place is an error too
  EXPECT_TRUE(writeSessionFile(dir.filePath(QStringLiteral("no/such/folder/x.shapecast")), good).has_value());
}

}  // namespace
}  // namespace sc::model
