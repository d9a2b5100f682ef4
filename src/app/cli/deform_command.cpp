#include "app/cli/deform_command.h"

#include "app/cli/cli_common.h"
#include "app/cli/drag_script.h"
#include "app/cli/level_output.h"
#include "model/mesh_writer.h"
#include "spectral/hausdorff.h"
#include "spectral/spectral_deformer.h"
#include "spectral/spectral_transform.h"

#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTextStream>

#include <algorithm>
#include <chrono>
#include <functional>

namespace sc::app {
namespace {

constexpr int kExitWriteError = 4;

/// The deform-specific options, as parsed.
struct DeformArguments {
  DragScript script;
  spectral::DeformationMode mode = spectral::DeformationMode::Linear;
  QString out;
  int level = 0;  ///< --level: 0 full resolution, 1–3 the default ladder, > 3 a vertex count.
};

/// The deform-specific options.
struct DeformOptions {
  QCommandLineOption script{QStringLiteral("script"), QStringLiteral("drag script (docs/drag-script.md)"),
                            QStringLiteral("file")};
  QCommandLineOption mode{QStringLiteral("mode"), QStringLiteral("linear or rigid (default linear)"),
                          QStringLiteral("mode"), QStringLiteral("linear")};
  QCommandLineOption out{QStringLiteral("out"),
                         QStringLiteral("output mesh (.off .obj .ply .stl; default MESH-deformed.off)"),
                         QStringLiteral("file")};
  QCommandLineOption level{QStringLiteral("level"),
                           QStringLiteral("output resolution: 0 full (default), 1/2/3 = 50/20/5 % of the vertices, "
                                          "> 3 a vertex count"),
                           QStringLiteral("N"), QStringLiteral("0")};
};

/// Reads --script, --mode, --out and --level (after command.parse()); prints why and returns nullopt on bad usage or
/// a bad script (exit code 2).
std::optional<DeformArguments> deformArguments(const SubcommandParser& command, const DeformOptions& options) {
  const QCommandLineParser& parser = command.parser();
  const QCommandLineOption &script = options.script, &mode = options.mode, &out = options.out;
  DeformArguments args;
  bool levelOk = false;
  args.level = parser.value(options.level).toInt(&levelOk);
  if (!levelOk || args.level < 0) {
    command.error(QStringLiteral("--level must be an integer ≥ 0, not '%1'").arg(parser.value(options.level)));
    return std::nullopt;
  }
  const QString modeName = parser.value(mode);
  if (modeName == QLatin1String("rigid"))
    args.mode = spectral::DeformationMode::Rigid;
  else if (modeName != QLatin1String("linear")) {
    command.error(QStringLiteral("--mode must be linear or rigid, not '%1'").arg(modeName));
    return std::nullopt;
  }
  if (!parser.isSet(script)) {
    command.error(QStringLiteral("--script DRAG.json is required"));
    return std::nullopt;
  }
  std::variant<DragScript, QString> parsed = readDragScript(parser.value(script));
  if (const auto* message = std::get_if<QString>(&parsed)) {
    command.error(*message);
    return std::nullopt;
  }
  args.script = std::get<DragScript>(std::move(parsed));
  args.out = parser.isSet(out) ? parser.value(out)
                               : QFileInfo(command.meshPath()).completeBaseName() + QStringLiteral("-deformed.off");
  const QString suffix = QFileInfo(args.out).suffix().toLower();
  if (!QStringList{QStringLiteral("off"), QStringLiteral("obj"), QStringLiteral("ply"), QStringLiteral("stl")}.contains(
          suffix)) {
    command.error(QStringLiteral("--out must end in .off .obj .ply or .stl: '%1'").arg(args.out));
    return std::nullopt;
  }
  return args;
}

/// What replaying the frames measured.
struct FrameRun {
  int frames = 0;
  double setupMs = 0.0;       ///< setConstraints(): forming and factoring the m×m system.
  double firstSolveUs = 0.0;  ///< the first frame (the rigid mode builds its clusters lazily).
  double medianSolveUs = 0.0;
  double maxSolveUs = 0.0;
  spectral::ConstraintResidual residual;  ///< of the last frame.
  Eigen::MatrixXd X;                      ///< the last frame's positions X̂ + HZ.
};

double microseconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double, std::micro>(d).count();
}

/// Runs every frame of the script; nullopt if the deformer rejects the constraint set (not expected: the set comes
/// from resolveConstraints(), which checks every index). `onFrame`, if set, gets each frame's Z after its timed solve.
std::optional<FrameRun> replay(const DragScript& script, const spectral::ConstraintSet& constraints,
                               const spectral::BasisComputation& basis, const Eigen::MatrixXd& rest,
                               spectral::DeformationMode mode,
                               const std::function<void(const Eigen::MatrixXd&)>& onFrame) {
  spectral::DeformerOptions options;
  options.mode = mode;
  spectral::SpectralDeformer deformer(basis.result.basis, basis.operators, rest, options);
  FrameRun run;
  const auto setupStart = std::chrono::steady_clock::now();
  if (!deformer.setConstraints(constraints)) return std::nullopt;
  run.setupMs = microseconds(std::chrono::steady_clock::now() - setupStart) / 1000.0;

  const double diagonal = spectral::boundingBoxDiagonal(rest);
  std::vector<spectral::HandleTransform> transforms(constraints.handles.size());
  std::vector<double> solveUs;
  for (double t : frameTimes(script)) {
    std::fill(transforms.begin(), transforms.end(), transformAt(poseAt(script, t), diagonal));
    const auto start = std::chrono::steady_clock::now();
    deformer.solve(transforms);
    solveUs.push_back(microseconds(std::chrono::steady_clock::now() - start));
    if (onFrame) onFrame(deformer.coefficients());
  }
  run.frames = static_cast<int>(solveUs.size());
  run.firstSolveUs = solveUs.front();
  run.maxSolveUs = *std::max_element(solveUs.begin(), solveUs.end());
  std::nth_element(solveUs.begin(), solveUs.begin() + solveUs.size() / 2, solveUs.end());
  run.medianSolveUs = solveUs[solveUs.size() / 2];
  run.residual = deformer.residual(transforms);
  run.X = spectral::reconstruct(rest, basis.result.basis.vectors, deformer.coefficients());
  return run;
}

std::size_t handleVertexCount(const spectral::ConstraintSet& constraints) {
  std::size_t count = 0;
  for (const spectral::HandleGroup& group : constraints.handles) count += group.vertices.size();
  return count;
}

QJsonObject report(const SubcommandParser& command, const DeformArguments& args, const model::LoadedMesh& mesh,
                   const spectral::ConstraintSet& constraints, const spectral::BasisComputation& basis,
                   const FrameRun& run) {
  const double diagonal = spectral::boundingBoxDiagonal(mesh.V);
  const auto pct = [diagonal](double d) { return spectral::percentOfDiagonal(d, diagonal); };
  const QJsonObject residual{{QStringLiteral("max_handle"), run.residual.maxHandle},
                             {QStringLiteral("rms_handle"), run.residual.rmsHandle},
                             {QStringLiteral("max_anchor"), run.residual.maxAnchor},
                             {QStringLiteral("max_handle_pct"), pct(run.residual.maxHandle)},
                             {QStringLiteral("max_anchor_pct"), pct(run.residual.maxAnchor)}};
  const bool rigid = args.mode == spectral::DeformationMode::Rigid;
  return {{QStringLiteral("mesh"), command.meshPath()},
          {QStringLiteral("vertices"), static_cast<qint64>(mesh.V.rows())},
          {QStringLiteral("m"), static_cast<qint64>(basis.result.basis.size())},
          {QStringLiteral("mode"), rigid ? QStringLiteral("rigid") : QStringLiteral("linear")},
          {QStringLiteral("handle_groups"), static_cast<qint64>(constraints.handles.size())},
          {QStringLiteral("handle_vertices"), static_cast<qint64>(handleVertexCount(constraints))},
          {QStringLiteral("anchors"), static_cast<qint64>(constraints.anchors.size())},
          {QStringLiteral("basis_s"), basis.totalSeconds},
          {QStringLiteral("cached"), basis.cached},
          {QStringLiteral("frames"), run.frames},
          {QStringLiteral("setup_ms"), run.setupMs},
          {QStringLiteral("first_solve_us"), run.firstSolveUs},
          {QStringLiteral("median_solve_us"), run.medianSolveUs},
          {QStringLiteral("max_solve_us"), run.maxSolveUs},
          {QStringLiteral("residual"), residual},
          {QStringLiteral("diagonal"), diagonal},
          {QStringLiteral("max_displacement_pct"), pct(spectral::maxVertexError(mesh.V, run.X))},
          {QStringLiteral("out"), args.out}};
}

void printDeformText(const QJsonObject& r) {
  QTextStream out(stdout);
  const auto line = [&out](const char* key, const QString& value) {
    out << qSetFieldWidth(22) << Qt::left << key << qSetFieldWidth(0) << value << '\n';
  };
  const auto number = [](const QJsonValue& value, int precision = 4) {
    return QString::number(value.toDouble(), 'g', precision);
  };
  for (const char* key : {"mesh", "mode", "out"}) line(key, r[QLatin1String(key)].toString());
  for (const char* key : {"vertices", "m", "handle_groups", "handle_vertices", "anchors", "frames"})
    line(key, number(r[QLatin1String(key)], 12));
  line("cached", r[QStringLiteral("cached")].toBool() ? QStringLiteral("yes") : QStringLiteral("no"));
  for (const char* key : {"basis_s", "setup_ms", "first_solve_us", "median_solve_us", "max_solve_us"})
    line(key, number(r[QLatin1String(key)]));
  const QJsonObject residual = r[QStringLiteral("residual")].toObject();
  line("residual_max_handle", number(residual[QStringLiteral("max_handle")], 3) + QStringLiteral(" (") +
                                  number(residual[QStringLiteral("max_handle_pct")], 3) + QStringLiteral(" %)"));
  line("residual_max_anchor", number(residual[QStringLiteral("max_anchor")], 3) + QStringLiteral(" (") +
                                  number(residual[QStringLiteral("max_anchor_pct")], 3) + QStringLiteral(" %)"));
  line("max_displacement_pct", number(r[QStringLiteral("max_displacement_pct")]));
  if (!r.contains(QStringLiteral("level"))) return;
  for (const char* key : {"level", "level_vertices", "level_triangles"}) line(key, number(r[QLatin1String(key)], 12));
  for (const char* key : {"level_build_s", "client_frame_us", "hausdorff_pct"})
    line(key, number(r[QLatin1String(key)]));
}

}  // namespace

