#include "session/wire/level_codec.h"

#include <meshoptimizer.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <limits>
#include <span>
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

/// Breadth-first visiting order over the edges of `faces` (3f' indices; indices ≥ n' are ignored), restarting at
/// the lowest unvisited vertex, and for each vertex its neighbours (CSR: offsets n'+1, targets). Cost: O(n' + f').
struct Traversal {
  std::vector<std::uint32_t> order;        // n' vertices
  std::vector<std::uint32_t> rank;         // position of each vertex in order
  std::vector<std::uint32_t> offsets;      // n' + 1
  std::vector<std::uint32_t> targets;      // ≤ 6f'
  std::vector<std::uint32_t> faceOffsets;  // n' + 1: the faces around each vertex (valid faces only)
  std::vector<std::uint32_t> faceIds;      // ≤ 3f'
  std::span<const std::uint32_t> faces;    // 3f' corners
};

Traversal traversal(std::uint32_t n, std::span<const std::uint32_t> faces) {
  Traversal t;
  t.offsets.assign(std::size_t{n} + 1, 0);
  const auto valid = [&](std::size_t face) {
    return faces[3 * face] < n && faces[3 * face + 1] < n && faces[3 * face + 2] < n;
  };
  const std::size_t faceCount = faces.size() / 3;
  for (std::size_t face = 0; face < faceCount; ++face)
    if (valid(face))
      for (int k = 0; k < 3; ++k) t.offsets[faces[3 * face + static_cast<std::size_t>(k)] + 1] += 2;
  for (std::size_t v = 0; v < n; ++v) t.offsets[v + 1] += t.offsets[v];
  t.targets.resize(t.offsets[n]);
  std::vector<std::uint32_t> fill(t.offsets.begin(), t.offsets.end() - 1);
  for (std::size_t face = 0; face < faceCount; ++face) {
    if (!valid(face)) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = faces[3 * face + static_cast<std::size_t>(k)];
      const std::uint32_t b = faces[3 * face + static_cast<std::size_t>((k + 1) % 3)];
      const std::uint32_t c = faces[3 * face + static_cast<std::size_t>((k + 2) % 3)];
      t.targets[fill[a]++] = b;
      t.targets[fill[a]++] = c;
    }
  }
  t.faces = faces;
  t.faceOffsets.assign(std::size_t{n} + 1, 0);
  for (std::size_t face = 0; face < faceCount; ++face)
    if (valid(face))
      for (int k = 0; k < 3; ++k) ++t.faceOffsets[faces[3 * face + static_cast<std::size_t>(k)] + 1];
  for (std::size_t v = 0; v < n; ++v) t.faceOffsets[v + 1] += t.faceOffsets[v];
  t.faceIds.resize(t.faceOffsets[n]);
  std::vector<std::uint32_t> at(t.faceOffsets.begin(), t.faceOffsets.end() - 1);
  for (std::size_t face = 0; face < faceCount; ++face)
    if (valid(face))
      for (int k = 0; k < 3; ++k)
        t.faceIds[at[faces[3 * face + static_cast<std::size_t>(k)]]++] = static_cast<std::uint32_t>(face);
  constexpr std::uint32_t kUnvisited = std::numeric_limits<std::uint32_t>::max();
  t.rank.assign(n, kUnvisited);
  t.order.reserve(n);
  for (std::uint32_t start = 0; start < n; ++start) {
    if (t.rank[start] != kUnvisited) continue;
    std::size_t head = t.order.size();
    t.rank[start] = static_cast<std::uint32_t>(t.order.size());
    t.order.push_back(start);
    for (; head < t.order.size(); ++head) {
      const std::uint32_t v = t.order[head];
      for (std::uint32_t e = t.offsets[v]; e < t.offsets[v + 1]; ++e) {
        const std::uint32_t u = t.targets[e];
        if (t.rank[u] != kUnvisited) continue;
        t.rank[u] = static_cast<std::uint32_t>(t.order.size());
        t.order.push_back(u);
      }
    }
  }
  return t;
}

/// How many faces around a vertex the parallelogram search looks at (bounds its cost on hostile faces).
constexpr std::uint32_t kMaxFacesSearched = 16;

/// A visited vertex c opposite v across the edge (a, b): the third corner of another face on (a, b), or nullopt.
std::optional<std::uint32_t> opposite(const Traversal& t, std::uint32_t v, std::uint32_t a, std::uint32_t b) {
  const std::uint32_t end = std::min(t.faceOffsets[a + 1], t.faceOffsets[a] + kMaxFacesSearched);
  for (std::uint32_t e = t.faceOffsets[a]; e < end; ++e) {
    const std::uint32_t* f = t.faces.data() + 3 * std::size_t{t.faceIds[e]};
    const bool hasB = f[0] == b || f[1] == b || f[2] == b;
    if (!hasB || f[0] == v || f[1] == v || f[2] == v) continue;
    const std::uint32_t c = f[0] != a && f[0] != b ? f[0] : (f[1] != a && f[1] != b ? f[1] : f[2]);
    if (c != a && c != b && t.rank[c] < t.rank[v]) return c;
  }
  return std::nullopt;
}

