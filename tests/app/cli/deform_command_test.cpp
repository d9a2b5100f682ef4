// End-to-end tests of `shapecast-cli deform`: the real executable on a generated torus and a drag script.

#include "cli_test_support.h"

#include "model/mesh_loader.h"
#include "spectral/hausdorff.h"

#include <gtest/gtest.h>
#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTemporaryDir>

namespace {

using sc::testing::CliRun;
using sc::testing::runCli;

/// Handle: a 10 % sphere around vertex 0 (outer equator of the torus); anchors: everything farther than 40 % from
/// it; drag: 10 % of the diagonal along +z in 0.5 s.
constexpr const char* kLift = R"({
  "handles": [{"sphere": {"vertex": 0, "radius_pct": 10}}],
  "anchors": {"farther_than_pct": 40, "from_vertex": 0},
  "frames": [{"t": 0}, {"t": 0.5, "translate_pct": [0, 0, 10]}]
})";

class DeformCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(m_dir.isValid());
    m_torus = sc::testing::torus(40, 16);
    m_mesh = m_dir.filePath(QStringLiteral("torus.off"));
    sc::testing::writeOff(m_mesh, m_torus);
    m_script = writeScript(QStringLiteral("lift.json"), kLift);
  }
  QString writeScript(const QString& name, const char* json) const {
    const QString path = m_dir.filePath(name);
    QFile file(path);
    EXPECT_TRUE(file.open(QIODevice::WriteOnly));
    file.write(json);
    return path;
  }
  QStringList deformArgs(const QString& script, const QStringList& extra) const {
    return QStringList{QStringLiteral("deform"),      m_mesh,
                       QStringLiteral("--script"),    script,
                       QStringLiteral("--cache-dir"), m_dir.filePath(QStringLiteral("cache")),
                       QStringLiteral("--m"),         QStringLiteral("40")} +
           extra;
  }
  Eigen::MatrixXd loadPositions(const QString& path) const {
    const sc::model::MeshLoadResult loaded = sc::model::loadMesh(path.toStdString());
    if (const auto* error = std::get_if<sc::model::MeshError>(&loaded)) {
      ADD_FAILURE() << error->message;
      return {};
    }
    const auto& mesh = std::get<sc::model::LoadedMesh>(loaded);
    EXPECT_EQ(mesh.F, m_torus.F) << "the connectivity is written unchanged";
    return mesh.V;
  }
  QTemporaryDir m_dir;
  sc::testing::GeneratedMesh m_torus;
  QString m_mesh, m_script;
};

TEST_F(DeformCommand, LinearDragMovesTheHandleAndKeepsTheAnchors) {
  const QString out = m_dir.filePath(QStringLiteral("lifted.off"));
  const CliRun run = runCli(deformArgs(m_script, {QStringLiteral("--out"), out, QStringLiteral("--json")}));
  ASSERT_EQ(run.exitCode, 0) << run.err.toStdString();
  const QJsonObject r = QJsonDocument::fromJson(run.out).object();
  EXPECT_EQ(r[QStringLiteral("frames")].toInt(), 16) << "0.5 s at 30 fps: 15 steps plus the first frame";
  EXPECT_GT(r[QStringLiteral("median_solve_us")].toDouble(), 0.0);
  EXPECT_EQ(r[QStringLiteral("out")].toString(), out);
  EXPECT_EQ(r[QStringLiteral("mode")].toString(), QStringLiteral("linear"));
  const QJsonObject residual = r[QStringLiteral("residual")].toObject();
  for (const char* key : {"max_handle", "rms_handle", "max_anchor"})
    EXPECT_TRUE(residual.contains(QLatin1String(key))) << key;

  const Eigen::MatrixXd X = loadPositions(out);
  ASSERT_EQ(X.rows(), m_torus.V.rows());
  const double diagonal = sc::spectral::boundingBoxDiagonal(m_torus.V);
  const Eigen::RowVector3d drag(0, 0, 0.1 * diagonal);
  const Eigen::RowVector3d centre = m_torus.V.row(0);
  double handleMiss = 0.0, anchorMove = 0.0;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    const double distance = (m_torus.V.row(v) - centre).norm();
    const Eigen::RowVector3d moved = X.row(v) - m_torus.V.row(v);
    if (distance <= 0.1 * diagonal) handleMiss = std::max(handleMiss, (moved - drag).norm());
    if (distance > 0.4 * diagonal) anchorMove = std::max(anchorMove, moved.norm());
  }
  EXPECT_LT(handleMiss, 0.05 * drag.norm()) << "handle vertices follow the drag (measured: 3.2 % miss at m = 40)";
  EXPECT_LT(anchorMove, 0.05 * drag.norm()) << "anchors stay (measured: 2.1 %; soft constraints, c ≫ m)";
  EXPECT_NEAR(residual[QStringLiteral("max_handle")].toDouble(), handleMiss, 1e-5 * diagonal)
      << "the reported residual is the miss of the written mesh (up to float32 output)";
}

