// shapecast-gpu-check: does the viewport's GPU path (the reconstruction vertex shader, K in a texture buffer,
// transform feedback) give the CPU kernel's positions on this machine's OpenGL, and how long does it take?
//
// No window: an offscreen surface and a 3.3 core context, so it runs on a GPU machine without a display server
// (QT_QPA_PLATFORM=minimalegl with the vendor's EGL) as well as under Xvfb (llvmpipe). For each mesh it builds a
// display level with a synthetic smooth m-column basis (the shader's cost and error do not depend on K's values),
// uploads it through the viewport's own ViewportBuffers, and for `--frames` random Z compares the shader's
// positions (GpuReconstructor::readBack) with spectral::reconstructInterleaved. Prints the renderer, the worst
// error over the bounding-box diagonal (the shader and the CPU kernel both read the int16 K; the quantisation's
// own error against float32 K is printed beside it) and the median time of a GPU frame (uniforms, draw with transform
// feedback, read-back) and of a CPU frame. Exit status 1 when the error exceeds 1e-5 of the diagonal or no context
// exists.
//
// Usage: shapecast-gpu-check [--m 100] [--frames 20] [--egl] MESH...
//   --egl  create the context with EGL by hand on EGL's default display, with a pbuffer config, and hand it to Qt
//          (QNativeInterface::QEGLContext): for GPU machines without a display server, where Qt's EGL platforms
//          ask for window configs that a device display does not have. Run with QT_QPA_PLATFORM=eglfs
//          QT_QPA_EGLFS_FB=/dev/null (scripts/gpu-check.sh).

#include "app/gui/viewport/gpu_reconstructor.h"
#include "app/gui/viewport/viewport_buffers.h"
#include "model/mesh_loader.h"
#include "spectral/display_level.h"
#include "spectral/quantized_basis.h"
#include "spectral/reconstruction_kernel.h"

#include <QtGui/qopenglcontext_platform.h>
#include <QCommandLineParser>
#include <QElapsedTimer>
#include <QGuiApplication>
#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLFramebufferObject>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLVersionFunctionsFactory>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <variant>
#include <vector>

