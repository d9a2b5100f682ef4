// shapecast: the desktop application.
//
//   shapecast                                   (first start: host the default mesh, ready to drag)
//   shapecast --demo [MESH]                     (one host and two client windows on loopback)
//   shapecast --demo [MESH] --screenshot-dir DIR [--after SECONDS]   (README screenshots, then exit)
//   shapecast [MESH] [--screenshot FILE.png] [--size WIDTHxHEIGHT]
//   shapecast --host MESH|SESSION.shapecast [--port P] [--name N] [--m M]
//   shapecast --join HOST:PORT [--name N] [--level full|N|P%] [--fingerprint HEX]
//
// --host starts hosting MESH at once (the basis is computed in the background), or a saved session file (its mesh,
// m, shape and undo history; --m is then the file's), --join joins a session at once;
// a password is asked for in the Host…/Join… dialogs only (never on the command line, where others can read it).
// With no arguments at all, the window hosts the default mesh (first_start.h: the fetched dragon, else another
// fetched mesh, else a generated torus) on port 47100 (any free port if taken) with a default handle and anchors,
// the lock requested and the Drag tool active. --demo is demo.h. With MESH, the mesh is loaded (viewed) at start-up.
// With --screenshot, the first rendered frame of the viewport is saved to FILE and the program exits: 0 on success, 1
// when MESH could not be loaded, 2 when the image could not be written, 64 for bad arguments. Load errors then go to
// stderr instead of a dialog. --demo --screenshot-dir is demo_screenshots.h: exit 0 when every PNG was written, 2
// otherwise (the reason on stderr).

#include "app/gui/demo.h"
#include "app/gui/demo_screenshots.h"
#include "app/gui/first_start.h"
#include "app/gui/host_dialog.h"
#include "app/gui/join_dialog.h"
#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/session_controller.h"
#include "session/net/tls_identity.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QImage>
#include <QRegularExpression>
#include <QSize>
#include <QSurfaceFormat>
#include <QTimer>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <span>
#include <string_view>

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

/// "HOST:PORT" (HOST may be a name, an IPv4 address or a bracketed IPv6 address) into (host, port).
std::optional<std::pair<QString, quint16>> parseHostPort(const QString& text) {
  static const QRegularExpression pattern(QStringLiteral("^(\\[[^\\]]+\\]|[^:\\s]+):(\\d{1,5})$"));
  const QRegularExpressionMatch match = pattern.match(text);
  if (!match.hasMatch()) return std::nullopt;
  const uint port = match.captured(2).toUInt();
  if (port == 0 || port > 65535) return std::nullopt;
  QString host = match.captured(1);
  if (host.startsWith(QLatin1Char('['))) host = host.mid(1, host.size() - 2);
  return std::pair<QString, quint16>(host, static_cast<quint16>(port));
}

/// "--level": "full", a vertex count N, or a percentage "P%" (0 < P ≤ 100) of the host's vertices.
bool parseLevel(const QString& text, sc::app::JoinSettings& settings) {
  if (text == QLatin1String("full")) return true;
  bool ok = false;
  if (text.endsWith(QLatin1Char('%'))) {
    const double percent = text.chopped(1).toDouble(&ok);
    if (!ok || !(percent > 0.0) || percent > 100.0) return false;
    if (percent < 100.0) settings.levelFraction = percent / 100.0;
    return true;
  }
  const uint vertices = text.toUInt(&ok);
  if (!ok) return false;
  settings.level = vertices;
  return true;
}

}  // namespace