TEST_F(DeformCommand, RigidModeAndTextOutputAndDefaultOutputName) {
  const CliRun run = runCli(deformArgs(m_script, {QStringLiteral("--mode"), QStringLiteral("rigid")}), m_dir.path());
  ASSERT_EQ(run.exitCode, 0) << run.err.toStdString();
  for (const char* key : {"mode", "frames", "median_solve_us", "residual_max_handle", "residual_max_anchor", "out"})
    EXPECT_TRUE(run.out.contains(key)) << key;
  EXPECT_TRUE(run.out.contains("rigid"));
  const QString out = m_dir.filePath(QStringLiteral("torus-deformed.off"));
  ASSERT_TRUE(QFile::exists(out)) << "default: MESH stem + -deformed.off in the current folder";
  const Eigen::MatrixXd X = loadPositions(out);
  const double lift = X(0, 2) - m_torus.V(0, 2);
  EXPECT_NEAR(lift, 0.1 * sc::spectral::boundingBoxDiagonal(m_torus.V),
              0.1 * 0.1 * sc::spectral::boundingBoxDiagonal(m_torus.V));
}

TEST_F(DeformCommand, WritesEveryFormatByExtension) {
  for (const char* name : {"out.obj", "out.ply", "out.stl"}) {
    const QString out = m_dir.filePath(QLatin1String(name));
    const CliRun run = runCli(deformArgs(m_script, {QStringLiteral("--out"), out}));
    ASSERT_EQ(run.exitCode, 0) << name << ": " << run.err.toStdString();
    EXPECT_TRUE(std::holds_alternative<sc::model::LoadedMesh>(sc::model::loadMesh(out.toStdString()))) << name;
  }
}

TEST_F(DeformCommand, LevelWritesTheLowResolutionMeshCloseToTheMappedFullResult) {
  const QString out = m_dir.filePath(QStringLiteral("level2.off"));
  const CliRun run = runCli(deformArgs(m_script, {QStringLiteral("--level"), QStringLiteral("2"),
                                                  QStringLiteral("--out"), out, QStringLiteral("--json")}));
  ASSERT_EQ(run.exitCode, 0) << run.err.toStdString();
  const QJsonObject r = QJsonDocument::fromJson(run.out).object();
  EXPECT_EQ(r[QStringLiteral("level")].toInt(), 2);
  const int target = 128;  // 20 % of the torus's 640 vertices
  const int vertices = r[QStringLiteral("level_vertices")].toInt();
  EXPECT_NEAR(vertices, target, 0.01 * target + 1);
  EXPECT_GT(r[QStringLiteral("level_triangles")].toInt(), 0);
  EXPECT_GT(r[QStringLiteral("level_build_s")].toDouble(), 0.0);
  EXPECT_GT(r[QStringLiteral("client_frame_us")].toDouble(), 0.0);
  EXPECT_GE(r[QStringLiteral("hausdorff_pct")].toDouble(), 0.0);
  EXPECT_LE(r[QStringLiteral("hausdorff_pct")].toDouble(), 0.5) << "X' is P·X up to X̂' − P·X̂ and float32";

  const sc::model::MeshLoadResult loaded = sc::model::loadMesh(out.toStdString());
  ASSERT_TRUE(std::holds_alternative<sc::model::LoadedMesh>(loaded));
  const auto& low = std::get<sc::model::LoadedMesh>(loaded);
  EXPECT_EQ(low.V.rows(), vertices) << "the written mesh is the level";
  EXPECT_EQ(low.F.rows(), r[QStringLiteral("level_triangles")].toInt());
  const double diagonal = sc::spectral::boundingBoxDiagonal(m_torus.V);
  EXPECT_GT(low.V.col(2).maxCoeff(), m_torus.V.col(2).maxCoeff() + 0.05 * diagonal) << "the handle was lifted";

  const CliRun explicitCount =
      runCli(deformArgs(m_script, {QStringLiteral("--level"), QStringLiteral("320"), QStringLiteral("--out"), out}));
  ASSERT_EQ(explicitCount.exitCode, 0) << explicitCount.err.toStdString();
  for (const char* key : {"level_vertices", "level_build_s", "client_frame_us", "hausdorff_pct"})
    EXPECT_TRUE(explicitCount.out.contains(key)) << key;
  const sc::model::MeshLoadResult half = sc::model::loadMesh(out.toStdString());
  ASSERT_TRUE(std::holds_alternative<sc::model::LoadedMesh>(half));
  EXPECT_NEAR(std::get<sc::model::LoadedMesh>(half).V.rows(), 320, 0.01 * 320 + 1) << "N > 3 is a vertex count";

  for (const char* bad : {"-1", "two"})
    EXPECT_EQ(runCli(deformArgs(m_script, {QStringLiteral("--level"), QLatin1String(bad)})).exitCode, 2) << bad;
}

