#include "session/engine/client_level_decode.h"

#include "session/wire/model_transfer.h"
#include "spectral/resolution_level.h"

#include <exception>
#include <span>
#include <utility>

namespace sc::session {

DecodedLevel decodeLevel(LevelJob job) {
  DecodedLevel out;
  try {
    if (!checksumMatches(job.payload, job.sha256)) {
      out.error = QStringLiteral("model transfer failed: %1")
                      .arg(QString::fromLatin1(toString(ModelReceiver::Status::BadChecksum)));
      return out;
    }
    const auto* data = reinterpret_cast<const std::byte*>(job.payload.constData());
    spectral::LevelDecodeResult decoded =
        spectral::decodeResolutionLevel(std::span<const std::byte>(data, static_cast<std::size_t>(job.payload.size())));
    if (!decoded.ok()) {
      out.error = QStringLiteral("bad level payload: %1").arg(QString::fromStdString(decoded.message));
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
