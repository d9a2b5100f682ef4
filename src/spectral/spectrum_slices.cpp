#include "spectral/spectrum_slices.h"

#include "spectral/block_lanczos.h"
#include "spectral/hierarchical_basis.h"
#include "spectral/lanczos_solver.h"
#include "spectral/large_mesh_eigenpairs.h"
#include "spectral/mesh_components.h"
#include "spectral/shift_invert_operator.h"
#include "spectral/single_threaded_blas.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

namespace sc::spectral::detail {
namespace {

/// Fewer pairs per slice than this cost more in factorisations and overlaps than they save in orthogonalisation.
constexpr int kMinimumPairsPerSlice = 12;
/// Relative eigenvalue agreement of two slices on a shared index: Spectra converges each Ritz value to 1e-10.
constexpr double kAgreement = 1e-7;
/// Smallest relative gap a hand-over may sit at: well above round-off, so that the two runs' vectors on either side
/// belong to different eigenspaces (their inner products are about residual/gap).
constexpr double kMinimumGap = 1e-4;
/// Extra runs a slice may make (on its factor) when its pairs do not reach both ends of its window.
constexpr int kCoverageAttempts = 2;
/// Bound on |HᵀMH − I| over the columns around each hand-over.
constexpr double kHandOverOrthonormality = 1e-8;

/// Indices [lo, hi) one slice must cover, and its shift.
struct SliceTask {
  int lo{};
  int hi{};
  double shift{};
  bool top = false;  ///< the slice that reaches m − 1: its thread also runs checkCountAboveBasis()
  double scale{};    ///< |σ| of slice 0: the scale of relative eigenvalue gaps
};

/// The outcome of one slice's run.
struct SliceRun {
  BasisResult result;
  SpectrumSlice slice;
  std::string countCheck;  ///< top slice: checkCountAboveBasis()'s finding (empty: the count holds)
};

/// The top slice first (its thread then runs the count check while the others finish); slice 0's window is half a
/// guard wider, because the others need pairs on both sides of their shifts.
std::vector<SliceTask> planSlices(const LaplaceOperators& ops, int m, int count, int guard, double sigma) {
  Eigen::VectorXi labels;
  const int components = connectedComponents(ops.stiffness, labels);
  const double perUnitEigenvalue = ops.totalArea / (4.0 * std::numbers::pi);  // Weyl: N(λ) ≈ components + Aλ/4π
  const auto boundary = [m, count, guard](int j) { return j == 0 ? 0 : j == count ? m : j * m / count + guard / 2; };
  std::vector<SliceTask> tasks;
  for (int j = count - 1; j >= 0; --j) {
    SliceTask task;
    task.lo = std::max(0, boundary(j) - guard);
    task.hi = std::min(m, boundary(j + 1) + guard);
    const double centre = 0.5 * (task.lo + task.hi) - components;
    task.shift = j == 0 ? sigma : std::max(centre, 0.5) / perUnitEigenvalue;
    task.top = j == count - 1;
    task.scale = std::abs(sigma);
    tasks.push_back(task);
  }
  return tasks;
}

/// How many pairs nearest the shift cover [lo, hi) when `below` eigenvalues lie under it. Nearest means by distance,
/// on either side, so unless nothing lies below the shift (slice 0), twice the window's farther side from the shift
/// (in indices; the spectrum's density is about even over a window), plus two.
int pairsCovering(const SliceTask& task, int below, Eigen::Index vertexCount) {
  const int over = std::max(0, task.hi - below);
  const int pairs = below == 0 ? over : 2 * std::max(below - task.lo, over) + 2;
  return static_cast<int>(std::min<Eigen::Index>(pairs, vertexCount - 2));
}

/// Sylvester's count just above the basis: in the top slice, the first index t ≥ m − 1 followed by a
/// relative gap of at least kMinimumGap, else its last index t; S − σM factored halfway across that gap (or, past the
/// last, half a minimum gap above it) must have exactly t + 1 eigenvalues below. This checks the part of the top slice
/// above its own shift, which no overlap does. Empty when it holds. Cost: one more simplicial factorisation, on
/// the top slice's operator (its symbolic analysis is reused; the slice's own factor is gone afterwards).
std::string checkCountAboveBasis(ShiftInvertOperator& op, const SpectrumSlice& top, int m, double scale) {
  if (top.last() < m - 1) return "the top slice ends at index " + std::to_string(top.last()) + ", below m - 1";
  const auto value = [&top](int index) { return top.eigenvalues[index - top.first]; };
  int t = std::max(m - 1, top.first);
  while (t < top.last() && (value(t + 1) - value(t)) / (std::abs(value(t + 1)) + scale) < kMinimumGap) ++t;
  const double shift =
      t < top.last() ? 0.5 * (value(t) + value(t + 1)) : value(t) + 0.5 * kMinimumGap * (std::abs(value(t)) + scale);
  try {
    op.set_shift(shift);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  const int below = op.eigenvaluesBelowShift();
  if (below == t + 1) return {};
  return std::to_string(below) + " eigenvalues lie below the count check above index " + std::to_string(t) +
         ", the slices found " + std::to_string(t + 1) + " (a slice missed one, or m cuts a cluster)";
}

SliceRun runSlice(const LaplaceOperators& ops, const SliceTask& task, const std::function<bool(int)>& observer,
                  const BasisOptions& options) {
  SliceRun run;
  ShiftInvertOperator op(ops.stiffness, ops.mass, observer);
  try {
    op.set_shift(task.shift);
  } catch (const std::runtime_error& e) {
    run.result.status = BasisStatus::FactorizationFailed;
    run.result.message = e.what();
    return run;
  }
  const int below = op.eigenvaluesBelowShift();
  int pairs = pairsCovering(task, below, ops.mass.size());
  for (int attempt = 0;; ++attempt) {
    run.result = nearestPairs(op, ops.mass, pairs, task.shift, options);
    if (!run.result.ok()) return run;
    const auto& values = run.result.basis.eigenvalues;
    const int first = below - static_cast<int>((values.array() < task.shift).count());
    const int last = first + static_cast<int>(values.size()) - 1;
    // the spectrum's density is uneven on the two sides of the shift: ask again for twice the shortfall
    const int shortfall = std::max(first - task.lo, task.hi - 1 - last);
    const int more = std::min<int>(pairs + 2 * shortfall + 2, static_cast<int>(ops.mass.size()) - 2);
    if (shortfall <= 0 || attempt == kCoverageAttempts || more <= pairs) {
      run.slice.first = first;
      break;
    }
    pairs = more;
  }
  run.slice.shift = task.shift;
  run.slice.eigenvalues = std::move(run.result.basis.eigenvalues);
  run.slice.vectors = std::move(run.result.basis.vectors);
  if (task.top) run.countCheck = checkCountAboveBasis(op, run.slice, options.m, task.scale);
  return run;
}

/// Runs every task on up to `threads` threads; progress and cancellation are shared through one observer.
std::vector<SliceRun> runSlices(const LaplaceOperators& ops, const std::vector<SliceTask>& tasks, int threads,
                                const BasisOptions& options) {
  std::atomic<int> solves{0};
  std::atomic<bool> cancelled{false};
  std::mutex progressMutex;
  double expected = 0.0;
  for (const SliceTask& task : tasks) expected += 3.5 * (task.hi - task.lo) + 10.0;  // 188 solves for 53 at 100k
  const std::function<bool(int)> observer = [&](int) {
    const int done = ++solves;
    if (cancelled) return false;
    if (!options.progress) return true;
    const std::lock_guard lock(progressMutex);
    if (!options.progress(std::min(0.99, done / expected))) cancelled = true;
    return !cancelled;
  };
  std::vector<SliceRun> runs(tasks.size());
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t j; (j = next++) < tasks.size();) {
      try {
        runs[j] = runSlice(ops, tasks[j], observer, options);
      } catch (const std::exception& e) {  // std::bad_alloc from a slice's vectors: reported, not thrown across threads
        runs[j].result.status = BasisStatus::NotConverged;
        runs[j].result.message = std::string("a slice failed: ") + e.what();
      }
    }
  };
  const std::optional<SingleThreadedBlas> oneBlasThread =
      threads > 1 ? std::optional<SingleThreadedBlas>(std::in_place) : std::nullopt;
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& thread : pool) thread.join();
  return runs;
}

