// Entry point of app_tests: one QApplication for every test, created after GoogleTest has parsed its flags.

#include "address_sanitizer.h"
#include "app/gui/viewport/renderer_defaults.h"
#include "keep_libraries_mapped.h"
#include "session/net/nats_client.h"

#include <gtest/gtest.h>

#include <QApplication>
#include <QSettings>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QTemporaryDir>

int main(int argc, char** argv) {
  sc::session::keepOpenSslStateUntilExit();  // before anything uses OpenSSL (the relay's TLS threads at exit)
  ::testing::InitGoogleTest(&argc, argv);
  // Test discovery (gtest_discover_tests runs --gtest_list_tests at build time) needs no display.
  if (GTEST_FLAG_GET(list_tests)) {
    return RUN_ALL_TESTS();
  }
  // Without any display, fall back to the offscreen platform: the widget tests still run, GL tests skip.
  if (qEnvironmentVariableIsEmpty("DISPLAY") && qEnvironmentVariableIsEmpty("WAYLAND_DISPLAY") &&
      qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) {
    qputenv("QT_QPA_PLATFORM", "offscreen");
  }
  // Settings (recent sessions, known hosts) and the host's TLS identity go to ~/.qttest, not the user's folders.
  QStandardPaths::setTestModeEnabled(true);
  // Each test process its own settings: ctest runs tests in parallel processes, and a test's Open Recent list or
  // window layout must not be another one's (one of them clearing "files" while the other read it failed CI once).
  const QTemporaryDir settingsDir;
  QSettings::setPath(QSettings::NativeFormat, QSettings::UserScope, settingsDir.path());
  QSettings::setPath(QSettings::IniFormat, QSettings::UserScope, settingsDir.path());
  // Frames at full resolution unless a test turns adaptive resolution on (pixel comparisons stay deterministic).
  if (qEnvironmentVariableIsEmpty("SHAPECAST_ADAPTIVE_RESOLUTION")) {
    qputenv("SHAPECAST_ADAPTIVE_RESOLUTION", "0");
  }
  QSurfaceFormat::setDefaultFormat(sc::app::RendererDefaults::preferredSurfaceFormat());
  QApplication app(argc, argv);
  const int result = RUN_ALL_TESTS();
  // Before the QApplication closes the display and with it the GL driver: see keep_libraries_mapped.h.
  if (sc::testing::kAddressSanitizer) {
    sc::testing::keepLoadedLibrariesMapped();
  }
  return result;
}
