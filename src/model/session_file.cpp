#include "model/session_file.h"

#include <QFile>
#include <QSaveFile>
#include <QtEndian>

#include <openssl/evp.h>
#include <Eigen/Dense>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <utility>

namespace sc::model {

namespace {

constexpr qsizetype kMagicBytes = sizeof(kSessionFileMagic);
constexpr qsizetype kHeaderBytes = kMagicBytes + 4 + 8;  // magic, version, payload length
constexpr qsizetype kChecksumBytes = 32;                 // SHA-256
constexpr double kRotationTolerance = 1e-6;              // |RᵀR − I| and |det R − 1|

// ---------------------------------------------------------------------------------------------------- writing

class Writer {
 public:
  void u8(std::uint8_t v) { m_bytes.append(static_cast<char>(v)); }
  void u32(std::uint32_t v) {
    const std::uint32_t le = qToLittleEndian(v);
    m_bytes.append(reinterpret_cast<const char*>(&le), sizeof le);
  }
  void u64(std::uint64_t v) {
    const std::uint64_t le = qToLittleEndian(v);
    m_bytes.append(reinterpret_cast<const char*>(&le), sizeof le);
  }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }

  /// An id list, or "the same as `previous`" when equal to it; `previous` becomes `ids`.
  void ids(const std::vector<int>& ids, std::optional<std::vector<int>>& previous) {
    if (previous && *previous == ids) {
      u8(0);
      return;
    }
    u8(1);
    u32(static_cast<std::uint32_t>(ids.size()));
    for (int id : ids) u32(static_cast<std::uint32_t>(id));
    previous = ids;
  }

  void deformation(const SavedDeformation& d) {
    ids(d.handle, m_lastHandle);
    ids(d.anchors, m_lastAnchors);
    for (int i = 0; i < 3; ++i) f64(d.translation(i));
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) f64(d.rotation(r, c));
  }

  QByteArray& bytes() { return m_bytes; }

 private:
  QByteArray m_bytes;
  std::optional<std::vector<int>> m_lastHandle;
  std::optional<std::vector<int>> m_lastAnchors;
};

// ---------------------------------------------------------------------------------------------------- reading

/// An id list as read: shared by every "same as previous" reference to it (nothing is copied while parsing).
using IdList = std::shared_ptr<const std::vector<int>>;

/// A deformation as read, its lists still shared (expanded into a SavedDeformation only once the whole file is
/// counted).
struct ParsedDeformation {
  IdList handle;
  IdList anchors;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();

  [[nodiscard]] SavedDeformation expanded() const {
    const auto copy = [](const IdList& list) { return list ? *list : std::vector<int>{}; };
    return SavedDeformation{copy(handle), copy(anchors), translation, rotation};
  }
};

/// Bounds-checked little-endian reader of the payload; the first failure sticks (error()). Id lists are checked as
/// they are read, before anything is expanded: an explicit list holds at most as many ids as the mesh has vertices,
/// and every list, explicit or "the same as the previous one", is counted against kMaxSessionFileIds (a "same"
/// list shares the earlier one: nothing is copied until the whole file is counted, see parsePayload()).
class Reader {
 public:
  explicit Reader(QByteArrayView data) : m_data(data) {}

  [[nodiscard]] bool ok() const { return m_error.isEmpty(); }
  [[nodiscard]] const QString& error() const { return m_error; }
  [[nodiscard]] qsizetype left() const { return m_data.size() - m_at; }
  void fail(const QString& why) {
    if (m_error.isEmpty()) m_error = why;
  }
  /// Whether `count` items of `size` bytes can still be read (fails otherwise, naming `what`).
  bool fits(std::uint64_t count, std::uint64_t size, const char* what) {
    if (!ok()) return false;
    if (count > static_cast<std::uint64_t>(left()) / size) {
      fail(QStringLiteral("truncated or corrupted: %1 %2 do not fit in the remaining %3 bytes")
               .arg(count)
               .arg(QLatin1StringView(what))
               .arg(left()));
      return false;
    }
    return true;
  }

