// End-to-end test of `shapecast-cli bench table1` on a generated mesh (the real meshes are the benchmark's job).

#include "cli_test_support.h"

#include <gtest/gtest.h>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QTemporaryDir>

namespace {

using sc::testing::runCli;

TEST(Table1Command, JsonRowHasEveryColumnWithPlausibleValues) {
  QTemporaryDir dir;
  ASSERT_TRUE(dir.isValid());
  const QString mesh = dir.filePath(QStringLiteral("sphere.off"));
  sc::testing::writeOff(mesh, sc::testing::icosphere(4));  // 2562 vertices
  const QString markdown = dir.filePath(QStringLiteral("bench.md"));
  const auto run =
      runCli({QStringLiteral("bench"), QStringLiteral("table1"), mesh, QStringLiteral("--m"), QStringLiteral("30"),
              QStringLiteral("--frames"), QStringLiteral("5"), QStringLiteral("--low-fraction"), QStringLiteral("0.2"),
              QStringLiteral("--json"), QStringLiteral("--markdown"), markdown});
  ASSERT_EQ(run.exitCode, 0) << run.err.toStdString();
  const QJsonArray rows = QJsonDocument::fromJson(run.out).array();
  ASSERT_EQ(rows.size(), 1);
  const QJsonObject r = rows[0].toObject();
  EXPECT_EQ(r[QStringLiteral("mesh")].toString(), QStringLiteral("sphere.off"));
  EXPECT_EQ(r[QStringLiteral("vertices_full")].toInt(), 2562);
  EXPECT_EQ(r[QStringLiteral("triangles_full")].toInt(), 5120);
  EXPECT_NEAR(r[QStringLiteral("vertices_low")].toInt(), 512, 6) << "20% of the vertices, within 1%";
  EXPECT_GT(r[QStringLiteral("triangles_low")].toInt(), 0);
  for (const char* key : {"precompute_full_s", "precompute_low_s", "server_frame_s", "client_full_s", "client_low_s"})
    EXPECT_GT(r[QLatin1String(key)].toDouble(), 0.0) << key;
  EXPECT_GE(r[QStringLiteral("precompute_low_s")].toDouble(), r[QStringLiteral("precompute_full_s")].toDouble());

  QFile written(markdown);
  ASSERT_TRUE(written.open(QIODevice::ReadOnly));
  const QByteArray text = written.readAll();
  EXPECT_TRUE(text.contains("<!-- table1:start -->") && text.contains("Dragon (paper)") && text.contains("sphere.off"));
}

TEST(Table1Command, BadOptionsAndMissingMeshesHaveExitCodes) {
  EXPECT_EQ(runCli({QStringLiteral("bench"), QStringLiteral("table1"), QStringLiteral("--low-fraction"),
                    QStringLiteral("1.5"), QStringLiteral("--markdown"), QString()})
                .exitCode,
            2);
  EXPECT_EQ(runCli({QStringLiteral("bench"), QStringLiteral("table1"), QStringLiteral("/nonexistent/mesh.off"),
                    QStringLiteral("--markdown"), QString()})
                .exitCode,
            1);
}

}  // namespace
