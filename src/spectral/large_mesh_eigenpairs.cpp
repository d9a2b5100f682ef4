#include "spectral/large_mesh_eigenpairs.h"

#include "spectral/block_lanczos.h"
#include "spectral/repeated_eigenvalues.h"
#include "spectral/shift_invert_operator.h"
#include "spectral/single_threaded_blas.h"

#include <algorithm>
#include <thread>

namespace sc::spectral::detail {

BasisResult blockLanczosEigenpairs(const LaplaceOperators& ops, int pairs, double sigma,
                                   const BasisOptions& meshOptions) {
  BasisOptions options = meshOptions;
  options.tolerance = meshOptions.largeMeshTolerance;
  const double expectedSolves = 3.2 * pairs + 20.0;  // 316 solves at 1M vertices and m = 100
  auto observer = [&options, expectedSolves](int solves) {
    return !options.progress || options.progress(std::min(0.99, solves / expectedSolves));
  };
  ShiftInvertOperator op(ops.stiffness, ops.mass, observer);
  op.setSolveThreads(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  const SingleThreadedBlas oneBlasThread;  // the run's own threads split the solves and the sweeps over Q
  bool singleVector = false;
  BasisResult result = nearestPairs(op, ops.mass, pairs, sigma, options, &singleVector);
  completeRepeatedEigenvalues(op, ops.mass, pairs, sigma, options, singleVector, result);
  return result;
}

}  // namespace sc::spectral::detail
