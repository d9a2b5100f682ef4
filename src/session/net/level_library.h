#pragma once
// The host's resolution ladder (docs/protocol.md, "Levels"): the full model and, built on demand, the display
// levels for the LevelBuilder's targets (level_builder.h; model::levelTargetList: 50%, 20%, 5% of n),
// each cached with its encoded payload (spectral::encodeResolutionLevel), which is what a ModelBegin/ModelChunk
// transfer carries. The figures (pick, levelList) are a LevelLadder's (engine/level_ladder.h).
//
// Threading contract: a LevelLibrary lives on one thread (the host's network thread). Building a level
// (LevelBuilder::build, e.g. decimation + barycentric map + K = P·H, or fullResolutionLevel for the full model;
// then its encoding and the payload's SHA-256) runs on ONE worker std::thread at a time (decimation is not
// thread-safe with other OpenMesh users), never on the owner's thread: the owner only hands out the cached payload and
// digest (ModelSender's precomputed-digest constructor), so no transfer encodes or hashes on the network thread. The
// result is handed back through a queued call, so levelReady()/levelFailed() are emitted on the owner's thread. The
// destructor joins a running build (it waits for it to finish). Each target is built at most once; a failure is cached
// too. Explicit request()s are built first (in order); prefetchAll() queues the rest of the ladder behind them
// (smallest first, the full model last), so that levelList() soon holds every level's exact figures (the LevelList
// message).

#include "session/engine/host_model.h"
#include "session/engine/level_builder.h"
#include "session/engine/level_ladder.h"
#include "session/wire/control_messages.h"

#include <QtCore/QByteArray>
#include <QtCore/QObject>
#include <QtCore/QString>

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

namespace sc::session {

class LevelLibrary final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(LevelLibrary)

 public:
  /// One built level, ready to be transferred.
  struct Level {
    std::uint32_t target = 0;       ///< the ladder target (n for the full model)
    std::uint32_t vertexCount = 0;  ///< the level's actual vertex count n' (decimation may miss the target)
    std::uint32_t faceCount = 0;    ///< the level's face count
    TransferKind kind = TransferKind::FullModel;
    QByteArray payload;         ///< encodeResolutionLevel() bytes, 1..kMaxTransferSize
    QByteArray sha256;          ///< sha256(payload), computed once on the worker (ModelBegin::sha256 of every transfer)
    double buildSeconds = 0.0;  ///< wall time of the worker's build, encoding, hashing and compression
  };

  /// @param model    non-null, with #V ≥ 3 and a basis of #V rows.
  /// @param builder  the ladder's targets and level builder; empty: the full model only.
  LevelLibrary(std::shared_ptr<const HostModel> model, LevelBuilder builder, QObject* parent = nullptr);
  ~LevelLibrary() override;

  /// The target serving a request for `wanted` vertices: n (the full model) for 0 or wanted ≥ n, otherwise the
  /// rung closest to `wanted` (ties: the larger), a rung counting as its built level's exact vertex count once
  /// built and as its target before; so a request for a vertex count from levelList() gets exactly that level.
  /// Cost: O(ladder · log ladder).
  [[nodiscard]] std::uint32_t pick(std::uint32_t wanted) const { return m_ladder.pick(wanted); }

  /// The built level for `target`, or nullptr while it is not built (or failed).
  [[nodiscard]] const Level* find(std::uint32_t target) const;

  /// Queues `target` for building unless it is built, building, queued or failed. When the build ends,
  /// levelReady(target) or levelFailed(target, reason) is emitted (later, never from inside this call).
  /// `target` must come from pick().
  void request(std::uint32_t target);

  /// Queues every rung not built, building, queued or failed (the smallest rung first: a progressive join's
  /// preview; then the full model, then largest first) behind the explicit requests; levelReady() follows for each
  /// as above. Cost: O(ladder).
  void prefetchAll();

  /// The built levels as a LevelList (level id 0 = full, i = ladder()[i − 1], total = ladder size + 1), ids
  /// ascending; a failed level stays unlisted (so such a list never becomes complete()). Cost: O(ladder).
  [[nodiscard]] LevelList levelList() const { return m_ladder.levelList(); }

  /// The ladder targets (excluding the full model), largest first.
  [[nodiscard]] const std::vector<std::uint32_t>& ladder() const { return m_ladder.ladder(); }
  [[nodiscard]] std::uint32_t fullTarget() const { return m_ladder.fullTarget(); }
  /// The smallest rung's target (what pick(1) serves before any level is built), the full model without a ladder.
  [[nodiscard]] std::uint32_t smallestTarget() const { return ladder().empty() ? fullTarget() : ladder().back(); }
  /// The figures of a built level (what HostEngine::onLevelReady() takes).
  [[nodiscard]] static LevelFigures figures(const Level& level);

 signals:
  void levelReady(std::uint32_t target);
  void levelFailed(std::uint32_t target, const QString& reason);

 private:
  struct BuildResult {
    std::optional<Level> level;
    QString error;
  };
  /// Runs on the worker thread: builds, encodes and hashes one level. Never throws.
  static BuildResult build(const HostModel& model, const LevelBuilder& builder, std::uint32_t target,
                           std::uint32_t full);
  void startNext();
  void finishBuild(std::uint32_t target, const std::shared_ptr<BuildResult>& result);

  std::shared_ptr<const HostModel> m_model;
  LevelBuilder m_builder;
  LevelLadder m_ladder;
  std::map<std::uint32_t, Level> m_levels;
  std::map<std::uint32_t, QString> m_failed;
  std::deque<std::uint32_t> m_queue;     ///< explicit requests, built first
  std::deque<std::uint32_t> m_prefetch;  ///< prefetchAll(), built when m_queue is empty
  std::optional<std::uint32_t> m_building;
  std::thread m_worker;
};

}  // namespace sc::session
