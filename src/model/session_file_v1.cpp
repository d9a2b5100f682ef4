#include "model/session_file_v1.h"

#include "model/session_file_codec.h"
#include "model/session_file_ids.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace sc::model::v1 {

namespace {

using detail::ByteReader;
using detail::ByteWriter;
using detail::SharedIdList;

constexpr double kRotationTolerance = 1e-6;  // |RᵀR − I| and |det R − 1|

class StateWriter {
 public:
  explicit StateWriter(ByteWriter& out) : m_out(out) {}
  void write(const SavedDeformation& d) {
    detail::writeLegacyIdList(m_out, d.handle, m_lastHandle);
    detail::writeLegacyIdList(m_out, d.anchors, m_lastAnchors);
    for (int i = 0; i < 3; ++i) m_out.f64(d.translation(i));
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m_out.f64(d.rotation(r, c));
  }

 private:
  ByteWriter& m_out;
  std::optional<std::vector<int>> m_lastHandle;
  std::optional<std::vector<int>> m_lastAnchors;
};

/// A state as read, its lists still shared (expanded only once the whole file is counted).
struct ParsedState {
  SharedIdList handle;
  SharedIdList anchors;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();

  [[nodiscard]] SavedDeformation expandedState() const {
    return {detail::expanded(handle), detail::expanded(anchors), translation, rotation};
  }
};

class StateReader {
 public:
  StateReader(ByteReader& in, std::uint32_t vertices) : m_in(in), m_lists(vertices) {}
  ParsedState read() {
    ParsedState d;
    d.handle = m_lists.read(m_in, m_lastHandle, "handle");
    d.anchors = m_lists.read(m_in, m_lastAnchors, "anchor");
    for (int i = 0; i < 3; ++i) d.translation(i) = m_in.f64();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) d.rotation(r, c) = m_in.f64();
    return d;
  }

 private:
  ByteReader& m_in;
  detail::LegacyIdListReader m_lists;
  SharedIdList m_lastHandle;
  SharedIdList m_lastAnchors;
};

LegacySessionFile parsePayload(ByteReader& in) {
  LegacySessionFile file;
  const std::uint32_t vertices = detail::readMeshPart(in, file.V, file.F, file.m, file.mode);
  StateReader states(in, vertices);
  const std::uint8_t hasCurrent = in.u8();
  if (hasCurrent > 1) in.fail(QStringLiteral("corrupted: current-state flag %1").arg(hasCurrent));
  std::optional<ParsedState> current;
  if (hasCurrent == 1) current = states.read();
  detail::readMatrix(in, file.Z, "coefficients");
  const std::uint32_t count = in.u32();
  const std::uint32_t index = in.u32();
  // each drag takes at least 2 × (2 list kinds + 12 doubles) = 196 bytes
  std::vector<std::pair<ParsedState, ParsedState>> history;
  if (in.fits(count, 2 * (2 + 12 * 8), "drags")) {
    history.reserve(count);
    for (std::uint32_t i = 0; i < count && in.ok(); ++i) {
      ParsedState before = states.read();
      history.emplace_back(std::move(before), states.read());
    }
  }
  file.historyIndex = static_cast<int>(std::min<std::uint32_t>(index, std::numeric_limits<int>::max()));
  if (in.ok() && in.left() != 0) in.fail(QStringLiteral("corrupted: %1 unexplained bytes at the end").arg(in.left()));
  if (!in.ok()) return file;
  // Every list was counted against kMaxSessionFileIds: the copies below are bounded.
  if (current) file.current = current->expandedState();
  file.history.reserve(history.size());
  for (const auto& drag : history) file.history.push_back({drag.first.expandedState(), drag.second.expandedState()});
  return file;
}

/// Empty when `d` is a usable version-1 state of a mesh with `n` vertices, else the problem (prefixed with `what`).
QString validateState(const SavedDeformation& d, int n, const QString& what) {
  if (d.handle.empty()) return QStringLiteral("%1 has an empty handle").arg(what);
  for (const std::vector<int>* list : {&d.handle, &d.anchors}) {
    for (int id : *list) {
      if (id < 0 || id >= n) return QStringLiteral("%1 has vertex id %2, outside 0..%3").arg(what).arg(id).arg(n - 1);
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

QString validate(const LegacySessionFile& file) {
  if (QString why = detail::validateMeshPart(file.V, file.F, file.m); !why.isEmpty()) return why;
  if (file.Z.rows() != file.m || file.Z.cols() != 3) {
    return QStringLiteral("Z is %1 × %2, not m × 3 = %3 × 3").arg(file.Z.rows()).arg(file.Z.cols()).arg(file.m);
  }
  const auto n = static_cast<int>(file.V.rows());
  if (file.current) {
    if (QString why = validateState(*file.current, n, QStringLiteral("the current state")); !why.isEmpty()) return why;
  }
  for (std::size_t i = 0; i < file.history.size(); ++i) {
    const SavedDrag& drag = file.history[i];
    if (QString why = validateState(drag.before, n, QStringLiteral("drag %1 (before)").arg(i + 1)); !why.isEmpty())
      return why;
    if (QString why = validateState(drag.after, n, QStringLiteral("drag %1 (after)").arg(i + 1)); !why.isEmpty())
      return why;
  }
  if (file.historyIndex < 0 || static_cast<std::size_t>(file.historyIndex) > file.history.size()) {
    return QStringLiteral("the history index %1 is not in 0..%2").arg(file.historyIndex).arg(file.history.size());
  }
  return {};
}

}  // namespace

QByteArray encodeLegacySessionFile(const LegacySessionFile& file) {
  ByteWriter payload;
  detail::writeMeshPart(payload, file.V, file.F, file.m, file.mode);
  StateWriter states(payload);
  payload.u8(file.current ? 1 : 0);
  if (file.current) states.write(*file.current);
  detail::writeMatrix(payload, file.Z);
  payload.u32(static_cast<std::uint32_t>(file.history.size()));
  payload.u32(static_cast<std::uint32_t>(file.historyIndex));
  for (const SavedDrag& drag : file.history) {
    states.write(drag.before);
    states.write(drag.after);
  }
  return detail::sealSessionPayload(kVersion, payload.bytes());
}

QString decodeLegacyPayload(QByteArrayView payload, SessionFile* out) {
  ByteReader in(payload);
  LegacySessionFile legacy = parsePayload(in);
  if (!in.ok()) return in.error();
  if (QString why = validate(legacy); !why.isEmpty()) return why;
  SessionFile file;
  file.V = std::move(legacy.V);
  file.F = std::move(legacy.F);
  file.m = legacy.m;
  file.mode = legacy.mode;
  file.Z = std::move(legacy.Z);
  if (legacy.current)
    file.current = detail::normalisedConstraints(std::move(legacy.current->handle), std::move(legacy.current->anchors));
  file.droppedLegacyDrags = static_cast<int>(legacy.history.size());
  *out = std::move(file);
  return {};
}

}  // namespace sc::model::v1
