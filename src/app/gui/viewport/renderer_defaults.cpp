#include "app/gui/viewport/renderer_defaults.h"

#include "app/gui/viewport/progressive_picture.h"

#include <QGuiApplication>
#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLFunctions>
#include <QStringList>

#include <algorithm>

namespace sc::app {

namespace {

// $name as an integer ≥ 0, or `otherwise` when unset or not an integer.
int environmentOr(const char* name, int otherwise) {
  bool ok = false;
  const int value = qEnvironmentVariableIntValue(name, &ok);
  return ok ? std::max(0, value) : otherwise;
}

}  // namespace

QSurfaceFormat RendererDefaults::preferredSurfaceFormat() {
  QSurfaceFormat format;
  format.setRenderableType(QSurfaceFormat::OpenGL);
  format.setVersion(3, 3);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setDepthBufferSize(24);
  return format;
}

QString RendererDefaults::openGlProblem() {
  QOpenGLContext context;
  context.setFormat(QSurfaceFormat::defaultFormat());
  const QString platform = QGuiApplication::platformName();
  const QString need = QStringLiteral(
      "the 3D view needs OpenGL 3.3 (core profile); run shapecast on a desktop or X display with an OpenGL driver "
      "(Mesa's llvmpipe is enough; on a machine without a display: xvfb-run)");
  // Platforms without windows of their own cannot compose an OpenGL widget (Qt warns "QOpenGLWidget is not
  // supported on this platform" and then crashes in its flush), even where they create a context.
  const QStringList windowless = {QStringLiteral("offscreen"), QStringLiteral("minimal"), QStringLiteral("vnc"),
                                  QStringLiteral("linuxfb")};
  if (windowless.contains(platform) || !context.create()) {
    return QStringLiteral("the \"%1\" display platform offers no OpenGL window: %2").arg(platform, need);
  }
  const QSurfaceFormat format = context.format();
  if (format.majorVersion() < 3 || (format.majorVersion() == 3 && format.minorVersion() < 3)) {
    return QStringLiteral("this display's OpenGL is %1.%2: %3")
        .arg(format.majorVersion())
        .arg(format.minorVersion())
        .arg(need);
  }
  return {};
}

QString RendererDefaults::rendererName() {
  QOpenGLContext context;
  context.setFormat(QSurfaceFormat::defaultFormat());
  if (!context.create()) {
    return {};
  }
  QOffscreenSurface surface;
  surface.setFormat(context.format());
  surface.create();
  if (!context.makeCurrent(&surface)) {
    return {};
  }
  const auto* name = reinterpret_cast<const char*>(context.functions()->glGetString(GL_RENDERER));
  QString result = name != nullptr ? QString::fromLatin1(name) : QString();
  context.doneCurrent();
  return result;
}

bool RendererDefaults::softwareRenderer() {
  static const bool software = [] {
    const QString renderer = rendererName().toLower();
    return renderer.contains(QLatin1String("llvmpipe")) || renderer.contains(QLatin1String("softpipe")) ||
           renderer.contains(QLatin1String("software"));
  }();
  return software;
}

int RendererDefaults::sampleCount() {
  static const int samples = environmentOr("SHAPECAST_MSAA", softwareRenderer() ? 0 : 4);
  return samples;
}

ReconstructionPath RendererDefaults::reconstructionPath() {
  static const ReconstructionPath path = [] {
    const QByteArray chosen = qgetenv("SHAPECAST_RECONSTRUCTION").toLower();
    if (chosen == "cpu" || chosen == "gpu") {
      return chosen == "gpu" ? ReconstructionPath::Gpu : ReconstructionPath::Cpu;
    }
    return softwareRenderer() ? ReconstructionPath::Cpu : ReconstructionPath::Gpu;
  }();
  return path;
}

bool RendererDefaults::adaptiveResolution() {
  static const bool adaptive = environmentOr("SHAPECAST_ADAPTIVE_RESOLUTION", softwareRenderer() ? 1 : 0) != 0;
  return adaptive;
}

int RendererDefaults::progressiveMinimumTriangles() {
  static const int triangles =
      std::max(0, environmentOr("SHAPECAST_PROGRESSIVE_TRIANGLES", ProgressivePicture::kDefaultMinimumTriangles));
  return triangles;
}

}  // namespace sc::app
