// Tests for src/app/gui/main.cpp: the shapecast executable's --screenshot mode, run as a child process.

#include "address_sanitizer.h"
#include "app_test_support.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QFileInfo>
#include <QImage>
#include <QProcess>
#include <QProcessEnvironment>
#include <QTemporaryDir>

namespace {

constexpr int kTimeoutMs = 120000;

struct RunResult {
  int exitCode = -1;
  QString standardError;
};

RunResult runShapecast(const QStringList& arguments) {
  QProcess process;
  if (sc::testing::kAddressSanitizer) {
    // The child exits with Mesa's GL driver already unloaded (see keep_libraries_mapped.h), so LeakSanitizer would
    // report the driver's blocks as leaks of `<unknown module>`; app_tests keeps the libraries mapped and checks
    // the GUI library for leaks, but the child's main is not a test's to change: no leak check in the child (ASan
    // and UBSan stay on). Known gap: main.cpp itself is not leak-checked.
    QProcessEnvironment environment = QProcessEnvironment::systemEnvironment();
    const QString options = environment.value(QStringLiteral("ASAN_OPTIONS"));
    environment.insert(QStringLiteral("ASAN_OPTIONS"), options.isEmpty() ? QStringLiteral("detect_leaks=0")
                                                                         : options + QStringLiteral(":detect_leaks=0"));
    process.setProcessEnvironment(environment);
  }
  process.start(QStringLiteral(SHAPECAST_EXE), arguments);
  if (!process.waitForFinished(kTimeoutMs) || process.exitStatus() != QProcess::NormalExit) {
    process.kill();
    return {};
  }
  return {process.exitCode(), QString::fromLocal8Bit(process.readAllStandardError())};
}

class ShapecastExe : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sc::testing::openGlAvailable()) {
      GTEST_SKIP() << "no OpenGL 3.3 context (run under xvfb-run)";
    }
    ASSERT_TRUE(m_dir.isValid());
  }
  QTemporaryDir m_dir;
};

}  // namespace

TEST_F(ShapecastExe, ScreenshotOfAGeneratedOffFile) {
  const QString mesh = m_dir.filePath(QStringLiteral("sphere.off"));
  const QString png = m_dir.filePath(QStringLiteral("shot.png"));
  const auto sphere = sc::testing::icosphere(3);
  ASSERT_TRUE(sc::testing::writeOff(mesh, sphere.V, sphere.F));

  const RunResult run =
      runShapecast({mesh, QStringLiteral("--screenshot"), png, QStringLiteral("--size"), QStringLiteral("320x240")});
  ASSERT_EQ(run.exitCode, 0) << run.standardError.toStdString();
  ASSERT_GT(QFileInfo(png).size(), 0);
  const QImage image(png);
  ASSERT_FALSE(image.isNull());
  EXPECT_EQ(image.size(), QSize(320, 240));
  EXPECT_NE(image.pixel(160, 120), image.pixel(0, 120)) << "the mesh is drawn in the centre";
}

TEST_F(ShapecastExe, MissingMeshExitsNonZeroWithoutScreenshot) {
  const QString png = m_dir.filePath(QStringLiteral("shot.png"));
  const RunResult run =
      runShapecast({m_dir.filePath(QStringLiteral("missing.off")), QStringLiteral("--screenshot"), png});
  EXPECT_NE(run.exitCode, 0);
  EXPECT_TRUE(run.standardError.contains(QStringLiteral("missing.off"))) << run.standardError.toStdString();
  EXPECT_FALSE(QFileInfo::exists(png));
}

TEST_F(ShapecastExe, BadSizeIsAUsageError) {
  const RunResult run = runShapecast({QStringLiteral("--screenshot"), m_dir.filePath(QStringLiteral("x.png")),
                                      QStringLiteral("--size"), QStringLiteral("big")});
  EXPECT_EQ(run.exitCode, 64);
}

TEST_F(ShapecastExe, ScreenshotDirNeedsTheDemoAndSensibleSeconds) {
  const QString dir = m_dir.filePath(QStringLiteral("shots"));
  EXPECT_EQ(runShapecast({QStringLiteral("--screenshot-dir"), dir}).exitCode, 64);
  EXPECT_EQ(runShapecast({QStringLiteral("--demo"), QStringLiteral("--screenshot-dir"), dir, QStringLiteral("--after"),
                          QStringLiteral("soon")})
                .exitCode,
            64);
  EXPECT_FALSE(QFileInfo::exists(dir));
}

TEST_F(ShapecastExe, MalformedFingerprintIsAUsageError) {
  const RunResult run = runShapecast({QStringLiteral("--join"), QStringLiteral("127.0.0.1:47100"),
                                      QStringLiteral("--fingerprint"), QStringLiteral("ab:cd:not-hex")});
  EXPECT_EQ(run.exitCode, 64);
  EXPECT_TRUE(run.standardError.contains(QStringLiteral("--fingerprint"))) << run.standardError.toStdString();
}
