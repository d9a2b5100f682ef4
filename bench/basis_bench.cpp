// shapecast-bench-basis: manifold-harmonic-basis time per mesh, median of N runs, with the project's eigensolvers
// (--solvers, default spectrum slicing, the product's default, then Lanczos, the reference, and the hierarchical
// subspace iteration) and the SciPy peer side by side in the same run.
//
// Each project run is a separate `shapecast-cli basis MESH --no-cache --json --solver S` process, so the peak memory
// is per mesh and solver. The SciPy peer (bench/scipy_basis_peer.py, when a Python with SciPy is found) solves the
// same S h = λ M h (the same cleaned mesh's operators, the same shift σ, m pairs) written to a temporary folder
// (bench/scipy_peer_problem.h); it runs each of its set-ups in its own process. Solvers and the peer alternate run
// by run so that they share the machine's noise. Without SciPy the project's figures are printed alone, with a note.
// Prints the tables and writes them, with the machine and load average, into docs/benchmarks.md (--section).
// Usage: shapecast-bench-basis [--repeats 3] [--m 100] [--meshes DIR | --mesh FILE …]
//          [--solvers slices,lanczos,hierarchical] [--python EXE] [--no-scipy] [--scipy-max-vertices 200000]
//          [--keep-problems DIR] [--out FILE] [--section basis-bench] [--title TEXT]

#include "experiments/report/machine_info.h"
#include "experiments/report/markdown_section.h"
#include "model/mesh_loader.h"
#include "scipy_peer_problem.h"
#include "scipy_peer_runner.h"
#include "spectral/laplace_operators.h"

#include <QCommandLineParser>
#include <QCoreApplication>
#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QTemporaryDir>
#include <QTextStream>

#include <algorithm>
#include <map>
#include <optional>
#include <variant>
#include <vector>