namespace {

Eigen::MatrixXd smoothBasis(const Eigen::MatrixXd& V, int m, double scale) {
  Eigen::MatrixXd K(V.rows(), m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> phase(0.0, 6.28);
  const double size = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  for (int k = 0; k < m; ++k) {
    const double p = phase(rng);
    const auto axis = static_cast<Eigen::Index>(k % 3);
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      K(i, k) = scale * std::sin((k + 1) * V(i, axis) / size * 6.0 + p);
    }
  }
  return K;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

struct MeshResult {
  double worstError = 0.0;    ///< max |GPU − CPU| over the diagonal, over all frames (both on the int16 K)
  double quantisation = 0.0;  ///< max |CPU on int16 K − CPU on float32 K| over the diagonal
  double gpuMs = 0.0, cpuMs = 0.0;
};

MeshResult check(QOpenGLFunctions_3_3_Core& gl, const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int m, int frames) {
  const Eigen::MatrixXd basis = smoothBasis(V, m, 0.01);
  const sc::spectral::QuantizedBasis K = sc::spectral::quantizeBasis(basis);
  const sc::spectral::RowMatrixXf floatK = basis.cast<float>();
  const std::vector<float> rest = sc::spectral::interleavedPositions(V);
  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  sc::app::ViewportBuffers buffers;
  buffers.create(gl, true);
  buffers.writeRest() = rest;
  std::vector<std::uint32_t> indices(static_cast<std::size_t>(F.size()));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) indices[static_cast<std::size_t>(3 * f + c)] = static_cast<std::uint32_t>(F(f, c));
  buffers.setIndices(std::move(indices));
  buffers.writeTints().assign(4 * static_cast<std::size_t>(V.rows()), 255);
  buffers.upload(gl, &K);
  sc::app::GpuReconstructor gpu;
  MeshResult result;
  if (!gpu.create(gl) || !gpu.available(V.rows(), m)) {
    std::printf("  the GPU path is not available here (program or texture size)\n");
    result.worstError = INFINITY;
    return result;
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> cpu(rest.size()), cpuFloat(rest.size());
  std::vector<double> gpuTimes, cpuTimes;
  for (int frame = 0; frame < frames; ++frame) {
    Eigen::MatrixXf Z(m, 3);
    for (Eigen::Index i = 0; i < Z.size(); ++i) Z.data()[i] = u(rng);
    QElapsedTimer timer;
    timer.start();
    const std::vector<float> shaded =
        gpu.readBack(gl, buffers.gpuVao(), buffers.basisTexture(), K.scaled(Z), static_cast<int>(V.rows()));
    if (const GLenum error = gl.glGetError(); error != GL_NO_ERROR) {
      std::printf("  GL error 0x%x in frame %d\n", error, frame);
      result.worstError = INFINITY;
      break;
    }
    gpuTimes.push_back(static_cast<double>(timer.nsecsElapsed()) / 1e6);
    timer.restart();
    sc::spectral::reconstructInterleaved(K, rest, Z, cpu);
    cpuTimes.push_back(static_cast<double>(timer.nsecsElapsed()) / 1e6);
    sc::spectral::reconstructInterleaved(floatK, rest, Z, cpuFloat);
    if (shaded.size() != cpu.size()) {
      result.worstError = INFINITY;
      break;
    }
    for (std::size_t i = 0; i < cpu.size(); ++i) {
      result.worstError = std::max(result.worstError, std::abs(static_cast<double>(shaded[i] - cpu[i])) / diagonal);
      result.quantisation =
          std::max(result.quantisation, std::abs(static_cast<double>(cpu[i] - cpuFloat[i])) / diagonal);
    }
  }
  gpu.destroy(gl);
  buffers.destroy(gl);
  result.gpuMs = median(gpuTimes);
  result.cpuMs = median(cpuTimes);
  return result;
}

/// An OpenGL 3.3 core context on EGL's default display with a pbuffer config, adopted by Qt; nullptr on failure.
QOpenGLContext* adoptEglContext() {
  EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  EGLint major = 0, minor = 0;
  if (display == EGL_NO_DISPLAY || eglInitialize(display, &major, &minor) == EGL_FALSE ||
      eglBindAPI(EGL_OPENGL_API) == EGL_FALSE) {
    std::fprintf(stderr, "EGL: no default display (0x%x)\n", eglGetError());
    return nullptr;
  }
  const EGLint configAttributes[] = {EGL_SURFACE_TYPE,
                                     EGL_PBUFFER_BIT,
                                     EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT,
                                     EGL_RED_SIZE,
                                     8,
                                     EGL_GREEN_SIZE,
                                     8,
                                     EGL_BLUE_SIZE,
                                     8,
                                     EGL_DEPTH_SIZE,
                                     24,
                                     EGL_NONE};
  EGLConfig config = nullptr;
  EGLint configs = 0;
  if (eglChooseConfig(display, configAttributes, &config, 1, &configs) == EGL_FALSE || configs < 1) {
    std::fprintf(stderr, "EGL: no pbuffer config (0x%x)\n", eglGetError());
    return nullptr;
  }
  const EGLint contextAttributes[] = {
      EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
  if (context == EGL_NO_CONTEXT) {
    std::fprintf(stderr, "EGL: no 3.3 core context (0x%x)\n", eglGetError());
    return nullptr;
  }
  std::printf("EGL %d.%d, vendor %s\n", major, minor, eglQueryString(display, EGL_VENDOR));
  return QNativeInterface::QEGLContext::fromNative(context, display);
}

}  // namespace

int main(int argc, char** argv) {
  QGuiApplication app(argc, argv);
  QCommandLineParser parser;
  parser.addHelpOption();
  parser.addOption({QStringLiteral("m"), QStringLiteral("Basis size."), QStringLiteral("m"), QStringLiteral("100")});
  parser.addOption(
      {QStringLiteral("frames"), QStringLiteral("Random frames per mesh."), QStringLiteral("n"), QStringLiteral("20")});
  parser.addOption({QStringLiteral("egl"), QStringLiteral("Create the context with EGL by hand (no display server).")});
  parser.addPositionalArgument(QStringLiteral("mesh"), QStringLiteral("Meshes to check."), QStringLiteral("MESH..."));
  parser.process(app);
  const int m = parser.value(QStringLiteral("m")).toInt();
  const int frames = std::max(1, parser.value(QStringLiteral("frames")).toInt());

  QSurfaceFormat format;
  format.setVersion(3, 3);
  format.setProfile(QSurfaceFormat::CoreProfile);
  std::unique_ptr<QOpenGLContext> context;
  if (parser.isSet(QStringLiteral("egl"))) {
    context.reset(adoptEglContext());
  } else {
    context = std::make_unique<QOpenGLContext>();
    context->setFormat(format);
    if (!context->create()) context.reset();
  }
  QOffscreenSurface surface;
  surface.setFormat(context ? context->format() : format);
  surface.create();
  if (!context || !context->makeCurrent(&surface)) {
    std::fprintf(stderr, "no OpenGL 3.3 core context on platform %s\n", qPrintable(QGuiApplication::platformName()));
    return 1;
  }
  auto* gl = QOpenGLVersionFunctionsFactory::get<QOpenGLFunctions_3_3_Core>(context.get());
  if (gl == nullptr) {
    std::fprintf(stderr, "no OpenGL 3.3 core functions\n");
    return 1;
  }
  const QSurfaceFormat got = context->format();
  std::printf("context   %d.%d %s%s\n", got.majorVersion(), got.minorVersion(),
              got.profile() == QSurfaceFormat::CoreProfile ? "core" : "not core",
              got.renderableType() == QSurfaceFormat::OpenGLES ? " (OpenGL ES)" : "");
  std::printf("platform  %s\nvendor    %s\nrenderer  %s\nversion   %s\n", qPrintable(QGuiApplication::platformName()),
              reinterpret_cast<const char*>(gl->glGetString(GL_VENDOR)),
              reinterpret_cast<const char*>(gl->glGetString(GL_RENDERER)),
              reinterpret_cast<const char*>(gl->glGetString(GL_VERSION)));
  // A framebuffer of our own: a surfaceless or pbuffer-less EGL context has no complete default framebuffer, and
  // a draw (even with rasterisation discarded) needs one. The viewport always draws into its widget's FBO.
  QOpenGLFramebufferObject framebuffer(QSize(16, 16));
  framebuffer.bind();
  bool ok = true;
  for (const QString& path : parser.positionalArguments()) {
    const sc::model::MeshLoadResult result = sc::model::loadMesh(path.toStdString());
    const auto* loaded = std::get_if<sc::model::LoadedMesh>(&result);
    if (loaded == nullptr) {
      std::fprintf(stderr, "%s\n", std::get<sc::model::MeshError>(result).message.c_str());
      ok = false;
      continue;
    }
    const MeshResult r = check(*gl, loaded->V, loaded->F, m, frames);
    std::printf(
        "%s: %lld vertices, m = %d, %d frames: max |GPU - CPU| = %.2e of the diagonal (int16 K; its "
        "quantisation against float32 K: %.2e); median frame GPU %.3f ms (draw + read-back), CPU %.3f ms\n",
        qPrintable(path), static_cast<long long>(loaded->V.rows()), m, frames, r.worstError, r.quantisation, r.gpuMs,
        r.cpuMs);
    ok = ok && r.worstError <= 1e-5;
  }
  std::printf("%s\n", ok ? "GPU path agrees with the CPU kernel" : "GPU path FAILED");
  return ok ? 0 : 1;
}