TEST_F(DeformCommand, ErrorsHaveExitCodesAndMessages) {
  const CliRun badKey =
      runCli(deformArgs(writeScript(QStringLiteral("typo.json"),
                                    R"({"handles":[{"vertices":[0]}],"frames":[{"t":0,"translate":[0,1,0]}]})"),
                        {}));
  EXPECT_EQ(badKey.exitCode, 2);
  EXPECT_TRUE(badKey.err.contains("frames[0].translate: unknown key")) << badKey.err.toStdString();

  const CliRun outOfRange = runCli(deformArgs(
      writeScript(QStringLiteral("range.json"), R"({"handles":[{"vertices":[640]}],"frames":[{"t":0}]})"), {}));
  EXPECT_EQ(outOfRange.exitCode, 2);
  EXPECT_TRUE(outOfRange.err.contains("out of range")) << outOfRange.err.toStdString();

  const CliRun noJson = runCli(deformArgs(writeScript(QStringLiteral("broken.json"), "{"), {}));
  EXPECT_EQ(noJson.exitCode, 2);
  EXPECT_TRUE(noJson.err.contains("broken.json")) << noJson.err.toStdString();

  EXPECT_EQ(runCli(deformArgs(m_dir.filePath(QStringLiteral("absent.json")), {})).exitCode, 2);
  EXPECT_EQ(runCli({QStringLiteral("deform"), m_mesh}).exitCode, 2) << "--script is required";
  EXPECT_EQ(runCli(deformArgs(m_script, {QStringLiteral("--mode"), QStringLiteral("wobbly")})).exitCode, 2);
  EXPECT_EQ(runCli(deformArgs(m_script, {QStringLiteral("--out"), QStringLiteral("x.png")})).exitCode, 2);

  const CliRun missingMesh = runCli(
      {QStringLiteral("deform"), m_dir.filePath(QStringLiteral("absent.off")), QStringLiteral("--script"), m_script});
  EXPECT_EQ(missingMesh.exitCode, 1);
  EXPECT_TRUE(missingMesh.err.contains("absent.off"));

  EXPECT_EQ(runCli(deformArgs(m_script, {QStringLiteral("--m"), QStringLiteral("5000")})).exitCode, 3);

  const CliRun unwritable =
      runCli(deformArgs(m_script, {QStringLiteral("--out"), m_dir.filePath(QStringLiteral("no/such/folder/out.off"))}));
  EXPECT_EQ(unwritable.exitCode, 4);
  EXPECT_TRUE(unwritable.err.contains("out.off")) << unwritable.err.toStdString();
}

}  // namespace
