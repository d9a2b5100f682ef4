#pragma once
// ViewportBuffers: MeshViewport's vertex data, host side and GL side, with one dirty mask (Polyscope's
// ManagedBuffer habit): whoever writes a host array marks its bit (the write*() accessors do it), and upload(), in
// paintGL(), sends exactly what is marked. No other class of the viewport holds a GL buffer of vertex data. The
// positions, normals, rest positions and triangles of a shown display level are the level's own arrays
// (shareLevel(): SharedArray, no copy on the GUI thread) until a frame writes new positions or normals.

#include "app/gui/compact_proxy.h"
#include "app/gui/viewport/shared_array.h"
#include "spectral/display_level.h"
#include "spectral/resolution_level.h"

#include <QOpenGLBuffer>
#include <QOpenGLVertexArrayObject>

#include <cstdint>
#include <span>
#include <vector>

class QOpenGLFunctions_3_3_Core;

namespace sc::app {

class ViewportBuffers {
 public:
  /// The dirty mask: one bit per GL buffer (group) whose host data changed since its last upload.
  enum Bit : unsigned {
    kPositions = 1U << 0,
    kNormals = 1U << 1,
    kTints = 1U << 2,
    kIndices = 1U << 3,        ///< the mesh's triangles, then the proxy's over mesh vertices (the GPU path's)
    kProxyVertices = 1U << 4,  ///< the compact proxy's positions and normals
    kProxyTints = 1U << 5,     ///< the compact proxy's tints
    kProxyIndices = 1U << 6,   ///< the compact proxy's triangles
    kRest = 1U << 7,           ///< the GPU path's rest positions
    kBasis = 1U << 8,          ///< the GPU path's K texture: uploaded only when upload() is given K
    kAll = (1U << 9) - 1,
  };

  // === host side. Positions are relative to the viewport's origin (MeshViewport::setMesh()).
  [[nodiscard]] std::span<const float> positions() const { return m_positions.view(); }      ///< 3·#V
  [[nodiscard]] std::span<const float> normals() const { return m_normals.view(); }          ///< 3·#V
  [[nodiscard]] const std::vector<std::uint8_t>& tints() const { return m_tints; }           ///< 4·#V, RGBA
  [[nodiscard]] std::span<const std::uint32_t> indices() const { return m_indices.view(); }  ///< 3·#F
  /// 3·#P indices into the mesh's vertices: the proxy's triangles as the GPU path draws them.
  [[nodiscard]] const std::vector<std::uint32_t>& proxyIndices() const { return m_proxyIndices; }
  /// The proxy's own vertices, for the CPU path (empty: no proxy).
  [[nodiscard]] const CompactProxy& proxy() const { return m_proxy; }
  /// 3·#V rest positions of a shown display level (relative to the origin; empty for a plain mesh).
  [[nodiscard]] std::span<const float> rest() const { return m_rest.view(); }
  /// Whether positions, normals and indices are a shared level's arrays (shareLevel(); no write since).
  [[nodiscard]] bool sharesLevel() const { return m_positions.shared() && m_normals.shared() && m_indices.shared(); }

  /// Write access for a write that sets every entry (resize, then fill): a shared level's array is let go, not
  /// copied (SharedArray::own()).
  std::vector<float>& writePositions() { return marked(kPositions, m_positions).own(); }
  std::vector<float>& writeNormals() { return marked(kNormals, m_normals).own(); }
  std::vector<std::uint8_t>& writeTints() { return marked(kTints, m_tints); }
  std::vector<float>& writeRest() { return marked(kRest, m_rest).own(); }
  /// Shows `level`'s geometry (spectral::DisplayGeometry, non-empty) without copying: positions are its rest
  /// positions, normals its rest normals, indices its faces, and with `rest` the GPU path's rest positions too; they
  /// hold the level until written. Drops the proxy and marks them for upload. Cost: O(1) (frees the own arrays).
  void shareLevel(const spectral::SharedDisplayLevel& level, bool rest);
  /// The proxy, for new positions or normals (marks kProxyVertices).
  CompactProxy& writeProxyVertices() { return marked(kProxyVertices, m_proxy); }
  /// The proxy's tints gathered from tints() (no proxy: nothing). Cost: O(#P).
  void gatherProxyTints();
  /// Replaces the mesh's triangles (3·#F) and drops the proxy.
  void setIndices(std::vector<std::uint32_t> indices);
  /// Replaces the proxy: `proxy` its compact vertices, `meshIndices` the same triangles over the mesh's vertices.
  void setProxy(CompactProxy proxy, std::vector<std::uint32_t> meshIndices);
  void mark(unsigned bits) { addDirty(bits); }
  [[nodiscard]] bool isMarked(unsigned bits) const { return (m_dirty & bits) != 0; }
  /// Versions of the host data a picture of the whole mesh is drawn from (ProgressivePicture's key), bumped by every
  /// mark of it, whether or not uploaded since: vertexVersion() the positions and normals (what the CPU path draws),
  /// sharedVersion() the triangles, rest positions and K, tintVersion() the tints (what both paths draw). Writes of
  /// the proxy alone, and its triangles appended to the index buffer, bump none.
  [[nodiscard]] unsigned vertexVersion() const { return m_vertexVersion; }
  [[nodiscard]] unsigned sharedVersion() const { return m_sharedVersion; }
  [[nodiscard]] unsigned tintVersion() const { return m_tintVersion; }
  /// Empties every host array (marks everything).
  void clear();

