#include "app/cli/level_output.h"

#include "model/mesh_decimation.h"
#include "spectral/hausdorff.h"
#include "spectral/reconstruction_kernel.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <thread>

namespace sc::app {

std::optional<int> levelVertexTarget(int level, int vertexCount) {
  assert(level >= 0 && "--level is validated by the caller");
  if (level == 0) return std::nullopt;
  const std::vector<int> ladder = model::levelTargets(vertexCount);
  if (level <= static_cast<int>(ladder.size())) return ladder[static_cast<std::size_t>(level - 1)];
  return level;
}

LevelOutput::LevelOutput(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::MatrixXd& H, int level,
                         int targetVertices)
    : m_levelArgument(level) {
  // === decimate the rest mesh, then P and K = P·H (closest points on every core)
  const auto start = std::chrono::steady_clock::now();
  const model::DecimatedMesh low = model::decimateMesh(V, F, std::max(3, targetVertices));
  const int threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  m_level = spectral::resolutionLevel(V, F, H, low.V, low.F, threads);
  m_buildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // === client buffers: the rest positions, and the output starting at rest
  m_rest = spectral::interleavedPositions(m_level.restV);
  m_out = m_rest;
  m_Z.resize(H.cols(), 3);
}

void LevelOutput::frame(const Eigen::MatrixXd& Z) {
  m_Z = Z.cast<float>();
  const auto start = std::chrono::steady_clock::now();
  spectral::reconstructInterleaved(m_level.K, m_rest, m_Z, m_out, 1);
  m_frameUs.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
}

Eigen::MatrixXd LevelOutput::positions() const {
  const Eigen::Index n = m_level.restV.rows();
  return Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>>(m_out.data(), n, 3).cast<double>();
}

QJsonObject LevelOutput::report(const Eigen::MatrixXd& X, double diagonal) const {
  double medianUs = 0.0;
  if (!m_frameUs.empty()) {
    std::vector<double> us = m_frameUs;
    std::nth_element(us.begin(), us.begin() + static_cast<std::ptrdiff_t>(us.size() / 2), us.end());
    medianUs = us[us.size() / 2];
  }
  const Eigen::MatrixXd mapped = m_level.P * X;
  const double hausdorff = spectral::hausdorffDistance(positions(), mapped).value;
  return {{QStringLiteral("level"), m_levelArgument},
          {QStringLiteral("level_vertices"), static_cast<qint64>(m_level.restV.rows())},
          {QStringLiteral("level_triangles"), static_cast<qint64>(m_level.F.rows())},
          {QStringLiteral("level_build_s"), m_buildSeconds},
          {QStringLiteral("client_frame_us"), medianUs},
          {QStringLiteral("hausdorff_pct"), spectral::percentOfDiagonal(hausdorff, diagonal)}};
}

}  // namespace sc::app
