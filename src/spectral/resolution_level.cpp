#include "spectral/resolution_level.h"

#include "spectral/basis_cache.h"
#include "spectral/closest_point.h"
#include "spectral/vertex_ids.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

namespace sc::spectral {
namespace {

static_assert(std::endian::native == std::endian::little, "the level format is little-endian; add byte swapping");

constexpr std::array<char, 8> kMagic = {'S', 'C', 'L', 'V', 'L', '\0', '\r', '\n'};
constexpr std::size_t kHeaderSize = 32;
constexpr std::size_t kChecksumSize = 8;

/// The counts in a level's header.
struct Header {
  std::uint32_t lowVertices{}, lowFaces{}, fullVertices{}, m{}, nonZeros{};
};

/// Bytes of the payload between header and checksum, or nullopt when it would exceed `limit` (no overflow).
std::optional<std::size_t> payloadSize(const Header& h, std::size_t limit) {
  // (count, bytes each): X̂', F', CSR offsets, columns + values, scales of K, K.
  const std::array<std::pair<std::uint64_t, std::uint64_t>, 6> parts = {{{h.lowVertices, 24},
                                                                         {h.lowFaces, 12},
                                                                         {std::uint64_t{h.lowVertices} + 1, 4},
                                                                         {h.nonZeros, 12},
                                                                         {h.m, 4},
                                                                         {h.lowVertices, 2ULL * h.m}}};
  std::uint64_t total = 0;
  for (const auto& [count, each] : parts) {
    if (count == 0 || each == 0) continue;
    if (count > (limit - total) / each) return std::nullopt;
    total += count * each;
  }
  return static_cast<std::size_t>(total);
}

/// Appends raw little-endian bytes.
class Writer {
 public:
  explicit Writer(std::size_t capacity) { m_out.reserve(capacity); }
  template <class T>
  void put(const T& value) {
    putBytes(&value, sizeof(T));
  }
  void putBytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const std::byte*>(data);
    m_out.insert(m_out.end(), p, p + size);
  }
  std::vector<std::byte>& bytes() { return m_out; }

 private:
  std::vector<std::byte> m_out;
};

/// Reads raw bytes from a buffer whose total length has already been checked.
class Reader {
 public:
  explicit Reader(std::span<const std::byte> in) : m_in(in) {}
  template <class T>
  T get() {
    T value;
    getBytes(&value, sizeof(T));
    return value;
  }
  void getBytes(void* data, std::size_t size) {
    assert(m_offset + size <= m_in.size());
    if (size == 0) return;  // an empty section's data() may be null, and memcpy(nullptr, …, 0) is undefined
    std::memcpy(data, m_in.data() + m_offset, size);
    m_offset += size;
  }

