#include "session/engine/client_level_decode.h"

#include "session/wire/level_codec.h"
#include "session/wire/model_transfer.h"
#include "spectral/resolution_level.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <span>
#include <utility>

namespace sc::session {
namespace {

QString mib(std::uint64_t bytes) {
  return QStringLiteral("%1 MiB").arg(static_cast<double>(bytes) / (1 << 20), 0, 'f', 1);
}

template <class Matrix>
bool allDisplayable(const Matrix& values) {
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    const double v = static_cast<double>(values.data()[i]);
    if (!std::isfinite(v) || std::abs(v) > kMaxAbsCoordinate) return false;
  }
  return true;
}

}  // namespace

PayloadBounds levelPayloadBounds(std::uint64_t vertices, std::uint64_t faces, std::uint64_t rows) {
  // header 32 + X̂' 24n' + F' 12f' + CSR offsets 4(n'+1) + P 12z + scales 4m + K 2n'm + checksum 8
  // (resolution_level.h, level format 2)
  const std::uint64_t fixed = 44 + 28 * vertices + 12 * faces + 4 * rows + 2 * vertices * rows;
  return PayloadBounds{fixed, fixed + 36 * vertices};
}

QString checkSessionShape(std::uint16_t rows, std::uint32_t vertices) {
  if (rows == 0 || vertices == 0) {
    return QStringLiteral("the host announced an empty model (m = %1, n = %2)").arg(rows).arg(vertices);
  }
  const std::uint64_t smallest = levelPayloadBounds(vertices, 1, rows).min + 12ull * vertices;
  if (smallest > kMaxTransferSize) {
    return QStringLiteral(
               "the host announced a model of %1 vertices and m = %2, which no transfer could carry "
               "(at least %3, the limit is %4)")
        .arg(vertices)
        .arg(rows)
        .arg(mib(smallest), mib(kMaxTransferSize));
  }
  return {};
}

QString checkLevelList(const LevelList& list, std::uint16_t rows, std::uint32_t vertices) {
  for (const LevelInfo& level : list.levels) {
    const QString which = QStringLiteral("level %1 of the host's level list").arg(level.levelId);
    if (level.vertexCount == 0 || level.vertexCount > vertices ||
        (level.levelId == 0 && level.vertexCount != vertices)) {
      return QStringLiteral("%1 has %2 vertices, but the model has %3").arg(which).arg(level.vertexCount).arg(vertices);
    }
    if (level.faceCount == 0 ||
        std::uint64_t{level.faceCount} > std::uint64_t{kMaxFacesPerVertex} * level.vertexCount) {
      return QStringLiteral("%1 has %2 faces for %3 vertices").arg(which).arg(level.faceCount).arg(level.vertexCount);
    }
    const PayloadBounds bounds = levelPayloadBounds(level.vertexCount, level.faceCount, rows);
    // Compressed (level_codec.h) a payload may be far below bounds.min, never above the canonical maximum.
    if (level.payloadBytes == 0 || level.payloadBytes > bounds.max) {
      return QStringLiteral("%1 announces %2 bytes, but %3 vertices, %4 faces and m = %5 imply at most %6 bytes")
          .arg(which)
          .arg(level.payloadBytes)
          .arg(level.vertexCount)
          .arg(level.faceCount)
          .arg(rows)
          .arg(bounds.max);
    }
  }
  return {};
}

QString checkAnnouncement(const ModelBegin& begin, const LevelList& list) {
  for (const LevelInfo& level : list.levels) {
    if (level.vertexCount == begin.vertexCount && level.payloadBytes == begin.totalSize &&
        (begin.kind != TransferKind::FullModel || level.levelId == 0)) {
      return {};
    }
  }
  return QStringLiteral(
             "the host announced a transfer of %1 bytes for %2 vertices that its level list does not "
             "contain")
      .arg(begin.totalSize)
      .arg(begin.vertexCount);
}

bool displayable(const Eigen::Ref<const Eigen::MatrixXd>& values) { return allDisplayable(values); }

DecodedLevel decodeLevel(LevelJob job) {
  DecodedLevel out;
  try {
    QByteArray canonical = job.payload;
    if (declaredLevelPayloadSize(job.payload)) {
      // The largest level this session's shape allows (every listed level is within it), and one transfer's limit.
      const std::uint64_t limit = std::min<std::uint64_t>(
          kMaxTransferSize,
          levelPayloadBounds(job.vertexCount, std::uint64_t{kMaxFacesPerVertex} * job.vertexCount, job.rowCount).max);
      LevelDecompression decompressed = decompressLevelPayload(job.payload, limit);
      if (!decompressed.ok()) {
        out.error = QStringLiteral("bad compressed level payload: %1").arg(decompressed.error);
        return out;
      }
      canonical = std::move(decompressed.payload);
    }
    if (!checksumMatches(canonical, job.sha256)) {
      out.error = QStringLiteral("model transfer failed: %1")
                      .arg(QString::fromLatin1(toString(ModelReceiver::Status::BadChecksum)));
      return out;
    }
    const auto* data = reinterpret_cast<const std::byte*>(canonical.constData());
    spectral::LevelDecodeResult decoded =
        spectral::decodeResolutionLevel(std::span<const std::byte>(data, static_cast<std::size_t>(canonical.size())));
    if (!decoded.ok()) {
      out.error = QStringLiteral("bad level payload: %1").arg(QString::fromStdString(decoded.message));
      return out;
    }
    if (decoded.level->restV.rows() == 0 || decoded.level->F.rows() == 0) {
      out.error = QStringLiteral("the host sent an empty level (%1 vertices, %2 faces)")
                      .arg(decoded.level->restV.rows())
                      .arg(decoded.level->F.rows());
      return out;
    }
    // |K(i, j)| ≤ 32768·scale(j) (an int16 entry times its column's scale).
    const Eigen::RowVectorXd largestK = 32768.0 * decoded.level->K.scale.cast<double>();
    if (!allDisplayable(decoded.level->restV) || !allDisplayable(largestK)) {
      out.error = QStringLiteral("the host sent a level with a coordinate or K entry beyond %1").arg(kMaxAbsCoordinate);
      return out;
    }
    if (decoded.level->K.cols() != job.rowCount || decoded.level->P.cols() != job.vertexCount ||
        decoded.level->K.rows() != decoded.level->restV.rows()) {
      out.error =
          QStringLiteral("level does not match the session (m = %1, n = %2)").arg(job.rowCount).arg(job.vertexCount);
      return out;
    }
    out.level = spectral::makeDisplayLevel(std::move(*decoded.level));
    out.payload = std::move(job.payload);
  } catch (const std::exception& e) {  // e.g. std::bad_alloc: never let it escape the worker
    out.level.reset();
    out.payload.clear();
    out.error = QStringLiteral("decoding the level failed: %1").arg(QString::fromLocal8Bit(e.what()));
  }
  return out;
}

}  // namespace sc::session
