#pragma once
// CompactProxy: the interactive proxy of a dense mesh (MeshViewport::setInteractiveProxy) as a small mesh of its
// own, so that a frame of a moving shape touches only the proxy's vertices: their positions are gathered from the
// mesh, or reconstructed by the spectral kernel on their rows of the basis, and their normals come from the proxy's
// triangles.

#include "spectral/reconstruction_kernel.h"

#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <vector>

namespace sc::app {

/// The vertices a proxy's triangles use, renumbered 0…#P−1 in order of first use (neighbouring triangles get
/// neighbouring numbers), with per-vertex positions, normals and tints ready for a vertex buffer. A
/// default-constructed CompactProxy is empty.
class CompactProxy {
 public:
  CompactProxy() = default;
  /// @param[in] triangles  #T by 3 indices into a mesh of `meshVertices` vertices, all in [0, meshVertices)
  ///            (the caller checks). Positions, normals and tints start at zero.
  /// Cost: O(#T + meshVertices).
  CompactProxy(const Eigen::MatrixXi& triangles, int meshVertices);

  [[nodiscard]] bool empty() const { return m_indices.empty(); }
  /// Vertices of the proxy (#P).
  [[nodiscard]] int vertexCount() const { return static_cast<int>(m_meshVertex.size()); }
  /// Whether mesh vertex v is one of the proxy's (v in [0, meshVertices); false for an empty proxy).
  [[nodiscard]] bool uses(int v) const {
    return v >= 0 && static_cast<std::size_t>(v) < m_compactOf.size() && m_compactOf[static_cast<std::size_t>(v)] >= 0;
  }
  /// 3·#T indices into the proxy's vertices, the triangles in their given order and orientation.
  [[nodiscard]] const std::vector<std::uint32_t>& indices() const { return m_indices; }
  /// 3·#P floats each, x y z per proxy vertex.
  [[nodiscard]] const std::vector<float>& positions() const { return m_positions; }
  [[nodiscard]] const std::vector<float>& normals() const { return m_normals; }
  /// 4·#P bytes, RGBA per proxy vertex.
  [[nodiscard]] const std::vector<std::uint8_t>& tints() const { return m_tints; }

  /// Positions of the proxy's vertices from the mesh's (normals: updateNormals()).
  /// @param[in] meshXyz  3·meshVertices floats. Cost: O(#P).
  void gatherPositions(std::span<const float> meshXyz);
  /// Area-weighted vertex normals (vertexNormals()) of the current positions over the proxy's triangles.
  /// Cost: O(#P + #T).
  void updateNormals();
  /// Tints of the proxy's vertices from the mesh's. @param[in] meshRgba 4·meshVertices bytes. Cost: O(#P).
  void gatherTints(std::span<const std::uint8_t> meshRgba);

  /// Positions X̂' + K·Z of the proxy's vertices: the spectral kernel on their rows of the mesh's K, read in place
  /// (spectral::reconstructRowsInterleaved; no copy of K is kept). Normals: updateNormals().
  /// @param[in] K  meshVertices by m basis (e.g. the shown level's). @param[in] rest  3·meshVertices floats.
  /// @param[in] Z  m by 3 (asserted).
  /// Cost: O(#P·m): a tenth of the mesh's reconstruction for the 20k-triangle proxy (10k vertices) of the 100k
  /// dragon.
  void reconstruct(const spectral::RowMatrixXf& K, std::span<const float> rest, const Eigen::MatrixXf& Z);

 private:
  std::vector<std::int32_t> m_compactOf;    // per mesh vertex: its proxy number, or −1
  std::vector<std::uint32_t> m_meshVertex;  // per proxy vertex: its mesh vertex
  std::vector<std::uint32_t> m_indices;
  std::vector<float> m_positions;
  std::vector<float> m_normals;
  std::vector<std::uint8_t> m_tints;
};

}  // namespace sc::app