/// Row v's prediction, m values: the mean of the parallelogram predictions Q_a + Q_b − Q_c over the faces (v, a, b)
/// with a and b visited and a visited c across (a, b) (second order along the mesh); without one, the rounded mean
/// of the rows of its neighbours visited before it; 0 when none is.
void predict(const Traversal& t, std::uint32_t v, std::span<const std::int16_t> Q, std::uint32_t m,
             std::vector<std::int64_t>& sum, std::vector<std::int16_t>& out) {
  std::fill(sum.begin(), sum.end(), 0);
  std::int64_t count = 0;
  const auto row = [&](std::uint32_t u) { return Q.data() + std::size_t{u} * m; };
  const std::uint32_t faceEnd = std::min(t.faceOffsets[v + 1], t.faceOffsets[v] + kMaxFacesSearched);
  for (std::uint32_t e = t.faceOffsets[v]; e < faceEnd; ++e) {
    const std::uint32_t* f = t.faces.data() + 3 * std::size_t{t.faceIds[e]};
    const std::uint32_t a = f[0] == v ? f[1] : f[0];
    const std::uint32_t b = f[2] == v ? f[1] : f[2];
    if (a == v || b == v || a == b || t.rank[a] >= t.rank[v] || t.rank[b] >= t.rank[v]) continue;
    const std::optional<std::uint32_t> c = opposite(t, v, a, b);
    if (!c) continue;
    const std::int16_t *qa = row(a), *qb = row(b), *qc = row(*c);
    for (std::uint32_t j = 0; j < m; ++j) sum[j] += std::int64_t{qa[j]} + qb[j] - qc[j];
    ++count;
  }
  if (count > 0) {
    for (std::uint32_t j = 0; j < m; ++j) {
      const std::int64_t twice = 2 * sum[j] + count;  // round half up, then clamp to int16
      const std::int64_t q = twice >= 0 ? twice / (2 * count) : -((-twice + 2 * count - 1) / (2 * count));
      out[j] = static_cast<std::int16_t>(std::clamp<std::int64_t>(q, -32768, 32767));
    }
    return;
  }
  std::fill(sum.begin(), sum.end(), 0);
  for (std::uint32_t e = t.offsets[v]; e < t.offsets[v + 1]; ++e) {
    const std::uint32_t u = t.targets[e];
    if (t.rank[u] >= t.rank[v]) continue;
    const std::int16_t* neighbour = row(u);
    for (std::uint32_t j = 0; j < m; ++j) sum[j] += neighbour[j];
    ++count;
  }
  for (std::uint32_t j = 0; j < m; ++j) {
    if (count == 0) {
      out[j] = 0;
      continue;
    }
    const std::int64_t twice = 2 * sum[j] + count;  // floor((2·sum + count) / (2·count)): round half up
    const std::int64_t q = twice >= 0 ? twice / (2 * count) : -((-twice + 2 * count - 1) / (2 * count));
    out[j] = static_cast<std::int16_t>(q);
  }
}

std::uint16_t zigzag(std::int16_t r) {
  return static_cast<std::uint16_t>((static_cast<std::uint16_t>(r) << 1) ^ static_cast<std::uint16_t>(r >> 15));
}
std::int16_t unzigzag(std::uint16_t z) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(z >> 1) ^ static_cast<std::uint16_t>(-(z & 1)));
}
std::int16_t wrapSub(std::int16_t a, std::int16_t b) {
  return static_cast<std::int16_t>(
      static_cast<std::uint16_t>(static_cast<std::uint16_t>(a) - static_cast<std::uint16_t>(b)));
}
std::int16_t wrapAdd(std::int16_t a, std::int16_t b) {
  return static_cast<std::int16_t>(
      static_cast<std::uint16_t>(static_cast<std::uint16_t>(a) + static_cast<std::uint16_t>(b)));
}

/// K's residual planes (2n'm bytes) from the canonical int16 K.
std::vector<std::uint8_t> residualPlanes(const Traversal& t, std::span<const std::int16_t> Q, std::uint32_t n,
                                         std::uint32_t m) {
  const std::size_t cells = std::size_t{n} * m;
  std::vector<std::uint8_t> planes(2 * cells);
  std::vector<std::int64_t> sum(m);
  std::vector<std::int16_t> prediction(m);
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t v = t.order[k];
    predict(t, v, Q, m, sum, prediction);
    for (std::uint32_t j = 0; j < m; ++j) {
      const std::uint16_t z = zigzag(wrapSub(Q[std::size_t{v} * m + j], prediction[j]));
      const std::size_t at = std::size_t{j} * n + k;
      planes[at] = static_cast<std::uint8_t>(z & 0xff);
      planes[cells + at] = static_cast<std::uint8_t>(z >> 8);
    }
  }
  return planes;
}

/// The inverse of residualPlanes(): the canonical int16 K (n' by m row-major).
std::vector<std::int16_t> fromResidualPlanes(const Traversal& t, std::span<const std::uint8_t> planes, std::uint32_t n,
                                             std::uint32_t m) {
  const std::size_t cells = std::size_t{n} * m;
  std::vector<std::int16_t> Q(cells);
  std::vector<std::int64_t> sum(m);
  std::vector<std::int16_t> prediction(m);
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t v = t.order[k];
    predict(t, v, Q, m, sum, prediction);
    for (std::uint32_t j = 0; j < m; ++j) {
      const std::size_t at = std::size_t{j} * n + k;
      const auto z = static_cast<std::uint16_t>(planes[at] | (planes[cells + at] << 8));
      Q[std::size_t{v} * m + j] = wrapAdd(prediction[j], unzigzag(z));
    }
  }
  return Q;
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
  const std::vector<std::uint8_t> planes = residualPlanes(traversal(l.n, faces), Q, l.n, l.m);
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
  const std::vector<std::int16_t> Q = fromResidualPlanes(traversal(l.n, faces), planes, l.n, l.m);
  std::memcpy(data + l.K, Q.data(), 2 * Q.size());
  return out;
}

}  // namespace sc::session
