#include "spectral/basis_cache.h"

#include <unistd.h>

#include <array>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace sc::spectral {
namespace {

static_assert(std::endian::native == std::endian::little, "the cache format is little-endian; add byte swapping");

constexpr std::array<char, 8> kMagic = {'S', 'C', 'M', 'H', 'B', '\0', '\r', '\n'};
constexpr std::size_t kHeaderSize = 40;

std::size_t fileSizeFor(std::size_t n, std::size_t m) { return kHeaderSize + 8 * m + 8 * n * m + 8; }

/// Appends the raw bytes of a trivially copyable value.
template <class T>
void put(std::vector<std::byte>& out, const T& value) {
  const auto* p = reinterpret_cast<const std::byte*>(&value);
  out.insert(out.end(), p, p + sizeof(T));
}

template <class T>
T get(const std::vector<std::byte>& in, std::size_t offset) {
  T value;
  std::memcpy(&value, in.data() + offset, sizeof(T));
  return value;
}

/// The header's solver field (the reserved 0 of older files is Lanczos).
/// Slices shares Lanczos's entries: both converge every pair to BasisOptions::tolerance (above sliceMaximumVertices
/// the slices' path to largeMeshTolerance: the same eigenvalues to 2e-14, residuals below 1e-6, so its entry serves
/// `--solver lanczos` too; --no-cache computes the reference afresh). The hierarchical solver converges to
/// residualTolerance instead, so its bases are kept apart.
std::uint32_t solverCode(BasisSolver solver) { return solver == BasisSolver::Hierarchical ? 1u : 0u; }

std::vector<std::byte> serialize(const BasisCacheKey& key, const HarmonicBasis& basis) {
  std::vector<std::byte> out;
  out.reserve(fileSizeFor(key.n, key.m));
  for (char c : kMagic) out.push_back(static_cast<std::byte>(c));
  put(out, kBasisCacheVersion);
  put(out, key.n);
  put(out, key.m);
  put(out, solverCode(key.solver));
  put(out, key.meshHash);
  put(out, key.shift);
  const auto* values = reinterpret_cast<const std::byte*>(basis.eigenvalues.data());
  out.insert(out.end(), values, values + 8 * basis.eigenvalues.size());
  const auto* vectors = reinterpret_cast<const std::byte*>(basis.vectors.data());
  out.insert(out.end(), vectors, vectors + 8 * basis.vectors.size());
  put(out, checksum64(out));
  return out;
}

}  // namespace

namespace {

constexpr std::uint64_t kChecksumSeed = 0xcbf29ce484222325ULL;
constexpr std::uint64_t kChecksumPrime = 0x100000001b3ULL;

/// Folds the whole 8-byte words at the start of `bytes` into `h`; returns the bytes taken (a multiple of 8).
std::size_t foldWords(std::uint64_t& h, std::span<const std::byte> bytes) {
  std::size_t i = 0;
  for (; i + 8 <= bytes.size(); i += 8) {
    std::uint64_t word;
    std::memcpy(&word, bytes.data() + i, 8);
    h = (h ^ word) * kChecksumPrime;
    h ^= h >> 29;
  }
  return i;
}

/// Folds the last (fewer than 8) bytes into `h`, one at a time.
void foldTail(std::uint64_t& h, std::span<const std::byte> bytes) {
  for (const std::byte b : bytes) h = (h ^ std::to_integer<std::uint64_t>(b)) * kChecksumPrime;
}

/// checksum64() of the bytes put() in order, through a 64 KiB buffer instead of a copy of them all.
class StreamingChecksum {
 public:
  template <class T>
  void put(const T& value) {
    if (m_size + sizeof(T) > m_buffer.size()) flush();
    std::memcpy(m_buffer.data() + m_size, &value, sizeof(T));
    m_size += sizeof(T);
  }
  std::uint64_t finish() {
    flush();
    foldTail(m_h, std::span(m_buffer).first(m_size));
    return m_h;
  }

 private:
  /// Folds the buffer's whole words; the rest (under 8 bytes) moves to its front.
  void flush() {
    const std::size_t taken = foldWords(m_h, std::span(m_buffer).first(m_size));
    std::memmove(m_buffer.data(), m_buffer.data() + taken, m_size - taken);
    m_size -= taken;
  }

  std::array<std::byte, std::size_t{64} << 10> m_buffer{};
  std::size_t m_size = 0;
  std::uint64_t m_h = kChecksumSeed;
};

}  // namespace

std::uint64_t checksum64(std::span<const std::byte> bytes) {
  std::uint64_t h = kChecksumSeed;
  foldTail(h, bytes.subspan(foldWords(h, bytes)));
  return h;
}

