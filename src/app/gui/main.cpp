// shapecast: the desktop application. The command line is launch_options.h; this file only builds the windows.
//
// --host starts hosting MESH at once (the basis is computed in the background), or a saved session file (its mesh,
// m, shape and undo history; --m is then the file's), --join joins a session at once.
// With no arguments at all, the window hosts the default mesh (first_start.h: the fetched dragon, else another
// fetched mesh, else a generated torus) on port 47100 (any free port if taken, said on stderr and in the status
// bar) with a default handle and anchors,
// the lock requested and the Drag tool active. --demo is demo.h. With MESH, the mesh is loaded (viewed) at start-up.
// With --screenshot, the first rendered frame of the viewport is saved to FILE and the program exits: 0 on success, 1
// when MESH could not be loaded, 2 when the image could not be written, 3 when the display offers no OpenGL 3.3 (said
// on stderr, in any mode), 64 for bad arguments. --host on a TCP port in use exits 4 at once, naming the port on
// stderr (the port is held from then on, before the window and the basis: port_reservation.h). Load errors then go to
// stderr instead of a dialog. --demo --screenshot-dir runs the sibling executable shapecast-screenshots with the
// same arguments (tools/screenshots/: README-screenshot automation is no part of the application): exit 0 when every
// PNG was written, 2 otherwise (the reason on stderr), 2 also when shapecast-screenshots cannot be run.

#include "app/common/legacy_store.h"
#include "app/common/sibling_executable.h"
#include "app/gui/app_theme.h"
#include "app/gui/demo.h"
#include "app/gui/event_loop_stalls.h"
#include "app/gui/first_start.h"
#include "app/gui/launch_options.h"
#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/view_actions.h"
#include "app/gui/viewport/renderer_defaults.h"
#include "session/net/nats_client.h"
#include "session/net/tls_identity.h"

#include <QApplication>
#include <QImage>
#include <QSettings>
#include <QSurfaceFormat>
#include <QTimer>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace {

using sc::app::kLaunchExitImageFailed;
using sc::app::kLaunchExitLoadFailed;
using sc::app::kLaunchExitNoOpenGl;
using sc::app::kLaunchExitPortBusy;
using sc::app::kLaunchExitUsage;
constexpr int kFirstFrameTimeoutMs = 10000;

void printError(const QString& message) { std::fprintf(stderr, "shapecast: %s\n", qUtf8Printable(message)); }

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
    QCoreApplication::exit(saved ? 0 : kLaunchExitImageFailed);
  };
  QObject::connect(
      viewport, &sc::app::MeshViewport::frameSwapped, viewport, [grabAndQuit] { QTimer::singleShot(0, grabAndQuit); },
      Qt::SingleShotConnection);
  QObject::connect(timeout, &QTimer::timeout, viewport, grabAndQuit);
  timeout->start(kFirstFrameTimeoutMs);
}

int runDemo(const sc::app::LaunchOptions& options) {
  sc::app::Demo demo(sc::app::demoOptions(options));
  QObject::connect(&demo, &sc::app::Demo::failed, printError);
  if (!demo.start()) return kLaunchExitLoadFailed;
  return QApplication::exec();
}

