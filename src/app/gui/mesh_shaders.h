#pragma once
// GLSL 3.30 core sources used by MeshViewport: a gradient background and a two-light Blinn–Phong mesh shader.

#include <QOpenGLShaderProgram>

#include <functional>
#include <memory>

namespace sc::app::shaders {

/// Compiles and links a program from vertex and fragment sources, or warns with the driver log and returns null.
/// `beforeLink` (optional) runs on the program id between compiling and linking (e.g. to declare transform
/// feedback varyings). Needs a current context.
std::unique_ptr<QOpenGLShaderProgram> makeProgram(const char* vertexSource, const char* fragmentSource,
                                                  const std::function<void(GLuint)>& beforeLink = {});

/// Full-screen triangle from gl_VertexID (draw 3 vertices with an empty VAO); passes the screen v coordinate.
extern const char* const kBackgroundVertex;
/// Vertical gradient; uniforms vec3 uTopColor, uBottomColor (sRGB, as written to the framebuffer).
extern const char* const kBackgroundFragment;

/// Mesh vertex shader. Attributes: location 0 = position, 1 = normal, 2 = tint (vec4: rgb sRGB colour, a = how
/// much it replaces the base colour, 0 = untinted; fed as normalised unsigned bytes). Uniforms: mat4 uModelView,
/// uProjection; mat3 uNormalMatrix. Outputs view-space position and normal, and the tint.
extern const char* const kMeshVertex;
/// Mesh vertex shader of the GPU reconstruction path: x = aRest + K·Z, then as kMeshVertex (same outputs; vNormal
/// is zero, the fragment shader then uses face normals, see uFaceNormals). Attributes: location 0 = rest
/// position, 2 = tint. Uniforms: isamplerBuffer uBasis (GL_RGBA16I, row i of the quantised K as uGroups texels from
/// i·uGroups, indexed by gl_VertexID); vec4 uZ[3·kMaxGroups] (the scaled Z, spectral::QuantizedBasis::scaled(): its
/// x column as uGroups vec4, then y, then z); int
/// uGroups = ⌈m/4⌉ ≤ kMaxGroups; mat4 uModelView, uProjection. Also writes vModelPosition (x) for transform
/// feedback.
extern const char* const kMeshReconstructVertex;
/// Largest uGroups kMeshReconstructVertex accepts.
inline constexpr int kMaxGroups = 64;

/// Mesh fragment shader: two view-space lights (warm key, cool fill), hemispherical ambient, Blinn specular and a
/// faint rim, computed in linear space and gamma-encoded. A back-facing fragment whose normal faces away from the
/// eye is lit with the flipped normal, so open meshes, clockwise meshes and meshes with a few flipped triangles
/// all shade correctly. The albedo is mix(uBaseColor, tint.rgb, tint.a) (both sRGB). Uniforms: vec3 uBaseColor;
/// vec4 uLineColor — when its alpha is > 0 the fragment is a wireframe line of exactly that colour (the wireframe
/// pass draws the same triangles with GL_LINE polygon mode), otherwise it is shaded. bool uFaceNormals (default
/// false): shade with the face normal cross(dFdx(vPosition), dFdy(vPosition)) instead of vNormal.
extern const char* const kMeshFragment;

}  // namespace sc::app::shaders