  std::uint8_t u8() { return take<std::uint8_t>(); }
  std::uint32_t u32() { return qFromLittleEndian(take<std::uint32_t>()); }
  std::uint64_t u64() { return qFromLittleEndian(take<std::uint64_t>()); }
  double f64() { return std::bit_cast<double>(u64()); }

  /// The mesh's vertex count, the most ids an explicit list may hold.
  void setVertexCount(std::uint32_t vertices) { m_vertices = vertices; }

  IdList ids(IdList& previous, const char* what) {
    const std::uint8_t kind = u8();
    if (!ok()) return {};
    if (kind == 0) {
      if (!previous) {
        fail(QStringLiteral("corrupted: a %1 list refers to an earlier one that is not there")
                 .arg(QLatin1StringView(what)));
        return {};
      }
      if (!spend(previous->size())) return {};
      return previous;
    }
    if (kind != 1) {
      fail(QStringLiteral("corrupted: unknown %1 list kind %2").arg(QLatin1StringView(what)).arg(kind));
      return {};
    }
    const std::uint32_t count = u32();
    if (ok() && count > m_vertices) {
      fail(QStringLiteral("a %1 list has %2 ids, more than the mesh's %3 vertices")
               .arg(QLatin1StringView(what))
               .arg(count)
               .arg(m_vertices));
      return {};
    }
    if (!fits(count, 4, what) || !spend(count)) return {};
    auto out = std::make_shared<std::vector<int>>(count);
    for (int& id : *out) {
      const std::uint32_t v = u32();
      id = v > static_cast<std::uint32_t>(std::numeric_limits<int>::max()) ? -1 : static_cast<int>(v);
    }
    previous = out;
    return out;
  }

  ParsedDeformation deformation() {
    ParsedDeformation d;
    d.handle = ids(m_lastHandle, "handle");
    d.anchors = ids(m_lastAnchors, "anchor");
    for (int i = 0; i < 3; ++i) d.translation(i) = f64();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) d.rotation(r, c) = f64();
    return d;
  }

 private:
  template <typename T>
  T take() {
    T v{};
    if (!ok()) return v;
    if (left() < static_cast<qsizetype>(sizeof(T))) {
      fail(QStringLiteral("truncated: the data ends %1 bytes after the header").arg(m_at));
      return v;
    }
    std::memcpy(&v, m_data.data() + m_at, sizeof(T));
    m_at += static_cast<qsizetype>(sizeof(T));
    return v;
  }

  /// Counts `count` more ids against kMaxSessionFileIds; fails once the file's lists would exceed it.
  bool spend(std::uint64_t count) {
    m_ids += count;
    if (m_ids <= static_cast<std::uint64_t>(kMaxSessionFileIds)) return true;
    fail(QStringLiteral("its constraint lists expand to more than %1 vertex ids").arg(kMaxSessionFileIds));
    return false;
  }

  QByteArrayView m_data;
  qsizetype m_at = 0;
  QString m_error;
  std::uint32_t m_vertices = 0;
  std::uint64_t m_ids = 0;  ///< ids in all lists so far, "same as previous" ones counted again
  IdList m_lastHandle;
  IdList m_lastAnchors;
};

/// SHA-256 through OpenSSL (EVP_Digest); empty only if OpenSSL fails.
QByteArray sha256(QByteArrayView bytes) {
  QByteArray digest(kChecksumBytes, Qt::Uninitialized);
  unsigned int size = 0;
  if (EVP_Digest(bytes.data(), static_cast<std::size_t>(bytes.size()), reinterpret_cast<unsigned char*>(digest.data()),
                 &size, EVP_sha256(), nullptr) != 1 ||
      size != static_cast<unsigned int>(kChecksumBytes)) {
    return {};
  }
  return digest;
}