  // === GL side: between create() and destroy(), with the context current.
  /// Creates the vertex arrays (mesh, compact proxy, GPU path) and buffers; `basisTexture`: also the texture buffer
  /// of K (when the GPU path's program exists). Marks everything for upload (a new context has empty buffers).
  void create(QOpenGLFunctions_3_3_Core& gl, bool basisTexture);
  void destroy(QOpenGLFunctions_3_3_Core& gl);
  /// Uploads what is marked and clears those bits. `K` (n' by m, the shown level's, read in place): its int16
  /// entries Q, padded to 4·⌈m/4⌉ columns while they are written into the GL buffer (no host copy; the scales are
  /// folded into the shader's Z, ShownLevel::scaledZ()); nullptr leaves kBasis marked.
  void upload(QOpenGLFunctions_3_3_Core& gl, const spectral::QuantizedBasis* K);
  QOpenGLVertexArrayObject& meshVao() { return m_meshVao; }               ///< positions 0, normals 1, tints 2
  QOpenGLVertexArrayObject& proxyVao() { return m_proxyVao; }             ///< the compact proxy's, same layout
  QOpenGLVertexArrayObject& gpuVao() { return m_gpuVao; }                 ///< rest 0, tints 2, the mesh's indices
  [[nodiscard]] unsigned basisTexture() const { return m_basisTexture; }  ///< GL_RGBA16I view of K (0: none)
  /// A patch: some of the mesh's triangles (3·#T indices into its vertices) in an element buffer of their own, which
  /// a mesh pass draws instead of the mesh's (MeshPass::patch). Cost: one upload of them.
  void uploadPatch(std::span<const std::uint32_t> indices);
  [[nodiscard]] int patchTriangles() const { return m_patchTriangles; }
  /// With the mesh's or the GPU path's vertex array bound: makes the patch its element buffer, or the mesh's again
  /// (the element array binding is the vertex array's state, so every bindPatch() needs its bindMeshTriangles()).
  void bindPatch(QOpenGLFunctions_3_3_Core& gl);
  void bindMeshTriangles() { m_indexBuffer.bind(); }

 private:
  template <typename T>
  T& marked(unsigned bit, T& value) {
    addDirty(bit);
    return value;
  }
  void addDirty(unsigned bits) {
    m_dirty |= bits;
    if ((bits & (kPositions | kNormals)) != 0) ++m_vertexVersion;
    if ((bits & (kIndices | kRest | kBasis)) != 0) ++m_sharedVersion;
    if ((bits & kTints) != 0) ++m_tintVersion;
  }
  void uploadBasis(QOpenGLFunctions_3_3_Core& gl, const spectral::QuantizedBasis& K);

  unsigned m_dirty = kAll;
  unsigned m_vertexVersion = 0;
  unsigned m_sharedVersion = 0;
  unsigned m_tintVersion = 0;
  SharedArray<float> m_positions;
  SharedArray<float> m_normals;
  std::vector<std::uint8_t> m_tints;
  SharedArray<std::uint32_t> m_indices;
  std::vector<std::uint32_t> m_proxyIndices;
  CompactProxy m_proxy;
  SharedArray<float> m_rest;

  QOpenGLVertexArrayObject m_meshVao;
  QOpenGLVertexArrayObject m_proxyVao;
  QOpenGLVertexArrayObject m_gpuVao;
  QOpenGLBuffer m_positionBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_normalBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_tintBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_indexBuffer{QOpenGLBuffer::IndexBuffer};
  QOpenGLBuffer m_proxyPositionBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_proxyNormalBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_proxyTintBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_proxyIndexBuffer{QOpenGLBuffer::IndexBuffer};
  QOpenGLBuffer m_restBuffer{QOpenGLBuffer::VertexBuffer};
  QOpenGLBuffer m_patchBuffer{QOpenGLBuffer::VertexBuffer};  // written as an array buffer: no vertex array's state
  int m_patchTriangles = 0;
  unsigned m_basisBuffer = 0;   // GL_TEXTURE_BUFFER storage of K
  unsigned m_basisTexture = 0;  // GL_RGBA16I view of it
};

}  // namespace sc::app
