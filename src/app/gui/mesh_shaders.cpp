#include "app/gui/mesh_shaders.h"

#include <QOpenGLShaderProgram>
#include <QtDebug>

namespace sc::app::shaders {

const char* const kBackgroundVertex = R"(#version 330 core
out float vV;
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  vV = p.y;
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

const char* const kBackgroundFragment = R"(#version 330 core
in float vV;
uniform vec3 uTopColor;
uniform vec3 uBottomColor;
out vec4 fragColor;
void main() {
  fragColor = vec4(mix(uBottomColor, uTopColor, clamp(vV, 0.0, 1.0)), 1.0);
}
)";

const char* const kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 aTint;
uniform mat4 uModelView;
uniform mat4 uProjection;
uniform mat3 uNormalMatrix;
out vec3 vPosition;
out vec3 vNormal;
out vec4 vTint;
void main() {
  vTint = aTint;
  vec4 p = uModelView * vec4(aPosition, 1.0);
  vPosition = p.xyz;
  vNormal = uNormalMatrix * aNormal;
  gl_Position = uProjection * p;
}
)";

// kMaxGroups = 64 appears literally in uZ's size.
const char* const kMeshReconstructVertex = R"(#version 330 core
layout(location = 0) in vec3 aRest;
layout(location = 2) in vec4 aTint;
uniform isamplerBuffer uBasis;
uniform vec4 uZ[192];
uniform int uGroups;
uniform mat4 uModelView;
uniform mat4 uProjection;
out vec3 vPosition;
out vec3 vNormal;
out vec4 vTint;
out vec3 vModelPosition;
void main() {
  vec4 sx = vec4(0.0);
  vec4 sy = vec4(0.0);
  vec4 sz = vec4(0.0);
  int row = gl_VertexID * uGroups;
  for (int g = 0; g < uGroups; ++g) {
    vec4 k = vec4(texelFetch(uBasis, row + g));
    sx += k * uZ[g];
    sy += k * uZ[uGroups + g];
    sz += k * uZ[2 * uGroups + g];
  }
  const vec4 one = vec4(1.0);
  vec3 x = aRest + vec3(dot(sx, one), dot(sy, one), dot(sz, one));
  vModelPosition = x;
  vTint = aTint;
  vNormal = vec3(0.0);
  vec4 p = uModelView * vec4(x, 1.0);
  vPosition = p.xyz;
  gl_Position = uProjection * p;
}
)";

const char* const kMeshFragment = R"(#version 330 core
in vec3 vPosition;
in vec3 vNormal;
in vec4 vTint;
uniform vec3 uBaseColor;
uniform vec4 uLineColor;
uniform bool uFaceNormals;
out vec4 fragColor;

vec3 toLinear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 toSrgb(vec3 c) { return pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)); }

// Diffuse plus Blinn specular for one directional light (all vectors unit, view space).
vec3 shade(vec3 n, vec3 v, vec3 l, vec3 lightColor, vec3 albedo, float specular, float shininess) {
  float diffuse = max(dot(n, l), 0.0);
  float highlight = diffuse > 0.0 ? pow(max(dot(n, normalize(l + v)), 0.0), shininess) : 0.0;
  return lightColor * (albedo * diffuse + vec3(specular * highlight));
}

void main() {
  if (uLineColor.a > 0.0) {
    fragColor = vec4(uLineColor.rgb, 1.0);
    return;
  }
  vec3 v = normalize(-vPosition);
  // Face normals: the plane of the drawn triangle, facing the eye (derivatives within one primitive).
  vec3 raw = uFaceNormals ? cross(dFdx(vPosition), dFdy(vPosition)) : vNormal;
  float len = length(raw);
  vec3 n = len > (uFaceNormals ? 0.0 : 1e-12) ? raw / len : v;
  // A back face whose normal also faces away is seen from behind (open mesh, or a mesh wound clockwise): flip.
  // A back face whose normal faces the eye is a single flipped triangle in an otherwise consistent mesh: the
  // vertex normals already agree with its neighbours, so keep them (no dark speckles).
  if (!gl_FrontFacing && dot(n, v) < 0.0) n = -n;

  vec3 albedo = toLinear(mix(uBaseColor, vTint.rgb, vTint.a));
  vec3 keyDir = normalize(vec3(-0.45, 0.65, 0.62));
  vec3 fillDir = normalize(vec3(0.75, -0.05, 0.45));
  vec3 color = shade(n, v, keyDir, vec3(1.00, 0.96, 0.90) * 1.05, albedo, 0.28, 48.0);
  color += shade(n, v, fillDir, vec3(0.62, 0.70, 0.85) * 0.45, albedo, 0.10, 24.0);

  vec3 sky = vec3(0.34, 0.38, 0.45);
  vec3 ground = vec3(0.16, 0.14, 0.12);
  color += albedo * mix(ground, sky, 0.5 + 0.5 * n.y) * 0.40;

  float t = 1.0 - max(dot(n, v), 0.0);
  float rim = t * t * t;
  color += vec3(0.55, 0.65, 0.80) * rim * 0.12;
  fragColor = vec4(toSrgb(color), 1.0);
}
)";

// Compiles and links a program, or warns with the driver log and returns null. `beforeLink` (optional) runs
// on the program id between compiling and linking (transform feedback varyings).
std::unique_ptr<QOpenGLShaderProgram> makeProgram(const char* vertexSource, const char* fragmentSource,
                                                  const std::function<void(GLuint)>& beforeLink) {
  auto program = std::make_unique<QOpenGLShaderProgram>();
  if (!program->addShaderFromSourceCode(QOpenGLShader::Vertex, vertexSource) ||
      !program->addShaderFromSourceCode(QOpenGLShader::Fragment, fragmentSource)) {
    qWarning().noquote() << "MeshViewport: shader compilation failed:" << program->log();
    return nullptr;
  }
  if (beforeLink) {
    beforeLink(program->programId());
  }
  if (!program->link()) {
    qWarning().noquote() << "MeshViewport: shader program failed:" << program->log();
    return nullptr;
  }
  return program;
}

}  // namespace sc::app::shaders