int runDeformCommand(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("deform"),
                           QStringLiteral("Replay a drag script on a mesh with the spectral deformer."));
  const DeformOptions options;
  command.parser().addOptions({options.script, options.mode, options.out, options.level});
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;
  const std::optional<DeformArguments> args = deformArguments(command, options);
  if (!args) return kExitUsage;

  const std::optional<model::LoadedMesh> mesh = loadMeshOrReport(command, command.meshPath());
  if (!mesh) return kExitMeshError;
  std::variant<spectral::ConstraintSet, QString> constraints = resolveConstraints(args->script, mesh->V);
  if (const auto* message = std::get_if<QString>(&constraints)) {
    command.error(QStringLiteral("drag script: ") + *message);
    return kExitUsage;
  }
  const spectral::BasisComputation basis = basisOrReport(command, *mesh);
  if (!basis.result.ok()) return kExitBasisError;

  // === optional display level: decimated rest mesh, P and K = P·H, reconstructed per frame as a client would
  std::optional<LevelOutput> level;
  if (const std::optional<int> target = levelVertexTarget(args->level, static_cast<int>(mesh->V.rows())))
    level.emplace(mesh->V, mesh->F, basis.result.basis.vectors, args->level, *target);
  std::function<void(const Eigen::MatrixXd&)> onFrame;
  if (level) onFrame = [&level](const Eigen::MatrixXd& Z) { level->frame(Z); };

  const auto& set = std::get<spectral::ConstraintSet>(constraints);
  const std::optional<FrameRun> run = replay(args->script, set, basis, mesh->V, args->mode, onFrame);
  if (!run) {
    command.error(QStringLiteral("the deformer rejected the constraint set"));
    return kExitUsage;
  }
  const auto error = level ? model::writeMesh(args->out.toStdString(), level->positions(), level->faces())
                           : model::writeMesh(args->out.toStdString(), run->X, mesh->F);
  if (error) {
    command.error(QString::fromStdString(error->message));
    return kExitWriteError;
  }
  QJsonObject r = report(command, *args, *mesh, set, basis, *run);
  if (level) {
    const QJsonObject levelReport = level->report(run->X, spectral::boundingBoxDiagonal(mesh->V));
    for (auto it = levelReport.begin(); it != levelReport.end(); ++it) r.insert(it.key(), it.value());
  }
  printReport(command, r, printDeformText);
  return kExitOk;
}

}  // namespace sc::app
