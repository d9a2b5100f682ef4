#include "app/cli/cli_common.h"

#include "app/common/host_address.h"
#include "model/cache_location.h"
#include "spectral/harmonic_basis.h"

#include <QFile>
#include <QJsonDocument>
#include <QTextStream>

#include <chrono>

namespace sc::app {

SubcommandParser::SubcommandParser(const QString& name, const QString& description, SubcommandKind kind)
    : m_name(name),
      m_kind(kind),
      m_m(QStringLiteral("m"), QStringLiteral("number of harmonics (default 100)"), QStringLiteral("count"),
          QStringLiteral("100")),
      m_noCache(QStringLiteral("no-cache"), QStringLiteral("always solve; neither read nor write")),
      m_cacheDir(QStringLiteral("cache-dir"), QStringLiteral("cache folder (default: per user)"),
                 QStringLiteral("dir")),
      m_json(QStringLiteral("json"), QStringLiteral("print one JSON object on stdout")),
      m_solver(QStringLiteral("solver"),
               QStringLiteral(
                   "eigensolver: slices (default; spectrum slicing: block Lanczos runs around several "
                   "shifts on parallel threads; Lanczos below 20,000 vertices, one block Lanczos run above 200,000), "
                   "lanczos (Spectra's, the reference), or hierarchical (coarse start + block subspace iteration to a "
                   "residual of 1e-6)"),
               QStringLiteral("name"), QStringLiteral("slices")) {
  m_parser.setApplicationDescription(description);
  m_parser.addHelpOption();
  if (kind == SubcommandKind::Mesh) {
    m_parser.addPositionalArgument(QStringLiteral("MESH"), QStringLiteral("mesh file (.off .obj .ply .stl)"));
    m_parser.addOptions({m_m, m_noCache, m_cacheDir, m_json, m_solver});
  } else if (kind == SubcommandKind::Peer) {
    m_parser.addPositionalArgument(QStringLiteral("HOST:PORT"), QStringLiteral("address and TCP port of the host"));
    m_parser.addOption(m_json);
  } else {
    m_parser.addOption(m_json);
  }
}

bool SubcommandParser::parse(const QStringList& arguments, int& exitCode) {
  QTextStream err(stderr);
  exitCode = kExitUsage;
  if (!m_parser.parse(QStringList{QStringLiteral("shapecast-cli ") + m_name} + arguments)) {
    err << "shapecast-cli " << m_name << ": " << m_parser.errorText() << "\n\n" << m_parser.helpText();
    return false;
  }
  if (m_parser.isSet(QStringLiteral("help"))) {
    QTextStream(stdout) << m_parser.helpText();
    exitCode = kExitOk;
    return false;
  }
  if (m_kind == SubcommandKind::Relay) {
    if (!m_parser.positionalArguments().isEmpty()) {
      err << "shapecast-cli " << m_name << ": takes no positional argument\n\n" << m_parser.helpText();
      return false;
    }
    m_basis.json = m_parser.isSet(m_json);
    exitCode = kExitOk;
    return true;
  }
  const QString positional = m_kind == SubcommandKind::Mesh ? QStringLiteral("MESH") : QStringLiteral("HOST:PORT");
  if (m_parser.positionalArguments().size() != 1) {
    err << "shapecast-cli " << m_name << ": expected exactly one " << positional << " argument\n\n"
        << m_parser.helpText();
    return false;
  }
  if (m_kind == SubcommandKind::Peer) return parsePeerAddress(exitCode);
  bool numeric = false;
  m_basis.m = m_parser.value(m_m).toInt(&numeric);
  if (!numeric || m_basis.m < 1) {
    error(QStringLiteral("--m must be a positive integer"));
    return false;
  }
  const QString solver = m_parser.value(m_solver);
  const std::optional<spectral::BasisSolver> chosen = spectral::basisSolverNamed(solver.toStdString());
  if (!chosen) {
    error(QStringLiteral("--solver must be lanczos, slices or hierarchical"));
    return false;
  }
  m_basis.solver = *chosen;
  m_basis.json = m_parser.isSet(m_json);
  m_basis.cacheDir.reset();
  if (!m_parser.isSet(m_noCache))
    m_basis.cacheDir = m_parser.isSet(m_cacheDir) ? std::filesystem::path(m_parser.value(m_cacheDir).toStdString())
                                                  : model::basisCacheDirectory();
  exitCode = kExitOk;
  return true;
}

bool SubcommandParser::parsePeerAddress(int& exitCode) {
  const QString address = m_parser.positionalArguments().constFirst();
  const std::optional<HostAddress> peer = parseHostAddress(address);
  if (!peer) {
    error(QStringLiteral("'%1' is not HOST:PORT (e.g. 127.0.0.1:47100)").arg(address));
    return false;
  }
  m_peerHost = peer->host;
  m_peerPort = peer->port;
  m_basis.json = m_parser.isSet(m_json);
  exitCode = kExitOk;
  return true;
}

std::optional<QString> readPasswordFile(const SubcommandParser& command, const QString& path) {
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly)) {
    command.error(QStringLiteral("cannot read the password file '%1': %2").arg(path, file.errorString()));
    return std::nullopt;
  }
  QByteArray line = file.readLine();
  QString password = QString::fromUtf8(line);
  line.fill('\0');  // the raw line is ours alone: overwritten before it is freed
  while (!password.isEmpty() && password.back().isSpace()) password.chop(1);
  if (password.isEmpty()) {
    command.error(QStringLiteral("the password file '%1' is empty (its first line is the password)").arg(path));
    return std::nullopt;
  }
  return password;
}

QString SubcommandParser::meshPath() const { return m_parser.positionalArguments().value(0); }

void SubcommandParser::error(const QString& message) const {
  QTextStream(stderr) << "shapecast-cli " << m_name << ": " << message << '\n';
}

std::optional<model::LoadedMesh> loadMeshOrReport(const SubcommandParser& command, const QString& path,
                                                  double* seconds) {
  const auto start = std::chrono::steady_clock::now();
  model::MeshLoadResult loaded = model::loadMesh(path.toStdString());
  if (seconds != nullptr) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (const auto* error = std::get_if<model::MeshError>(&loaded)) {
    command.error(QString::fromStdString(error->message));
    return std::nullopt;
  }
  return std::get<model::LoadedMesh>(std::move(loaded));
}

spectral::BasisComputation basisOrReport(const SubcommandParser& command, const model::LoadedMesh& mesh) {
  spectral::BasisOptions options;
  options.m = command.basisArguments().m;
  options.solver = command.basisArguments().solver;
  spectral::BasisComputation computation =
      spectral::basisForMesh(mesh.V, mesh.F, options, command.basisArguments().cacheDir);
  if (!computation.result.ok())
    command.error(QString::fromLatin1(spectral::toString(computation.result.status)) + QStringLiteral(": ") +
                  QString::fromStdString(computation.result.message));
  return computation;
}

void printReport(const SubcommandParser& command, const QJsonObject& report,
                 const std::function<void(const QJsonObject&)>& printText) {
  if (command.basisArguments().json)
    QTextStream(stdout) << QJsonDocument(report).toJson(QJsonDocument::Compact) << '\n';
  else
    printText(report);
}

}  // namespace sc::app
