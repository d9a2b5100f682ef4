#pragma once
// What the shapecast-cli subcommands share: the basis options (--m, --cache-dir, --no-cache, --json, --solver),
// command-line parsing with the common usage errors, and mesh loading / basis computation that report failures on
// stderr.
//
// Exit codes, the same for every subcommand: 0 ok, 1 the mesh could not be loaded, 2 bad usage (or bad input
// file other than the mesh), 3 the basis could not be computed, 4 a network/session failure.

#include "model/mesh_loader.h"
#include "spectral/basis_pipeline.h"

#include <QCommandLineOption>
#include <QCommandLineParser>
#include <QJsonObject>
#include <QString>
#include <QStringList>

#include <filesystem>
#include <functional>
#include <optional>

namespace sc::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitMeshError = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitBasisError = 3;
inline constexpr int kExitNetwork = 4;  ///< could not listen / connect, refused by the host, or the session failed

/// The basis-related options every subcommand accepts, as parsed.
struct BasisArguments {
  int m = 100;                                    ///< --m: number of harmonics (≥ 1).
  std::optional<std::filesystem::path> cacheDir;  ///< --cache-dir, the per-user default, or nullopt (--no-cache).
  bool json = false;                              ///< --json: one JSON object on stdout.
  /// --solver slices|lanczos|hierarchical: the eigensolver (default slices; see spectral::BasisSolver).
  spectral::BasisSolver solver = spectral::BasisSolver::Lanczos;
};

/// What a subcommand's one positional argument is.
enum class SubcommandKind {
  Mesh,   ///< MESH, plus the basis options --m, --no-cache, --cache-dir, --json and --solver
  Peer,   ///< HOST:PORT of a running host, plus --json (no basis options: the host owns the basis)
  Relay,  ///< no positional argument (the broker and session are options), plus --json
};

/// A QCommandLineParser for one subcommand ("shapecast-cli NAME"), with --help, one positional argument (MESH or
/// HOST:PORT) and the options of its kind; the subcommand adds its own options with parser().addOption() before
/// parse().
class SubcommandParser {
 public:
  /// @param name  the subcommand as typed ("basis"), used in messages.
  /// @param description  one line for --help.
  SubcommandParser(const QString& name, const QString& description, SubcommandKind kind = SubcommandKind::Mesh);

  QCommandLineParser& parser() { return m_parser; }
  const QCommandLineParser& parser() const { return m_parser; }
  const QString& name() const { return m_name; }

  /// Parses `arguments` (those after the subcommand name). On --help prints the help and sets exitCode = 0; on a
  /// parse error, a MESH count other than one, a bad --m or --solver prints why and the help to stderr and sets
  /// exitCode = 2.
  /// @return true when the command should run (exitCode untouched).
  bool parse(const QStringList& arguments, int& exitCode);

  /// The MESH argument (after a successful parse()).
  QString meshPath() const;
  /// The HOST:PORT argument of a Peer command, split (after a successful parse(), which checks it).
  QString peerHost() const { return m_peerHost; }
  quint16 peerPort() const { return m_peerPort; }

  /// The basis options (after a successful parse()).
  const BasisArguments& basisArguments() const { return m_basis; }

  /// Prints "shapecast-cli NAME: message" on stderr.
  void error(const QString& message) const;

 private:
  bool parsePeerAddress(int& exitCode);

  QString m_name;
  SubcommandKind m_kind;
  QString m_peerHost;
  quint16 m_peerPort = 0;
  QCommandLineParser m_parser;
  QCommandLineOption m_m;
  QCommandLineOption m_noCache;
  QCommandLineOption m_cacheDir;
  QCommandLineOption m_json;
  QCommandLineOption m_solver;
  BasisArguments m_basis;
};

/// Loads and cleans the mesh at `path` (model::loadMesh); on failure prints the error through `command.error()`.
/// @param[out] seconds  wall time of the load, if not null.
/// @return the mesh, or nullopt (exit code kExitMeshError).
std::optional<model::LoadedMesh> loadMeshOrReport(const SubcommandParser& command, const QString& path,
                                                  double* seconds = nullptr);

/// Computes (or loads from the cache) the basis of `mesh` with the parsed basis options (spectral::basisForMesh);
/// on failure prints the status and message through `command.error()`.
/// @return the computation; `result.ok()` false means exit code kExitBasisError.
spectral::BasisComputation basisOrReport(const SubcommandParser& command, const model::LoadedMesh& mesh);

/// Reads a session password from the first line of `path` (trailing whitespace and the newline removed), so that
/// it never appears in a process list or shell history. An unreadable or empty file prints why through
/// `command.error()` and returns nullopt (exit code kExitUsage).
std::optional<QString> readPasswordFile(const SubcommandParser& command, const QString& path);

/// Prints a finished report: one compact JSON line on stdout when the command was given --json, else through
/// `printText` (the subcommand's human-readable layout).
void printReport(const SubcommandParser& command, const QJsonObject& report,
                 const std::function<void(const QJsonObject&)>& printText);

}  // namespace sc::app