 private:
  std::span<const std::byte> m_in;
  std::size_t m_offset = 0;
};

std::uint32_t checkedCount(Eigen::Index count) {
  assert(count >= 0 && static_cast<std::uint64_t>(count) <= std::numeric_limits<std::uint32_t>::max());
  return static_cast<std::uint32_t>(count);
}

LevelDecodeResult failure(LevelDecodeStatus status, std::string message) {
  LevelDecodeResult r;
  r.status = status;
  r.message = std::move(message);
  return r;
}

/// Checks indices and CSR offsets of a decoded level; empty string when valid.
std::string contentError(const ResolutionLevel& level, const std::vector<std::uint32_t>& rows,
                         const std::vector<std::uint32_t>& cols, std::uint32_t n) {
  if (level.F.size() > 0 && (level.F.minCoeff() < 0 || level.F.maxCoeff() >= level.restV.rows()))
    return "face index out of range";
  if (rows.front() != 0 || rows.back() != cols.size()) return "CSR offsets do not span the non-zeros";
  for (std::size_t i = 1; i < rows.size(); ++i)
    if (rows[i] < rows[i - 1]) return "CSR offsets decrease";
  for (std::size_t i = 0; i + 1 < rows.size(); ++i)
    for (std::uint32_t k = rows[i]; k < rows[i + 1]; ++k)
      if (cols[k] >= n || (k > rows[i] && cols[k] <= cols[k - 1])) return "P column out of range or unsorted";
  return {};
}

/// Reads the payload after a validated header; the buffer length is already known to match.
LevelDecodeResult readPayload(Reader& in, const Header& h) {
  ResolutionLevel level;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> V(h.lowVertices, 3);
  Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor> F(h.lowFaces, 3);
  std::vector<std::uint32_t> rows(std::size_t{h.lowVertices} + 1), cols(h.nonZeros);
  std::vector<double> values(h.nonZeros);
  level.K.scale.resize(h.m);
  level.K.Q.resize(h.lowVertices, h.m);
  in.getBytes(V.data(), 8 * static_cast<std::size_t>(V.size()));
  in.getBytes(F.data(), 4 * static_cast<std::size_t>(F.size()));
  in.getBytes(rows.data(), 4 * rows.size());
  in.getBytes(cols.data(), 4 * cols.size());
  in.getBytes(values.data(), 8 * values.size());
  in.getBytes(level.K.scale.data(), 4 * static_cast<std::size_t>(level.K.scale.size()));
  in.getBytes(level.K.Q.data(), 2 * static_cast<std::size_t>(level.K.Q.size()));
  level.restV = V;
  level.F = F.cast<int>();
  if (std::string error = contentError(level, rows, cols, h.fullVertices); !error.empty())
    return failure(LevelDecodeStatus::BadContent, error);
  // NaN or ∞ would flow into every reconstructed position (and the viewport's bounds) of this client.
  const bool weightsFinite = std::all_of(values.begin(), values.end(), [](double w) { return std::isfinite(w); });
  if (!level.restV.allFinite() || !weightsFinite || !level.K.scale.allFinite())
    return failure(LevelDecodeStatus::BadContent, "a position, weight or scale of K is not finite");
  if (level.K.scale.size() > 0 && level.K.scale.minCoeff() < 0.0f)
    return failure(LevelDecodeStatus::BadContent, "a scale of K is negative");
  level.P.resize(h.lowVertices, h.fullVertices);
  level.P.reserve(static_cast<Eigen::Index>(h.nonZeros));
  for (std::uint32_t i = 0; i < h.lowVertices; ++i) {
    level.P.startVec(i);
    for (std::uint32_t k = rows[i]; k < rows[i + 1]; ++k) level.P.insertBack(i, cols[k]) = values[k];
  }
  level.P.finalize();
  LevelDecodeResult r;
  r.status = LevelDecodeStatus::Ok;
  r.level = std::move(level);
  return r;
}

/// For each row of Q, a vertex of (V, F) referenced by a face at exactly that position (the first in index
/// order), or −1. Such a vertex is the query's closest point on the surface (distance 0), so its P row is the unit
/// row of that vertex — what the closest-point query returns too (weight 1 on that corner of an incident face).
/// Positions are matched bit for bit (hashing only the #Q queries); a near miss just goes to the tree.
/// Cost: O(#Q + #V + #F) expected.
std::vector<int> coincidentVertices(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& Q) {
  using Key = std::array<std::uint64_t, 3>;
  const auto key = [](const Eigen::MatrixXd& X, Eigen::Index i) {
    Key k{};
    for (int c = 0; c < 3; ++c) k[static_cast<std::size_t>(c)] = std::bit_cast<std::uint64_t>(X(i, c));
    return k;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = k[0];
      for (std::size_t c = 1; c < 3; ++c) h = (h ^ (h >> 29)) * 0xBF58476D1CE4E5B9ULL + k[c];
      return static_cast<std::size_t>(h ^ (h >> 32));
    }
  };
  std::unordered_map<Key, int, KeyHash> vertexAt;  // query position → vertex, −1 while none found
  vertexAt.reserve(static_cast<std::size_t>(Q.rows()));
  for (Eigen::Index i = 0; i < Q.rows(); ++i) vertexAt.emplace(key(Q, i), -1);
  std::vector<bool> referenced(static_cast<std::size_t>(V.rows()), false);
  for (Eigen::Index i = 0; i < F.size(); ++i) referenced[static_cast<std::size_t>(F.data()[i])] = true;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    if (!referenced[static_cast<std::size_t>(v)]) continue;
    if (const auto it = vertexAt.find(key(V, v)); it != vertexAt.end() && it->second < 0)
      it->second = static_cast<int>(v);
  }
  std::vector<int> out(static_cast<std::size_t>(Q.rows()));
  for (Eigen::Index i = 0; i < Q.rows(); ++i) out[static_cast<std::size_t>(i)] = vertexAt.at(key(Q, i));
  return out;
}

}  // namespace

