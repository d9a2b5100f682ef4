#include "session/wire/level_codec.h"

#include "session/wire/mesh_row_prediction.h"

#include <meshoptimizer.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

namespace sc::session {
namespace {

static_assert(std::endian::native == std::endian::little, "the level codec is little-endian; add byte swapping");

constexpr std::array<char, 8> kCanonicalMagic = {'S', 'C', 'L', 'V', 'L', '\0', '\r', '\n'};
constexpr std::uint32_t kCanonicalVersion = 2;  // spectral::kResolutionLevelVersion, the layout read here
constexpr std::array<char, 8> kMagic = {'S', 'C', 'L', 'V', 'Z', '\0', '\r', '\n'};
constexpr std::size_t kCanonicalHeader = 32;
constexpr std::size_t kChecksum = 8;
constexpr std::size_t kHeader = 52;
constexpr std::uint32_t kFacesRaw = 1U;
constexpr std::size_t kSections = 4;

/// The canonical payload's counts and the offsets of its sections.
struct Layout {
  std::uint32_t n = 0, f = 0, full = 0, m = 0, z = 0;  // n', f', n, m, z
  std::uint64_t size = 0, faces = 0, tables = 0, K = 0, checksum = 0;

  [[nodiscard]] std::uint64_t tablesSize() const { return K - tables + kChecksum; }
  [[nodiscard]] std::uint64_t kSize() const { return checksum - K; }
};

/// The layout for these counts, or nullopt when the canonical size would exceed `limit` (no overflow).
std::optional<Layout> layoutOf(const std::array<std::uint32_t, 5>& counts, std::uint64_t limit) {
  Layout l;
  l.n = counts[0];
  l.f = counts[1];
  l.full = counts[2];
  l.m = counts[3];
  l.z = counts[4];
  std::uint64_t total = kCanonicalHeader + kChecksum;
  if (total > limit) return std::nullopt;
  const auto add = [&](std::uint64_t count, std::uint64_t each) {
    if (each != 0 && count > (limit - total) / each) return false;
    total += count * each;
    return true;
  };
  const std::uint64_t positions = kCanonicalHeader;
  if (!add(l.n, 24)) return std::nullopt;
  l.faces = positions + 24ULL * l.n;
  if (!add(l.f, 12)) return std::nullopt;
  l.tables = l.faces + 12ULL * l.f;
  if (!add(std::uint64_t{l.n} + 1, 4) || !add(l.z, 12) || !add(l.m, 4)) return std::nullopt;
  l.K = l.tables + 4ULL * (std::uint64_t{l.n} + 1) + 12ULL * l.z + 4ULL * l.m;
  if (!add(l.n, 2ULL * l.m)) return std::nullopt;
  l.checksum = l.K + 2ULL * l.n * l.m;
  l.size = total;
  return l;
}

template <class T>
T readAt(const char* data, std::uint64_t offset) {
  T value;
  std::memcpy(&value, data + offset, sizeof(T));
  return value;
}

template <class T>
void append(QByteArray& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

QByteArray zstdFrame(const void* data, std::size_t size, int level) {
  QByteArray out(static_cast<qsizetype>(ZSTD_compressBound(size)), Qt::Uninitialized);
  const std::size_t written = ZSTD_compress(out.data(), static_cast<std::size_t>(out.size()), data, size, level);
  if (ZSTD_isError(written)) return {};
  out.truncate(static_cast<qsizetype>(written));
  return out;
}

/// Decompresses one zstd section into exactly `size` bytes at `out`; an error text otherwise.
QString unzstdExact(QByteArrayView section, void* out, std::uint64_t size, const char* what) {
  const unsigned long long declared =
      ZSTD_getFrameContentSize(section.data(), static_cast<std::size_t>(section.size()));
  if (declared == ZSTD_CONTENTSIZE_ERROR || declared == ZSTD_CONTENTSIZE_UNKNOWN)
    return QStringLiteral("the %1 section is not a zstd frame with a declared size").arg(QLatin1String(what));
  if (declared != size)
    return QStringLiteral("the %1 section declares %2 bytes, the level's counts imply %3")
        .arg(QLatin1String(what))
        .arg(declared)
        .arg(size);
  const std::size_t written =
      ZSTD_decompress(out, static_cast<std::size_t>(size), section.data(), static_cast<std::size_t>(section.size()));
  if (ZSTD_isError(written))
    return QStringLiteral("zstd error in the %1 section: %2")
        .arg(QLatin1String(what), QLatin1String(ZSTD_getErrorName(written)));
  if (written != size) return QStringLiteral("the %1 section decodes to the wrong size").arg(QLatin1String(what));
  return {};
}

std::array<std::uint32_t, 5> countsAt(const char* data, std::size_t offset) {
  std::array<std::uint32_t, 5> counts{};
  for (std::size_t i = 0; i < counts.size(); ++i) counts[i] = readAt<std::uint32_t>(data, offset + 4 * i);
  return counts;
}

LevelDecompression refused(QString why) {
  LevelDecompression out;
  out.error = std::move(why);
  return out;
}

}  // namespace

QByteArray compressLevelPayload(QByteArrayView canonical, int zstdLevel) {
  const char* in = canonical.data();
  if (static_cast<std::size_t>(canonical.size()) < kCanonicalHeader ||
      std::memcmp(in, kCanonicalMagic.data(), kCanonicalMagic.size()) != 0 ||
      readAt<std::uint32_t>(in, 8) != kCanonicalVersion)
    return {};
  const std::array<std::uint32_t, 5> counts = countsAt(in, 12);
  const std::optional<Layout> layout = layoutOf(counts, static_cast<std::uint64_t>(canonical.size()));
  if (!layout || layout->size != static_cast<std::uint64_t>(canonical.size())) return {};
  const Layout& l = *layout;

  // === positions: the vertex codec on the f64 xyz (24-byte vertices)
  QByteArray positions(static_cast<qsizetype>(meshopt_encodeVertexBufferBound(l.n, 24)), Qt::Uninitialized);
  positions.truncate(static_cast<qsizetype>(
      meshopt_encodeVertexBuffer(reinterpret_cast<unsigned char*>(positions.data()),
                                 static_cast<std::size_t>(positions.size()), in + kCanonicalHeader, l.n, 24)));
  // === faces: the index codec when it gives the same triangles back (it may rotate a triangle's corners)
  std::vector<std::uint32_t> faces(3 * std::size_t{l.f});
  std::memcpy(faces.data(), in + l.faces, 12 * std::size_t{l.f});
  QByteArray faceBytes(static_cast<qsizetype>(meshopt_encodeIndexBufferBound(faces.size(), l.n)), Qt::Uninitialized);
  faceBytes.truncate(static_cast<qsizetype>(
      meshopt_encodeIndexBuffer(reinterpret_cast<unsigned char*>(faceBytes.data()),
                                static_cast<std::size_t>(faceBytes.size()), faces.data(), faces.size())));
  std::vector<std::uint32_t> roundTrip(faces.size());
  std::uint32_t flags = 0;
  if (meshopt_decodeIndexBuffer(roundTrip.data(), roundTrip.size(), 4,
                                reinterpret_cast<const unsigned char*>(faceBytes.constData()),
                                static_cast<std::size_t>(faceBytes.size())) != 0 ||
      roundTrip != faces) {
    flags |= kFacesRaw;
    faceBytes = zstdFrame(in + l.faces, 12 * std::size_t{l.f}, zstdLevel);
  }
  // === tables: CSR offsets, P's columns and weights, K's scales, and the checksum
  QByteArray tables(in + l.tables, static_cast<qsizetype>(l.K - l.tables));
  tables.append(in + l.checksum, kChecksum);
  tables = zstdFrame(tables.constData(), static_cast<std::size_t>(tables.size()), zstdLevel);
  // === K: prediction along the mesh, then zstd
  std::vector<std::int16_t> Q(std::size_t{l.n} * l.m);
  std::memcpy(Q.data(), in + l.K, 2 * Q.size());
  const std::vector<std::uint8_t> planes = kResidualPlanes(faces, Q, l.n, l.m);
  const QByteArray kBytes = zstdFrame(planes.data(), planes.size(), zstdLevel);
  if (tables.isEmpty() || kBytes.isEmpty() || faceBytes.isEmpty() || positions.isEmpty()) return {};

  QByteArray out;
  out.reserve(static_cast<qsizetype>(kHeader) + positions.size() + faceBytes.size() + tables.size() + kBytes.size());
  out.append(kMagic.data(), kMagic.size());
  append(out, kLevelCodecVersion);
  for (const std::uint32_t c : counts) append(out, c);
  append(out, flags);
  const std::array<const QByteArray*, kSections> sections = {&positions, &faceBytes, &tables, &kBytes};
  for (const QByteArray* section : sections) append(out, static_cast<std::uint32_t>(section->size()));
  for (const QByteArray* section : sections) out.append(*section);
  return out;
}

std::optional<std::uint64_t> declaredLevelPayloadSize(QByteArrayView compressed) {
  if (static_cast<std::size_t>(compressed.size()) < kHeader ||
      std::memcmp(compressed.data(), kMagic.data(), kMagic.size()) != 0 ||
      readAt<std::uint32_t>(compressed.data(), 8) != kLevelCodecVersion)
    return std::nullopt;
  const std::optional<Layout> l =
      layoutOf(countsAt(compressed.data(), 12), std::numeric_limits<std::uint64_t>::max() / 4);
  if (!l) return std::nullopt;
  return l->size;
}

LevelDecompression decompressLevelPayload(QByteArrayView compressed, std::uint64_t maxPayloadBytes) {
  const char* in = compressed.data();
  if (static_cast<std::size_t>(compressed.size()) < kHeader) return refused(QStringLiteral("shorter than its header"));
  if (std::memcmp(in, kMagic.data(), kMagic.size()) != 0)
    return refused(QStringLiteral("not a compressed ShapeCast level"));
  if (const auto version = readAt<std::uint32_t>(in, 8); version != kLevelCodecVersion)
    return refused(QStringLiteral("level codec version %1, this client reads %2").arg(version).arg(kLevelCodecVersion));
  const std::array<std::uint32_t, 5> counts = countsAt(in, 12);
  const std::optional<Layout> layout = layoutOf(counts, maxPayloadBytes);
  if (!layout)
    return refused(QStringLiteral("its counts declare a level larger than the %1 bytes allowed").arg(maxPayloadBytes));
  const Layout& l = *layout;
  const auto flags = readAt<std::uint32_t>(in, 32);
  if ((flags & ~kFacesRaw) != 0) return refused(QStringLiteral("unknown flags %1").arg(flags));
  std::array<QByteArrayView, kSections> section;
  std::uint64_t offset = kHeader;
  for (std::size_t i = 0; i < kSections; ++i) {
    const auto size = readAt<std::uint32_t>(in, 36 + 4 * i);
    if (size > static_cast<std::uint64_t>(compressed.size()) - offset)
      return refused(QStringLiteral("its sections run past its end"));
    section[i] = compressed.sliced(static_cast<qsizetype>(offset), size);
    offset += size;
  }
  if (offset != static_cast<std::uint64_t>(compressed.size()))
    return refused(QStringLiteral("bytes after its last section"));

  LevelDecompression out;
  out.payload = QByteArray(static_cast<qsizetype>(l.size), Qt::Uninitialized);
  char* data = out.payload.data();
  std::memcpy(data, kCanonicalMagic.data(), kCanonicalMagic.size());
  std::memcpy(data + 8, &kCanonicalVersion, 4);
  std::memcpy(data + 12, counts.data(), 20);
  if (meshopt_decodeVertexBuffer(data + kCanonicalHeader, l.n, 24,
                                 reinterpret_cast<const unsigned char*>(section[0].data()),
                                 static_cast<std::size_t>(section[0].size())) != 0)
    return refused(QStringLiteral("vertex codec error in the positions section"));
  std::vector<std::uint32_t> faces(3 * std::size_t{l.f});
  if ((flags & kFacesRaw) != 0) {
    if (QString e = unzstdExact(section[1], faces.data(), 12ULL * l.f, "faces"); !e.isEmpty()) return refused(e);
  } else if (meshopt_decodeIndexBuffer(faces.data(), faces.size(), 4,
                                       reinterpret_cast<const unsigned char*>(section[1].data()),
                                       static_cast<std::size_t>(section[1].size())) != 0) {
    return refused(QStringLiteral("index codec error in the faces section"));
  }
  std::memcpy(data + l.faces, faces.data(), 12 * std::size_t{l.f});
  std::vector<char> tables(static_cast<std::size_t>(l.tablesSize()));
  if (QString e = unzstdExact(section[2], tables.data(), tables.size(), "tables"); !e.isEmpty()) return refused(e);
  std::memcpy(data + l.tables, tables.data(), tables.size() - kChecksum);
  std::memcpy(data + l.checksum, tables.data() + tables.size() - kChecksum, kChecksum);
  std::vector<std::uint8_t> planes(static_cast<std::size_t>(l.kSize()));
  if (QString e = unzstdExact(section[3], planes.data(), planes.size(), "K"); !e.isEmpty()) return refused(e);
  const std::vector<std::int16_t> Q = kFromResidualPlanes(faces, planes, l.n, l.m);
  std::memcpy(data + l.K, Q.data(), 2 * Q.size());
  return out;
}

}  // namespace sc::session
