// Fuzz target "level": decodeResolutionLevel(), the payload of a Level model transfer (and of FullModel ones).
//
// Input: one mode byte, then a payload. Mode (low bit): 0 decodes the payload as is; 1 appends its valid
// trailing checksum64 first, so the fuzzer gets past the checksum to the size, CSR and index checks.
// Invariants checked: a decoded level has consistent sizes (F indices in [0, n'), P n' by n with CSR offsets
// inside its non-zeros, K n' rows) and re-encodes to exactly the input bytes (bit-exact inverse).

#include "fuzz_support.h"
#include "spectral/basis_cache.h"
#include "spectral/resolution_level.h"

#include <algorithm>
#include <cstring>
#include <vector>

namespace {

void checkLevel(const sc::spectral::ResolutionLevel& level, std::span<const std::byte> input) {
  const Eigen::Index lowVertices = level.restV.rows();
  sc::fuzz::check(level.restV.cols() == 3 && level.F.cols() == 3, "three columns of positions and corners");
  sc::fuzz::check(level.F.size() == 0 || (level.F.minCoeff() >= 0 && level.F.maxCoeff() < lowVertices),
                  "face corners index low-res vertices");
  sc::fuzz::check(level.P.rows() == lowVertices && level.K.rows() == lowVertices, "P and K have one row per vertex");
  const std::vector<std::byte> again = sc::spectral::encodeResolutionLevel(level);
  sc::fuzz::check(again.size() == input.size() && std::equal(again.begin(), again.end(), input.begin()),
                  "a decoded level re-encodes to the same bytes");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const sc::fuzz::Input input = sc::fuzz::splitMode(data, size);
  std::vector<std::byte> bytes(input.rest.size());
  if (!bytes.empty()) std::memcpy(bytes.data(), input.rest.data(), bytes.size());
  if ((input.mode & 1) != 0) {
    const std::uint64_t checksum = sc::spectral::checksum64(bytes);  // little-endian, as the format stores it
    for (int shift = 0; shift < 64; shift += 8) bytes.push_back(static_cast<std::byte>(checksum >> shift));
  }
  const sc::spectral::LevelDecodeResult result = sc::spectral::decodeResolutionLevel(bytes);
  sc::fuzz::check(result.ok() == result.level.has_value(), "a level exactly when Ok");
  if (result.level) checkLevel(*result.level, bytes);
  return 0;
}
