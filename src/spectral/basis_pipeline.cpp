#include "spectral/basis_pipeline.h"

#include <chrono>
#include <cmath>
#include <numbers>

namespace sc::spectral {
namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

BasisComputation basisForMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const BasisOptions& options,
                              const std::optional<std::filesystem::path>& cacheDir) {
  const auto start = std::chrono::steady_clock::now();
  BasisComputation out;

  // === step 1: operators
  out.operators = laplaceOperators(V, F);
  out.operatorSeconds = secondsSince(start);

  // === step 2: cache look-up
  const BasisCacheKey key{meshContentHash(V, F), static_cast<std::uint32_t>(V.rows()),
                          static_cast<std::uint32_t>(options.m),
                          -options.shiftFactor * 4.0 * std::numbers::pi / out.operators.totalArea, options.solver};
  if (cacheDir) {
    out.cacheFile = *cacheDir / basisCacheFileName(key);
    out.cacheStatus = readBasisCache(out.cacheFile, key, out.result.basis);
    if (out.cacheStatus == CacheReadStatus::Hit) {
      out.cached = true;
      out.result.status = BasisStatus::Ok;
      out.totalSeconds = secondsSince(start);
      return out;
    }
  }

  // === step 3: eigensolve, then cache write
  const auto solveStart = std::chrono::steady_clock::now();
  out.result = manifoldHarmonicBasis(out.operators, options);
  out.eigensolveSeconds = secondsSince(solveStart);
  if (out.result.ok() && cacheDir) writeBasisCache(out.cacheFile, key, out.result.basis);
  out.totalSeconds = secondsSince(start);
  return out;
}

}  // namespace sc::spectral
