#pragma once
// ReorthogonalisationSchedule: when block Lanczos re-orthogonalises a new block against its whole Krylov basis
// (partial re-orthogonalisation). Pure rules over the drifts it is told; no linear algebra. Internal to src/spectral
// (block_lanczos.cpp).

#include <algorithm>

namespace sc::spectral::detail {

/// When a new block is re-orthogonalised against the whole basis (partial re-orthogonalisation: the full pass, two
/// reads of the #V × K basis, took 5.5–7 s of a 437k-vertex slice's 12 s when it ran on every block). Lanczos vectors
/// lose M-orthogonality to the old ones by a factor of 30–50 per block on the dragons, and by 10⁻¹¹–10⁻¹⁰ in a single
/// block at interior shifts (the solve's error there lies along the eigenvectors near σ, which the basis already
/// holds). Each full pass measures the drift it removes, the largest |q_kᵀ M w|/‖w‖_M, which is the most the skipped
/// blocks reached: above kDriftTarget the interval of skipped blocks shrinks by one (to zero above ten times it), below
/// kDriftTarget/kGrowth it grows by one, up to kMaximumInterval. kDriftTarget stays 15 times below √ε, Simon's
/// semi-orthogonality, which keeps the Ritz values as accurate as full re-orthogonalisation does. Blocks are
/// re-orthogonalised in consecutive pairs, because the recurrence carries the drift of both into the next block; the
/// interval starts at zero.
class ReorthogonalisationSchedule {
 public:
  /// Whether the next block needs the full pass.
  bool due() const { return m_pending > 0 || m_skipped >= m_interval; }

  /// After each block: the drift its full pass removed, or a negative value when it had none.
  void record(double drift) {
    if (drift < 0.0) {
      ++m_skipped;
      return;
    }
    if (m_pending == 0) {
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
  static constexpr double kDriftTarget = 1e-9;
  static constexpr int kMaximumInterval = 8;
  static constexpr double kGrowth = 50.0;
  int m_interval = 0;
  int m_skipped = 0;
  int m_pending = 0;
};

}  // namespace sc::spectral::detail
