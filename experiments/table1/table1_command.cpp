#include "experiments/table1/table1_command.h"

#include "app/cli/cli_common.h"
#include "experiments/report/machine_info.h"
#include "experiments/report/markdown_section.h"
#include "experiments/table1/table1_measurement.h"

#include <QCommandLineParser>
#include <QDateTime>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTextStream>

#include <vector>

namespace sc::app {
namespace {

/// The paper's Table 1 (Tang et al. 2010; a 2010 PC): model, #V HR/LR, #T HR/LR, pre-computing HR, LR,
/// server run time, client HR, client LR — all in seconds.
constexpr const char* kPaperRows =
    "| Heart (paper) | 1752 / 252 | 3500 / 500 | 0.613 | 0.652 | 0.005026 | 0.003659 | 0.00176 |\n"
    "| Lion (paper) | 5000 / 2502 | 9996 / 5000 | 1.962 | 2.186 | 0.013542 | 0.023987 | 0.01195 |\n"
    "| Brain (paper) | 26077 / 5002 | 52150 / 10000 | 25.485 | 25.949 | 0.067058 | 0.058571 | 0.030488 |\n"
    "| Dragon (paper) | 50000 / 2500 | 100000 / 5000 | 49.676 | 49.935 | 0.131773 | 0.170512 | 0.026368 |\n";

QStringList defaultMeshes() {
  QStringList meshes;
  for (const char* name : {"lion.off", "ChineseDragon-10kv.off", "dragon_vrip_res3.ply", "dragon_vrip_res2.ply"})
    meshes << QStringLiteral(SHAPECAST_ASSETS_DIR "/") + QLatin1String(name);
  return meshes;
}

QJsonObject toJson(const Table1Row& r) {
  return {{QStringLiteral("mesh"), QString::fromStdString(r.mesh)},
          {QStringLiteral("vertices_full"), r.verticesFull},
          {QStringLiteral("vertices_low"), r.verticesLow},
          {QStringLiteral("triangles_full"), r.trianglesFull},
          {QStringLiteral("triangles_low"), r.trianglesLow},
          {QStringLiteral("precompute_full_s"), r.precomputeFullSeconds},
          {QStringLiteral("precompute_low_s"), r.precomputeLowSeconds},
          {QStringLiteral("level_build_s"), r.levelBuildSeconds},
          {QStringLiteral("decimation_s"), r.decimationSeconds},
          {QStringLiteral("server_frame_s"), r.serverFrameSeconds},
          {QStringLiteral("server_handle_vertices"), r.serverHandleVertices},
          {QStringLiteral("constraint_change_s"), r.constraintChangeSeconds},
          {QStringLiteral("constraint_change_handle_vertices"), r.changeHandleVertices},
          {QStringLiteral("client_full_s"), r.clientFullSeconds},
          {QStringLiteral("client_low_s"), r.clientLowSeconds}};
}

QString markdownTable(const std::vector<Table1Row>& rows) {
  QString t = QStringLiteral(
      "| model | #vertex HR / LR | #triangle HR / LR | pre-computing HR (s) | pre-computing LR (s) | server run time "
      "(s) "
      "| client HR (s) | client LR (s) |\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Table1Row& r : rows)
    t += QStringLiteral("| %1 | %2 / %3 | %4 / %5 | %6 | %7 | %8 | %9 | %10 |\n")
             .arg(QString::fromStdString(r.mesh))
             .arg(r.verticesFull)
             .arg(r.verticesLow)
             .arg(r.trianglesFull)
             .arg(r.trianglesLow)
             .arg(r.precomputeFullSeconds, 0, 'f', 3)
             .arg(r.precomputeLowSeconds, 0, 'f', 3)
             .arg(r.serverFrameSeconds, 0, 'e', 2)
             .arg(r.clientFullSeconds, 0, 'e', 2)
             .arg(r.clientLowSeconds, 0, 'e', 2);
  return t + QLatin1String(kPaperRows);
}

QString details(const std::vector<Table1Row>& rows) {
  QString d = QStringLiteral(
      "\n| model | level build (s) | of which decimation (s) | server handle vertices | constraint change (s) | "
      "change handle vertices |\n|---|---:|---:|---:|---:|---:|\n");
  for (const Table1Row& r : rows)
    d += QStringLiteral("| %1 | %2 | %3 | %4 | %5 | %6 |\n")
             .arg(QString::fromStdString(r.mesh))
             .arg(r.levelBuildSeconds, 0, 'f', 3)
             .arg(r.decimationSeconds, 0, 'f', 3)
             .arg(r.serverHandleVertices)
             .arg(r.constraintChangeSeconds, 0, 'e', 2)
             .arg(r.changeHandleVertices);
  return d;
}

/// Measures every mesh; prints the reason and returns the exit code on the first failure, else kExitOk.
int measureAll(const QStringList& meshes, const Table1Options& options, std::vector<Table1Row>& rows) {
  QTextStream err(stderr);
  for (const QString& path : meshes) {
    const model::MeshLoadResult loaded = model::loadMesh(path.toStdString());
    if (const auto* error = std::get_if<model::MeshError>(&loaded)) {
      err << "shapecast-cli bench table1: " << QString::fromStdString(error->message) << '\n';
      return kExitMeshError;
    }
    Table1Row row;
    std::string error;
    if (!measureTable1Row(QFileInfo(path).fileName().toStdString(), std::get<model::LoadedMesh>(loaded), options, row,
                          error)) {
      err << "shapecast-cli bench table1: " << path << ": " << QString::fromStdString(error) << '\n';
      return kExitBasisError;
    }
    rows.push_back(row);
  }
  return kExitOk;
}

QString markdownBody(const std::vector<Table1Row>& rows, const Table1Options& options) {
  return QStringLiteral(
             "## Table 1 of the paper, on this machine (m = %1, low resolution %2% of the "
             "vertices)\n\nMeasured %3 with `shapecast-cli bench table1` (medians of %4 "
             "frames; client times on one thread, float32).\n\nMachine: %5\n\n%6%7")
      .arg(options.m)
      .arg(options.lowFraction * 100.0)
      .arg(QDateTime::currentDateTimeUtc().toString(Qt::ISODate))
      .arg(options.frames)
      .arg(report::machineDescription(), markdownTable(rows), details(rows));
}

}  // namespace

int runTable1Command(const QStringList& arguments) {
  QCommandLineParser parser;
  parser.setApplicationDescription(QStringLiteral("Reproduce the paper's Table 1 on this machine."));
  parser.addHelpOption();
  parser.addPositionalArgument(QStringLiteral("MESH"), QStringLiteral("meshes (default: the fetched real meshes)"),
                               QStringLiteral("[MESH...]"));
  const QCommandLineOption m(QStringLiteral("m"), QStringLiteral("harmonics"), QStringLiteral("count"),
                             QStringLiteral("100"));
  const QCommandLineOption low(QStringLiteral("low-fraction"),
                               QStringLiteral("low resolution as a fraction of the vertices"), QStringLiteral("f"),
                               QStringLiteral("0.05"));
  const QCommandLineOption frames(QStringLiteral("frames"), QStringLiteral("timed frames"), QStringLiteral("n"),
                                  QStringLiteral("200"));
  const QCommandLineOption json(QStringLiteral("json"), QStringLiteral("print a JSON list on stdout"));
  const QCommandLineOption markdown(QStringLiteral("markdown"), QStringLiteral("Markdown file to update (\"\": none)"),
                                    QStringLiteral("file"), QStringLiteral(SHAPECAST_SOURCE_DIR "/docs/benchmarks.md"));
  parser.addOptions({m, low, frames, json, markdown});
  QTextStream err(stderr);
  if (!parser.parse(QStringList{QStringLiteral("shapecast-cli bench table1")} + arguments)) {
    err << "shapecast-cli bench table1: " << parser.errorText() << '\n';
    return kExitUsage;
  }
  if (parser.isSet(QStringLiteral("help"))) {
    QTextStream(stdout) << parser.helpText();
    return kExitOk;
  }
  Table1Options options;
  bool okM = false, okLow = false, okFrames = false;
  options.m = parser.value(m).toInt(&okM);
  options.lowFraction = parser.value(low).toDouble(&okLow);
  options.frames = parser.value(frames).toInt(&okFrames);
  if (!okM || !okLow || !okFrames || options.m < 1 || options.frames < 1 || options.lowFraction <= 0.0 ||
      options.lowFraction >= 1.0) {
    err << "shapecast-cli bench table1: --m and --frames must be positive integers, --low-fraction in (0, 1)\n";
    return kExitUsage;
  }

  const QStringList meshes = parser.positionalArguments().isEmpty() ? defaultMeshes() : parser.positionalArguments();
  std::vector<Table1Row> rows;
  if (const int code = measureAll(meshes, options, rows); code != kExitOk) return code;
  const QString body = markdownBody(rows, options);
  if (parser.isSet(json)) {
    QJsonArray list;
    for (const Table1Row& r : rows) list.append(toJson(r));
    QTextStream(stdout) << QJsonDocument(list).toJson(QJsonDocument::Compact) << '\n';
  } else {
    QTextStream(stdout) << body;
  }
  if (!parser.value(markdown).isEmpty() &&
      !report::writeMarkdownSection(parser.value(markdown), QStringLiteral("table1"), body)) {
    err << "shapecast-cli bench table1: cannot write " << parser.value(markdown) << '\n';
    return kExitUsage;
  }
  return kExitOk;
}

}  // namespace sc::app
