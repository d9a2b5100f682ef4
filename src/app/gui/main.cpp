// shapecast: the desktop application.
//
//   shapecast [MESH] [--screenshot FILE.png] [--size WIDTHxHEIGHT]
//
// With MESH, the mesh is loaded at start-up. With --screenshot, the first rendered frame of the viewport is saved
// to FILE and the program exits: 0 on success, 1 when MESH could not be loaded, 2 when the image could not be
// written, 64 for bad arguments. Load errors then go to stderr instead of a dialog.

#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QImage>
#include <QRegularExpression>
#include <QSize>
#include <QSurfaceFormat>
#include <QTimer>

#include <cstdio>
#include <optional>

namespace {

constexpr int kExitLoadFailed = 1;
constexpr int kExitScreenshotFailed = 2;
constexpr int kExitUsage = 64;
constexpr int kFirstFrameTimeoutMs = 10000;

std::optional<QSize> parseSize(const QString& text) {
  static const QRegularExpression pattern(QStringLiteral("^(\\d{1,5})x(\\d{1,5})$"));
  const QRegularExpressionMatch match = pattern.match(text);
  if (!match.hasMatch()) {
    return std::nullopt;
  }
  const QSize size(match.captured(1).toInt(), match.captured(2).toInt());
  return size.width() > 0 && size.height() > 0 ? std::optional<QSize>(size) : std::nullopt;
}

// Saves the viewport's first rendered frame to file, then exits the event loop with 0, or 2 if saving failed. If
// no frame is reported within the timeout (no exposure), the framebuffer is grabbed anyway.
void saveFirstFrameAndQuit(sc::app::MeshViewport* viewport, const QString& file) {
  auto* timeout = new QTimer(viewport);
  timeout->setSingleShot(true);
  const auto grabAndQuit = [viewport, file, timeout] {
    timeout->stop();
    const QImage image = viewport->grabFramebuffer();
    const bool saved = !image.isNull() && image.save(file, "PNG");
    if (!saved) {
      std::fprintf(stderr, "shapecast: could not write screenshot %s\n", qUtf8Printable(file));
    }
    QCoreApplication::exit(saved ? 0 : kExitScreenshotFailed);
  };
  QObject::connect(
      viewport, &QOpenGLWidget::frameSwapped, viewport, [grabAndQuit] { QTimer::singleShot(0, grabAndQuit); },
      Qt::SingleShotConnection);
  QObject::connect(timeout, &QTimer::timeout, viewport, grabAndQuit);
  timeout->start(kFirstFrameTimeoutMs);
}

}  // namespace

int main(int argc, char* argv[]) {
  QSurfaceFormat::setDefaultFormat(sc::app::MeshViewport::preferredSurfaceFormat());
  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("shapecast"));
  QApplication::setApplicationVersion(QStringLiteral(SHAPECAST_VERSION));

  QCommandLineParser parser;
  parser.setApplicationDescription(QStringLiteral("ShapeCast: view triangle meshes (OFF, OBJ, PLY, STL)."));
  parser.addHelpOption();
  parser.addVersionOption();
  parser.addPositionalArgument(QStringLiteral("mesh"), QStringLiteral("Mesh file to open."), QStringLiteral("[MESH]"));
  const QCommandLineOption screenshotOption(QStringLiteral("screenshot"),
                                            QStringLiteral("Save the first rendered frame to <file> (PNG) and exit."),
                                            QStringLiteral("file"));
  const QCommandLineOption sizeOption(QStringLiteral("size"),
                                      QStringLiteral("Viewport size for --screenshot (default 1024x768)."),
                                      QStringLiteral("WIDTHxHEIGHT"), QStringLiteral("1024x768"));
  parser.addOption(screenshotOption);
  parser.addOption(sizeOption);
  parser.process(app);

  const QStringList positional = parser.positionalArguments();
  const bool screenshot = parser.isSet(screenshotOption);
  const std::optional<QSize> viewportSize = parseSize(parser.value(sizeOption));
  if (positional.size() > 1 || !viewportSize) {
    std::fprintf(stderr, "%s\n", qUtf8Printable(parser.helpText()));
    return kExitUsage;
  }

  sc::app::MainWindow window;
  window.setErrorDialogsEnabled(!screenshot);
  QObject::connect(&window, &sc::app::MainWindow::loadFailed, [](const QString&, const QString& message) {
    std::fprintf(stderr, "shapecast: %s\n", qUtf8Printable(message));
  });
  const bool loaded = positional.isEmpty() || window.openMesh(positional.first());
  if (!screenshot) {
    window.show();
    return QApplication::exec();
  }
  if (!loaded) {
    return kExitLoadFailed;
  }
  window.viewport()->setFixedSize(*viewportSize);
  window.show();
  saveFirstFrameAndQuit(window.viewport(), parser.value(screenshotOption));
  return QApplication::exec();
}
