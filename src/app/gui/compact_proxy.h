#pragma once
// CompactProxy: the interactive proxy of a dense mesh (MeshViewport::setInteractiveProxy) as a small mesh of its
// own, so that a frame of a moving shape touches only the proxy's vertices: their positions are gathered from the
// mesh, or reconstructed from their rows of the basis, and their normals come from the proxy's triangles.

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

  /// Keeps the proxy's rows of K and of the rest positions for reconstruct(). The one partial copy of a shown
  /// level's K (#P of its rows, a tenth for the 100k dragon): the kernel on these contiguous rows takes 0.6 ms per
  /// frame where the same rows read in place, scattered over K, take 3.3 ms (shapecast-bench-viewport, llvmpipe VM).
  /// @param[in] K  meshVertices by m' quantised basis (the level's; its rows are copied as int16).
  /// @param[in] rest  3·meshVertices floats. Cost: O(#P·m') time and memory.
  void setBasis(const spectral::QuantizedBasis& K, std::span<const float> rest);
  void clearBasis();
  [[nodiscard]] bool hasBasis() const { return m_basis.cols() > 0; }
  /// Positions rest + K·Z of the proxy's vertices (spectral::reconstructInterleaved on its rows; normals:
  /// updateNormals()).
  /// @param[in] Z  m' by 3, m' = setBasis()'s K columns (asserted). Needs hasBasis().
  /// Cost: O(#P·m'): a tenth of the mesh's reconstruction for the 20k-triangle proxy (10k vertices) of the 100k
  /// dragon.
  void reconstruct(const Eigen::MatrixXf& Z);

 private:
  std::vector<std::int32_t> m_compactOf;    // per mesh vertex: its proxy number, or −1
  std::vector<std::uint32_t> m_meshVertex;  // per proxy vertex: its mesh vertex
  std::vector<std::uint32_t> m_indices;
  std::vector<float> m_positions;
  std::vector<float> m_normals;
  std::vector<std::uint8_t> m_tints;
  spectral::QuantizedBasis m_basis;  // #P by m'
  std::vector<float> m_rest;         // 3·#P
};

}  // namespace sc::app
