// shapecast-bench-basis: manifold-harmonic-basis time for every mesh in assets/meshes, median of N runs, with both
// eigensolvers side by side (Lanczos, the default and reference, and the hierarchical subspace iteration).
//
// Each run is a separate `shapecast-cli basis MESH --no-cache --json --solver S` process, so the peak memory is per
// mesh and solver; the two solvers alternate run by run so that they share the machine's noise.
// Prints a table and writes it, with the machine description, into docs/benchmarks.md (section basis-bench).
// Usage: shapecast-bench-basis [--repeats 3] [--m 100] [--meshes DIR] [--out FILE]

#include "experiments/report/machine_info.h"
#include "experiments/report/markdown_section.h"

#include <QCommandLineParser>
#include <QCoreApplication>
#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QTextStream>

#include <algorithm>
#include <optional>
#include <vector>

namespace {

/// The runs of one solver on one mesh.
struct SolverFigures {
  QJsonObject first;  ///< one full report (sizes, components, orthonormality, residual)
  std::vector<double> total, operators, eigensolve, peakMb;
};

struct MeshFigures {
  QString name;
  SolverFigures lanczos, hierarchical;
};

const char* const kSolvers[] = {"lanczos", "hierarchical"};

/// The first three fields of /proc/loadavg ("1.20 0.95 0.80"), or "unknown": the figures are only comparable
/// with the load they were measured under.
QString loadAverage() {
  QFile file(QStringLiteral("/proc/loadavg"));
  if (!file.open(QIODevice::ReadOnly)) return QStringLiteral("unknown");
  return QString::fromLatin1(file.readAll()).section(QLatin1Char(' '), 0, 2);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

std::optional<QJsonObject> runCli(const QString& cli, const QString& mesh, int m, const char* solver) {
  QProcess process;
  process.start(cli,
                {QStringLiteral("basis"), mesh, QStringLiteral("--no-cache"), QStringLiteral("--json"),
                 QStringLiteral("--m"), QString::number(m), QStringLiteral("--solver"), QString::fromLatin1(solver)});
  if (!process.waitForFinished(600000) || process.exitCode() != 0) {
    QTextStream(stderr) << "failed on " << mesh << ": " << process.readAllStandardError() << '\n';
    return std::nullopt;
  }
  return QJsonDocument::fromJson(process.readAllStandardOutput()).object();
}

double peak(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

QString tableOf(const std::vector<MeshFigures>& meshes) {
  QString t = QStringLiteral(
      "| mesh | vertices | components | operators (s) | Lanczos eigensolve (s) | hierarchical eigensolve (s) | "
      "speed-up | peak RSS L / H (MB) | solves L / H | sweeps | max residual L / H | max abs(HᵀMH − I) L / H |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const MeshFigures& f : meshes) {
    const QJsonObject& l = f.lanczos.first;
    const QJsonObject& h = f.hierarchical.first;
    t += QStringLiteral("| %1 | %2 | %3 | %4 | %5 | %6 | %7× | %8 / %9 | %15 / %16 | %10 | %11 / %12 | %13 / %14 |\n")
             .arg(f.name)
             .arg(l[QStringLiteral("vertices")].toInt())
             .arg(l[QStringLiteral("components")].toInt())
             .arg(median(f.hierarchical.operators), 0, 'f', 3)
             .arg(median(f.lanczos.eigensolve), 0, 'f', 2)
             .arg(median(f.hierarchical.eigensolve), 0, 'f', 2)
             .arg(median(f.lanczos.eigensolve) / std::max(1e-9, median(f.hierarchical.eigensolve)), 0, 'f', 1)
             .arg(peak(f.lanczos.peakMb), 0, 'f', 0)
             .arg(peak(f.hierarchical.peakMb), 0, 'f', 0)
             .arg(h[QStringLiteral("solver")].toString() == QLatin1String("hierarchical")
                      ? QString::number(h[QStringLiteral("sweeps")].toInt())
                      : QStringLiteral("(Lanczos: too small)"))
             .arg(l[QStringLiteral("max_residual")].toDouble(), 0, 'e', 1)
             .arg(h[QStringLiteral("max_residual")].toDouble(), 0, 'e', 1)
             .arg(l[QStringLiteral("orthonormality_error")].toDouble(), 0, 'e', 1)
             .arg(h[QStringLiteral("orthonormality_error")].toDouble(), 0, 'e', 1)
             .arg(l[QStringLiteral("solves")].toInt())
             .arg(h[QStringLiteral("solves")].toInt());
  }
  return t;
}

}  // namespace

int main(int argc, char* argv[]) {
  QCoreApplication app(argc, argv);
  QCommandLineParser parser;
  parser.addHelpOption();
  const QCommandLineOption repeats(QStringLiteral("repeats"), QStringLiteral("runs per mesh"), QStringLiteral("n"),
                                   QStringLiteral("3"));
  const QCommandLineOption mOption(QStringLiteral("m"), QStringLiteral("harmonics"), QStringLiteral("m"),
                                   QStringLiteral("100"));
  const QCommandLineOption meshes(QStringLiteral("meshes"), QStringLiteral("mesh folder"), QStringLiteral("dir"),
                                  QStringLiteral(SHAPECAST_ASSETS_DIR));
  const QCommandLineOption out(QStringLiteral("out"), QStringLiteral("Markdown file to update"), QStringLiteral("file"),
                               QStringLiteral(SHAPECAST_SOURCE_DIR "/docs/benchmarks.md"));
  parser.addOptions({repeats, mOption, meshes, out});
  parser.process(app);

  const QString cli = QCoreApplication::applicationDirPath() + QStringLiteral("/shapecast-cli");
  const int m = parser.value(mOption).toInt();
  QTextStream log(stdout);
  std::vector<MeshFigures> figures;
  const QString loadBefore = loadAverage();
  const QDir dir(parser.value(meshes));
  for (const QFileInfo& file : dir.entryInfoList(
           {QStringLiteral("*.off"), QStringLiteral("*.ply"), QStringLiteral("*.obj"), QStringLiteral("*.stl")},
           QDir::Files, QDir::Name)) {
    MeshFigures f{file.fileName(), {}, {}};
    for (int run = 0; run < parser.value(repeats).toInt(); ++run)
      for (const char* solver : kSolvers) {
        const auto report = runCli(cli, file.filePath(), m, solver);
        if (!report) return 1;
        SolverFigures& sf = solver == kSolvers[0] ? f.lanczos : f.hierarchical;
        if (run == 0) sf.first = *report;
        sf.total.push_back((*report)[QStringLiteral("total_s")].toDouble());
        sf.operators.push_back((*report)[QStringLiteral("operator_s")].toDouble());
        sf.eigensolve.push_back((*report)[QStringLiteral("eigensolve_s")].toDouble());
        sf.peakMb.push_back((*report)[QStringLiteral("peak_rss_mb")].toDouble());
        log << file.fileName() << " " << solver << " run " << run + 1 << ": eigensolve " << sf.eigensolve.back()
            << " s, max residual " << (*report)[QStringLiteral("max_residual")].toDouble() << '\n'
            << Qt::flush;
      }
    figures.push_back(f);
  }
  if (figures.empty()) {
    QTextStream(stderr) << "no meshes in " << dir.path() << " (run scripts/fetch-meshes.sh)\n";
    return 1;
  }

  const QString body = QStringLiteral(
                           "## Manifold harmonic basis (m = %1)\n\nMeasured %2 with `scripts/bench.sh` "
                           "(median of %3 runs per solver, each a fresh `shapecast-cli basis MESH --no-cache --json "
                           "--solver lanczos|hierarchical` process, the two solvers alternating; load time excluded; "
                           "OPENBLAS_NUM_THREADS=%6; load average %7 before, %8 after). Max residual: ‖Sh − λMh‖ in "
                           "the M⁻¹-norm over (|λ| + |σ|), the "
                           "largest over the m pairs.\n\nMachine: %4\n\n%5\n")
                           .arg(m)
                           .arg(QDateTime::currentDateTimeUtc().toString(Qt::ISODate))
                           .arg(parser.value(repeats))
                           .arg(sc::report::machineDescription(), tableOf(figures),
                                qEnvironmentVariable("OPENBLAS_NUM_THREADS", QStringLiteral("unset (all cores)")),
                                loadBefore, loadAverage());
  log << '\n' << body;
  if (!sc::report::writeMarkdownSection(parser.value(out), QStringLiteral("basis-bench"), body)) return 1;
  log << "written to " << parser.value(out) << '\n';
  return 0;
}
