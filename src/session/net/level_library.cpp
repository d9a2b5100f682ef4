#include "session/net/level_library.h"

#include "session/wire/level_codec.h"
#include "session/wire/model_transfer.h"
#include "spectral/resolution_level.h"

#include <QtCore/QMetaObject>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <utility>

namespace sc::session {

namespace {

std::uint32_t vertexCount(const HostModel& model) { return static_cast<std::uint32_t>(model.vertexCount()); }

}  // namespace

LevelLibrary::LevelLibrary(std::shared_ptr<const HostModel> model, LevelBuilder builder, QObject* parent)
    : QObject(parent),
      m_model(std::move(model)),
      m_builder(std::move(builder)),
      m_ladder(vertexCount(*m_model), m_builder.targetsFor(vertexCount(*m_model))) {}

LevelLibrary::~LevelLibrary() {
  if (m_worker.joinable()) m_worker.join();
}

const LevelLibrary::Level* LevelLibrary::find(std::uint32_t target) const {
  const auto it = m_levels.find(target);
  return it == m_levels.end() ? nullptr : &it->second;
}

void LevelLibrary::request(std::uint32_t target) {
  if (m_levels.contains(target) || m_failed.contains(target) || m_building == target ||
      std::find(m_queue.begin(), m_queue.end(), target) != m_queue.end()) {
    return;
  }
  std::erase(m_prefetch, target);  // explicitly wanted now: ahead of the prefetch
  m_queue.push_back(target);
  startNext();
}

void LevelLibrary::prefetchAll() {
  // The smallest rung first (also a progressive join's preview, issue 17 item 4), the full model last: the first
  // prefetch starts at the first Welcome, before that client's ResolutionRequest arrives, and whatever it asks for
  // waits for the build under way. The smallest build is the shortest wait (437k scan: 5% level 7.6 s against the full
  // model's 27 s, which a 5% joiner waited for when the full model came first).
  std::vector<std::uint32_t> rungs(ladder().rbegin(), ladder().rend());  // ladder(): descending
  rungs.push_back(fullTarget());
  for (const std::uint32_t target : rungs) {
    if (m_levels.contains(target) || m_failed.contains(target) || m_building == target ||
        std::find(m_queue.begin(), m_queue.end(), target) != m_queue.end() ||
        std::find(m_prefetch.begin(), m_prefetch.end(), target) != m_prefetch.end()) {
      continue;
    }
    m_prefetch.push_back(target);
  }
  startNext();
}

LevelFigures LevelLibrary::figures(const Level& level) {
  return {level.vertexCount, level.faceCount, static_cast<std::uint32_t>(level.payload.size())};
}

void LevelLibrary::startNext() {
  if (m_building || (m_queue.empty() && m_prefetch.empty())) return;
  if (m_worker.joinable()) m_worker.join();  // the previous build already handed its result back
  std::deque<std::uint32_t>& from = m_queue.empty() ? m_prefetch : m_queue;
  m_building = from.front();
  from.pop_front();
  m_worker = std::thread([this, model = m_model, target = *m_building, full = fullTarget()] {
    auto result = std::make_shared<BuildResult>(build(*model, m_builder, target, full));
    QMetaObject::invokeMethod(
        this, [this, target, result] { finishBuild(target, result); }, Qt::QueuedConnection);
  });
}

void LevelLibrary::finishBuild(std::uint32_t target, const std::shared_ptr<BuildResult>& result) {
  m_building.reset();
  if (result->level) {
    m_ladder.setBuilt(target, figures(*result->level));
    m_levels.emplace(target, std::move(*result->level));
    emit levelReady(target);
  } else {
    m_ladder.setFailed(target);
    m_failed.emplace(target, result->error);
    emit levelFailed(target, result->error);
  }
  startNext();
}

LevelLibrary::BuildResult LevelLibrary::build(const HostModel& model, const LevelBuilder& builder, std::uint32_t target,
                                              std::uint32_t full) {
  BuildResult result;
  const auto started = std::chrono::steady_clock::now();
  try {
    spectral::ResolutionLevel level;
    Level out;
    out.target = target;
    if (target >= full) {
      level = spectral::fullResolutionLevel(model.V, model.F, model.basis.vectors);
      out.kind = TransferKind::FullModel;
    } else {
      if (builder.empty()) {
        result.error = QStringLiteral("no level builder for %1 vertices").arg(target);
        return result;
      }
      level = builder.build(model.V, model.F, model.basis.vectors, target);
      if (level.restV.rows() < 3 || level.F.rows() < 1) {
        result.error = QStringLiteral("the level for %1 vertices has no mesh").arg(target);
        return result;
      }
      out.kind = TransferKind::Level;
    }
    out.vertexCount = static_cast<std::uint32_t>(level.restV.rows());
    out.faceCount = static_cast<std::uint32_t>(level.F.rows());
    const std::vector<std::byte> bytes = spectral::encodeResolutionLevel(level);
    if (bytes.empty() || bytes.size() > kMaxTransferSize) {
      result.error = QStringLiteral("level of %1 vertices encodes to %2 bytes (limit %3)")
                         .arg(out.vertexCount)
                         .arg(bytes.size())
                         .arg(kMaxTransferSize);
      return result;
    }
    const QByteArray canonical(reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size()));
    out.sha256 = sha256(canonical);  // once per level, here rather than per transfer on the network thread
    // Sent compressed (level_codec.h) unless that is no smaller (a level of a few vertices); the SHA-256 is the
    // canonical payload's either way.
    QByteArray compressed = compressLevelPayload(canonical);
    out.payload = !compressed.isEmpty() && compressed.size() < canonical.size() ? std::move(compressed) : canonical;
    out.buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    result.level = std::move(out);
  } catch (const std::exception& e) {
    result.error = QStringLiteral("building the level for %1 vertices failed: %2").arg(target).arg(e.what());
  }
  return result;
}

}  // namespace sc::session
