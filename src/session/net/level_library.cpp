#include "session/net/level_library.h"

#include "model/mesh_decimation.h"
#include "session/wire/model_transfer.h"
#include "spectral/resolution_level.h"

#include <QtCore/QMetaObject>

#include <algorithm>
#include <cstdlib>
#include <exception>

namespace sc::session {

LevelLibrary::LevelLibrary(std::shared_ptr<const HostModel> model, QObject* parent)
    : QObject(parent), m_model(std::move(model)) {
  m_full = static_cast<std::uint32_t>(m_model->vertexCount());
  for (const int target : model::levelTargets(m_model->vertexCount())) {
    const auto t = static_cast<std::uint32_t>(target);
    if (t < m_full && std::find(m_ladder.begin(), m_ladder.end(), t) == m_ladder.end()) m_ladder.push_back(t);
  }
  std::sort(m_ladder.begin(), m_ladder.end(), std::greater<>());
}

LevelLibrary::~LevelLibrary() {
  if (m_worker.joinable()) m_worker.join();
}

std::uint32_t LevelLibrary::pick(std::uint32_t wanted) const {
  if (wanted == 0 || wanted >= m_full || m_ladder.empty()) return m_full;
  const auto count = [this](std::uint32_t target) {
    const Level* level = find(target);
    return level ? level->vertexCount : target;
  };
  const auto distance = [wanted](std::uint32_t v) { return v > wanted ? v - wanted : wanted - v; };
  std::uint32_t best = m_ladder.front();
  for (const std::uint32_t t : m_ladder) {
    const std::uint32_t d = distance(count(t)), bestD = distance(count(best));
    if (d < bestD || (d == bestD && count(t) > count(best))) best = t;
  }
  return best;
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
  std::vector<std::uint32_t> rungs{m_full};
  rungs.insert(rungs.end(), m_ladder.begin(), m_ladder.end());
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

LevelList LevelLibrary::levelList() const {
  LevelList list;
  list.total = static_cast<std::uint8_t>(std::min<std::size_t>(m_ladder.size() + 1, kMaxLevels));
  for (std::size_t i = 0; i < list.total; ++i) {
    const Level* level = find(i == 0 ? m_full : m_ladder[i - 1]);
    if (level == nullptr) continue;
    list.levels.push_back(LevelInfo{static_cast<std::uint8_t>(i), level->vertexCount, level->faceCount,
                                    static_cast<std::uint32_t>(level->payload.size())});
  }
  return list;
}

void LevelLibrary::startNext() {
  if (m_building || (m_queue.empty() && m_prefetch.empty())) return;
  if (m_worker.joinable()) m_worker.join();  // the previous build already handed its result back
  std::deque<std::uint32_t>& from = m_queue.empty() ? m_prefetch : m_queue;
  m_building = from.front();
  from.pop_front();
  m_worker = std::thread([this, model = m_model, target = *m_building, full = m_full] {
    auto result = std::make_shared<BuildResult>(build(*model, target, full));
    QMetaObject::invokeMethod(
        this, [this, target, result] { finishBuild(target, result); }, Qt::QueuedConnection);
  });
}

void LevelLibrary::finishBuild(std::uint32_t target, const std::shared_ptr<BuildResult>& result) {
  m_building.reset();
  if (result->level) {
    m_levels.emplace(target, std::move(*result->level));
    emit levelReady(target);
  } else {
    m_failed.emplace(target, result->error);
    emit levelFailed(target, result->error);
  }
  startNext();
}

LevelLibrary::BuildResult LevelLibrary::build(const HostModel& model, std::uint32_t target, std::uint32_t full) {
  BuildResult result;
  try {
    spectral::ResolutionLevel level;
    Level out;
    out.target = target;
    if (target >= full) {
      level = spectral::fullResolutionLevel(model.V, model.F, model.basis.vectors);
      out.kind = TransferKind::FullModel;
    } else {
      const model::DecimatedMesh low = model::decimateMesh(model.V, model.F, static_cast<int>(target));
      if (low.V.rows() < 3 || low.F.rows() < 1) {
        result.error = QStringLiteral("decimation to %1 vertices left no mesh").arg(target);
        return result;
      }
      level = spectral::resolutionLevel(model.V, model.F, model.basis.vectors, low.V, low.F);
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
    out.payload = QByteArray(reinterpret_cast<const char*>(bytes.data()), static_cast<qsizetype>(bytes.size()));
    out.sha256 = sha256(out.payload);  // once per level, here rather than per transfer on the network thread
    result.level = std::move(out);
  } catch (const std::exception& e) {
    result.error = QStringLiteral("building the level for %1 vertices failed: %2").arg(target).arg(e.what());
  }
  return result;
}

}  // namespace sc::session
