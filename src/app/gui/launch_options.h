#pragma once
// The shapecast command line (main.cpp), parsed into what the application should start with:
//
//   shapecast                                   (first start: host the default mesh, ready to drag)
//   shapecast --demo [MESH]                     (one host and two client windows on loopback, demo.h)
//   shapecast --demo [MESH] --screenshot-dir DIR [--after SECONDS]   (README screenshots, then exit; run by the
//                                                sibling executable shapecast-screenshots, tools/screenshots/)
//   shapecast [MESH] [--screenshot FILE.png] [--size WIDTHxHEIGHT]
//   shapecast --host MESH|SESSION.shapecast [--port P] [--name N] [--m M]
//   shapecast --host MESH … --nats URL --session ID --nats-user U --nats-password-file F [--nats-ca CA.pem]
//                                                (relay, issue 18: launch_relay_options.h)
//   shapecast --join HOST:PORT [--name N] [--level full|N|P%] [--fingerprint HEX]
//   shapecast --watch nats://HOST:PORT --session ID --nats-user U (--nats-password P | --nats-password-file F)
//             [--pin HEX] [--level full|N|P%] [--nats-ca CA.pem]   (watch a relayed session read-only,
//                                                watch_settings.h; tls://HOST:PORT for TLS to the broker)
//
// A password is asked for in the Host…/Join… dialogs only (never on the command line, where others can read it).
// Parsing needs no QApplication and opens nothing: main() then builds the windows from a LaunchOptions.

#include "app/gui/demo.h"
#include "app/gui/launch_relay_options.h"
#include "app/gui/session_controller.h"
#include "app/gui/watch_settings.h"

#include <QCommandLineOption>
#include <QCommandLineParser>
#include <QCoreApplication>
#include <QSize>
#include <QString>
#include <QStringList>

#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace sc::app {

/// shapecast's exit codes (shapecast-screenshots' too): a mesh could not be loaded (or found, for the demo), an
/// image could not be written, bad arguments (EX_USAGE).
inline constexpr int kLaunchExitLoadFailed = 1;
inline constexpr int kLaunchExitImageFailed = 2;
inline constexpr int kLaunchExitNoOpenGl = 3;  ///< the display offers no OpenGL 3.3 core context
inline constexpr int kLaunchExitPortBusy = 4;  ///< --host's TCP port is in use (said before any work, naming it)
inline constexpr int kLaunchExitUsage = 64;

/// What shapecast was asked to do, checked (every field consistent with the others).
struct LaunchOptions {
  QString meshPath;                       ///< the MESH argument (empty: none): viewed at start-up, or the demo's mesh
  QString name;                           ///< --name, trimmed (empty: not given; host/join hold the default used)
  std::optional<HostSettings> host;       ///< --host: host at once (validateHostSettings() passed)
  std::optional<JoinSettings> join;       ///< --join: join at once (validateJoinSettings() passed)
  std::optional<WatchSettings> watch;     ///< --watch: watch through NATS at once (validateWatchSettings() passed)
  std::optional<QString> screenshotFile;  ///< --screenshot: save the first frame there and exit
  QSize viewportSize{1024, 768};          ///< --size, for --screenshot
  bool demo = false;                      ///< --demo (never with host, join or screenshotFile)
  std::optional<QString> screenshotDirectory;  ///< --screenshot-dir (only with demo)
  double afterSeconds = 20.0;                  ///< --after: seconds of dragging before the demo's screenshots, 1..600

  /// No mesh, session or screenshot asked for: host the default mesh, ready to drag (first_start.h).
  [[nodiscard]] bool firstStart() const {
    return meshPath.isEmpty() && !host && !join && !watch && !screenshotFile && !demo;
  }
};

/// A command line that cannot run: exit code kLaunchExitUsage after printing `message` ("shapecast: " before it), or
/// the help text when `showHelp` (a wrong number of arguments, a malformed --size).
struct LaunchError {
  QString message;
  bool showHelp = false;
};

