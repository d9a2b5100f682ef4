#include "experiments/table1/table1_measurement.h"

#include "model/mesh_decimation.h"
#include "spectral/basis_pipeline.h"
#include "spectral/reconstruction_kernel.h"
#include "spectral/resolution_level.h"
#include "spectral/spectral_deformer.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>

namespace sc::app {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// Median wall time of `repeats` calls of `work(i)`.
double medianSeconds(int repeats, const std::function<void(int)>& work) {
  std::vector<double> times;
  times.reserve(static_cast<std::size_t>(repeats));
  for (int i = 0; i < repeats; ++i) {
    const auto start = Clock::now();
    work(i);
    times.push_back(secondsSince(start));
  }
  std::nth_element(times.begin(), times.begin() + repeats / 2, times.end());
  return times[static_cast<std::size_t>(repeats / 2)];
}

/// The `count` vertices nearest to vertex 0 (a handle region as a user would pick it).
std::vector<int> nearestToFirst(const Eigen::MatrixXd& V, int count) {
  std::vector<int> order(static_cast<std::size_t>(V.rows()));
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  const Eigen::RowVector3d origin = V.row(0);
  std::partial_sort(order.begin(), order.begin() + count, order.end(), [&](int a, int b) {
    return (V.row(a) - origin).squaredNorm() < (V.row(b) - origin).squaredNorm();
  });
  order.resize(static_cast<std::size_t>(count));
  return order;
}

/// Median time of one reconstruction X̂ + K·Z (K quantised to int16, as a client holds it) on one thread.
double clientSeconds(const spectral::QuantizedBasis& K, const Eigen::MatrixXd& rest, int frames) {
  const std::vector<float> restXyz = spectral::interleavedPositions(rest);
  std::vector<float> out(restXyz.size());
  const Eigen::MatrixXf Z = Eigen::MatrixXf::Random(K.cols(), 3) * 1e-3f;
  return medianSeconds(frames, [&](int) { spectral::reconstructInterleaved(K, restXyz, Z, out, 1); });
}

void measureServer(const spectral::HarmonicBasis& basis, const spectral::LaplaceOperators& ops,
                   const model::LoadedMesh& mesh, const Table1Options& options, Table1Row& row) {
  const int n = static_cast<int>(mesh.V.rows());
  spectral::SpectralDeformer deformer(basis, ops, mesh.V);
  const std::vector<int> big = nearestToFirst(mesh.V, std::min(3000, n / 3));
  row.changeHandleVertices = static_cast<int>(big.size());
  row.constraintChangeSeconds = medianSeconds(5, [&](int) { deformer.setConstraints({{{big}}, {}}); });

  const std::vector<int> handle(big.begin(), big.begin() + std::min<std::ptrdiff_t>(2000, n / 5));
  row.serverHandleVertices = static_cast<int>(handle.size());
  deformer.setConstraints({{{handle}}, {}});
  const double diagonal = (mesh.V.colwise().maxCoeff() - mesh.V.colwise().minCoeff()).norm();
  row.serverFrameSeconds = medianSeconds(options.frames, [&](int frame) {
    spectral::HandleTransform T;
    T.translation = Eigen::Vector3d(0, 1e-3 * diagonal * frame, 0);
    const spectral::HandleTransform transforms[] = {T};
    deformer.solve(transforms);
  });
}

}  // namespace

bool measureTable1Row(const std::string& name, const model::LoadedMesh& mesh, const Table1Options& options,
                      Table1Row& row, std::string& error) {
  row = {};
  row.mesh = name;
  row.verticesFull = static_cast<int>(mesh.V.rows());
  row.trianglesFull = static_cast<int>(mesh.F.rows());

  // === pre-computing: the basis, then the low-resolution level
  spectral::BasisOptions basisOptions;
  basisOptions.m = options.m;
  const spectral::BasisComputation basis = spectral::basisForMesh(mesh.V, mesh.F, basisOptions, std::nullopt);
  if (!basis.result.ok()) {
    error = basis.result.message;
    return false;
  }
  row.precomputeFullSeconds = basis.totalSeconds;
  const auto levelStart = Clock::now();
  const int target = std::max(4, static_cast<int>(options.lowFraction * row.verticesFull));
  const model::DecimatedMesh low = model::decimateMesh(mesh.V, mesh.F, target);
  row.decimationSeconds = secondsSince(levelStart);
  const spectral::ResolutionLevel level =
      spectral::resolutionLevel(mesh.V, mesh.F, basis.result.basis.vectors, low.V, low.F);
  row.levelBuildSeconds = secondsSince(levelStart);
  row.precomputeLowSeconds = row.precomputeFullSeconds + row.levelBuildSeconds;
  row.verticesLow = static_cast<int>(level.restV.rows());
  row.trianglesLow = static_cast<int>(level.F.rows());

  // === run time: server frame and constraint change, client reconstruction at both resolutions
  measureServer(basis.result.basis, basis.operators, mesh, options, row);
  const spectral::QuantizedBasis fullK = spectral::quantizeBasis(basis.result.basis.vectors);
  row.clientFullSeconds = clientSeconds(fullK, mesh.V, options.frames);
  row.clientLowSeconds = clientSeconds(level.K, level.restV, options.frames);
  return true;
}

}  // namespace sc::app
