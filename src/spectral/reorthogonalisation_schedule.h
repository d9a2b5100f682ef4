#pragma once
// ReorthogonalisationSchedule: when block Lanczos re-orthogonalises a new block against its whole Krylov basis
// (partial re-orthogonalisation) and how many of its columns that pass covers. Pure rules over the drifts it is told.
// Internal to src/spectral (block_lanczos.cpp).

#include <Eigen/Core>

#include <algorithm>

namespace sc::spectral::detail {

/// What a full pass measured: the largest drift over its columns, and how many leading columns drifted (1 + the
/// last one above ReorthogonalisationSchedule's threshold, 0 if none).
struct DriftProfile {
  double drift = 0.0;
  Eigen::Index drifting = 0;
};

/// When a new block is re-orthogonalised against the whole basis (partial re-orthogonalisation: the full pass, two
/// reads of the #V × K basis, took 5.5–7 s of a 437k-vertex slice's 12 s when it ran on every block). Lanczos vectors
/// lose M-orthogonality to the old ones by a factor of 30–50 per block on the dragons, and by 10⁻¹¹–10⁻¹⁰ in a single
/// block at interior shifts (the solve's error there lies along the eigenvectors near σ, which the basis already
/// holds). Each full pass measures the drift it removes, the largest |q_kᵀ M w|/‖w‖_M, which is the most the skipped
/// blocks reached: above kDriftTarget the interval of skipped blocks shrinks by one (to zero above ten times it), below
/// kDriftTarget/kGrowth it grows by one, up to kMaximumInterval. kDriftTarget stays below √ε, Simon's
/// semi-orthogonality, which keeps the Ritz values as accurate as full re-orthogonalisation does. Blocks are
/// re-orthogonalised in consecutive pairs, because the recurrence carries the drift of both into the next block; the
/// interval starts at zero.
///
/// How far back a pass reaches: the drift lies along the Ritz vectors that have converged, whose coordinates are
/// in the basis's leading columns (Paige; Simon's partial re-orthogonalisation orthogonalises only against the
/// columns whose drift exceeds ε^{3/4}). On the 437k dragon (K = 284) the drifts above 10⁻¹² were all in the first
/// 30 columns, the rest at 10⁻¹³–10⁻¹⁶. The first pass of a pair covers every column and tells how many leading ones
/// drifted (above kDriftingColumn and kDriftingFraction of its largest drift); the second covers twice that many
/// plus kReachMargin, or every column when drift reaches its last block (cutShort(): the caller repeats it). What a
/// second pass leaves is not benign: spread by the recurrence, it grows with the head until the next pair's first pass
/// removes it, which is why every first pass stays complete. On the 100k dragon's spectrum slices the interior slice's
/// second passes found drift too far back to be cut, and gave the same bits as complete ones; the slice below the
/// spectrum gave the same eigenvalues to 10⁻¹⁴ relative (beyond the zero and near-zero modes) with a largest
/// residual of 1.8e-7 instead of 9.8e-8.
class ReorthogonalisationSchedule {
 public:
  /// A column drifts when its drift, relative to ‖w‖_M, exceeds both this and kDriftingFraction of the pass's
  /// largest. The fraction keeps the reach on the head: by the next pair the columns a second pass left (10⁻¹⁴) have
  /// grown to 10⁻¹², above any fixed floor that would still leave the head's growth out.
  static constexpr double kDriftingColumn = 1e-13;
  static constexpr double kDriftingFraction = 1e-3;
  /// The drift a full pass may find: 5 times below √ε (Simon's semi-orthogonality). 10⁻⁹ (15 times below) took the
  /// 437k run's full passes over 4,570 columns, 3·10⁻⁹ over 4,100, with the same 292 solves, the same eigenvalues to
  /// 1e-14 relative at 100k, 437k and 1M, and an M-orthonormality error of 4e-11 at 1M against 2.4e-12; 10⁻⁸ read
  /// more (4,236: a drift above ten times the target resets the interval more often).
  static constexpr double kDriftTarget = 3e-9;

  /// The drift profile of a pass: `columnDrift[k]` = max |q_kᵀ M w|/‖w‖_M over the block's columns w. Cost: O(k).
  static DriftProfile profile(const Eigen::VectorXd& columnDrift) {
    DriftProfile result;
    if (columnDrift.size() == 0) return result;
    result.drift = columnDrift.maxCoeff();
    const double threshold = std::max(kDriftingColumn, kDriftingFraction * result.drift);
    for (Eigen::Index k = columnDrift.size(); k > 0 && result.drifting == 0; --k) {
      if (columnDrift[k - 1] > threshold) result.drifting = k;
    }
    return result;
  }

  /// Whether the next block needs the full pass.
  bool due() const { return m_pending > 0 || m_skipped >= m_interval; }

  /// How many leading columns of a basis of `size` columns the due pass covers: all for the first pass of a pair,
  /// else twice those its first pass found drifting plus kReachMargin (at most `size`).
  Eigen::Index reach(Eigen::Index size) const {
    return m_pending > 0 ? std::min(size, 2 * m_drifting + kReachMargin) : size;
  }

  /// Whether a pass that covered `reach` of `size` columns, in blocks of `block`, found drift in its last block, which
  /// may go on beyond it: the caller then repeats the pass over every column.
  static bool cutShort(const DriftProfile& pass, Eigen::Index reach, Eigen::Index size, Eigen::Index block) {
    return reach < size && pass.drifting > reach - block;
  }

  /// After a block without a full pass.
  void recordSkipped() { ++m_skipped; }

  /// After a block's full pass: what it measured.
  void record(const DriftProfile& pass) {
    const double drift = pass.drift;
    if (m_pending == 0) {
      m_drifting = pass.drifting;
      if (drift > kDriftTarget)
        m_interval = drift > 10.0 * kDriftTarget ? 0 : std::max(0, m_interval - 1);
      else if (drift < kDriftTarget / kGrowth)
        m_interval = std::min(m_interval + 1, kMaximumInterval);
      m_pending = 1;
    } else {
      --m_pending;
    }
    m_skipped = 0;
  }

 private:
  static constexpr Eigen::Index kReachMargin = 16;
  static constexpr int kMaximumInterval = 8;
  static constexpr double kGrowth = 50.0;
  int m_interval = 0;
  int m_skipped = 0;
  int m_pending = 0;
  Eigen::Index m_drifting = 0;
};

}  // namespace sc::spectral::detail
