// shapecast-bench-viewport: per-frame cost of showing a client's deformation frames in the real MeshViewport.
//
// Opens a MeshViewport of the given size (a top-level window; run under xvfb-run on a headless machine) on each
// mesh, shows it as a display level with a synthetic m-column basis (smooth sines of the rest coordinates: the cost
// does not depend on K's values) and, for each reconstruction path, shows a new Z every frame: showFrame(), a
// synchronous repaint() and glFinish(). This file is the viewport's timing probe: the widget only exposes frameTimes(),
// paintCount() and a stage hook (MeshViewport::setStageHook()) that --profile fills with glFinish(). Prints median and
// p90 of every stage (FrameTimes) and of the whole frame, with "compose" = frame − host stages − paintGL stages (the
// swap of the viewport's window surface, ViewportSurface, i.e. the Xvfb blit; a QOpenGLWidget's composition into the
// window before issue 16 item 5). Baselines: "empty" (no mesh: background
// only) and "static" (mesh, no new positions).
//
// Usage: shapecast-bench-viewport [--frames 30] [--size 1024x768] [--m 100] [--profile] [--proxy-only] [MESH ...]
//   --profile  glFinish() after each GL stage (attributes the rasteriser's work to its stage; slower overall).
//   --proxy-only  only the frames with the interactive proxy (a client's frames of a dense mesh in the app).
//   MESH       default: assets/meshes/dragon_vrip_res3.ply (23k) and dragon_vrip_res2.ply (100k).

#include "app/gui/interactive_proxy.h"
#include "app/gui/mesh_viewport.h"
#include "experiments/report/machine_info.h"
#include "model/mesh_loader.h"
#include "model/mesh_proxy.h"
#include "spectral/display_level.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QElapsedTimer>
#include <QOpenGLContext>
#include <QOpenGLFunctions>
#include <QThread>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <functional>
#include <random>
#include <utility>
#include <variant>
#include <vector>

