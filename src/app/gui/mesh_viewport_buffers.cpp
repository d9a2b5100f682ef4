// MeshViewport, the vertex data on the GL side: the vertex arrays of the mesh and of its compact interactive proxy,
// and the upload of the host buffers that changed (positions, normals, tints, indices, the GPU path's rest positions
// and basis).

#include "app/gui/mesh_viewport.h"

#include <QOpenGLFramebufferObject>  // complete types for the unique_ptr members
#include <QOpenGLShaderProgram>

namespace sc::app {

namespace {

struct VertexBuffers {
  QOpenGLBuffer* positions;
  QOpenGLBuffer* normals;
  QOpenGLBuffer* tints;
  QOpenGLBuffer* indices;
};

// Records in `vao` one buffer per attribute of the mesh program (positions and normals change per frame, tints
// per selection) and the index buffer binding. Needs the current context.
void recordVertexArray(QOpenGLFunctions& gl, QOpenGLVertexArrayObject& vao, const VertexBuffers& buffers) {
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
    a.buffer->create();
    a.buffer->setUsagePattern(location == 2 ? QOpenGLBuffer::StaticDraw : QOpenGLBuffer::DynamicDraw);
    a.buffer->bind();
    gl.glEnableVertexAttribArray(location);
    gl.glVertexAttribPointer(location, a.size, a.type, a.type == GL_UNSIGNED_BYTE ? GL_TRUE : GL_FALSE, 0, nullptr);
    a.buffer->release();
  }
  buffers.indices->create();
  buffers.indices->setUsagePattern(QOpenGLBuffer::StaticDraw);
  buffers.indices->bind();  // VAO state
}

}  // namespace

// The mesh's VAO and the compact proxy's, both for m_meshProgram (attribute locations 0, 1, 2).
void MeshViewport::createMeshVaos() {
  recordVertexArray(*this, m_meshVao, {&m_positionBuffer, &m_normalBuffer, &m_tintBuffer, &m_indexBuffer});
  recordVertexArray(*this, m_proxyVao,
                    {&m_proxyPositionBuffer, &m_proxyNormalBuffer, &m_proxyTintBuffer, &m_proxyIndexBuffer});
}

void MeshViewport::uploadIfDirty() {
  const auto upload = [](QOpenGLBuffer& buffer, const auto& values) {
    buffer.bind();
    buffer.allocate(values.data(), static_cast<int>(values.size() * sizeof(values[0])));
    buffer.release();
  };
  if (m_vertexDataDirty) {
    upload(m_positionBuffer, m_positions);
    upload(m_normalBuffer, m_normals);
    m_vertexDataDirty = false;
  }
  if (m_tintsDirty) {
    upload(m_tintBuffer, m_tints);
    m_tintsDirty = false;
  }
  if (m_proxyDataDirty) {
    upload(m_proxyPositionBuffer, m_proxy.positions());
    upload(m_proxyNormalBuffer, m_proxy.normals());
    m_proxyDataDirty = false;
  }
  if (m_proxyTintsDirty) {
    upload(m_proxyTintBuffer, m_proxy.tints());
    m_proxyTintsDirty = false;
  }
  if (m_proxyIndicesDirty) {
    QOpenGLVertexArrayObject::Binder vaoBinder(&m_proxyVao);
    m_proxyIndexBuffer.bind();  // stays bound: VAO state
    m_proxyIndexBuffer.allocate(m_proxy.indices().data(), static_cast<int>(m_proxy.indices().size() * 4));
    m_proxyIndicesDirty = false;
  }
  if (m_indicesDirty) {
    QOpenGLVertexArrayObject::Binder vaoBinder(&m_meshVao);
    m_indexBuffer.bind();  // stays bound: the element array binding is VAO state
    const auto bytes = [](const std::vector<std::uint32_t>& v) { return static_cast<int>(v.size() * 4); };
    m_indexBuffer.allocate(bytes(m_indices) + bytes(m_proxyIndices));
    m_indexBuffer.write(0, m_indices.data(), bytes(m_indices));
    m_indexBuffer.write(bytes(m_indices), m_proxyIndices.data(), bytes(m_proxyIndices));
    m_indicesDirty = false;
  }
  if (m_restDirty && m_restBuffer.isCreated()) {
    upload(m_restBuffer, m_rest);
    m_restDirty = false;
  }
  if (m_basisDirty && m_basisBuffer != 0) {
    glBindBuffer(GL_TEXTURE_BUFFER, m_basisBuffer);
    glBufferData(GL_TEXTURE_BUFFER, static_cast<GLsizeiptr>(m_basis.size() * sizeof(float)), m_basis.data(),
                 GL_STATIC_DRAW);
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
    m_basisDirty = false;
  }
}

}  // namespace sc::app
