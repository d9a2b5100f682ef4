#pragma once
// What the shapecast-cli subcommands share: the basis options (--m, --cache-dir, --no-cache, --json), command-line
// parsing with the common usage errors, and mesh loading / basis computation that report failures on stderr.
//
// Exit codes, the same for every subcommand: 0 ok, 1 the mesh could not be loaded, 2 bad usage (or bad input
// file other than the mesh), 3 the basis could not be computed.

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

/// The basis-related options every subcommand accepts, as parsed.
struct BasisArguments {
  int m = 100;                                    ///< --m: number of harmonics (≥ 1).
  std::optional<std::filesystem::path> cacheDir;  ///< --cache-dir, the per-user default, or nullopt (--no-cache).
  bool json = false;                              ///< --json: one JSON object on stdout.
};

/// A QCommandLineParser for one subcommand ("shapecast-cli NAME"), with --help, one MESH positional argument and
/// the basis options; the subcommand adds its own options with parser().addOption() before parse().
class SubcommandParser {
 public:
  /// @param name  the subcommand as typed ("basis"), used in messages.
  /// @param description  one line for --help.
  SubcommandParser(const QString& name, const QString& description);

  QCommandLineParser& parser() { return m_parser; }
  const QCommandLineParser& parser() const { return m_parser; }
  const QString& name() const { return m_name; }

  /// Parses `arguments` (those after the subcommand name). On --help prints the help and sets exitCode = 0; on a
  /// parse error, a MESH count other than one or a bad --m prints why and the help to stderr and sets exitCode = 2.
  /// @return true when the command should run (exitCode untouched).
  bool parse(const QStringList& arguments, int& exitCode);

  /// The MESH argument (after a successful parse()).
  QString meshPath() const;

  /// The basis options (after a successful parse()).
  const BasisArguments& basisArguments() const { return m_basis; }

  /// Prints "shapecast-cli NAME: message" on stderr.
  void error(const QString& message) const;

 private:
  QString m_name;
  QCommandLineParser m_parser;
  QCommandLineOption m_m;
  QCommandLineOption m_noCache;
  QCommandLineOption m_cacheDir;
  QCommandLineOption m_json;
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

/// Prints a finished report: one compact JSON line on stdout when the command was given --json, else through
/// `printText` (the subcommand's human-readable layout).
void printReport(const SubcommandParser& command, const QJsonObject& report,
                 const std::function<void(const QJsonObject&)>& printText);

}  // namespace sc::app
