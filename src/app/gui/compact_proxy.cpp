#include "app/gui/compact_proxy.h"

#include "app/gui/vertex_normals.h"

#include <cassert>

namespace sc::app {

CompactProxy::CompactProxy(const Eigen::MatrixXi& triangles, int meshVertices) {
  m_compactOf.assign(static_cast<std::size_t>(meshVertices), -1);
  m_indices.resize(static_cast<std::size_t>(triangles.size()));
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (Eigen::Index c = 0; c < 3; ++c) {
      const auto v = static_cast<std::size_t>(triangles(t, c));
      if (m_compactOf[v] < 0) {
        m_compactOf[v] = static_cast<std::int32_t>(m_meshVertex.size());
        m_meshVertex.push_back(static_cast<std::uint32_t>(v));
      }
      m_indices[static_cast<std::size_t>(3 * t + c)] = static_cast<std::uint32_t>(m_compactOf[v]);
    }
  }
  m_positions.assign(3 * m_meshVertex.size(), 0.0f);
  m_normals.assign(3 * m_meshVertex.size(), 0.0f);
  m_tints.assign(4 * m_meshVertex.size(), 0);
}

void CompactProxy::gatherPositions(std::span<const float> meshXyz) {
  assert(meshXyz.size() == 3 * m_compactOf.size() && "gatherPositions needs 3 floats per mesh vertex");
  for (std::size_t i = 0; i < m_meshVertex.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      m_positions[3 * i + k] = meshXyz[3 * m_meshVertex[i] + k];
    }
  }
}

void CompactProxy::gatherTints(std::span<const std::uint8_t> meshRgba) {
  assert(meshRgba.size() == 4 * m_compactOf.size() && "gatherTints needs 4 bytes per mesh vertex");
  for (std::size_t i = 0; i < m_meshVertex.size(); ++i) {
    for (std::size_t k = 0; k < 4; ++k) {
      m_tints[4 * i + k] = meshRgba[4 * m_meshVertex[i] + k];
    }
  }
}

void CompactProxy::setBasis(const spectral::QuantizedBasis& K, std::span<const float> rest) {
  assert(static_cast<std::size_t>(K.rows()) == m_compactOf.size() && rest.size() == 3 * m_compactOf.size() &&
         "setBasis needs the mesh's K and rest positions");
  m_basis = K.gathered(m_meshVertex);
  m_rest.resize(3 * m_meshVertex.size());
  for (std::size_t i = 0; i < m_meshVertex.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      m_rest[3 * i + k] = rest[3 * m_meshVertex[i] + k];
    }
  }
}

void CompactProxy::clearBasis() {
  m_basis = {};
  m_rest.clear();
}

void CompactProxy::reconstruct(const Eigen::MatrixXf& Z) {
  assert(hasBasis() && Z.rows() == m_basis.cols() && Z.cols() == 3 && "reconstruct needs setBasis()'s m' by 3 Z");
  spectral::reconstructInterleaved(m_basis, m_rest, Z, m_positions);
}

void CompactProxy::updateNormals() { vertexNormals(m_positions, m_indices, m_normals); }

}  // namespace sc::app