/// Empty when `d` is a usable state of a mesh with `n` vertices, else the problem (prefixed with `what`).
QString validateDeformation(const SavedDeformation& d, int n, const QString& what) {
  if (d.handle.empty()) return QStringLiteral("%1 has an empty handle").arg(what);
  const auto outOfRange = [n](int id) { return id < 0 || id >= n; };
  for (const std::vector<int>* list : {&d.handle, &d.anchors}) {
    for (int id : *list) {
      if (outOfRange(id)) return QStringLiteral("%1 has vertex id %2, outside 0..%3").arg(what).arg(id).arg(n - 1);
    }
  }
  if (!d.translation.allFinite() || !d.rotation.allFinite())
    return QStringLiteral("%1 has a non-finite pose").arg(what);
  const double orthogonality =
      (d.rotation.transpose() * d.rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthogonality > kRotationTolerance || std::abs(d.rotation.determinant() - 1.0) > kRotationTolerance) {
    return QStringLiteral("%1 has a pose whose rotation is not a rotation").arg(what);
  }
  return {};
}

SessionFileError error(const QString& why) {
  return SessionFileError{QStringLiteral("Not a usable ShapeCast session file: %1.").arg(why)};
}

SessionFile parsePayload(Reader& in) {
  SessionFile file;
  const std::uint32_t vertices = in.u32();
  const std::uint32_t faces = in.u32();
  in.setVertexCount(vertices);
  if (in.fits(vertices, 24, "vertices")) {
    file.V.resize(vertices, 3);
    for (Eigen::Index i = 0; i < file.V.rows(); ++i)
      for (int c = 0; c < 3; ++c) file.V(i, c) = in.f64();
  }
  if (in.fits(faces, 12, "faces")) {
    file.F.resize(faces, 3);
    for (Eigen::Index i = 0; i < file.F.rows(); ++i) {
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t v = in.u32();
        file.F(i, c) = v >= vertices ? -1 : static_cast<int>(v);  // validate() names it
      }
    }
  }
  file.m = static_cast<int>(std::min<std::uint32_t>(in.u32(), std::numeric_limits<int>::max()));
  const std::uint8_t mode = in.u8();
  if (mode > 1) in.fail(QStringLiteral("unknown deformation mode %1").arg(mode));
  file.mode = mode == 1 ? spectral::DeformationMode::Rigid : spectral::DeformationMode::Linear;
  const std::uint8_t hasCurrent = in.u8();
  if (hasCurrent > 1) in.fail(QStringLiteral("corrupted: current-state flag %1").arg(hasCurrent));
  std::optional<ParsedDeformation> current;
  if (hasCurrent == 1) current = in.deformation();
  const std::uint32_t zRows = in.u32();
  const std::uint32_t zCols = in.u32();
  if (zCols > 3) in.fail(QStringLiteral("Z has %1 columns (3 expected)").arg(zCols));
  if (in.fits(std::uint64_t{zRows} * zCols, 8, "coefficients")) {
    file.Z.resize(zRows, zCols);
    for (Eigen::Index r = 0; r < file.Z.rows(); ++r)
      for (Eigen::Index c = 0; c < file.Z.cols(); ++c) file.Z(r, c) = in.f64();
  }
  const std::uint32_t count = in.u32();
  const std::uint32_t index = in.u32();
  // each drag takes at least 2 × (2 list kinds + 12 doubles) = 196 bytes
  std::vector<std::pair<ParsedDeformation, ParsedDeformation>> history;
  if (in.fits(count, 2 * (2 + 12 * 8), "drags")) {
    history.reserve(count);
    for (std::uint32_t i = 0; i < count && in.ok(); ++i) {
      ParsedDeformation before = in.deformation();
      history.emplace_back(std::move(before), in.deformation());
    }
  }
  file.historyIndex = static_cast<int>(std::min<std::uint32_t>(index, std::numeric_limits<int>::max()));
  if (in.ok() && in.left() != 0) in.fail(QStringLiteral("corrupted: %1 unexplained bytes at the end").arg(in.left()));
  if (!in.ok()) return file;
  // Every list was counted against kMaxSessionFileIds: the copies below are bounded.
  if (current) file.current = current->expanded();
  file.history.reserve(history.size());
  for (const auto& drag : history) file.history.push_back(SavedDrag{drag.first.expanded(), drag.second.expanded()});
  return file;
}

}  // namespace