std::uint64_t meshContentHash(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F) {
  StreamingChecksum checksum;  // the checksum64 of these bytes laid end to end (26 MB at 437k vertices, not copied)
  checksum.put(static_cast<std::uint64_t>(V.rows()));
  checksum.put(static_cast<std::uint64_t>(F.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i)  // row-major order, independent of Eigen's storage
    for (Eigen::Index c = 0; c < V.cols(); ++c) checksum.put(V(i, c));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (Eigen::Index c = 0; c < F.cols(); ++c) checksum.put(static_cast<std::int32_t>(F(f, c)));
  return checksum.finish();
}

std::filesystem::path basisCacheFileName(const BasisCacheKey& key) {
  char name[64];
  std::snprintf(name, sizeof name, "%016llx-n%u-m%u%s.mhb", static_cast<unsigned long long>(key.meshHash), key.n, key.m,
                key.solver == BasisSolver::Hierarchical ? "-hierarchical" : "");
  return name;
}

CacheReadStatus readBasisCache(const std::filesystem::path& file, const BasisCacheKey& expected, HarmonicBasis& basis) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return CacheReadStatus::Missing;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec || size < kHeaderSize + 8) return CacheReadStatus::Corrupt;
  std::vector<std::byte> in(size);
  std::ifstream stream(file, std::ios::binary);
  if (!stream.read(reinterpret_cast<char*>(in.data()), static_cast<std::streamsize>(size)))
    return CacheReadStatus::Corrupt;

  if (std::memcmp(in.data(), kMagic.data(), kMagic.size()) != 0) return CacheReadStatus::Corrupt;
  if (get<std::uint32_t>(in, 8) != kBasisCacheVersion) return CacheReadStatus::Corrupt;
  const std::uint32_t solver = get<std::uint32_t>(in, 20);
  if (solver > 1) return CacheReadStatus::Corrupt;
  // a Lanczos entry serves a Slices request too (solverCode): compare in the requested solver's terms
  const BasisSolver stored = solver == 1                                    ? BasisSolver::Hierarchical
                             : expected.solver == BasisSolver::Hierarchical ? BasisSolver::Lanczos
                                                                            : expected.solver;
  const BasisCacheKey key{get<std::uint64_t>(in, 24), get<std::uint32_t>(in, 12), get<std::uint32_t>(in, 16),
                          get<double>(in, 32), stored};
  if (size != fileSizeFor(key.n, key.m)) return CacheReadStatus::Corrupt;
  if (get<std::uint64_t>(in, size - 8) != checksum64(std::span(in.data(), size - 8))) return CacheReadStatus::Corrupt;
  if (!(key == expected)) return CacheReadStatus::Mismatch;

  basis.shift = key.shift;
  basis.eigenvalues.resize(key.m);
  basis.vectors.resize(key.n, key.m);
  // An empty (n or m = 0) basis has null data(), and memcpy(nullptr, …, 0) is undefined: copy only real bytes.
  if (key.m > 0) std::memcpy(basis.eigenvalues.data(), in.data() + kHeaderSize, 8 * key.m);
  if (basis.vectors.size() > 0)
    std::memcpy(basis.vectors.data(), in.data() + kHeaderSize + 8 * key.m, 8 * std::size_t{key.n} * key.m);
  return CacheReadStatus::Hit;
}

bool writeBasisCache(const std::filesystem::path& file, const BasisCacheKey& key, const HarmonicBasis& basis) {
  if (basis.vectors.rows() != key.n || basis.vectors.cols() != key.m || basis.eigenvalues.size() != key.m) return false;
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  if (ec) return false;
  const std::vector<std::byte> bytes = serialize(key, basis);
  // A unique temporary beside the file, created exclusively (mkstemp: O_CREAT | O_EXCL, mode 0600), so two writers
  // never share one and a file or link already there is never followed.
  std::string pattern = file.string() + ".XXXXXX";
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) return false;
  const std::filesystem::path temporary = pattern;
  bool written = true;
  for (std::size_t done = 0; written && done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    written = n > 0;
    if (written) done += static_cast<std::size_t>(n);
  }
  written = ::fsync(fd) == 0 && written;
  written = ::close(fd) == 0 && written;
  if (written) std::filesystem::rename(temporary, file, ec);
  if (!written || ec) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    return false;
  }
  return true;
}

const char* toString(CacheReadStatus status) {
  switch (status) {
    case CacheReadStatus::Hit:
      return "hit";
    case CacheReadStatus::Missing:
      return "missing";
    case CacheReadStatus::Corrupt:
      return "corrupt";
    case CacheReadStatus::Mismatch:
      return "mismatch";
  }
  return "unknown";
}

}  // namespace sc::spectral