// The main window: first start, MESH viewed, --host, --join, or --screenshot.
int runWindow(const sc::app::LaunchOptions& options) {
  // --host's port first: a busy one is an error now, not after the basis (the window path does the same).
  std::optional<sc::app::PortReservation> hostPort;
  if (options.host) {
    QString error;
    hostPort = sc::app::PortReservation::take(options.host->port, &error);
    if (!hostPort) {
      printError(error);
      return kLaunchExitPortBusy;
    }
  }
  sc::app::MainWindow window;
  window.setErrorDialogsEnabled(!options.screenshotFile);
  window.viewActions()->rememberUpAxes();
  if (!options.screenshotFile) window.viewActions()->rememberLayout();  // a screenshot's window keeps its size
  QObject::connect(&window, &sc::app::MainWindow::loadFailed,
                   [](const QString&, const QString& message) { printError(message); });
  // A mesh with nothing else to do (no screenshot, no session) is read on a worker once the window shows, with
  // progress and Cancel in the status bar as File → Open: the million-vertex dragon takes about 2 s to read, which
  // left the user without a window. A screenshot or a session needs the mesh first.
  const bool readInBackground =
      !options.meshPath.isEmpty() && !options.screenshotFile && !options.host && !options.join && !options.watch;
  const bool loaded = options.meshPath.isEmpty() || readInBackground || window.openMesh(options.meshPath);
  if (options.firstStart()) {
    QString error;
    sc::app::HostSettings settings;
    settings.meshPath = sc::app::defaultMeshOrGenerated(sc::app::defaultMeshFolders(), &error);
    const quint16 preferred = settings.port;
    settings.port = sc::app::availablePort(preferred);
    if (settings.port != preferred) {  // nobody chose the port: take a free one, and say so
      printError(
          QStringLiteral("TCP port %1 is in use: hosting on a free port (the status bar says which).").arg(preferred));
    }
    QSettings store;
    settings.name = sc::app::firstStartName(options.name, sc::app::RecentSessions::load(store));
    if (settings.meshPath.isEmpty()) {
      std::fprintf(stderr, "shapecast: no default mesh: %s\n", qUtf8Printable(error));
    } else {
      sc::app::hostReadyToDrag(window, settings);
    }
  }
  if (options.host) window.hostSession(*options.host, std::move(*hostPort));
  if (options.join) window.joinSession(*options.join);
  if (options.watch) window.watchSession(*options.watch);
  if (!options.screenshotFile) {
    window.show();
    if (readInBackground) window.loadMeshInBackground(options.meshPath);
    return QApplication::exec();
  }
  if (!loaded) {
    return kLaunchExitLoadFailed;
  }
  window.viewport()->setFixedSize(options.viewportSize);
  window.show();
  saveFirstFrameAndQuit(window.viewport(), *options.screenshotFile);
  return QApplication::exec();
}

}  // namespace

int main(int argc, char* argv[]) {
  sc::session::keepOpenSslStateUntilExit();  // before anything uses OpenSSL (the relay's TLS threads at exit)
  // --help and --version print and exit inside QApplication's parser: they must work without a display too.
  const std::span<char*> arguments(argv, static_cast<std::size_t>(argc));
  const bool onlyPrints = std::any_of(arguments.begin() + 1, arguments.end(), [](const char* a) {
    const std::string_view arg(a);
    return arg == "--help" || arg == "-h" || arg == "-?" || arg == "--help-all" || arg == "--version" || arg == "-v";
  });
  if (onlyPrints) qputenv("QT_QPA_PLATFORM", "offscreen");
  QSurfaceFormat::setDefaultFormat(sc::app::RendererDefaults::preferredSurfaceFormat());
  // Our options that a platform plugin would take first (X11: --name) are joined to their values. The strings live
  // as long as the QApplication, which keeps pointers to them.
  std::vector<std::string> shielded = sc::app::shieldedArguments(arguments);
  std::vector<char*> shieldedArgv;
  for (std::string& argument : shielded) shieldedArgv.push_back(argument.data());
  shieldedArgv.push_back(nullptr);
  // The arguments before QApplication takes out the options it knows, for shapecast-screenshots.
  const std::vector<char*> given(shieldedArgv.begin() + 1, shieldedArgv.end() - 1);
  int shieldedArgc = static_cast<int>(shielded.size());
  QApplication app(shieldedArgc, shieldedArgv.data());
  sc::app::LaunchParser parser;
  const std::optional<sc::app::LaunchOptions> parsed =
      parser.processApplication(app, QStringLiteral(SHAPECAST_VERSION));
  if (!parsed) return kLaunchExitUsage;
  sc::app::migrateLegacyStoreIntoThisOne(sc::session::defaultTlsIdentityDirectory());
  const sc::app::LaunchOptions& options = *parsed;
  if (const QString problem = sc::app::RendererDefaults::openGlProblem(); !problem.isEmpty()) {
    printError(problem);
    return kLaunchExitNoOpenGl;
  }
  sc::app::applySystemColorScheme();
  // SHAPECAST_STALL_MS=N: say on stderr each time the window's event loop stood still for N ms or more (and, from
  // MainWindow, each session level's install time on the GUI thread and its first paint's stages).
  bool stallsAsked = false;
  const int stallMs = qEnvironmentVariableIntValue("SHAPECAST_STALL_MS", &stallsAsked);
  std::optional<sc::app::EventLoopStalls> stalls;
  if (stallsAsked && stallMs > 0) stalls.emplace(std::chrono::milliseconds(stallMs), true);
  if (options.screenshotDirectory) {
    printError(sc::app::execSibling(QStringLiteral("shapecast-screenshots"), given) +
               QStringLiteral(" (--screenshot-dir: build the target shapecast-screenshots, tools/screenshots/)"));
    return kLaunchExitImageFailed;
  }
  return options.demo ? runDemo(options) : runWindow(options);
}