bool sameSessionFile(const SessionFile& a, const SessionFile& b) {
  const auto same = [](const auto& x, const auto& y) { return x.rows() == y.rows() && x.cols() == y.cols() && x == y; };
  return same(a.V, b.V) && same(a.F, b.F) && a.m == b.m && a.mode == b.mode && a.current == b.current &&
         same(a.Z, b.Z) && a.history == b.history && a.historyIndex == b.historyIndex;
}

QString validateSessionFile(const SessionFile& file) {
  const auto n = static_cast<int>(file.V.rows());
  if (file.V.cols() != 3 || n < 4) return QStringLiteral("the mesh has %1 vertices (at least 4 needed)").arg(n);
  if (file.F.cols() != 3 || file.F.rows() < 1) return QStringLiteral("the mesh has no faces");
  if (!file.V.allFinite()) return QStringLiteral("a vertex position is not finite");
  if (file.F.minCoeff() < 0 || file.F.maxCoeff() >= n) {
    return QStringLiteral("a face refers to a vertex outside 0..%1").arg(n - 1);
  }
  if (file.m < 1 || file.m >= n) return QStringLiteral("m = %1 is not in 1..%2").arg(file.m).arg(n - 1);
  if (file.Z.rows() != file.m || file.Z.cols() != 3) {
    return QStringLiteral("Z is %1 × %2, not m × 3 = %3 × 3").arg(file.Z.rows()).arg(file.Z.cols()).arg(file.m);
  }
  if (!file.Z.allFinite()) return QStringLiteral("a coefficient is not finite");
  if (file.current) {
    if (QString why = validateDeformation(*file.current, n, QStringLiteral("the current state")); !why.isEmpty()) {
      return why;
    }
  }
  for (std::size_t i = 0; i < file.history.size(); ++i) {
    const SavedDrag& drag = file.history[i];
    if (QString why = validateDeformation(drag.before, n, QStringLiteral("drag %1 (before)").arg(i + 1));
        !why.isEmpty()) {
      return why;
    }
    if (QString why = validateDeformation(drag.after, n, QStringLiteral("drag %1 (after)").arg(i + 1));
        !why.isEmpty()) {
      return why;
    }
  }
  if (file.historyIndex < 0 || static_cast<std::size_t>(file.historyIndex) > file.history.size()) {
    return QStringLiteral("the history index %1 is not in 0..%2").arg(file.historyIndex).arg(file.history.size());
  }
  return {};
}

QByteArray encodeSessionFile(const SessionFile& file) {
  Writer payload;
  payload.u32(static_cast<std::uint32_t>(file.V.rows()));
  payload.u32(static_cast<std::uint32_t>(file.F.rows()));
  for (Eigen::Index i = 0; i < file.V.rows(); ++i)
    for (Eigen::Index c = 0; c < file.V.cols(); ++c) payload.f64(file.V(i, c));
  for (Eigen::Index i = 0; i < file.F.rows(); ++i)
    for (Eigen::Index c = 0; c < file.F.cols(); ++c) payload.u32(static_cast<std::uint32_t>(file.F(i, c)));
  payload.u32(static_cast<std::uint32_t>(file.m));
  payload.u8(file.mode == spectral::DeformationMode::Rigid ? 1 : 0);
  payload.u8(file.current ? 1 : 0);
  if (file.current) payload.deformation(*file.current);
  payload.u32(static_cast<std::uint32_t>(file.Z.rows()));
  payload.u32(static_cast<std::uint32_t>(file.Z.cols()));
  for (Eigen::Index r = 0; r < file.Z.rows(); ++r)
    for (Eigen::Index c = 0; c < file.Z.cols(); ++c) payload.f64(file.Z(r, c));
  payload.u32(static_cast<std::uint32_t>(file.history.size()));
  payload.u32(static_cast<std::uint32_t>(file.historyIndex));
  for (const SavedDrag& drag : file.history) {
    payload.deformation(drag.before);
    payload.deformation(drag.after);
  }

  Writer out;
  out.bytes().append(kSessionFileMagic, kMagicBytes);
  out.u32(kSessionFileVersion);
  out.u64(static_cast<std::uint64_t>(payload.bytes().size()));
  out.bytes().append(payload.bytes());
  out.bytes().append(sha256(out.bytes()));
  return std::move(out.bytes());
}

