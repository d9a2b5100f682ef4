#pragma once
// The host's resolution ladder as figures (docs/protocol.md, "Levels"): the full model (target n) and the rungs
// (targets < n, largest first), which of them are built (their exact vertex, face and payload sizes) and which
// failed. Pure bookkeeping shared by the HostEngine (which picks and lists levels) and the LevelLibrary (which builds
// and caches the payloads): no threads, no payloads. Level id 0 is the full model, id i the rung ladder()[i − 1].
// Cost: O(ladder) per call unless stated. Not thread-safe.

#include "session/wire/control_messages.h"

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <vector>

namespace sc::session {

/// One built level's figures.
struct LevelFigures {
  std::uint32_t vertexCount = 0;  ///< the level's actual vertex count n' (decimation may miss the target)
  std::uint32_t faceCount = 0;
  std::uint32_t payloadSize = 0;  ///< bytes of its encoded transfer payload
};

class LevelLadder {
 public:
  /// @param full     n, the full model's vertex count (its target).
  /// @param targets  the rungs' targets: any order; duplicates and values ≥ n are dropped.
  LevelLadder(std::uint32_t full, const std::vector<std::uint32_t>& targets);

  /// The target serving a request for `wanted` vertices: n for 0 or wanted ≥ n (or no rung), otherwise the rung
  /// closest to `wanted` (ties: the larger), a rung counting as its built level's exact vertex count once built and
  /// as its target before; so a request for a vertex count from levelList() gets exactly that level.
  [[nodiscard]] std::uint32_t pick(std::uint32_t wanted) const;

  /// The built level's figures, or nullptr while `target` is not built (or failed). Cost: O(log ladder).
  [[nodiscard]] const LevelFigures* find(std::uint32_t target) const;
  [[nodiscard]] bool failed(std::uint32_t target) const { return m_failed.contains(target); }

  void setBuilt(std::uint32_t target, LevelFigures figures) { m_built.insert_or_assign(target, figures); }
  void setFailed(std::uint32_t target) { m_failed.insert(target); }

  /// The built levels as a LevelList (total = ladder size + 1), ids ascending; a failed level stays unlisted.
  [[nodiscard]] LevelList levelList() const;

  /// The rungs' targets (excluding the full model), largest first.
  [[nodiscard]] const std::vector<std::uint32_t>& ladder() const { return m_ladder; }
  [[nodiscard]] std::uint32_t fullTarget() const { return m_full; }

 private:
  std::uint32_t m_full = 0;
  std::vector<std::uint32_t> m_ladder;
  std::map<std::uint32_t, LevelFigures> m_built;
  std::set<std::uint32_t> m_failed;
};

}  // namespace sc::session
