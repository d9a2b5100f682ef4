#include "app/gui/viewport/viewport_buffers.h"

#include <QOpenGLFunctions_3_3_Core>

#include <algorithm>
#include <cstring>
#include <span>

namespace sc::app {

namespace {

struct VertexBuffers {
  QOpenGLBuffer* positions;
  QOpenGLBuffer* normals;  // nullptr: no attribute 1 (the GPU path's VAO)
  QOpenGLBuffer* tints;
  QOpenGLBuffer* indices;
};

// Records in `vao` one buffer per attribute of the mesh programs (location 0 positions, 1 normals, 2 tints) and
// the index buffer binding. Creates the buffers not created yet (the GPU path's VAO shares tints and indices).
void recordVertexArray(QOpenGLFunctions_3_3_Core& gl, QOpenGLVertexArrayObject& vao, const VertexBuffers& buffers) {
  vao.create();
  QOpenGLVertexArrayObject::Binder vaoBinder(&vao);
  struct Attribute {
    QOpenGLBuffer* buffer;
    GLenum type;
    int size;
  };
  const Attribute attributes[] = {
      {buffers.positions, GL_FLOAT, 3}, {buffers.normals, GL_FLOAT, 3}, {buffers.tints, GL_UNSIGNED_BYTE, 4}};
  for (GLuint location = 0; location < 3; ++location) {
    const Attribute& a = attributes[location];
    if (a.buffer == nullptr) {
      continue;
    }
    if (!a.buffer->isCreated()) {
      a.buffer->create();
      a.buffer->setUsagePattern(location == 2 ? QOpenGLBuffer::StaticDraw : QOpenGLBuffer::DynamicDraw);
    }
    a.buffer->bind();
    gl.glEnableVertexAttribArray(location);
    gl.glVertexAttribPointer(location, a.size, a.type, a.type == GL_UNSIGNED_BYTE ? GL_TRUE : GL_FALSE, 0, nullptr);
    a.buffer->release();
  }
  if (!buffers.indices->isCreated()) {
    buffers.indices->create();
    buffers.indices->setUsagePattern(QOpenGLBuffer::StaticDraw);
  }
  buffers.indices->bind();  // VAO state
}

template <typename T>
void send(QOpenGLBuffer& buffer, std::span<const T> values) {
  buffer.bind();
  buffer.allocate(values.data(), static_cast<int>(values.size() * sizeof(T)));
  buffer.release();
}

int bytesOf(std::span<const std::uint32_t> v) { return static_cast<int>(v.size() * sizeof(std::uint32_t)); }

}  // namespace

void ViewportBuffers::gatherProxyTints() {
  if (!m_proxy.empty()) {
    m_proxy.gatherTints(m_tints);
    m_dirty |= kProxyTints;
  }
}

void ViewportBuffers::setIndices(std::vector<std::uint32_t> indices) {
  m_indices.own() = std::move(indices);
  setProxy(CompactProxy(), {});
  addDirty(kIndices);
}

void ViewportBuffers::shareLevel(const spectral::SharedDisplayLevel& level, bool rest) {
  const spectral::DisplayGeometry& g = level->geometry;
  m_positions.share(level, g.rest);
  m_normals.share(level, g.normals);
  m_indices.share(level, g.indices);
  if (rest) {
    m_rest.share(level, g.rest);
  } else {
    m_rest.own().clear();
  }
  setProxy(CompactProxy(), {});
  addDirty(kPositions | kNormals | kRest | kIndices);
}

void ViewportBuffers::setProxy(CompactProxy proxy, std::vector<std::uint32_t> meshIndices) {
  m_proxy = std::move(proxy);
  m_proxyIndices = std::move(meshIndices);
  m_dirty |= kIndices | kProxyVertices | kProxyTints | kProxyIndices;  // the mesh's own triangles are unchanged
}

void ViewportBuffers::clear() {
  m_positions.own().clear();
  m_normals.own().clear();
  m_tints.clear();
  m_rest.own().clear();
  setIndices({});
  addDirty(kAll);
}

void ViewportBuffers::create(QOpenGLFunctions_3_3_Core& gl, bool basisTexture) {
  recordVertexArray(gl, m_meshVao, {&m_positionBuffer, &m_normalBuffer, &m_tintBuffer, &m_indexBuffer});
  recordVertexArray(gl, m_proxyVao,
                    {&m_proxyPositionBuffer, &m_proxyNormalBuffer, &m_proxyTintBuffer, &m_proxyIndexBuffer});
  m_restBuffer.create();
  m_restBuffer.setUsagePattern(QOpenGLBuffer::StaticDraw);
  recordVertexArray(gl, m_gpuVao, {&m_restBuffer, nullptr, &m_tintBuffer, &m_indexBuffer});
  m_patchBuffer.create();
  m_patchBuffer.setUsagePattern(QOpenGLBuffer::StreamDraw);
  m_patchTriangles = 0;
  if (basisTexture) {
    gl.glGenBuffers(1, &m_basisBuffer);
    gl.glGenTextures(1, &m_basisTexture);
    gl.glBindBuffer(GL_TEXTURE_BUFFER, m_basisBuffer);
    gl.glBindTexture(GL_TEXTURE_BUFFER, m_basisTexture);
    gl.glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA16I, m_basisBuffer);
    gl.glBindTexture(GL_TEXTURE_BUFFER, 0);
    gl.glBindBuffer(GL_TEXTURE_BUFFER, 0);
  }
  addDirty(kAll);
}