/// shapecast's options on a QCommandLineParser (help and version included).
class LaunchParser {
 public:
  LaunchParser();

  /// The underlying parser: main() calls process() on it, so that --help, --help-all, --version and unknown
  /// options print and exit as Qt does (exit 0, or 1 for an unknown option), then options().
  QCommandLineParser& commandLine() { return m_parser; }
  [[nodiscard]] QString helpText() const { return m_parser.helpText(); }

  /// Interprets what commandLine() has parsed (process() or parse()). Checks, in this order: the argument count
  /// and --size; --host with --join; --screenshot-dir without --demo; --demo with --host, --join or --screenshot;
  /// --after; then the host's (--port 0..65535, --m a number, validateHostSettings()) and the join's (HOST:PORT
  /// as parseHostAddress() takes it, --level, --fingerprint, validateJoinSettings()), then the watch's (--watch with
  /// --host, --join or --demo; --session, the password file, --pin, --level, validateWatchSettings()). The first
  /// problem wins.
  [[nodiscard]] std::variant<LaunchOptions, LaunchError> options() const;

  /// For main(), once the QApplication exists: names it (organisation "ShapeCast", application "shapecast": the
  /// settings and caches it uses; `version` for --version), lets process() act on --help, --version and unknown
  /// options as Qt does, then options(). A LaunchError is printed on stderr (the help text, or "shapecast: " and
  /// the message). @return the options, or nullopt: exit with kLaunchExitUsage.
  std::optional<LaunchOptions> processApplication(const QCoreApplication& app, const QString& version);

  /// parse(arguments) (arguments[0] is the program) then options(); a parse error of Qt's (unknown option,
  /// missing value) becomes a LaunchError with Qt's text. --help and --version are not acted on here.
  std::variant<LaunchOptions, LaunchError> parse(const QStringList& arguments);

 private:
  [[nodiscard]] std::optional<LaunchError> readDemo(LaunchOptions& options) const;
  [[nodiscard]] std::optional<LaunchError> readHost(LaunchOptions& options) const;
  [[nodiscard]] std::optional<LaunchError> readJoin(LaunchOptions& options) const;
  [[nodiscard]] std::optional<LaunchError> readWatch(LaunchOptions& options) const;

  QCommandLineParser m_parser;
  QCommandLineOption m_screenshot, m_size, m_host, m_join, m_name, m_level, m_fingerprint, m_port, m_m, m_demo,
      m_screenshotDir, m_after, m_watch, m_pin;

  // --- the relay through NATS (issue 18): a host's --nats and the credentials a viewer (--watch) shares
  RelayLaunchOptions m_relay;
};

/// argv for QApplication with the options of ours that a Qt platform plugin would take first joined to their
/// value: X11's plugin takes "--name NAME" (as "-name") for its window-manager class name before any parser of ours
/// sees it, so "--name bob" becomes "--name=bob" (which the plugin leaves alone). Every other argument, argv[0]
/// included, is kept as it is. Cost: O(argc).
std::vector<std::string> shieldedArguments(std::span<char* const> argv);

/// LaunchParser().parse(arguments): the testable whole of shapecast's argument handling.
std::variant<LaunchOptions, LaunchError> parseLaunchArguments(const QStringList& arguments);

/// The demo's options from a --demo command line: its MESH (empty: the default mesh), and error dialogs unless
/// screenshots are taken (their failures then go to stderr).
DemoOptions demoOptions(const LaunchOptions& options);

/// "--level": "full", a vertex count N, or a percentage "P%" (0 < P ≤ 100) of the host's vertices, into
/// settings.level / settings.levelFraction. False for anything else.
bool parseLevel(const QString& text, JoinSettings& settings);

/// "WIDTHxHEIGHT" with 1 to 5 digits each, both > 0; nullopt otherwise.
std::optional<QSize> parseSize(const QString& text);

}  // namespace sc::app