namespace {

/// The runs of one solver (or one SciPy set-up) on one mesh.
struct SolverFigures {
  QJsonObject first;  ///< one full report (sizes, components, orthonormality, residual)
  std::vector<double> operators, eigensolve, peakMb;
  bool accepted = true;  ///< SciPy: every run converged to the peer's acceptance bounds
};

struct MeshFigures {
  QString name;
  std::map<QString, SolverFigures> solvers;  ///< by --solvers name
  std::map<QString, SolverFigures> scipy;    ///< by SciPy set-up ("a", "b", …)
};

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

double peak(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

QString exponent(const QJsonObject& o, const char* key) {
  return o.contains(QLatin1String(key)) ? QString::number(o[QLatin1String(key)].toDouble(), 'e', 1)
                                        : QStringLiteral("–");
}

std::optional<QJsonObject> runCli(const QString& cli, const QString& mesh, int m, const QString& solver) {
  QProcess process;
  process.start(cli, {QStringLiteral("basis"), mesh, QStringLiteral("--no-cache"), QStringLiteral("--json"),
                      QStringLiteral("--m"), QString::number(m), QStringLiteral("--solver"), solver});
  if (!process.waitForFinished(600000) || process.exitCode() != 0) {
    QTextStream(stderr) << "failed on " << mesh << ": " << process.readAllStandardError() << '\n';
    return std::nullopt;
  }
  return QJsonDocument::fromJson(process.readAllStandardOutput()).object();
}

/// Writes the SciPy peer's problem for `mesh` into `folder`: the mesh cleaned as shapecast-cli does, its operators,
/// and σ and the eigenvalues of the project's `reference` report. False (reason on stderr) on failure.
bool writePeerProblem(const QString& mesh, const QJsonObject& reference, int m, const QString& folder) {
  QTextStream err(stderr);
  auto loaded = sc::model::loadMesh(mesh.toStdString());
  if (const auto* error = std::get_if<sc::model::MeshError>(&loaded)) {
    err << QString::fromStdString(error->message) << '\n';
    return false;
  }
  const auto& cleaned = std::get<sc::model::LoadedMesh>(loaded);
  const sc::spectral::LaplaceOperators ops = sc::spectral::laplaceOperators(cleaned.V, cleaned.F);
  if (ops.mass.size() != reference[QStringLiteral("vertices")].toInteger()) {
    err << mesh << ": the bench's cleaned mesh and shapecast-cli's differ in size\n";
    return false;
  }
  QString why;
  if (!sc::bench::writeScipyPeerProblem(folder, ops, m, reference[QStringLiteral("shift")].toDouble(),
                                        reference[QStringLiteral("eigenvalues")].toArray(), why)) {
    err << why << '\n';
    return false;
  }
  return true;
}

/// Adds one peer run's set-ups to `scipy`.
void addPeerRun(const QJsonObject& peer, std::map<QString, SolverFigures>& scipy, QTextStream& log) {
  for (const QJsonValue& value : peer[QStringLiteral("setups")].toArray()) {
    const QJsonObject s = value.toObject();
    SolverFigures& f = scipy[s[QStringLiteral("setup")].toString()];
    if (f.first.isEmpty()) f.first = s;
    const bool solved = s.contains(QStringLiteral("solve_s"));
    f.accepted = f.accepted && solved && s[QStringLiteral("accepted")].toBool();
    if (solved) {
      f.eigensolve.push_back(s[QStringLiteral("solve_s")].toDouble());
      f.peakMb.push_back(s[QStringLiteral("peak_rss_mb")].toDouble());
    }
    log << "  SciPy " << s[QStringLiteral("setup")].toString() << " (" << s[QStringLiteral("description")].toString()
        << "): "
        << (solved ? QString::number(s[QStringLiteral("solve_s")].toDouble(), 'f', 2) + QStringLiteral(" s")
                   : s[QStringLiteral("error")].toString())
        << '\n'
        << Qt::flush;
  }
}

/// One sentence for the report: which Python ran the peer, or why none did.
QString peerNote(bool skipped, const std::optional<sc::bench::ScipyPython>& scipy, const QStringList& candidates,
                 qint64 maxVertices) {
  if (skipped) return QStringLiteral("SciPy peer skipped (--no-scipy)");
  if (!scipy)
    return QStringLiteral("SciPy not found (`import scipy` failed with %1): project figures only")
        .arg(candidates.join(QStringLiteral(", ")));
  return QStringLiteral("SciPy peer: %1 with SciPy %2, `bench/scipy_basis_peer.py`, on meshes of at most %3 vertices")
      .arg(scipy->executable, scipy->scipyVersion, QString::number(maxVertices));
}

/// The accepted SciPy set-up with the lowest median solve time, or nullptr.
const std::pair<const QString, SolverFigures>* bestScipy(const MeshFigures& f) {
  const std::pair<const QString, SolverFigures>* best = nullptr;
  for (const auto& entry : f.scipy)
    if (entry.second.accepted && !entry.second.eigensolve.empty() &&
        (best == nullptr || median(entry.second.eigensolve) < median(best->second.eigensolve)))
      best = &entry;
  return best;
}

QString solverTable(const std::vector<MeshFigures>& meshes, const QStringList& solvers) {
  QString t = QStringLiteral(
      "| mesh | vertices | components | solver | operators (s) | eigensolve (s) | peak RSS (MB) | solves | sweeps | "
      "max residual | max abs(HᵀMH − I) | SciPy best (s) | SciPy set-up | SciPy peak RSS (MB) | speed-up vs SciPy |\n"
      "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|\n");
  for (const MeshFigures& f : meshes) {
    const auto* best = bestScipy(f);
    for (const QString& solver : solvers) {
      const SolverFigures& s = f.solvers.at(solver);
      const QJsonObject& r = s.first;
      const bool hierarchical = r[QStringLiteral("solver")].toString() == QLatin1String("hierarchical");
      const double eigensolve = median(s.eigensolve);
      t += QStringLiteral("| %1 | %2 | %3 | %4 | %5 | %6 | %7 | %8 | %9 | %10 | %11 | %12 | %13 | %14 | %15 |\n")
               .arg(f.name)
               .arg(r[QStringLiteral("vertices")].toInt())
               .arg(r[QStringLiteral("components")].toInt())
               .arg(solver == r[QStringLiteral("solver")].toString()
                        ? solver
                        : solver + QStringLiteral(" (ran ") + r[QStringLiteral("solver")].toString() + QLatin1Char(')'))
               .arg(median(s.operators), 0, 'f', 3)
               .arg(eigensolve, 0, 'f', 2)
               .arg(peak(s.peakMb), 0, 'f', 0)
               .arg(r[QStringLiteral("solves")].toInt())
               .arg(hierarchical ? QString::number(r[QStringLiteral("sweeps")].toInt()) : QStringLiteral("–"))
               .arg(exponent(r, "max_residual"), exponent(r, "orthonormality_error"),
                    best ? QString::number(median(best->second.eigensolve), 'f', 2) : QStringLiteral("–"),
                    best ? best->first : QStringLiteral("–"),
                    best ? QString::number(peak(best->second.peakMb), 'f', 0) : QStringLiteral("–"),
                    best ? QString::number(median(best->second.eigensolve) / std::max(1e-9, eigensolve), 'f', 1) +
                               QStringLiteral("×")
                         : QStringLiteral("–"));
    }
  }
  return t;
}

QString scipyTable(const std::vector<MeshFigures>& meshes, const QString& reference) {
  QString t = QStringLiteral(
                  "| mesh | SciPy set-up | solve (s) | peak RSS (MB) | of it loaded (MB) | max residual | "
                  "max abs(HᵀMH − I) | max eigenvalue difference to %1 |\n|---|---|---:|---:|---:|---:|---:|---:|\n")
                  .arg(reference);
  for (const MeshFigures& f : meshes)
    for (const auto& [key, s] : f.scipy)
      t += QStringLiteral("| %1 | %2: %3 | %4 | %5 | %6 | %7 | %8 | %9 |\n")
               .arg(f.name, key, s.first[QStringLiteral("description")].toString())
               .arg(s.eigensolve.empty() ? s.first[QStringLiteral("error")].toString()
                                         : QString::number(median(s.eigensolve), 'f', 2))
               .arg(peak(s.peakMb), 0, 'f', 0)
               .arg(s.first[QStringLiteral("loaded_rss_mb")].toDouble(), 0, 'f', 0)
               .arg(exponent(s.first, "max_residual"), exponent(s.first, "orthonormality_error"),
                    exponent(s.first, "max_eigenvalue_diff"));
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
  const QCommandLineOption meshFiles(
      QStringLiteral("mesh"), QStringLiteral("mesh file (repeatable; replaces --meshes)"), QStringLiteral("file"));
  const QCommandLineOption solversOption(QStringLiteral("solvers"),
                                         QStringLiteral("shapecast-cli --solver values, comma-separated; the first "
                                                        "one's σ and eigenvalues are the SciPy peer's reference"),
                                         QStringLiteral("list"), QStringLiteral("slices,lanczos,hierarchical"));
  const QCommandLineOption python(QStringLiteral("python"),
                                  QStringLiteral("Python with SciPy (default: the first of python3, /usr/bin/python3 "
                                                 "that imports scipy)"),
                                  QStringLiteral("exe"));
  const QCommandLineOption keepProblems(
      QStringLiteral("keep-problems"),
      QStringLiteral("write the SciPy peer's problems into DIR/MESH (kept, to run "
                     "bench/scipy_basis_peer.py by hand) instead of a temporary folder"),
      QStringLiteral("dir"));
  const QCommandLineOption scipyMax(QStringLiteral("scipy-max-vertices"),
                                    QStringLiteral("run the SciPy peer only on meshes with at most n vertices"),
                                    QStringLiteral("n"), QStringLiteral("200000"));
  const QCommandLineOption noScipy(QStringLiteral("no-scipy"), QStringLiteral("skip the SciPy peer"));
  const QCommandLineOption out(QStringLiteral("out"), QStringLiteral("Markdown file to update"), QStringLiteral("file"),
                               QStringLiteral(SHAPECAST_SOURCE_DIR "/docs/benchmarks.md"));
  const QCommandLineOption section(QStringLiteral("section"), QStringLiteral("generated section name in --out"),
                                   QStringLiteral("name"), QStringLiteral("basis-bench"));
  const QCommandLineOption title(QStringLiteral("title"),
                                 QStringLiteral("heading of the generated section (default: \"## Manifold harmonic "
                                                "basis (m = M)\")"),
                                 QStringLiteral("text"));
  parser.addOptions({repeats, mOption, meshes, meshFiles, solversOption, python, keepProblems, scipyMax, noScipy, out,
                     section, title});
  parser.process(app);

  const QString cli = QCoreApplication::applicationDirPath() + QStringLiteral("/shapecast-cli");
  const QString peerScript = QStringLiteral(SHAPECAST_SOURCE_DIR "/bench/scipy_basis_peer.py");
  const int m = parser.value(mOption).toInt();
  const QStringList solvers = parser.value(solversOption).split(QLatin1Char(','), Qt::SkipEmptyParts);
  if (solvers.isEmpty()) {
    QTextStream(stderr) << "--solvers is empty\n";
    return 1;
  }
  if (parser.value(repeats).toInt() < 1) {
    QTextStream(stderr) << "--repeats must be at least 1\n";
    return 1;
  }
  const qint64 scipyMaxVertices = parser.value(scipyMax).toLongLong();
  QTextStream log(stdout);

  // === step 1: the meshes, and the SciPy peer if there is a Python with SciPy
  QStringList paths = parser.values(meshFiles);
  if (paths.isEmpty()) {
    const QDir dir(parser.value(meshes));
    for (const QFileInfo& file : dir.entryInfoList(
             {QStringLiteral("*.off"), QStringLiteral("*.ply"), QStringLiteral("*.obj"), QStringLiteral("*.stl")},
             QDir::Files, QDir::Name))
      paths << file.filePath();
  }
  if (paths.isEmpty()) {
    QTextStream(stderr) << "no meshes in " << parser.value(meshes) << " (run scripts/fetch-meshes.sh)\n";
    return 1;
  }
  const QStringList pythonCandidates = parser.isSet(python)
                                           ? QStringList{parser.value(python)}
                                           : QStringList{QStringLiteral("python3"), QStringLiteral("/usr/bin/python3")};
  std::optional<sc::bench::ScipyPython> scipy;
  if (!parser.isSet(noScipy)) scipy = sc::bench::findScipyPython(pythonCandidates);
  const QString scipyNote = peerNote(parser.isSet(noScipy), scipy, pythonCandidates, scipyMaxVertices);
  log << scipyNote << '\n' << Qt::flush;

  // === step 2: runs, alternating solvers and the peer
  std::vector<MeshFigures> figures;
  const QString loadBefore = loadAverage();
  for (const QString& path : paths) {
    MeshFigures f{QFileInfo(path).fileName(), {}, {}};
    QTemporaryDir temporary;
    bool peerReady = false;  ///< the peer's problem folder is written
    const QString problem =
        parser.isSet(keepProblems) ? parser.value(keepProblems) + QLatin1Char('/') + f.name : temporary.path();
    for (int run = 0; run < parser.value(repeats).toInt(); ++run) {
      for (const QString& solver : solvers) {
        const auto report = runCli(cli, path, m, solver);
        if (!report) return 1;
        SolverFigures& sf = f.solvers[solver];
        if (run == 0) sf.first = *report;
        sf.operators.push_back((*report)[QStringLiteral("operator_s")].toDouble());
        sf.eigensolve.push_back((*report)[QStringLiteral("eigensolve_s")].toDouble());
        sf.peakMb.push_back((*report)[QStringLiteral("peak_rss_mb")].toDouble());
        log << f.name << " " << solver << " run " << run + 1 << ": eigensolve " << sf.eigensolve.back()
            << " s, max residual " << (*report)[QStringLiteral("max_residual")].toDouble() << '\n'
            << Qt::flush;
      }
      // A failing peer costs the mesh its SciPy figures (the table shows "–"), not the project's.
      if (!scipy) continue;
      const QJsonObject& reference = f.solvers[solvers.first()].first;
      if (run == 0)
        peerReady = reference[QStringLiteral("vertices")].toInteger() <= scipyMaxVertices && temporary.isValid() &&
                    QDir().mkpath(problem) && writePeerProblem(path, reference, m, problem);
      if (!peerReady) continue;
      QString why;
      const auto peer = sc::bench::runScipyPeer(*scipy, peerScript, problem, 3600 * 1000, why);
      if (!peer) {
        QTextStream(stderr) << f.name << ": " << why << " (no SciPy figures for this run)\n";
        continue;
      }
      log << f.name << " SciPy run " << run + 1 << ":\n";
      addPeerRun(*peer, f.scipy, log);
    }
    figures.push_back(std::move(f));
  }

  // === step 3: the tables
  const QString heading =
      parser.isSet(title) ? parser.value(title) : QStringLiteral("## Manifold harmonic basis (m = %1)").arg(m);
  const QString measured =
      QStringLiteral(
          "Measured %1 with `scripts/bench.sh` (median of %2 runs per solver, each a fresh `shapecast-cli basis MESH "
          "--no-cache --json --solver S` process, the solvers and the SciPy peer alternating; load time excluded; "
          "OPENBLAS_NUM_THREADS=%5; load average %6 before, %7 after). Max residual: ‖Sh − λMh‖ in the M⁻¹-norm over "
          "(|λ| + |σ|), the largest over the m pairs. %8.\n\nMachine: %3\n\n%4\n")
          .arg(QDateTime::currentDateTimeUtc().toString(Qt::ISODate), parser.value(repeats),
               sc::report::machineDescription(), solverTable(figures, solvers),
               qEnvironmentVariable("OPENBLAS_NUM_THREADS", QStringLiteral("unset (all cores)")), loadBefore,
               loadAverage(), scipyNote);
  QString body = heading + QStringLiteral("\n\n") + measured;
  if (scipy)
    body += QStringLiteral(
                "SciPy set-ups (each its own process; solve = factorisation + eigsh at ARPACK tol 1e-10, file loading "
                "excluded; "
                "peak RSS includes Python, SciPy and the loaded matrices; eigenvalue difference: max |λ − λ_ref| / "
                "(|λ_ref| + |σ|); SciPy best: the fastest set-up with residual and difference below 1e-6; speed-up "
                "vs SciPy = SciPy best / eigensolve):\n\n") +
            scipyTable(figures, solvers.first());
  log << '\n' << body;
  if (!sc::report::writeMarkdownSection(parser.value(out), parser.value(section), body)) return 1;
  log << "written to " << parser.value(out) << '\n';
  return 0;
}
