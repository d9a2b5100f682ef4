#include "app/gui/launch_options.h"

#include "app/common/host_address.h"
#include "app/common/legacy_store.h"
#include "app/gui/host_dialog.h"
#include "app/gui/join_dialog.h"
#include "session/net/tls_identity.h"
#include "session/wire/relay_message.h"

#include <QRegularExpression>

#include <cstdio>

namespace sc::app {

namespace {

QCommandLineOption option(const char* name, const char* description, const char* valueName = nullptr,
                          const char* defaultValue = nullptr) {
  QCommandLineOption result(QString::fromLatin1(name), QString::fromUtf8(description));
  if (valueName != nullptr) result.setValueName(QString::fromLatin1(valueName));
  if (defaultValue != nullptr) result.setDefaultValue(QString::fromLatin1(defaultValue));
  return result;
}

LaunchError usage(const char* message) { return LaunchError{QString::fromUtf8(message), false}; }

}  // namespace

LaunchParser::LaunchParser()
    : m_screenshot(option("screenshot", "Save the first rendered frame to <file> (PNG) and exit.", "file")),
      m_size(option("size", "Viewport size for --screenshot (default 1024x768).", "WIDTHxHEIGHT", "1024x768")),
      m_host(option("host", "Host a session sharing <mesh>.", "mesh")),
      m_join(option("join", "Join the session at <host:port>.", "host:port")),
      m_name(option("name", "Your display name in the session.", "name")),
      m_level(option("level", "Display resolution when joining: full, a vertex count, or a percentage such as 20%.",
                     "level", "full")),
      m_fingerprint(option("fingerprint",
                           "With --join: the host's SHA-256 certificate fingerprint (64 hex digits, colons optional); "
                           "without it the first fingerprint seen for host:port is remembered and a changed one "
                           "refused.",
                           "hex")),
      m_port(option("port", "TCP port to host on (default 47100; 0 = any free port).", "port", "47100")),
      m_m(option("m", "Number of frequencies when hosting (default 100).", "m", "100")),
      m_demo(option("demo",
                    "Open a host and two client windows (full and 5% resolution, 10% emulated loss) on loopback, "
                    "sharing MESH or the default mesh.")),
      m_screenshotDir(option("screenshot-dir",
                             "With --demo: drag on the host for a while, save the windows as PNG images into <dir>, "
                             "exit.",
                             "dir")),
      m_after(option("after", "With --screenshot-dir: seconds of dragging before the images (default 20).", "seconds",
                     "20")),
      m_watch(option("watch",
                     "Watch a session relayed through the NATS server at <url> (read-only; no host "
                     "connection).",
                     "url")),
      m_pin(option("pin", "With --watch: the host's SHA-256 certificate fingerprint (default: trust the first).",
                   "hex")) {
  m_parser.setApplicationDescription(
      QStringLiteral("ShapeCast: deform a triangle mesh (OFF, OBJ, PLY, STL) together with others, live, over the "
                     "network: host a session, join one, or open MESH on its own."));
  m_parser.addHelpOption();
  m_parser.addVersionOption();
  m_parser.addPositionalArgument(QStringLiteral("mesh"), QStringLiteral("Mesh file to open."),
                                 QStringLiteral("[MESH]"));
  m_parser.addOptions({m_screenshot, m_size, m_host, m_join, m_name, m_level, m_fingerprint, m_port, m_m, m_demo,
                       m_screenshotDir, m_after, m_watch, m_pin});
  m_relay.addTo(m_parser);
}

std::optional<LaunchOptions> LaunchParser::processApplication(const QCoreApplication& app, const QString& version) {
  nameApplication(version);
  m_parser.process(app);
  std::variant<LaunchOptions, LaunchError> parsed = options();
  if (auto* launch = std::get_if<LaunchOptions>(&parsed)) return std::move(*launch);
  const LaunchError& error = std::get<LaunchError>(parsed);
  if (error.showHelp) {
    std::fprintf(stderr, "%s\n", qUtf8Printable(m_parser.helpText()));
  } else {
    std::fprintf(stderr, "shapecast: %s\n", qUtf8Printable(error.message));
  }
  return std::nullopt;
}

std::variant<LaunchOptions, LaunchError> LaunchParser::parse(const QStringList& arguments) {
  if (!m_parser.parse(arguments)) return LaunchError{m_parser.errorText(), false};
  return options();
}

std::variant<LaunchOptions, LaunchError> LaunchParser::options() const {
  LaunchOptions options;
  const QStringList positional = m_parser.positionalArguments();
  const std::optional<QSize> size = parseSize(m_parser.value(m_size));
  if (positional.size() > 1 || !size) return LaunchError{{}, true};
  options.meshPath = positional.value(0);
  options.viewportSize = *size;
  if (m_parser.isSet(m_screenshot)) options.screenshotFile = m_parser.value(m_screenshot);
  options.name = m_parser.value(m_name).trimmed();
  if (m_parser.isSet(m_host) && m_parser.isSet(m_join)) return usage("--host and --join cannot be used together");
  if (m_parser.isSet(m_screenshotDir) && !m_parser.isSet(m_demo)) return usage("--screenshot-dir needs --demo");
  std::optional<LaunchError> problem = readDemo(options);
  if (!problem && !m_parser.isSet(m_host) && !m_parser.isSet(m_watch) && m_relay.given(m_parser))
    problem = usage("--nats, --session, --nats-user and --nats-password[-file] need --host (or --watch URL)");
  if (!problem && m_parser.isSet(m_watch) && m_relay.urlGiven(m_parser))
    problem = usage("--watch takes the NATS URL itself: leave out --nats");
  if (!problem && m_parser.isSet(m_host)) problem = readHost(options);
  if (!problem && m_parser.isSet(m_join)) problem = readJoin(options);
  if (!problem && m_parser.isSet(m_watch)) problem = readWatch(options);
  if (problem) return *problem;
  return options;
}

std::optional<LaunchError> LaunchParser::readDemo(LaunchOptions& options) const {
  if (!m_parser.isSet(m_demo)) return std::nullopt;
  if (m_parser.isSet(m_host) || m_parser.isSet(m_join) || m_parser.isSet(m_watch) || m_parser.isSet(m_screenshot))
    return usage("--demo cannot be used with --host, --join, --watch or --screenshot");
  options.demo = true;
  if (m_parser.isSet(m_screenshotDir)) options.screenshotDirectory = m_parser.value(m_screenshotDir);
  bool ok = false;
  options.afterSeconds = m_parser.value(m_after).toDouble(&ok);
  if (!ok || !(options.afterSeconds >= 1.0) || options.afterSeconds > 600.0)
    return usage("--after takes seconds from 1 to 600");
  return std::nullopt;
}

std::optional<LaunchError> LaunchParser::readHost(LaunchOptions& options) const {
  HostSettings settings;
  settings.meshPath = m_parser.value(m_host);
  bool ok = false;
  const uint port = m_parser.value(m_port).toUInt(&ok);
  if (!ok || port > 65535) return usage("--port takes a number from 0 to 65535");
  settings.port = static_cast<quint16>(port);
  settings.m = m_parser.value(m_m).toInt(&ok);
  if (!ok) return usage("--m takes a number");
  settings.name = options.name.isEmpty() ? QStringLiteral("host") : options.name;
  const QString problem = validateHostSettings(settings);
  if (!problem.isEmpty()) return LaunchError{problem, false};
  auto relay = m_relay.read(m_parser);  // issue 18 item 3: also relay through NATS
  if (const QString* why = std::get_if<QString>(&relay)) return LaunchError{*why, false};
  settings.relay = std::get<std::optional<HostRelaySettings>>(std::move(relay));
  options.host = settings;
  return std::nullopt;
}

std::optional<LaunchError> LaunchParser::readJoin(LaunchOptions& options) const {
  const std::optional<HostAddress> address = parseHostAddress(m_parser.value(m_join));
  if (!address) return usage("--join takes HOST:PORT, e.g. 192.168.1.20:47100");
  JoinSettings settings;
  settings.host = address->host;
  settings.port = address->port;
  settings.name = options.name.isEmpty() ? qEnvironmentVariable("USER", QStringLiteral("guest")) : options.name;
  if (!parseLevel(m_parser.value(m_level), settings))
    return usage("--level takes full, a vertex count or a percentage such as 20%");
  if (m_parser.isSet(m_fingerprint)) {
    const std::optional<QByteArray> pinned = session::parseFingerprint(m_parser.value(m_fingerprint));
    if (!pinned) return usage("--fingerprint takes 64 hex digits (colons or spaces allowed)");
    settings.fingerprint = *pinned;
  }
  const QString problem = validateJoinSettings(settings);
  if (!problem.isEmpty()) return LaunchError{problem, false};
  options.join = settings;
  return std::nullopt;
}

std::optional<LaunchError> LaunchParser::readWatch(LaunchOptions& options) const {
  if (m_parser.isSet(m_host) || m_parser.isSet(m_join) || m_parser.isSet(m_demo))
    return usage("--watch cannot be used with --host, --join or --demo");
  WatchSettings settings;
  settings.url = m_parser.value(m_watch);
  const std::variant<RelayCredentials, QString> credentials = m_relay.readCredentials(m_parser);
  if (const QString* problem = std::get_if<QString>(&credentials)) return LaunchError{*problem, false};
  const RelayCredentials& given = std::get<RelayCredentials>(credentials);
  settings.sessionId = given.sessionId;
  settings.user = given.user;
  settings.password = given.password;
  settings.caFile = given.caFile;
  if (m_parser.isSet(m_pin)) {
    const std::optional<QByteArray> pinned = session::parseFingerprint(m_parser.value(m_pin));
    if (!pinned) return usage("--pin takes 64 hex digits (colons or spaces allowed)");
    settings.pin = *pinned;
  }
  JoinSettings level;
  if (!parseLevel(m_parser.value(m_level), level))
    return usage("--level takes full, a vertex count or a percentage such as 20%");
  settings.level = level.level;
  settings.levelFraction = level.levelFraction;
  const QString problem = validateWatchSettings(settings);
  if (!problem.isEmpty()) return LaunchError{problem, false};
  options.watch = settings;
  return std::nullopt;
}

std::variant<LaunchOptions, LaunchError> parseLaunchArguments(const QStringList& arguments) {
  return LaunchParser().parse(arguments);
}

DemoOptions demoOptions(const LaunchOptions& options) {
  DemoOptions demo;
  demo.meshPath = options.meshPath;
  demo.errorDialogs = !options.screenshotDirectory;
  return demo;
}

bool parseLevel(const QString& text, JoinSettings& settings) {
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

std::optional<QSize> parseSize(const QString& text) {
  static const QRegularExpression pattern(QStringLiteral("^(\\d{1,5})x(\\d{1,5})$"));
  const QRegularExpressionMatch match = pattern.match(text);
  if (!match.hasMatch()) return std::nullopt;
  const QSize size(match.captured(1).toInt(), match.captured(2).toInt());
  return size.width() > 0 && size.height() > 0 ? std::optional<QSize>(size) : std::nullopt;
}

std::vector<std::string> shieldedArguments(std::span<char* const> argv) {
  std::vector<std::string> out;
  out.reserve(argv.size());
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string_view arg(argv[i]);
    if (i > 0 && (arg == "--name" || arg == "--session") && i + 1 < argv.size()) {
      // QGuiApplication also takes "--session ID" (X11 session management) before our parser: --session=ID.
      out.push_back(std::string(arg) + "=" + std::string(argv[++i]));
    } else {
      out.emplace_back(arg);
    }
  }
  return out;
}

}  // namespace sc::app
