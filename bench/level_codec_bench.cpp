// shapecast-bench-level-codec: bytes of a mesh's level payloads as a host sends them: the canonical payload (level
// format 2: K as int16) and the compressed one (session::compressLevelPayload: meshoptimizer for X̂' and F', zstd
// for the tables and the mesh-predicted K), per level of the host's ladder and the full resolution, with the time
// to compress and to decompress (one run each, one thread).
// Usage: shapecast-bench-level-codec MESH [m = 100] [zstd level = 9] [K bits = 13, the product's: fewer requantise K,
//        to measure]

#include "experiments/report/machine_info.h"
#include "model/mesh_decimation.h"
#include "model/mesh_loader.h"
#include "session/wire/level_codec.h"
#include "spectral/basis_pipeline.h"
#include "spectral/quantized_basis.h"
#include "spectral/resolution_level.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <variant>
#include <vector>

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The product's significant bits of K: ±kQuantizedBasisLevels = ±(2¹² − 1), 13 bits with the sign.
constexpr int kProductBits = 13;
static_assert(sc::spectral::kQuantizedBasisLevels == (1 << (kProductBits - 1)) - 1);

/// K requantised to `bits` (< kProductBits) significant bits, still int16 with a scale per column: what a coarser
/// quantiser would send (measurement only).
sc::spectral::ResolutionLevel coarser(sc::spectral::ResolutionLevel level, int bits) {
  const float factor = static_cast<float>(1 << (kProductBits - bits));
  level.K.Q = (level.K.Q.cast<float>() / factor).array().round().cast<std::int16_t>();
  level.K.scale *= factor;
  return level;
}

void report(const sc::spectral::ResolutionLevel& original, int zstdLevel, int bits) {
  const sc::spectral::ResolutionLevel level = bits < kProductBits ? coarser(original, bits) : original;
  const std::vector<std::byte> bytes = sc::spectral::encodeResolutionLevel(level);
  const QByteArray canonical(reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size()));
  auto start = std::chrono::steady_clock::now();
  const QByteArray compressed = sc::session::compressLevelPayload(canonical, zstdLevel);
  const double encodeSeconds = secondsSince(start);
  start = std::chrono::steady_clock::now();
  const sc::session::LevelDecompression decoded =
      sc::session::decompressLevelPayload(compressed, static_cast<std::uint64_t>(canonical.size()));
  const double decodeSeconds = secondsSince(start);
  const double k16 = 2.0 * static_cast<double>(level.K.rows() * level.K.cols()) / 1e6;
  const double float32 = static_cast<double>(canonical.size()) / 1e6 + k16;  // level format 1: 4 bytes per K entry
  std::uint32_t sections[4] = {};  // positions, faces, tables, K (level_codec.h, offset 36)
  std::memcpy(sections, compressed.constData() + 36, sizeof sections);
  std::printf(
      "n' %7ld  f' %7ld  float32-K payload %7.2f MB  int16-K payload %7.2f MB  compressed %7.2f MB  "
      "(%4.1f%%: X %.2f F %.2f P+scales %.2f K %.2f MB)  compress %.2f s  decompress %.3f s  %s\n",
      static_cast<long>(level.restV.rows()), static_cast<long>(level.F.rows()), float32,
      static_cast<double>(canonical.size()) / 1e6, static_cast<double>(compressed.size()) / 1e6,
      100.0 * static_cast<double>(compressed.size()) / static_cast<double>(canonical.size()), sections[0] / 1e6,
      sections[1] / 1e6, sections[2] / 1e6, sections[3] / 1e6, encodeSeconds, decodeSeconds,
      decoded.ok() && decoded.payload == canonical ? "round trip exact" : "ROUND TRIP FAILED");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: shapecast-bench-level-codec MESH [m] [zstd level] [K bits]\n");
    return 2;
  }
  const int m = argc > 2 ? std::atoi(argv[2]) : 100;
  const int zstdLevel = argc > 3 ? std::atoi(argv[3]) : 9;
  const int bits = argc > 4 ? std::clamp(std::atoi(argv[4]), 8, kProductBits) : kProductBits;
  const sc::model::MeshLoadResult loaded = sc::model::loadMesh(argv[1]);
  if (const auto* error = std::get_if<sc::model::MeshError>(&loaded)) {
    std::fprintf(stderr, "%s\n", error->message.c_str());
    return 1;
  }
  const sc::model::LoadedMesh& mesh = std::get<sc::model::LoadedMesh>(loaded);
  sc::spectral::BasisOptions options;
  options.m = m;
  const sc::spectral::BasisComputation basis = sc::spectral::basisForMesh(mesh.V, mesh.F, options, std::nullopt);
  if (!basis.result.ok()) {
    std::fprintf(stderr, "basis: %s\n", basis.result.message.c_str());
    return 1;
  }
  const Eigen::MatrixXd& H = basis.result.basis.vectors;
  std::printf("machine   %s\n", qPrintable(sc::report::machineDescription()));
  std::printf("mesh      %s, #V %ld, m = %d, zstd level %d, K bits %d\n", argv[1], static_cast<long>(mesh.V.rows()), m,
              zstdLevel, bits);
  report(sc::spectral::fullResolutionLevel(mesh.V, mesh.F, H), zstdLevel, bits);
  const std::vector<int> targets = sc::model::levelTargets(static_cast<int>(mesh.V.rows()));
  for (const sc::model::DecimatedMesh& low : sc::model::resolutionLadder(mesh.V, mesh.F, targets))
    report(sc::spectral::resolutionLevel(mesh.V, mesh.F, H, low.V, low.F), zstdLevel, bits);
  return 0;
}