double handOverOrthonormality(const MergedSlices& merged, const Eigen::VectorXd& mass, int width) {
  double worst = 0.0;
  const auto m = static_cast<int>(merged.eigenvalues.size());
  for (const int s : merged.handOvers) {
    const int begin = std::max(0, s - width);
    const int end = std::min(m, s + width);
    const auto block = merged.vectors.middleCols(begin, end - begin);
    const Eigen::MatrixXd gram = block.transpose() * (mass.asDiagonal() * block);
    worst = std::max(worst, (gram - Eigen::MatrixXd::Identity(gram.rows(), gram.cols())).cwiseAbs().maxCoeff());
  }
  return worst;
}

/// The hierarchical solver's block iteration finds every copy of a multiple eigenvalue, which single-vector Lanczos
/// (a slice, or the plain solver) may not; it falls back to Lanczos itself on meshes too small to coarsen.
BasisResult fallBack(const LaplaceOperators& ops, double sigma, const BasisOptions& options, const std::string& why) {
  BasisResult result = hierarchicalEigenpairs(ops, sigma, options);
  if (result.ok())
    result.message = std::string("spectrum slicing fell back to the ") +
                     (result.solver == BasisSolver::Hierarchical ? "hierarchical" : "lanczos") + " solver: " + why;
  return result;
}

}  // namespace

