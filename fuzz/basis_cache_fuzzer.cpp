// Fuzz target "basis_cache": readBasisCache(), the on-disk basis cache reader (it takes a path, so the input is
// written to a scratch file first).
//
// Input: one mode byte, then a cache file. Mode bit 0: append the file's valid trailing checksum64, so the fuzzer
// gets past the checksum; bit 1: expect another key than the file's header names (the Mismatch path), otherwise
// the key the header names (so a consistent file is a Hit).
// Invariants checked: Hit exactly for a consistent file with the expected key, and then the basis is n by m with m
// eigenvalues; the output basis is untouched unless Hit.

#include "fuzz_support.h"
#include "spectral/basis_cache.h"

#include <cstring>
#include <vector>

namespace {

/// Reads a little-endian field of the header, or 0 when the input is too short.
template <typename T>
T headerField(const std::vector<std::uint8_t>& bytes, std::size_t offset) {
  T value{};
  if (bytes.size() >= offset + sizeof(T)) std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static sc::fuzz::ScratchFile file("input.mhb");
  const sc::fuzz::Input input = sc::fuzz::splitMode(data, size);
  std::vector<std::uint8_t> bytes(input.rest.begin(), input.rest.end());
  if ((input.mode & 1) != 0) {
    const std::uint64_t checksum = sc::spectral::checksum64(std::as_bytes(std::span(bytes)));
    for (int shift = 0; shift < 64; shift += 8) bytes.push_back(static_cast<std::uint8_t>(checksum >> shift));
  }
  sc::spectral::BasisCacheKey expected{headerField<std::uint64_t>(bytes, 24), headerField<std::uint32_t>(bytes, 12),
                                       headerField<std::uint32_t>(bytes, 16), headerField<double>(bytes, 32)};
  if ((input.mode & 2) != 0) ++expected.meshHash;

  sc::spectral::HarmonicBasis basis;
  const sc::spectral::CacheReadStatus status = sc::spectral::readBasisCache(file.write(bytes), expected, basis);
  if (status == sc::spectral::CacheReadStatus::Hit) {
    sc::fuzz::check((input.mode & 2) == 0, "no Hit for another key");
    sc::fuzz::check(basis.vectors.rows() == expected.n && basis.vectors.cols() == expected.m &&
                        basis.eigenvalues.size() == expected.m,
                    "a hit basis is n by m with m eigenvalues");
  } else {
    sc::fuzz::check(basis.vectors.size() == 0 && basis.eigenvalues.size() == 0, "basis untouched unless Hit");
  }
  return 0;
}
