#include "model/session_file.h"

#include "model/session_file_codec.h"
#include "model/session_file_ids.h"
#include "model/session_file_v1.h"

#include <QFile>
#include <QSaveFile>
#include <QStringDecoder>

#include <algorithm>
#include <cstring>
#include <limits>
#include <utility>

namespace sc::model {

namespace {

using detail::ByteReader;
using detail::ByteWriter;
using detail::kSessionChecksumBytes;
using detail::kSessionHeaderBytes;

constexpr qsizetype kMagicBytes = sizeof(kSessionFileMagic);
constexpr std::uint64_t kMinStepBytes = 2;  // author length, undone (ΔZ: m·24 more)

/// `bytes` as UTF-8, strictly: nullopt for anything that is not valid UTF-8 (an initial BOM is kept as U+FEFF, so
/// every valid string round-trips byte for byte).
std::optional<QString> strictUtf8(QByteArrayView bytes) {
  QStringDecoder decoder(QStringDecoder::Utf8,
                         QStringDecoder::Flag::Stateless | QStringDecoder::Flag::ConvertInitialBom);
  QString text = decoder.decode(bytes);
  if (decoder.hasError()) return std::nullopt;
  return text;
}

/// Empty when `step` (the `index`-th, 0-based) is a usable step of a file with `m` frequencies.
QString validateStep(const SavedEditStep& step, int m, std::size_t index) {
  const QByteArray author = step.author.toUtf8();
  if (author.size() > kMaxStepAuthorBytes) {
    return QStringLiteral("edit step %1's author has %2 UTF-8 bytes (at most %3)")
        .arg(index + 1)
        .arg(author.size())
        .arg(kMaxStepAuthorBytes);
  }
  if (strictUtf8(author) != step.author) {
    return QStringLiteral("edit step %1's author is not valid UTF-8 text").arg(index + 1);
  }
  if (step.delta.rows() != m || step.delta.cols() != 3) {
    return QStringLiteral("edit step %1's ΔZ is %2 × %3, not m × 3 = %4 × 3")
        .arg(index + 1)
        .arg(step.delta.rows())
        .arg(step.delta.cols())
        .arg(m);
  }
  if (!step.delta.allFinite()) return QStringLiteral("edit step %1's ΔZ is not finite").arg(index + 1);
  return {};
}

void writeStep(ByteWriter& out, const SavedEditStep& step, int m) {
  QByteArray author = step.author.toUtf8();
  // refused when read: a name UTF-8 cannot carry (a lone surrogate) as the invalid byte 0xFF, one over
  // kMaxStepAuthorBytes cut at 255 bytes (its length is a u8)
  if (strictUtf8(author) != step.author) author = QByteArray(1, '\xFF');
  author.truncate(255);
  out.u8(static_cast<std::uint8_t>(author.size()));
  out.raw(author);
  out.u8(step.undone ? 1 : 0);
  // exactly m × 3 values: a ΔZ of another size is written as NaNs, which the reader refuses
  const bool fits = step.delta.rows() == m && step.delta.cols() == 3;
  for (int r = 0; r < m; ++r)
    for (int c = 0; c < 3; ++c) out.f64(fits ? step.delta(r, c) : std::numeric_limits<double>::quiet_NaN());
}

/// Reads the step list; the count is bounded (kMaxSavedEditSteps, and the data left) before anything is allocated.
std::vector<SavedEditStep> readSteps(ByteReader& in, int m) {
  const std::uint32_t count = in.u32();
  if (in.ok() && count > static_cast<std::uint32_t>(kMaxSavedEditSteps)) {
    in.fail(QStringLiteral("it has %1 edit steps (at most %2)").arg(count).arg(kMaxSavedEditSteps));
    return {};
  }
  const std::uint64_t stepBytes = kMinStepBytes + 24 * static_cast<std::uint64_t>(std::max(m, 0));
  if (!in.fits(count, stepBytes, "edit steps")) return {};
  std::vector<SavedEditStep> steps(count);
  for (std::uint32_t i = 0; i < count && in.ok(); ++i) {
    SavedEditStep& step = steps[i];
    const std::uint8_t length = in.u8();
    if (in.ok() && length > kMaxStepAuthorBytes) {
      in.fail(QStringLiteral("edit step %1's author has %2 bytes (at most %3)")
                  .arg(i + 1)
                  .arg(length)
                  .arg(kMaxStepAuthorBytes));
    }
    const QByteArrayView name = in.raw(length);
    if (!in.ok()) break;
    if (std::optional<QString> author = strictUtf8(name)) {
      step.author = std::move(*author);
    } else {
      in.fail(QStringLiteral("edit step %1's author is not valid UTF-8").arg(i + 1));
    }
    const std::uint8_t undone = in.u8();
    if (undone > 1) in.fail(QStringLiteral("corrupted: edit step %1's undone flag is %2").arg(i + 1).arg(undone));
    step.undone = undone == 1;
    if (!in.ok()) break;
    step.delta.resize(m, 3);  // within the data left: checked for all steps above
    for (int r = 0; r < m; ++r)
      for (int c = 0; c < 3; ++c) step.delta(r, c) = in.f64();
  }
  return steps;
}

SessionFile parsePayload(ByteReader& in) {
  SessionFile file;
  const std::uint32_t vertices = detail::readMeshPart(in, file.V, file.F, file.m, file.mode);
  const std::uint8_t hasCurrent = in.u8();
  if (hasCurrent > 1) in.fail(QStringLiteral("corrupted: current-constraints flag %1").arg(hasCurrent));
  if (hasCurrent == 1) {
    SavedConstraints current;
    current.handle = detail::readIdList(in, vertices, "handle");
    current.anchors = detail::readIdList(in, vertices, "anchor");
    file.current = std::move(current);
  }
  detail::readMatrix(in, file.Z, "coefficients");
  file.steps = readSteps(in, file.m);
  if (in.ok() && in.left() != 0) in.fail(QStringLiteral("corrupted: %1 unexplained bytes at the end").arg(in.left()));
  return file;
}

SessionFileError error(const QString& why) {
  return SessionFileError{QStringLiteral("Not a usable ShapeCast session file: %1.").arg(why)};
}

}  // namespace

bool sameSessionFile(const SessionFile& a, const SessionFile& b) {
  const auto same = [](const auto& x, const auto& y) { return x.rows() == y.rows() && x.cols() == y.cols() && x == y; };
  return same(a.V, b.V) && same(a.F, b.F) && a.m == b.m && a.mode == b.mode && a.current == b.current &&
         same(a.Z, b.Z) && a.steps == b.steps && a.droppedLegacyDrags == b.droppedLegacyDrags;
}

QString validateSessionFile(const SessionFile& file) {
  if (QString why = detail::validateMeshPart(file.V, file.F, file.m); !why.isEmpty()) return why;
  const bool emptyZ = file.Z.rows() == 0 && file.Z.cols() == 0;
  if (!emptyZ && (file.Z.rows() != file.m || file.Z.cols() != 3)) {
    return QStringLiteral("Z is %1 × %2, not m × 3 = %3 × 3 (or empty)")
        .arg(file.Z.rows())
        .arg(file.Z.cols())
        .arg(file.m);
  }
  if (!file.Z.allFinite()) return QStringLiteral("a coefficient is not finite");
  if (file.current) {
    const QString why = detail::validateConstraintIds(*file.current, static_cast<int>(file.V.rows()),
                                                      QStringLiteral("the current constraint set"));
    if (!why.isEmpty()) return why;
  }
  if (file.steps.size() > static_cast<std::size_t>(kMaxSavedEditSteps)) {
    return QStringLiteral("it has %1 edit steps (at most %2)").arg(file.steps.size()).arg(kMaxSavedEditSteps);
  }
  for (std::size_t i = 0; i < file.steps.size(); ++i) {
    if (QString why = validateStep(file.steps[i], file.m, i); !why.isEmpty()) return why;
  }
  if (file.droppedLegacyDrags < 0) return QStringLiteral("a negative count of dropped drags");
  return {};
}

QByteArray encodeSessionFile(const SessionFile& file) {
  ByteWriter payload;
  detail::writeMeshPart(payload, file.V, file.F, file.m, file.mode);
  payload.u8(file.current ? 1 : 0);
  if (file.current) {
    detail::writeIdList(payload, file.current->handle);
    detail::writeIdList(payload, file.current->anchors);
  }
  detail::writeMatrix(payload, file.Z);
  payload.u32(static_cast<std::uint32_t>(file.steps.size()));
  for (const SavedEditStep& step : file.steps) writeStep(payload, step, file.m);
  return detail::sealSessionPayload(kSessionFileVersion, payload.bytes());
}

SessionFileResult decodeSessionFile(const QByteArray& bytes) {
  if (bytes.size() > kMaxSessionFileBytes) {
    return error(QStringLiteral("it is too large (%1 bytes, at most %2)").arg(bytes.size()).arg(kMaxSessionFileBytes));
  }
  if (bytes.size() < kMagicBytes || std::memcmp(bytes.constData(), kSessionFileMagic, kMagicBytes) != 0) {
    return error(QStringLiteral("it does not start with the session file signature (another kind of file?)"));
  }
  if (bytes.size() < kSessionHeaderBytes + kSessionChecksumBytes) {
    return error(QStringLiteral("truncated: only %1 bytes").arg(bytes.size()));
  }
  ByteReader header(QByteArrayView(bytes).sliced(kMagicBytes, kSessionHeaderBytes - kMagicBytes));
  const std::uint32_t version = header.u32();
  const std::uint64_t length = header.u64();
  if (version == 0 || version > kSessionFileVersion) {
    return error(
        QStringLiteral("it has format version %1; this ShapeCast reads versions 1 to %2 (a newer ShapeCast wrote it?)")
            .arg(version)
            .arg(kSessionFileVersion));
  }
  const auto available = static_cast<std::uint64_t>(bytes.size() - kSessionHeaderBytes - kSessionChecksumBytes);
  if (length > available) {
    return error(QStringLiteral("truncated: %1 of %2 bytes")
                     .arg(bytes.size())
                     .arg(length + static_cast<std::uint64_t>(kSessionHeaderBytes + kSessionChecksumBytes)));
  }
  if (length < available) {
    return error(QStringLiteral("%1 unexpected bytes after the checksum").arg(available - length));
  }
  const qsizetype end = kSessionHeaderBytes + static_cast<qsizetype>(length);
  if (detail::sha256(QByteArrayView(bytes).first(end)) != QByteArrayView(bytes).sliced(end, kSessionChecksumBytes)) {
    return error(QStringLiteral("corrupted: the SHA-256 checksum does not match the content"));
  }
  const QByteArrayView payload = QByteArrayView(bytes).sliced(kSessionHeaderBytes, static_cast<qsizetype>(length));
  SessionFile file;
  if (version == v1::kVersion) {
    if (const QString why = v1::decodeLegacyPayload(payload, &file); !why.isEmpty()) return error(why);
  } else {
    ByteReader in(payload);
    file = parsePayload(in);
    if (!in.ok()) return error(in.error());
  }
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
