#include "app/gui/viewport/gpu_reconstructor.h"

#include "app/gui/mesh_shaders.h"

#include <QMatrix4x4>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QOpenGLVertexArrayObject>

namespace sc::app {

namespace {

constexpr int kBasisTextureUnit = 0;

int groupsOf(long long columns) { return static_cast<int>((columns + 3) / 4); }

}  // namespace

GpuReconstructor::GpuReconstructor() = default;
GpuReconstructor::~GpuReconstructor() = default;

bool GpuReconstructor::create(QOpenGLFunctions_3_3_Core& gl) {
  m_program = shaders::makeProgram(shaders::kMeshReconstructVertex, shaders::kMeshFragment, [&gl](GLuint program) {
    const char* varyings[] = {"vModelPosition"};
    gl.glTransformFeedbackVaryings(program, 1, varyings, GL_INTERLEAVED_ATTRIBS);
  });
  if (!m_program) {
    return false;
  }
  GLint maxTexels = 0;
  gl.glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  m_maxTexels = maxTexels;
  return true;
}

void GpuReconstructor::destroy(QOpenGLFunctions_3_3_Core& gl) {
  m_program.reset();
  if (m_feedbackBuffer != 0) {
    gl.glDeleteBuffers(1, &m_feedbackBuffer);
  }
  m_feedbackBuffer = 0;
  m_maxTexels = 0;
}

bool GpuReconstructor::available(long long vertices, int basisSize) const {
  if (!m_program) {
    return false;
  }
  const int groups = groupsOf(basisSize);
  return basisSize == 0 || (groups <= shaders::kMaxGroups && vertices * groups <= m_maxTexels);
}
static_assert(GpuReconstructor::kMaxBasisSize == 4 * shaders::kMaxGroups);

void GpuReconstructor::setUniforms(QOpenGLFunctions_3_3_Core& gl, unsigned basisTexture, const Eigen::MatrixXf& Z) {
  const int groups = groupsOf(Z.rows());
  m_paddedZ = Eigen::MatrixXf::Zero(4 * groups, 3);
  m_paddedZ.topRows(Z.rows()) = Z;
  gl.glActiveTexture(GL_TEXTURE0 + kBasisTextureUnit);
  gl.glBindTexture(GL_TEXTURE_BUFFER, basisTexture);
  m_program->setUniformValue("uBasis", kBasisTextureUnit);
  m_program->setUniformValue("uGroups", groups);
  m_program->setUniformValue("uFaceNormals", true);
  // Z is column-major 4G by 3: x column then y then z, each G vec4, exactly uZ's layout.
  gl.glUniform4fv(m_program->uniformLocation("uZ"), 3 * groups, m_paddedZ.data());
}

void GpuReconstructor::unbind(QOpenGLFunctions_3_3_Core& gl) { gl.glBindTexture(GL_TEXTURE_BUFFER, 0); }

std::vector<float> GpuReconstructor::readBack(QOpenGLFunctions_3_3_Core& gl, QOpenGLVertexArrayObject& vao,
                                              unsigned basisTexture, const Eigen::MatrixXf& Z, int vertices) {
  std::vector<float> xyz(3 * static_cast<std::size_t>(vertices));
  const auto bytes = static_cast<GLsizeiptr>(xyz.size() * sizeof(float));
  if (m_feedbackBuffer == 0) {
    gl.glGenBuffers(1, &m_feedbackBuffer);
  }
  gl.glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, m_feedbackBuffer);
  gl.glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, bytes, nullptr, GL_STREAM_READ);
  m_program->bind();
  m_program->setUniformValue("uModelView", QMatrix4x4());
  m_program->setUniformValue("uProjection", QMatrix4x4());
  setUniforms(gl, basisTexture, Z);
  {
    QOpenGLVertexArrayObject::Binder vaoBinder(&vao);
    gl.glEnable(GL_RASTERIZER_DISCARD);
    gl.glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, m_feedbackBuffer);
    gl.glBeginTransformFeedback(GL_POINTS);
    gl.glDrawArrays(GL_POINTS, 0, vertices);  // gl_VertexID = i, as in the indexed draw
    gl.glEndTransformFeedback();
    gl.glDisable(GL_RASTERIZER_DISCARD);
  }
  gl.glGetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, bytes, xyz.data());
  gl.glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
  gl.glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, 0);
  unbind(gl);
  m_program->release();
  return xyz;
}

}  // namespace sc::app
