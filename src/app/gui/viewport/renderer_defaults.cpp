#include "app/gui/viewport/renderer_defaults.h"

#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLFunctions>

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

}  // namespace sc::app
