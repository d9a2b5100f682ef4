#pragma once
// GpuReconstructor: the GPU path of a shown level's frames. X̂' + K·Z is evaluated in the vertex shader
// (shaders::kMeshReconstructVertex: K's int16 entries in a GL_RGBA16I texture buffer owned by ViewportBuffers, the
// scaled Z (scale ⊙ Z, ShownLevel::scaledZ()) in a uniform array, the rest positions as the vertex attribute); this
// class owns the program, says whether the context can draw a basis, sets the per-frame uniforms and reads the shader's
// positions back through transform feedback. The shading uses face normals (screen-space derivatives of the
// reconstructed position in the fragment shader): exact for the drawn triangles, so no per-frame read-back or CPU work
// at all, at the price of a faceted look that smooth CPU vertex normals do not have (invisible at 100k vertices,
// visible on a coarse level).

#include <Eigen/Core>

#include <memory>
#include <vector>

class QOpenGLFunctions_3_3_Core;
class QOpenGLShaderProgram;
class QOpenGLVertexArrayObject;

namespace sc::app {

class GpuReconstructor {
 public:
  /// Largest m the path handles (Z lives in a uniform array of 3·⌈m/4⌉ vec4, shaders::kMaxGroups of them).
  static constexpr int kMaxBasisSize = 256;

  GpuReconstructor();
  ~GpuReconstructor();
  GpuReconstructor(const GpuReconstructor&) = delete;
  GpuReconstructor& operator=(const GpuReconstructor&) = delete;

  /// Compiles the program and reads GL_MAX_TEXTURE_BUFFER_SIZE (context current). Returns false when the shader
  /// fails (the path is then unavailable).
  bool create(QOpenGLFunctions_3_3_Core& gl);
  void destroy(QOpenGLFunctions_3_3_Core& gl);
  [[nodiscard]] bool created() const { return m_program != nullptr; }
  [[nodiscard]] QOpenGLShaderProgram* program() const { return m_program.get(); }

  /// Whether it can draw #V = `vertices` with an m-column basis: the program exists, ⌈m/4⌉ ≤ shaders::kMaxGroups
  /// (m ≤ 256) and #V·⌈m/4⌉ texels fit GL_MAX_TEXTURE_BUFFER_SIZE. m = 0: whether the program exists.
  [[nodiscard]] bool available(long long vertices, int basisSize) const;

  /// With the program bound: binds K's texture to its unit and sets Z (m by 3, the scaled Z of the quantised K;
  /// padded here to 4·⌈m/4⌉ rows, the uniform array's layout). unbind() releases the texture.
  void setUniforms(QOpenGLFunctions_3_3_Core& gl, unsigned basisTexture, const Eigen::MatrixXf& Z);
  void unbind(QOpenGLFunctions_3_3_Core& gl);

  /// The shader's positions for `vertices` vertices of `vao` (the GPU path's, uploaded, K included), 3·#V floats
  /// in the rest buffer's coordinates. Synchronous (transform feedback, then a read-back). Context current.
  [[nodiscard]] std::vector<float> readBack(QOpenGLFunctions_3_3_Core& gl, QOpenGLVertexArrayObject& vao,
                                            unsigned basisTexture, const Eigen::MatrixXf& Z, int vertices);

 private:
  std::unique_ptr<QOpenGLShaderProgram> m_program;
  long long m_maxTexels = 0;
  unsigned m_feedbackBuffer = 0;
  Eigen::MatrixXf m_paddedZ;  // 4G by 3
};

}  // namespace sc::app