void ViewportBuffers::destroy(QOpenGLFunctions_3_3_Core& gl) {
  for (QOpenGLBuffer* buffer :
       {&m_positionBuffer, &m_normalBuffer, &m_tintBuffer, &m_indexBuffer, &m_proxyPositionBuffer, &m_proxyNormalBuffer,
        &m_proxyTintBuffer, &m_proxyIndexBuffer, &m_restBuffer, &m_patchBuffer}) {
    buffer->destroy();
  }
  m_meshVao.destroy();
  m_proxyVao.destroy();
  m_gpuVao.destroy();
  if (m_basisTexture != 0) {
    gl.glDeleteTextures(1, &m_basisTexture);
  }
  if (m_basisBuffer != 0) {
    gl.glDeleteBuffers(1, &m_basisBuffer);
  }
  m_basisTexture = m_basisBuffer = 0;
}

void ViewportBuffers::upload(QOpenGLFunctions_3_3_Core& gl, const spectral::QuantizedBasis* K) {
  if (isMarked(kPositions)) send(m_positionBuffer, positions());
  if (isMarked(kNormals)) send(m_normalBuffer, normals());
  if (isMarked(kTints)) send<std::uint8_t>(m_tintBuffer, m_tints);
  if (isMarked(kProxyVertices)) {
    send<float>(m_proxyPositionBuffer, m_proxy.positions());
    send<float>(m_proxyNormalBuffer, m_proxy.normals());
  }
  if (isMarked(kProxyTints)) send<std::uint8_t>(m_proxyTintBuffer, m_proxy.tints());
  if (isMarked(kProxyIndices)) {
    QOpenGLVertexArrayObject::Binder vaoBinder(&m_proxyVao);
    m_proxyIndexBuffer.bind();  // stays bound: VAO state
    m_proxyIndexBuffer.allocate(m_proxy.indices().data(), bytesOf(m_proxy.indices()));
  }
  if (isMarked(kIndices)) {
    QOpenGLVertexArrayObject::Binder vaoBinder(&m_meshVao);
    m_indexBuffer.bind();  // stays bound: the element array binding is VAO state
    const std::span<const std::uint32_t> mesh = indices();
    m_indexBuffer.allocate(bytesOf(mesh) + bytesOf(m_proxyIndices));
    m_indexBuffer.write(0, mesh.data(), bytesOf(mesh));
    m_indexBuffer.write(bytesOf(mesh), m_proxyIndices.data(), bytesOf(m_proxyIndices));
  }
  if (isMarked(kRest)) send(m_restBuffer, rest());
  m_dirty &= kBasis;
  if (isMarked(kBasis) && K != nullptr && m_basisBuffer != 0) {
    uploadBasis(gl, *K);
    m_dirty = 0;
  }
}

void ViewportBuffers::uploadPatch(std::span<const std::uint32_t> indices) {
  m_patchBuffer.bind();
  m_patchBuffer.allocate(indices.data(), bytesOf(indices));
  m_patchBuffer.release();
  m_patchTriangles = static_cast<int>(indices.size() / 3);
}

void ViewportBuffers::bindPatch(QOpenGLFunctions_3_3_Core& gl) {
  gl.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_patchBuffer.bufferId());
}

// K's int16 entries padded to 4·⌈m/4⌉ columns of zeros (the texture's RGBA16I texels), written row by row into the
// mapped buffer.
void ViewportBuffers::uploadBasis(QOpenGLFunctions_3_3_Core& gl, const spectral::QuantizedBasis& K) {
  const auto m = static_cast<std::size_t>(K.cols());
  const std::size_t padded = 4 * ((m + 3) / 4);
  const auto bytes = static_cast<GLsizeiptr>(static_cast<std::size_t>(K.rows()) * padded * sizeof(std::int16_t));
  gl.glBindBuffer(GL_TEXTURE_BUFFER, m_basisBuffer);
  if (padded == m || bytes == 0) {
    gl.glBufferData(GL_TEXTURE_BUFFER, bytes, K.Q.data(), GL_STATIC_DRAW);
  } else {
    gl.glBufferData(GL_TEXTURE_BUFFER, bytes, nullptr, GL_STATIC_DRAW);
    auto* out = static_cast<std::int16_t*>(
        gl.glMapBufferRange(GL_TEXTURE_BUFFER, 0, bytes, GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT));
    if (out != nullptr) {
      const std::int16_t* in = K.Q.data();  // row-major: row i at i·m
      for (Eigen::Index i = 0; i < K.rows(); ++i, in += m, out += padded) {
        std::memcpy(out, in, m * sizeof(std::int16_t));
        std::fill(out + m, out + padded, std::int16_t{0});
      }
      gl.glUnmapBuffer(GL_TEXTURE_BUFFER);
    }
  }
  gl.glBindBuffer(GL_TEXTURE_BUFFER, 0);
}

}  // namespace sc::app