BarycentricMap barycentricMap(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& lowV,
                              Eigen::VectorXd* distances, int threads) {
  // === queries on a vertex of the mesh (all of them for a halfedge-collapse decimation) are their own closest point
  const std::vector<int> coincident = coincidentVertices(V, F, lowV);
  std::vector<Eigen::Index> rest;  // rows left for the tree
  for (Eigen::Index i = 0; i < lowV.rows(); ++i)
    if (coincident[static_cast<std::size_t>(i)] < 0) rest.push_back(i);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(3 * static_cast<std::size_t>(lowV.rows()));
  if (distances) distances->setZero(lowV.rows());
  for (Eigen::Index i = 0; i < lowV.rows(); ++i)
    if (const int v = coincident[static_cast<std::size_t>(i)]; v >= 0) entries.emplace_back(i, v, 1.0);
  // === exact closest points of the others (CGAL AABB tree), built only when there are any
  if (!rest.empty()) {
    Eigen::MatrixXd queries(static_cast<Eigen::Index>(rest.size()), 3);
    for (std::size_t r = 0; r < rest.size(); ++r) queries.row(static_cast<Eigen::Index>(r)) = lowV.row(rest[r]);
    const ClosestPoints hits = ClosestPointQuery(V, F).query(queries, threads);
    for (std::size_t r = 0; r < rest.size(); ++r) {
      const auto q = static_cast<Eigen::Index>(r);
      for (int k = 0; k < 3; ++k)
        if (hits.barycentric(q, k) > 0) entries.emplace_back(rest[r], F(hits.faces(q), k), hits.barycentric(q, k));
      if (distances) (*distances)(rest[r]) = hits.distances(q);
    }
  }
  BarycentricMap P(lowV.rows(), V.rows());
  P.setFromTriplets(entries.begin(), entries.end());  // sorts, and sums repeated corners of degenerate faces
  return P;
}

ResolutionLevel resolutionLevel(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& H,
                                const Eigen::MatrixXd& lowV, const Eigen::MatrixXi& lowF, int threads) {
  assert(H.rows() == V.rows() && "H must have one row per full-resolution vertex");
  ResolutionLevel level;
  level.restV = lowV;
  level.F = lowF;
  level.P = barycentricMap(V, F, lowV, nullptr, threads);
  level.K = quantizeBasis(level.P * H);
  return level;
}

ResolutionLevel fullResolutionLevel(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& H) {
  assert(H.rows() == V.rows() && "H must have one row per vertex");
  ResolutionLevel level;
  level.restV = V;
  level.F = F;
  level.P.resize(V.rows(), V.rows());
  level.P.setIdentity();
  level.K = quantizeBasis(H);
  return level;
}

std::optional<FullVertexId> dominantFullVertex(const BarycentricMap& P, DisplayVertexId displayed) {
  if (displayed.index() >= static_cast<std::size_t>(P.rows())) return std::nullopt;
  Eigen::Index best = -1;
  double bestWeight = -1.0;
  for (BarycentricMap::InnerIterator it(P, static_cast<Eigen::Index>(displayed.index())); it; ++it) {
    if (it.value() > bestWeight) {
      bestWeight = it.value();
      best = it.col();
    }
  }
  if (best < 0) return std::nullopt;
  return FullVertexId(static_cast<std::uint32_t>(best));
}

