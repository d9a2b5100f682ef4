#include "session/level_library.h"

#include "model/mesh_decimation.h"
#include "session/model_transfer.h"
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
  std::uint32_t best = m_ladder.front();
  for (const std::uint32_t t : m_ladder) {  // largest first: a tie keeps the larger
    const auto distance = [wanted](std::uint32_t v) { return v > wanted ? v - wanted : wanted - v; };
    if (distance(t) < distance(best)) best = t;
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
  m_queue.push_back(target);
  startNext();
}

void LevelLibrary::startNext() {
  if (m_building || m_queue.empty()) return;
  if (m_worker.joinable()) m_worker.join();  // the previous build already handed its result back
  m_building = m_queue.front();
  m_queue.pop_front();
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