namespace {

using sc::app::FramePolicy;
using sc::app::FrameTimes;
using sc::app::InteractiveProxyBuilder;
using sc::app::MeshViewport;
using sc::app::ReconstructionPath;
using sc::app::RendererDefaults;

constexpr unsigned long kFrameGapMs = 20;  // Qt defers a repaint() within one display frame of the last one
constexpr int kWarmupFrames = 3;

/// Column k: scale·sin((k+1)·x_axis + phase_k), axis = k mod 3; deterministic.
sc::spectral::RowMatrixXf syntheticBasis(const Eigen::MatrixXd& V, int m, float scale) {
  sc::spectral::RowMatrixXf K(V.rows(), m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> phase(0.0f, 6.28f);
  const double size = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  for (int k = 0; k < m; ++k) {
    const float p = phase(rng);
    const auto axis = static_cast<Eigen::Index>(k % 3);
    const auto frequency = static_cast<float>((1 + k % 8) * 6.28 / size);
    for (Eigen::Index i = 0; i < V.rows(); ++i) {
      K(i, k) = scale * std::sin(frequency * static_cast<float>(V(i, axis)) + p);
    }
  }
  return K;
}

struct Series {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  [[nodiscard]] double quantile(double q) const {
    if (values.empty()) return 0.0;
    std::vector<double> v = values;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
  }
};

struct Stages {
  Series set, reconstruct, normals, bounds, upload, background, mesh, overlay, compose, frame, cpu, scale;
  void add(const FrameTimes& t, double setMs, double frameMs, double cpuMs) {
    cpu.add(cpuMs);
    scale.add(t.renderScale);
    set.add(setMs);
    reconstruct.add(t.reconstructMs);
    normals.add(t.normalsMs);
    bounds.add(t.boundsMs);
    upload.add(t.uploadMs);
    background.add(t.backgroundMs);
    mesh.add(t.meshMs);
    overlay.add(t.overlayMs);
    compose.add(frameMs - setMs - t.paintMs());
    frame.add(frameMs);
  }
  void print(const char* label) const {
    const std::pair<const char*, const Series*> rows[] = {
        {"reconstruct", &reconstruct}, {"normals", &normals}, {"bounds", &bounds},   {"upload", &upload},
        {"background", &background},   {"mesh", &mesh},       {"overlay", &overlay}, {"compose+swap", &compose}};
    std::printf("  %-10s frame median %7.2f ms  p90 %7.2f ms  (%zu frames), process CPU %7.2f ms |", label,
                frame.quantile(0.5), frame.quantile(0.9), frame.values.size(), cpu.quantile(0.5));
    std::printf(" scale %.2f/%.2f |", scale.quantile(0.5), scale.quantile(0.1));
    for (const auto& [name, series] : rows) {
      std::printf(" %s %.2f/%.2f", name, series->quantile(0.5), series->quantile(0.9));
    }
    std::printf("\n");
  }
};

/// CPU time of this process (all threads, llvmpipe's included) in ms: unlike wall time it hardly depends on what
/// else runs on the machine.
double processCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

void glFinishOn(MeshViewport& viewport) {
  viewport.makeCurrent();
  QOpenGLContext::currentContext()->functions()->glFinish();
  viewport.doneCurrent();
}

/// Runs `frames` synchronous frames: change(frame) (the host side, timed as "set"), repaint(), glFinish().
Stages runFrames(MeshViewport& viewport, int frames, const std::function<void(int)>& change) {
  Stages stages;
  for (int frame = -kWarmupFrames; frame < frames; ++frame) {
    QCoreApplication::processEvents();
    QThread::msleep(kFrameGapMs);
    const int painted = viewport.paintCount();
    QElapsedTimer timer;
    const double cpuStart = processCpuMs();
    timer.start();
    change(frame);
    const double setMs = static_cast<double>(timer.nsecsElapsed()) * 1e-6;
    viewport.repaint();
    glFinishOn(viewport);
    const double frameMs = static_cast<double>(timer.nsecsElapsed()) * 1e-6;
    if (frame >= 0 && viewport.paintCount() != painted) {
      stages.add(viewport.frameTimes(), setMs, frameMs, processCpuMs() - cpuStart);
    }
  }
  return stages;
}

bool waitForFirstPaint(MeshViewport& viewport) {
  QElapsedTimer timer;
  timer.start();
  while (viewport.paintCount() == 0 && timer.elapsed() < 10000) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
  }
  return viewport.paintCount() > 0;
}

void benchMesh(const QString& file, QSize size, int m, int frames, bool profile, bool proxyOnly) {
  const auto loaded = sc::model::loadMesh(file.toStdString());
  if (!std::holds_alternative<sc::model::LoadedMesh>(loaded)) {
    std::printf("%s: cannot load, skipped\n", qPrintable(file));
    return;
  }
  const auto& mesh = std::get<sc::model::LoadedMesh>(loaded);
  MeshViewport viewport;
  if (profile) {  // each GL stage ends with glFinish(): FrameTimes attributes the rasteriser's work to its stage
    viewport.setStageHook([] { QOpenGLContext::currentContext()->functions()->glFinish(); });
  }
  viewport.resize(size);
  viewport.show();
  if (!waitForFirstPaint(viewport)) {
    std::printf("%s: the viewport never painted (no display?), skipped\n", qPrintable(file));
    return;
  }
  std::printf("%s: %lld vertices, %lld triangles, m = %d, %dx%d logical px (dpr %.2f), samples %d\n",
              qPrintable(QFileInfo(file).fileName()), static_cast<long long>(mesh.V.rows()),
              static_cast<long long>(mesh.F.rows()), m, size.width(), size.height(), viewport.devicePixelRatioF(),
              viewport.sampleCount());
  if (!proxyOnly) {
    runFrames(viewport, frames, [](int) {}).print("empty");
  }
  viewport.setMesh(mesh.V, mesh.F);
  if (!proxyOnly) {
    runFrames(viewport, frames, [](int) {}).print("static");
  }
  {
    // A level's install (issue 19 item 3): what the app's decode worker does (makeDisplayLevel: the level's
    // DisplayGeometry), what the GUI thread does (setDisplayLevel), and the upload and draw of the next paint.
    sc::spectral::ResolutionLevel level{
        mesh.V, mesh.F, {}, sc::spectral::quantizeBasis(syntheticBasis(mesh.V, m, 0.004f).cast<double>())};
    QElapsedTimer timer;
    timer.start();
    sc::spectral::SharedDisplayLevel shared = sc::spectral::makeDisplayLevel(std::move(level));
    const double workerMs = static_cast<double>(timer.nsecsElapsed()) / 1e6;
    timer.restart();
    viewport.setDisplayLevel(std::move(shared));
    const double guiMs = static_cast<double>(timer.nsecsElapsed()) / 1e6;
    QThread::msleep(kFrameGapMs);
    const int painted = viewport.paintCount();
    viewport.repaint();
    glFinishOn(viewport);
    const FrameTimes& paint = viewport.frameTimes();
    if (viewport.paintCount() == painted) std::printf("  install    (the first paint was deferred: no paint stages)\n");
    std::printf(
        "  install    makeDisplayLevel %.1f ms (decode worker), setDisplayLevel %.1f ms (GUI thread); first "
        "paint: upload %.1f ms, mesh %.1f ms\n",
        workerMs, guiMs, paint.uploadMs, paint.meshMs);
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  Eigen::MatrixXf Z0(m, 3);
  for (Eigen::Index i = 0; i < Z0.size(); ++i) Z0.data()[i] = u(rng);
  const auto frame = [&](int f) {
    viewport.showFrame({static_cast<std::uint32_t>(f + kWarmupFrames), Z0 * std::sin(0.3f * static_cast<float>(f))});
  };
  // Both paths with the mesh's own triangles, then (a dense mesh) with the interactive proxy the app builds.
  const bool dense = mesh.F.rows() > InteractiveProxyBuilder::kMinTriangles;
  for (const bool proxy : {false, true}) {
    if (proxy && !dense) break;
    if (!proxy && proxyOnly) continue;
    if (proxy) {
      QElapsedTimer timer;
      timer.start();
      viewport.setInteractiveProxy(sc::model::proxyTriangles(mesh.V, mesh.F, InteractiveProxyBuilder::kProxyTriangles));
      std::printf("  proxy      %d triangles, built in %.2f s (on a worker thread in the app)\n",
                  viewport.proxyTriangleCount(), static_cast<double>(timer.elapsed()) * 1e-3);
    }
    for (const ReconstructionPath path : {ReconstructionPath::Cpu, ReconstructionPath::Gpu}) {
      viewport.setReconstructionPath(path);
      const QString label = QString::fromLatin1(path == ReconstructionPath::Cpu ? "cpu" : "gpu") +
                            (proxy ? QStringLiteral("+proxy") : QString());
      if (viewport.reconstructionPath() != path) {
        std::printf("  %-10s unavailable here\n", qPrintable(label));
        continue;
      }
      runFrames(viewport, frames, frame).print(qPrintable(label));
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(RendererDefaults::preferredSurfaceFormat());
  QApplication app(argc, argv);
  QCommandLineParser parser;
  parser.addHelpOption();
  parser.addOption(
      {QStringLiteral("frames"), QStringLiteral("Frames per path."), QStringLiteral("n"), QStringLiteral("30")});
  parser.addOption({QStringLiteral("size"), QStringLiteral("Viewport size WxH."), QStringLiteral("size"),
                    QStringLiteral("1024x768")});
  parser.addOption({QStringLiteral("m"), QStringLiteral("Basis size."), QStringLiteral("m"), QStringLiteral("100")});
  parser.addOption({QStringLiteral("profile"), QStringLiteral("glFinish() after each GL stage.")});
  parser.addOption({QStringLiteral("proxy-only"), QStringLiteral("Only the frames with the interactive proxy.")});
  parser.addPositionalArgument(QStringLiteral("meshes"), QStringLiteral("Mesh files."), QStringLiteral("[MESH...]"));
  parser.process(app);
  const QStringList size = parser.value(QStringLiteral("size")).split(QLatin1Char('x'));
  const int frames = parser.value(QStringLiteral("frames")).toInt();
  const int m = parser.value(QStringLiteral("m")).toInt();
  if (size.size() != 2 || size[0].toInt() <= 0 || size[1].toInt() <= 0 || frames <= 0 || m <= 0) {
    std::fprintf(stderr,
                 "usage: shapecast-bench-viewport [--frames N] [--size WxH] [--m M] [--profile] [--proxy-only] "
                 "[MESH...]\n");
    return 2;
  }
  QStringList meshes = parser.positionalArguments();
  if (meshes.isEmpty()) {
    const QDir assets(QStringLiteral(SHAPECAST_ASSETS_DIR));
    meshes = {assets.filePath(QStringLiteral("dragon_vrip_res3.ply")),
              assets.filePath(QStringLiteral("dragon_vrip_res2.ply"))};
  }
  std::printf("machine   %s\n", qPrintable(sc::report::machineDescription()));
  std::printf("adaptive resolution %s (paint budget %.0f ms)\n", RendererDefaults::adaptiveResolution() ? "on" : "off",
              FramePolicy::kPaintBudgetMs);
  std::printf(
      "renderer  %s; LP_NUM_THREADS=%s; QThread::idealThreadCount %d\n", qPrintable(RendererDefaults::rendererName()),
      qEnvironmentVariableIsSet("LP_NUM_THREADS") ? qPrintable(qEnvironmentVariable("LP_NUM_THREADS")) : "unset",
      QThread::idealThreadCount());
  std::printf("per stage: median/p90 ms; frame = showFrame + repaint + glFinish%s\n",
              parser.isSet(QStringLiteral("profile")) ? " (profiling: glFinish after each GL stage)" : "");
  for (const QString& mesh : meshes) {
    benchMesh(mesh, QSize(size[0].toInt(), size[1].toInt()), m, frames, parser.isSet(QStringLiteral("profile")),
              parser.isSet(QStringLiteral("proxy-only")));
  }
  return 0;
}
