// shapecast-bench-basis: manifold-harmonic-basis time for every mesh in assets/meshes, median of N runs.
//
// Each run is a separate `shapecast-cli basis MESH --no-cache --json` process, so the peak memory is per mesh.
// Prints a table and writes it, with the machine description, into docs/benchmarks.md (section basis-bench).
// Usage: shapecast-bench-basis [--repeats 3] [--m 100] [--meshes DIR] [--out FILE]

#include "experiments/report/machine_info.h"
#include "experiments/report/markdown_section.h"

#include <QCommandLineParser>
#include <QCoreApplication>
#include <QDateTime>
#include <QDir>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QTextStream>

#include <algorithm>
#include <optional>
#include <vector>

namespace {

struct MeshFigures {
  QString name;
  QJsonObject first;  ///< one full report (sizes, components, orthonormality)
  std::vector<double> total, operators, eigensolve, peakMb;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

std::optional<QJsonObject> runCli(const QString& cli, const QString& mesh, int m) {
  QProcess process;
  process.start(cli, {QStringLiteral("basis"), mesh, QStringLiteral("--no-cache"), QStringLiteral("--json"),
                      QStringLiteral("--m"), QString::number(m)});
  if (!process.waitForFinished(600000) || process.exitCode() != 0) {
    QTextStream(stderr) << "failed on " << mesh << ": " << process.readAllStandardError() << '\n';
    return std::nullopt;
  }
  return QJsonDocument::fromJson(process.readAllStandardOutput()).object();
}

QString tableOf(const std::vector<MeshFigures>& meshes) {
  QString t = QStringLiteral(
      "| mesh | vertices | faces | components | operators (s) | eigensolve (s) | total (s) | peak RSS (MB) | "
      "max abs(HᵀMH − I) |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const MeshFigures& f : meshes)
    t += QStringLiteral("| %1 | %2 | %3 | %4 | %5 | %6 | **%7** | %8 | %9 |\n")
             .arg(f.name)
             .arg(f.first[QStringLiteral("vertices")].toInt())
             .arg(f.first[QStringLiteral("faces")].toInt())
             .arg(f.first[QStringLiteral("components")].toInt())
             .arg(median(f.operators), 0, 'f', 3)
             .arg(median(f.eigensolve), 0, 'f', 2)
             .arg(median(f.total), 0, 'f', 2)
             .arg(*std::max_element(f.peakMb.begin(), f.peakMb.end()), 0, 'f', 0)
             .arg(f.first[QStringLiteral("orthonormality_error")].toDouble(), 0, 'e', 1);
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
  const QDir dir(parser.value(meshes));
  for (const QFileInfo& file : dir.entryInfoList(
           {QStringLiteral("*.off"), QStringLiteral("*.ply"), QStringLiteral("*.obj"), QStringLiteral("*.stl")},
           QDir::Files, QDir::Name)) {
    MeshFigures f{file.fileName(), {}, {}, {}, {}, {}};
    for (int run = 0; run < parser.value(repeats).toInt(); ++run) {
      const auto report = runCli(cli, file.filePath(), m);
      if (!report) return 1;
      if (run == 0) f.first = *report;
      f.total.push_back((*report)[QStringLiteral("total_s")].toDouble());
      f.operators.push_back((*report)[QStringLiteral("operator_s")].toDouble());
      f.eigensolve.push_back((*report)[QStringLiteral("eigensolve_s")].toDouble());
      f.peakMb.push_back((*report)[QStringLiteral("peak_rss_mb")].toDouble());
      log << file.fileName() << " run " << run + 1 << ": total " << f.total.back() << " s\n" << Qt::flush;
    }
    figures.push_back(f);
  }
  if (figures.empty()) {
    QTextStream(stderr) << "no meshes in " << dir.path() << " (run scripts/fetch-meshes.sh)\n";
    return 1;
  }

  const QString body = QStringLiteral(
                           "## Manifold harmonic basis (m = %1)\n\nMeasured %2 with `scripts/bench.sh` "
                           "(median of %3 runs, each a fresh `shapecast-cli basis MESH --no-cache --json` "
                           "process; load time excluded).\n\nMachine: %4\n\n%5\n")
                           .arg(m)
                           .arg(QDateTime::currentDateTimeUtc().toString(Qt::ISODate))
                           .arg(parser.value(repeats))
                           .arg(sc::report::machineDescription(), tableOf(figures));
  log << '\n' << body;
  if (!sc::report::writeMarkdownSection(parser.value(out), QStringLiteral("basis-bench"), body)) return 1;
  log << "written to " << parser.value(out) << '\n';
  return 0;
}