int main(int argc, char* argv[]) {
  // --help and --version print and exit inside QApplication's parser: they must work without a display too.
  const std::span<char*> arguments(argv, static_cast<std::size_t>(argc));
  const bool onlyPrints = std::any_of(arguments.begin() + 1, arguments.end(), [](const char* a) {
    const std::string_view arg(a);
    return arg == "--help" || arg == "-h" || arg == "-?" || arg == "--help-all" || arg == "--version" || arg == "-v";
  });
  if (onlyPrints) qputenv("QT_QPA_PLATFORM", "offscreen");
  QSurfaceFormat::setDefaultFormat(sc::app::MeshViewport::preferredSurfaceFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName(QStringLiteral("ShapeCast"));
  QApplication::setApplicationName(QStringLiteral("shapecast"));
  QApplication::setApplicationVersion(QStringLiteral(SHAPECAST_VERSION));

  QCommandLineParser parser;
  parser.setApplicationDescription(
      QStringLiteral("ShapeCast: deform a triangle mesh (OFF, OBJ, PLY, STL) together with others, live, over the "
                     "network: host a session, join one, or open MESH on its own."));
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
  const QCommandLineOption hostOption(QStringLiteral("host"), QStringLiteral("Host a session sharing <mesh>."),
                                      QStringLiteral("mesh"));
  const QCommandLineOption joinOption(QStringLiteral("join"), QStringLiteral("Join the session at <host:port>."),
                                      QStringLiteral("host:port"));
  const QCommandLineOption nameOption(QStringLiteral("name"), QStringLiteral("Your display name in the session."),
                                      QStringLiteral("name"));
  const QCommandLineOption levelOption(
      QStringLiteral("level"),
      QStringLiteral("Display resolution when joining: full, a vertex count, or a percentage such as 20%."),
      QStringLiteral("level"), QStringLiteral("full"));
  const QCommandLineOption fingerprintOption(
      QStringLiteral("fingerprint"),
      QStringLiteral("With --join: the host's SHA-256 certificate fingerprint (64 hex digits, colons optional); "
                     "without it the first fingerprint seen for host:port is remembered and a changed one refused."),
      QStringLiteral("hex"));
  const QCommandLineOption portOption(QStringLiteral("port"),
                                      QStringLiteral("TCP port to host on (default 47100; 0 = any free port)."),
                                      QStringLiteral("port"), QStringLiteral("47100"));
  const QCommandLineOption frequenciesOption(QStringLiteral("m"),
                                             QStringLiteral("Number of frequencies when hosting (default 100)."),
                                             QStringLiteral("m"), QStringLiteral("100"));
  const QCommandLineOption demoOption(
      QStringLiteral("demo"),
      QStringLiteral("Open a host and two client windows (full and 5% resolution, 10% emulated loss) on loopback, "
                     "sharing MESH or the default mesh."));
  const QCommandLineOption screenshotDirOption(
      QStringLiteral("screenshot-dir"),
      QStringLiteral("With --demo: drag on the host for a while, save the windows as PNG images into <dir>, exit."),
      QStringLiteral("dir"));
  const QCommandLineOption afterOption(
      QStringLiteral("after"),
      QStringLiteral("With --screenshot-dir: seconds of dragging before the images (default 20)."),
      QStringLiteral("seconds"), QStringLiteral("20"));
  parser.addOptions({hostOption, joinOption, nameOption, levelOption, fingerprintOption, portOption, frequenciesOption,
                     demoOption, screenshotDirOption, afterOption});
  parser.process(app);

  const QStringList positional = parser.positionalArguments();
  const bool screenshot = parser.isSet(screenshotOption);
  const std::optional<QSize> viewportSize = parseSize(parser.value(sizeOption));
  if (positional.size() > 1 || !viewportSize) {
    std::fprintf(stderr, "%s\n", qUtf8Printable(parser.helpText()));
    return kExitUsage;
  }
  const auto usageError = [](const QString& message) {
    std::fprintf(stderr, "shapecast: %s\n", qUtf8Printable(message));
    return kExitUsage;
  };
  if (parser.isSet(hostOption) && parser.isSet(joinOption)) {
    return usageError(QStringLiteral("--host and --join cannot be used together"));
  }
  if (parser.isSet(screenshotDirOption) && !parser.isSet(demoOption)) {
    return usageError(QStringLiteral("--screenshot-dir needs --demo"));
  }
  if (parser.isSet(demoOption)) {
    if (parser.isSet(hostOption) || parser.isSet(joinOption) || screenshot) {
      return usageError(QStringLiteral("--demo cannot be used with --host, --join or --screenshot"));
    }
    sc::app::DemoOptions options;
    if (!positional.isEmpty()) options.meshPath = positional.first();
    const bool shots = parser.isSet(screenshotDirOption);
    options.errorDialogs = !shots;
    sc::app::DemoScreenshotOptions shotOptions;
    shotOptions.directory = parser.value(screenshotDirOption);
    bool ok = false;
    shotOptions.afterSeconds = parser.value(afterOption).toDouble(&ok);
    if (!ok || !(shotOptions.afterSeconds >= 1.0) || shotOptions.afterSeconds > 600.0) {
      return usageError(QStringLiteral("--after takes seconds from 1 to 600"));
    }
    sc::app::Demo demo(options);
    QObject::connect(&demo, &sc::app::Demo::failed,
                     [](const QString& message) { std::fprintf(stderr, "shapecast: %s\n", qUtf8Printable(message)); });
    sc::app::DemoScreenshots screenshots(demo, shotOptions);
    QObject::connect(&screenshots, &sc::app::DemoScreenshots::finished, [](bool written, const QString& message) {
      if (!written) std::fprintf(stderr, "shapecast: %s\n", qUtf8Printable(message));
      QCoreApplication::exit(written ? 0 : kExitScreenshotFailed);
    });
    if (!demo.start()) return kExitLoadFailed;
    if (shots) screenshots.start();
    return QApplication::exec();
  }
  std::optional<sc::app::HostSettings> hostSettings;
  std::optional<sc::app::JoinSettings> joinSettings;
  const QString name = parser.value(nameOption).trimmed();
  if (parser.isSet(hostOption)) {
    sc::app::HostSettings settings;
    settings.meshPath = parser.value(hostOption);
    bool ok = false;
    const uint port = parser.value(portOption).toUInt(&ok);
    if (!ok || port > 65535) return usageError(QStringLiteral("--port takes a number from 0 to 65535"));
    settings.port = static_cast<quint16>(port);
    settings.m = parser.value(frequenciesOption).toInt(&ok);
    if (!ok) return usageError(QStringLiteral("--m takes a number"));
    settings.name = name.isEmpty() ? QStringLiteral("host") : name;
    const QString problem = sc::app::validateHostSettings(settings);
    if (!problem.isEmpty()) return usageError(problem);
    hostSettings = settings;
  }
  if (parser.isSet(joinOption)) {
    const auto address = parseHostPort(parser.value(joinOption));
    if (!address) return usageError(QStringLiteral("--join takes HOST:PORT, e.g. 192.168.1.20:47100"));
    sc::app::JoinSettings settings;
    settings.host = address->first;
    settings.port = address->second;
    settings.name = name.isEmpty() ? qEnvironmentVariable("USER", QStringLiteral("guest")) : name;
    if (!parseLevel(parser.value(levelOption), settings)) {
      return usageError(QStringLiteral("--level takes full, a vertex count or a percentage such as 20%"));
    }
    if (parser.isSet(fingerprintOption)) {
      const std::optional<QByteArray> pinned = sc::session::parseFingerprint(parser.value(fingerprintOption));
      if (!pinned) return usageError(QStringLiteral("--fingerprint takes 64 hex digits (colons or spaces allowed)"));
      settings.fingerprint = *pinned;
    }
    const QString problem = sc::app::validateJoinSettings(settings);
    if (!problem.isEmpty()) return usageError(problem);
    joinSettings = settings;
  }

  sc::app::MainWindow window;
  window.setErrorDialogsEnabled(!screenshot);
  QObject::connect(&window, &sc::app::MainWindow::loadFailed, [](const QString&, const QString& message) {
    std::fprintf(stderr, "shapecast: %s\n", qUtf8Printable(message));
  });
  const bool loaded = positional.isEmpty() || window.openMesh(positional.first());
  const bool firstStart = positional.isEmpty() && !hostSettings && !joinSettings && !screenshot;
  if (firstStart) {
    QString error;
    sc::app::HostSettings settings;
    settings.meshPath = sc::app::defaultMeshOrGenerated(sc::app::defaultMeshFolders(), &error);
    settings.port = sc::app::availablePort(settings.port);
    settings.name = name.isEmpty() ? QStringLiteral("host") : name;
    if (settings.meshPath.isEmpty()) {
      std::fprintf(stderr, "shapecast: no default mesh: %s\n", qUtf8Printable(error));
    } else {
      sc::app::hostReadyToDrag(window, settings);
    }
  }
  if (hostSettings) window.hostSession(*hostSettings);
  if (joinSettings) window.joinSession(*joinSettings);
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