MergedSlices mergeSlices(std::vector<SpectrumSlice> slices, int m, double scale, double agreement, double minimumGap) {
  MergedSlices merged;
  std::sort(slices.begin(), slices.end(), [](const SpectrumSlice& a, const SpectrumSlice& b) {
    return a.first != b.first ? a.first < b.first : a.last() > b.last();
  });
  const auto value = [](const SpectrumSlice* slice, int index) { return slice->eigenvalues[index - slice->first]; };
  // every two slices that share indices must agree on all of them, whether or not both end up used
  for (std::size_t i = 0; i < slices.size(); ++i) {
    for (std::size_t j = i + 1; j < slices.size(); ++j) {
      const SpectrumSlice* a = &slices[i];
      const SpectrumSlice* b = &slices[j];
      for (int k = std::max(a->first, b->first); k <= std::min(a->last(), b->last()); ++k) {
        if (std::abs(value(a, k) - value(b, k)) > agreement * (std::abs(value(a, k)) + scale)) {
          merged.error = "two slices disagree on eigenvalue " + std::to_string(k) + " (one missed an eigenvalue)";
          return merged;
        }
      }
    }
  }
  std::vector<const SpectrumSlice*> kept;
  for (const SpectrumSlice& slice : slices) {
    if (slice.eigenvalues.size() == 0 || (!kept.empty() && slice.last() <= kept.back()->last())) continue;
    if (!kept.empty() && kept.back()->last() >= m - 1) break;
    kept.push_back(&slice);
  }
  if (kept.empty() || kept.front()->first > 0) {
    merged.error = "no slice starts at the smallest eigenvalue";
    return merged;
  }
  if (kept.back()->last() < m - 1) {
    merged.error = "the slices end at index " + std::to_string(kept.back()->last()) + ", below m - 1";
    return merged;
  }
  std::vector<int> starts{0};
  for (std::size_t j = 0; j + 1 < kept.size(); ++j) {
    const SpectrumSlice* a = kept[j];
    const SpectrumSlice* b = kept[j + 1];
    if (b->first > a->last() + 1) {
      merged.error = "no slice covers indices " + std::to_string(a->last() + 1) + " to " + std::to_string(b->first - 1);
      return merged;
    }
    int handOver = -1;
    double widest = -1.0;
    for (int s = std::max({b->first, starts.back(), a->first + 1}); s <= a->last() + 1; ++s) {
      const double gap = (value(b, s) - value(a, s - 1)) / (std::abs(value(b, s)) + scale);
      if (gap > widest) {
        widest = gap;
        handOver = s;
      }
    }
    if (handOver < 0 || widest < minimumGap) {
      merged.error = "no gap between eigenvalues " + std::to_string(b->first) + " and " + std::to_string(a->last()) +
                     " to hand over at (a cluster spans two slices' overlap)";
      return merged;
    }
    starts.push_back(handOver);
    merged.handOvers.push_back(handOver);
  }
  const Eigen::Index rows = kept.front()->vectors.rows();
  merged.eigenvalues.resize(m);
  merged.vectors.resize(rows, m);
  for (std::size_t j = 0; j < kept.size(); ++j) {
    const int begin = starts[j];
    const int end = j + 1 < kept.size() ? starts[j + 1] : m;
    const SpectrumSlice* slice = kept[j];
    merged.eigenvalues.segment(begin, end - begin) = slice->eigenvalues.segment(begin - slice->first, end - begin);
    merged.vectors.middleCols(begin, end - begin) = slice->vectors.middleCols(begin - slice->first, end - begin);
  }
  return merged;
}

