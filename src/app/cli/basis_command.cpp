#include "app/cli/basis_command.h"

#include "app/cli/cli_common.h"
#include "app/cli/peak_memory.h"

#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTextStream>

#include <optional>

namespace sc::app {
namespace {

QJsonObject cleaningJson(const model::MeshCleanReport& r) {
  return {{QStringLiteral("merged_duplicate_vertices"), r.mergedDuplicateVertices},
          {QStringLiteral("dropped_repeated_index_faces"), r.droppedRepeatedIndexFaces},
          {QStringLiteral("dropped_zero_area_faces"), r.droppedZeroAreaFaces},
          {QStringLiteral("dropped_duplicate_faces"), r.droppedDuplicateFaces},
          {QStringLiteral("dropped_unreferenced_vertices"), r.droppedUnreferencedVertices},
          {QStringLiteral("non_manifold_edges"), r.nonManifoldEdges},
          {QStringLiteral("boundary_loops"), r.boundaryLoops}};
}

/// The solve computed it; a basis read from the cache is checked here.
double maxResidual(const spectral::BasisComputation& c) {
  return c.cached ? spectral::maxRelativeResidual(c.operators, c.result.basis) : c.result.maxResidual;
}

QJsonObject report(const QString& meshPath, const model::LoadedMesh& mesh, const spectral::BasisComputation& c,
                   double loadSeconds) {
  const spectral::HarmonicBasis& basis = c.result.basis;
  QJsonArray eigenvalues;
  for (double lambda : basis.eigenvalues) eigenvalues.append(lambda);
  return {{QStringLiteral("mesh"), meshPath},
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
          {QStringLiteral("max_residual"), maxResidual(c)},
          {QStringLiteral("solver"), QString::fromLatin1(c.cached ? "cache" : spectral::toString(c.result.solver))},
          {QStringLiteral("sweeps"), c.result.sweeps},
          {QStringLiteral("slices"), c.result.slices},
          {QStringLiteral("note"), QString::fromStdString(c.result.message)},
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
  line("solver", r[QStringLiteral("solver")].toString());
  line("solves", number("solves", 12));
  line("sweeps", number("sweeps", 12));
  line("slices", number("slices", 12));
  if (const QString note = r[QStringLiteral("note")].toString(); !note.isEmpty()) line("note", note);
  line("orthonormality_error", number("orthonormality_error", 3));
  line("max_residual", number("max_residual", 3));
  line("eigenvalues[0..4]", firstEigenvalues.join(QLatin1Char(' ')));
  line("cached", r[QStringLiteral("cached")].toBool() ? QStringLiteral("yes") : QStringLiteral("no"));
  line("cache_file", r[QStringLiteral("cache_file")].toString());
}

}  // namespace

int runBasisCommand(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("basis"), QStringLiteral("Compute the manifold harmonic basis of a mesh."));
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;

  double loadSeconds = 0.0;
  const std::optional<model::LoadedMesh> mesh = loadMeshOrReport(command, command.meshPath(), &loadSeconds);
  if (!mesh) return kExitMeshError;
  const spectral::BasisComputation computation = basisOrReport(command, *mesh);
  if (!computation.result.ok()) return kExitBasisError;
  const QJsonObject r = report(command.meshPath(), *mesh, computation, loadSeconds);
  printReport(command, r, printText);
  return kExitOk;
}

}  // namespace sc::app