SessionFileResult decodeSessionFile(const QByteArray& bytes) {
  if (bytes.size() > kMaxSessionFileBytes) {
    return error(QStringLiteral("it is too large (%1 bytes, at most %2)").arg(bytes.size()).arg(kMaxSessionFileBytes));
  }
  if (bytes.size() < kMagicBytes || std::memcmp(bytes.constData(), kSessionFileMagic, kMagicBytes) != 0) {
    return error(QStringLiteral("it does not start with the session file signature (another kind of file?)"));
  }
  if (bytes.size() < kHeaderBytes + kChecksumBytes) {
    return error(QStringLiteral("truncated: only %1 bytes").arg(bytes.size()));
  }
  Reader header(QByteArrayView(bytes).sliced(kMagicBytes, 12));
  const std::uint32_t version = header.u32();
  const std::uint64_t length = header.u64();
  if (version == 0 || version > kSessionFileVersion) {
    return error(
        QStringLiteral("it has format version %1; this ShapeCast reads version %2 (a newer ShapeCast wrote it?)")
            .arg(version)
            .arg(kSessionFileVersion));
  }
  const auto available = static_cast<std::uint64_t>(bytes.size() - kHeaderBytes - kChecksumBytes);
  if (length > available) {
    return error(QStringLiteral("truncated: %1 of %2 bytes")
                     .arg(bytes.size())
                     .arg(length + static_cast<std::uint64_t>(kHeaderBytes + kChecksumBytes)));
  }
  if (length < available) {
    return error(QStringLiteral("%1 unexpected bytes after the checksum").arg(available - length));
  }
  const qsizetype end = kHeaderBytes + static_cast<qsizetype>(length);
  if (sha256(QByteArrayView(bytes).first(end)) != QByteArrayView(bytes).sliced(end, kChecksumBytes)) {
    return error(QStringLiteral("corrupted: the SHA-256 checksum does not match the content"));
  }
  Reader payload(QByteArrayView(bytes).sliced(kHeaderBytes, static_cast<qsizetype>(length)));
  SessionFile file = parsePayload(payload);
  if (!payload.ok()) return error(payload.error());
  if (const QString why = validateSessionFile(file); !why.isEmpty()) return error(why);
  return file;
}

std::optional<QString> writeSessionFile(const QString& path, const SessionFile& file) {
  if (const QString why = validateSessionFile(file); !why.isEmpty()) {
    return QStringLiteral("The session cannot be saved: %1.").arg(why);
  }
  const QByteArray bytes = encodeSessionFile(file);
  QSaveFile out(path);
  if (!out.open(QIODevice::WriteOnly)) return QStringLiteral("Cannot write %1: %2").arg(path, out.errorString());
  if (out.write(bytes) != bytes.size()) {
    const QString why = out.errorString();
    out.cancelWriting();
    return QStringLiteral("Cannot write %1: %2").arg(path, why);
  }
  if (!out.commit()) return QStringLiteral("Cannot write %1: %2").arg(path, out.errorString());
  return std::nullopt;
}

SessionFileResult readSessionFile(const QString& path) {
  QFile in(path);
  if (!in.open(QIODevice::ReadOnly)) {
    return SessionFileError{QStringLiteral("Cannot read %1: %2").arg(path, in.errorString())};
  }
  if (in.size() > kMaxSessionFileBytes) {
    return SessionFileError{QStringLiteral("%1 is too large (%2 bytes, at most %3) for a session file")
                                .arg(path)
                                .arg(in.size())
                                .arg(kMaxSessionFileBytes)};
  }
  SessionFileResult result = decodeSessionFile(in.readAll());
  if (auto* failure = std::get_if<SessionFileError>(&result))
    failure->message = path + QStringLiteral(": ") + failure->message;
  return result;
}

bool isSessionFile(const QString& path) {
  QFile in(path);
  if (!in.open(QIODevice::ReadOnly)) return false;
  const QByteArray start = in.read(kMagicBytes);
  return start.size() == kMagicBytes && std::memcmp(start.constData(), kSessionFileMagic, kMagicBytes) == 0;
}

}  // namespace sc::model