FullVertexIds dominantFullVertices(const BarycentricMap& P, std::span<const DisplayVertexId> displayed) {
  FullVertexIds ids;
  ids.reserve(displayed.size());
  for (const DisplayVertexId low : displayed) {
    if (const std::optional<FullVertexId> id = dominantFullVertex(P, low)) ids.push_back(*id);
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

std::vector<std::byte> encodeResolutionLevel(const ResolutionLevel& level) {
  BarycentricMap P = level.P;
  P.makeCompressed();
  const Header h{checkedCount(level.restV.rows()), checkedCount(level.F.rows()), checkedCount(P.cols()),
                 checkedCount(level.K.cols()), checkedCount(P.nonZeros())};
  assert(P.rows() == level.restV.rows() && level.K.rows() == level.restV.rows() && "inconsistent level");
  const std::size_t payload = *payloadSize(h, std::numeric_limits<std::size_t>::max() / 2);
  Writer out(kHeaderSize + payload + kChecksumSize);
  out.putBytes(kMagic.data(), kMagic.size());
  for (std::uint32_t value : {kResolutionLevelVersion, h.lowVertices, h.lowFaces, h.fullVertices, h.m, h.nonZeros})
    out.put(value);
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> V = level.restV;
  const Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor> F = level.F.cast<std::int32_t>();
  out.putBytes(V.data(), 8 * static_cast<std::size_t>(V.size()));
  out.putBytes(F.data(), 4 * static_cast<std::size_t>(F.size()));
  for (Eigen::Index i = 0; i <= P.rows(); ++i) out.put(static_cast<std::uint32_t>(P.outerIndexPtr()[i]));
  for (Eigen::Index k = 0; k < P.nonZeros(); ++k) out.put(static_cast<std::uint32_t>(P.innerIndexPtr()[k]));
  out.putBytes(P.valuePtr(), 8 * static_cast<std::size_t>(P.nonZeros()));
  assert(level.K.scale.size() == level.K.cols() && "K needs one scale per column");
  out.putBytes(level.K.scale.data(), 4 * static_cast<std::size_t>(level.K.scale.size()));
  out.putBytes(level.K.Q.data(), 2 * static_cast<std::size_t>(level.K.Q.size()));
  out.put(checksum64(out.bytes()));
  return std::move(out.bytes());
}

LevelDecodeResult decodeResolutionLevel(std::span<const std::byte> bytes) {
  if (bytes.size() < kHeaderSize + kChecksumSize) return failure(LevelDecodeStatus::Truncated, "shorter than a header");
  if (std::memcmp(bytes.data(), kMagic.data(), kMagic.size()) != 0)
    return failure(LevelDecodeStatus::BadMagic, "not a ShapeCast resolution level");
  Reader in(bytes.subspan(kMagic.size()));
  if (const auto version = in.get<std::uint32_t>(); version != kResolutionLevelVersion)
    return failure(LevelDecodeStatus::UnsupportedVersion, "format version " + std::to_string(version));
  Header h;
  for (std::uint32_t* field : {&h.lowVertices, &h.lowFaces, &h.fullVertices, &h.m, &h.nonZeros})
    *field = in.get<std::uint32_t>();
  const auto payload = payloadSize(h, bytes.size() - kHeaderSize - kChecksumSize);
  if (!payload) return failure(LevelDecodeStatus::Truncated, "shorter than its declared sizes");
  if (kHeaderSize + *payload + kChecksumSize != bytes.size())
    return failure(LevelDecodeStatus::BadSize, "longer than its declared sizes");
  std::uint64_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - kChecksumSize, kChecksumSize);
  if (stored != checksum64(bytes.first(bytes.size() - kChecksumSize)))
    return failure(LevelDecodeStatus::BadChecksum, "checksum mismatch");
  return readPayload(in, h);
}

const char* toString(LevelDecodeStatus status) {
  switch (status) {
    case LevelDecodeStatus::Ok:
      return "ok";
    case LevelDecodeStatus::Truncated:
      return "truncated";
    case LevelDecodeStatus::BadMagic:
      return "bad magic";
    case LevelDecodeStatus::UnsupportedVersion:
      return "unsupported version";
    case LevelDecodeStatus::BadSize:
      return "bad size";
    case LevelDecodeStatus::BadChecksum:
      return "bad checksum";
    case LevelDecodeStatus::BadContent:
      return "bad content";
  }
  return "unknown";
}

}  // namespace sc::spectral
