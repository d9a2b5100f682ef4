// The experiments' own executable and the compatibility alias to it (src/app/cli/lab_alias.h,
// experiments/lab_command.h): `shapecast-cli experiment …` and `bench table1 …` run shapecast-lab with their
// arguments, output and exit code unchanged; shapecast-lab takes both the old and the short spellings. (The
// experiments themselves run through the alias in session_commands_test.cpp and table1_command_test.cpp.)

#include "cli_test_support.h"

#include <gtest/gtest.h>

#include <QFile>
#include <QFileInfo>
#include <QProcess>
#include <QTemporaryDir>

namespace {

using sc::testing::CliRun;
using sc::testing::runCli;
using sc::testing::runLab;

TEST(LabAlias, ExperimentCommandsRunShapecastLab) {
  const CliRun help = runCli({QStringLiteral("experiment"), QStringLiteral("loss"), QStringLiteral("--help")});
  EXPECT_EQ(help.exitCode, 0) << help.err.toStdString();
  EXPECT_TRUE(help.out.contains("--burst-length")) << "the loss experiment's own help, on stdout";
  const CliRun table1 = runCli({QStringLiteral("bench"), QStringLiteral("table1"), QStringLiteral("--help")});
  EXPECT_EQ(table1.exitCode, 0) << table1.err.toStdString();
  EXPECT_TRUE(table1.out.contains("--frames"));
  const CliRun bare = runCli({QStringLiteral("experiment")});
  EXPECT_EQ(bare.exitCode, 2);
  EXPECT_TRUE(bare.err.contains("usage: shapecast-cli experiment loss|load")) << bare.err.toStdString();
  EXPECT_EQ(runCli({QStringLiteral("bench")}).exitCode, 2) << "bench alone is no command, as before";
  const CliRun usage = runCli({QStringLiteral("--help")});
  EXPECT_TRUE(usage.out.contains("experiment loss") && usage.out.contains("shapecast-lab"));
}

TEST(LabAlias, ShapecastLabTakesShortAndOldSpellings) {
  const CliRun help = runLab({QStringLiteral("--help")});
  EXPECT_EQ(help.exitCode, 0);
  for (const char* command : {"loss", "load", "table1"}) EXPECT_TRUE(help.out.contains(command)) << command;
  EXPECT_EQ(runLab({QStringLiteral("table1"), QStringLiteral("--help")}).exitCode, 0);
  EXPECT_EQ(runLab({QStringLiteral("load"), QStringLiteral("--help")}).exitCode, 0);
  EXPECT_EQ(runLab({QStringLiteral("experiment"), QStringLiteral("load"), QStringLiteral("--help")}).exitCode, 0);
  EXPECT_EQ(runLab({QStringLiteral("table1"), QStringLiteral("--low-fraction"), QStringLiteral("1.5"),
                    QStringLiteral("--markdown"), QString()})
                .exitCode,
            2);
  const CliRun unknown = runLab({QStringLiteral("fly")});
  EXPECT_EQ(unknown.exitCode, 2);
  EXPECT_TRUE(unknown.err.contains("unknown subcommand 'fly'")) << unknown.err.toStdString();
  EXPECT_EQ(runLab({}).exitCode, 2);
}

TEST(LabAlias, MissingShapecastLabIsReported) {
  QTemporaryDir dir;  // shapecast-cli alone, without its sibling
  ASSERT_TRUE(dir.isValid());
  const QString cli = dir.filePath(QStringLiteral("shapecast-cli"));
  ASSERT_TRUE(QFile::copy(QStringLiteral(SHAPECAST_CLI), cli));
  ASSERT_TRUE(QFile::setPermissions(cli, QFileInfo(QStringLiteral(SHAPECAST_CLI)).permissions()));
  QProcess process;
  process.start(cli, {QStringLiteral("experiment"), QStringLiteral("loss")});
  ASSERT_TRUE(process.waitForFinished(60000));
  EXPECT_EQ(process.exitCode(), 127);
  EXPECT_TRUE(process.readAllStandardError().contains("shapecast-lab"));
}

}  // namespace
