#include "app/cli/basis_command.h"

#include "app/cli/peak_memory.h"
#include "model/cache_location.h"
#include "model/mesh_loader.h"
#include "spectral/basis_pipeline.h"

#include <QCommandLineParser>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTextStream>

#include <chrono>
#include <optional>

namespace sc::app {
namespace {

struct BasisArguments {
  QString meshPath;
  int m = 100;
  std::optional<std::filesystem::path> cacheDir;
  bool json = false;
};

/// Parses the subcommand's arguments; returns std::nullopt (after printing why) on bad usage or --help.
std::optional<BasisArguments> parseArguments(const QStringList& arguments, int& exitCode) {
  QCommandLineParser parser;
  parser.setApplicationDescription(QStringLiteral("Compute the manifold harmonic basis of a mesh."));
  parser.addHelpOption();
  parser.addPositionalArgument(QStringLiteral("MESH"), QStringLiteral("mesh file (.off .obj .ply .stl)"));
  const QCommandLineOption mOption(QStringLiteral("m"), QStringLiteral("number of harmonics (default 100)"),
                                   QStringLiteral("count"), QStringLiteral("100"));
  const QCommandLineOption noCache(QStringLiteral("no-cache"), QStringLiteral("always solve; neither read nor write"));
  const QCommandLineOption cacheDir(QStringLiteral("cache-dir"), QStringLiteral("cache folder (default: per user)"),
                                    QStringLiteral("dir"));
  const QCommandLineOption json(QStringLiteral("json"), QStringLiteral("print one JSON object on stdout"));
  parser.addOptions({mOption, noCache, cacheDir, json});

  QTextStream err(stderr);
  exitCode = 2;
  if (!parser.parse(QStringList{QStringLiteral("shapecast-cli basis")} + arguments)) {
    err << "shapecast-cli basis: " << parser.errorText() << "\n\n" << parser.helpText();
    return std::nullopt;
  }
  if (parser.isSet(QStringLiteral("help"))) {
    QTextStream(stdout) << parser.helpText();
    exitCode = 0;
    return std::nullopt;
  }
  if (parser.positionalArguments().size() != 1) {
    err << "shapecast-cli basis: expected exactly one MESH argument\n\n" << parser.helpText();
    return std::nullopt;
  }
  BasisArguments out;
  out.meshPath = parser.positionalArguments().constFirst();
  bool numeric = false;
  out.m = parser.value(mOption).toInt(&numeric);
  if (!numeric || out.m < 1) {
    err << "shapecast-cli basis: --m must be a positive integer\n";
    return std::nullopt;
  }
  out.json = parser.isSet(json);
  if (!parser.isSet(noCache))
    out.cacheDir = parser.isSet(cacheDir) ? std::filesystem::path(parser.value(cacheDir).toStdString())
                                          : model::basisCacheDirectory();
  return out;
}

QJsonObject cleaningJson(const model::MeshCleanReport& r) {
  return {{QStringLiteral("merged_duplicate_vertices"), r.mergedDuplicateVertices},
          {QStringLiteral("dropped_repeated_index_faces"), r.droppedRepeatedIndexFaces},
          {QStringLiteral("dropped_zero_area_faces"), r.droppedZeroAreaFaces},
          {QStringLiteral("dropped_duplicate_faces"), r.droppedDuplicateFaces},
          {QStringLiteral("dropped_unreferenced_vertices"), r.droppedUnreferencedVertices},
          {QStringLiteral("non_manifold_edges"), r.nonManifoldEdges},
          {QStringLiteral("boundary_loops"), r.boundaryLoops}};
}

QJsonObject report(const BasisArguments& args, const model::LoadedMesh& mesh, const spectral::BasisComputation& c,
                   double loadSeconds) {
  const spectral::HarmonicBasis& basis = c.result.basis;
  QJsonArray eigenvalues;
  for (double lambda : basis.eigenvalues) eigenvalues.append(lambda);
  return {{QStringLiteral("mesh"), args.meshPath},
          {QStringLiteral("vertices"), static_cast<qint64>(mesh.V.rows())},
          {QStringLiteral("faces"), static_cast<qint64>(mesh.F.rows())},
          {QStringLiteral("components"), mesh.cleaning.components},
          {QStringLiteral("cleaning"), cleaningJson(mesh.cleaning)},
          {QStringLiteral("m"), static_cast<qint64>(basis.size())},
          {QStringLiteral("load_s"), loadSeconds},
          {QStringLiteral("operator_s"), c.operatorSeconds},
          {QStringLiteral("eigensolve_s"), c.eigensolveSeconds},
          {QStringLiteral("total_s"), c.totalSeconds},
          {QStringLiteral("peak_rss_mb"), peakResidentMegabytes()},
          {QStringLiteral("orthonormality_error"), spectral::orthonormalityError(basis.vectors, c.operators.mass)},
          {QStringLiteral("shift"), basis.shift},
          {QStringLiteral("solves"), c.result.operatorApplications},
          {QStringLiteral("eigenvalues"), eigenvalues},
          {QStringLiteral("cached"), c.cached},
          {QStringLiteral("cache"), QString::fromLatin1(spectral::toString(c.cacheStatus))},
          {QStringLiteral("cache_file"), QString::fromStdString(c.cacheFile.string())}};
}

void printText(const QJsonObject& r) {
  QTextStream out(stdout);
  const QJsonObject cleaning = r[QStringLiteral("cleaning")].toObject();
  QStringList cleaningParts;
  for (auto it = cleaning.begin(); it != cleaning.end(); ++it)
    if (it.value().toInt() != 0) cleaningParts << it.key() + QLatin1Char('=') + QString::number(it.value().toInt());
  QStringList firstEigenvalues;
  const QJsonArray eigenvalues = r[QStringLiteral("eigenvalues")].toArray();
  for (qsizetype k = 0; k < std::min<qsizetype>(5, eigenvalues.size()); ++k)
    firstEigenvalues << QString::number(eigenvalues[k].toDouble(), 'g', 8);
  auto line = [&out](const char* key, const QString& value) {
    out << qSetFieldWidth(22) << Qt::left << key << qSetFieldWidth(0) << value << '\n';
  };
  auto number = [&r](const char* key, int precision = 4) {
    return QString::number(r[QLatin1String(key)].toDouble(), 'g', precision);
  };
  line("mesh", r[QStringLiteral("mesh")].toString());
  line("vertices", number("vertices", 12));
  line("faces", number("faces", 12));
  line("components", number("components", 12));
  line("cleaning", cleaningParts.isEmpty() ? QStringLiteral("nothing to clean") : cleaningParts.join(QLatin1Char(' ')));
  line("m", number("m", 12));
  line("load_s", number("load_s"));
  line("operator_s", number("operator_s"));
  line("eigensolve_s", number("eigensolve_s"));
  line("total_s", number("total_s"));
  line("peak_rss_mb", number("peak_rss_mb"));
  line("orthonormality_error", number("orthonormality_error", 3));
  line("eigenvalues[0..4]", firstEigenvalues.join(QLatin1Char(' ')));
  line("cached", r[QStringLiteral("cached")].toBool() ? QStringLiteral("yes") : QStringLiteral("no"));
  line("cache_file", r[QStringLiteral("cache_file")].toString());
}

}  // namespace

int runBasisCommand(const QStringList& arguments) {
  int exitCode = 0;
  const std::optional<BasisArguments> args = parseArguments(arguments, exitCode);
  if (!args) return exitCode;

  QTextStream err(stderr);
  const auto loadStart = std::chrono::steady_clock::now();
  const model::MeshLoadResult loaded = model::loadMesh(args->meshPath.toStdString());
  const double loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - loadStart).count();
  if (const auto* error = std::get_if<model::MeshError>(&loaded)) {
    err << "shapecast-cli basis: " << QString::fromStdString(error->message) << '\n';
    return 1;
  }
  const auto& mesh = std::get<model::LoadedMesh>(loaded);

  spectral::BasisOptions options;
  options.m = args->m;
  const spectral::BasisComputation computation = spectral::basisForMesh(mesh.V, mesh.F, options, args->cacheDir);
  if (!computation.result.ok()) {
    err << "shapecast-cli basis: " << spectral::toString(computation.result.status) << ": "
        << QString::fromStdString(computation.result.message) << '\n';
    return 3;
  }
  const QJsonObject r = report(*args, mesh, computation, loadSeconds);
  if (args->json)
    QTextStream(stdout) << QJsonDocument(r).toJson(QJsonDocument::Compact) << '\n';
  else
    printText(r);
  return 0;
}

}  // namespace sc::app