BasisResult slicedEigenpairs(const LaplaceOperators& ops, double sigma, const BasisOptions& options) {
  const int m = options.m;
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int count =
      options.slices > 0 ? options.slices : std::clamp(hardware, 2, std::max(2, m / kMinimumPairsPerSlice));
  const Eigen::Index n = ops.mass.size();
  if (n > options.sliceMaximumVertices && options.blockLanczos) return blockLanczosEigenpairs(ops, m, sigma, options);
  if (n < options.sliceMinimumVertices || n > options.sliceMaximumVertices || count < 2 || m < 2 * count) {
    return lanczosEigenpairs(ops, m, sigma, options);
  }
  const int guard = std::max(3, m / (10 * count));
  const std::vector<SliceTask> tasks = planSlices(ops, m, count, guard, sigma);
  const int threads = std::clamp(options.sliceThreads > 0 ? options.sliceThreads : hardware, 1, count);
  std::vector<SliceRun> runs = runSlices(ops, tasks, threads, options);

  int solves = 0;
  std::vector<SpectrumSlice> slices;
  for (SliceRun& run : runs) {
    solves += run.result.operatorApplications;
    if (run.result.status == BasisStatus::Cancelled || run.result.status == BasisStatus::FactorizationFailed) {
      run.result.operatorApplications = solves;
      return std::move(run.result);
    }
    if (!run.result.ok()) return fallBack(ops, sigma, options, run.result.message);
    if (!run.countCheck.empty()) return fallBack(ops, sigma, options, run.countCheck);
    slices.push_back(std::move(run.slice));
  }
  runs.clear();
  MergedSlices merged = mergeSlices(std::move(slices), m, std::abs(sigma), kAgreement, kMinimumGap);
  if (!merged.error.empty()) return fallBack(ops, sigma, options, merged.error);
  if (const double defect = handOverOrthonormality(merged, ops.mass, 2 * guard); defect > kHandOverOrthonormality)
    return fallBack(ops, sigma, options,
                    "the columns around a hand-over are not orthonormal (" + std::to_string(defect) + ")");

  BasisResult result;
  result.status = BasisStatus::Ok;
  result.solver = BasisSolver::Slices;
  result.slices = count;
  result.operatorApplications = solves;
  result.basis.eigenvalues = std::move(merged.eigenvalues);
  result.basis.vectors = std::move(merged.vectors);
  result.basis.shift = sigma;
  return result;
}

}  // namespace sc::spectral::detail
