// Fuzz target "level": decodeResolutionLevel(), the payload of a Level model transfer (and of FullModel ones), and
// decompressLevelPayload() (session/wire/level_codec.h), what a transfer carries since protocol version 6.
//
// Input: one mode byte, then a payload. Mode bit 1 set: the payload is a compressed level, decompressed first
// (limit 16 MiB; a refusal must come with a message, a success must be exactly the declared size) and the result
// decoded. Then (low bit): 0 decodes the payload as is; 1 appends its valid trailing checksum64 first (plain
// payloads only), so the fuzzer gets past the checksum to the size, CSR and index checks.
// Invariants checked: a decoded level has consistent sizes (F indices in [0, n'), P n' by n with CSR offsets
// inside its non-zeros, K n' rows) and re-encodes to exactly the input bytes (bit-exact inverse).

#include "fuzz_support.h"
#include "session/wire/level_codec.h"
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
  if ((input.mode & 2) != 0) {
    const QByteArrayView compressed(reinterpret_cast<const char*>(input.rest.data()),
                                    static_cast<qsizetype>(input.rest.size()));
    const sc::session::LevelDecompression out = sc::session::decompressLevelPayload(compressed, 16U << 20);
    sc::fuzz::check(out.ok() || out.payload.isEmpty(), "a refusal carries no payload");
    if (!out.ok()) {
      sc::fuzz::check(!out.error.isEmpty(), "a refusal says why");
      return 0;
    }
    sc::fuzz::check(static_cast<std::uint64_t>(out.payload.size()) == sc::session::declaredLevelPayloadSize(compressed),
                    "the decoded payload has its declared size");
    bytes.resize(static_cast<std::size_t>(out.payload.size()));
    if (!bytes.empty()) std::memcpy(bytes.data(), out.payload.constData(), bytes.size());
  } else if ((input.mode & 1) != 0) {
    const std::uint64_t checksum = sc::spectral::checksum64(bytes);  // little-endian, as the format stores it
    for (int shift = 0; shift < 64; shift += 8) bytes.push_back(static_cast<std::byte>(checksum >> shift));
  }
  const sc::spectral::LevelDecodeResult result = sc::spectral::decodeResolutionLevel(bytes);
  sc::fuzz::check(result.ok() == result.level.has_value(), "a level exactly when Ok");
  if (result.level) checkLevel(*result.level, bytes);
  return 0;
}
