// shapecast-screenshots: the README screenshots of the demo (demo_screenshots.h).
//
//   shapecast-screenshots --demo [MESH] --screenshot-dir DIR [--after SECONDS]
//
// The same command line as `shapecast --demo --screenshot-dir …` (which runs this program with its own arguments),
// parsed by the application's own parser (app/gui/launch_options.h). Exit: 0 when every PNG was written, 1 when no
// mesh could be found for the demo, 2 when an image could not be made (the reason on stderr), 64 for bad arguments
// (anything but --demo with --screenshot-dir).

#include "app/gui/demo.h"
#include "app/gui/launch_options.h"
#include "app/gui/viewport/renderer_defaults.h"
#include "tools/screenshots/demo_screenshots.h"

#include <QApplication>
#include <QSurfaceFormat>

#include <cstdio>

namespace {

using sc::app::kLaunchExitImageFailed;
using sc::app::kLaunchExitLoadFailed;
using sc::app::kLaunchExitUsage;

void printError(const QString& message) { std::fprintf(stderr, "shapecast: %s\n", qUtf8Printable(message)); }

}  // namespace

int main(int argc, char* argv[]) {
  QSurfaceFormat::setDefaultFormat(sc::app::RendererDefaults::preferredSurfaceFormat());
  QApplication app(argc, argv);
  sc::app::LaunchParser parser;  // the application's names and command line: the same settings as shapecast's
  const std::optional<sc::app::LaunchOptions> parsed =
      parser.processApplication(app, QStringLiteral(SHAPECAST_VERSION));
  if (!parsed) return kLaunchExitUsage;
  const sc::app::LaunchOptions& options = *parsed;
  if (!options.screenshotDirectory) {
    printError(QStringLiteral("shapecast-screenshots takes --demo [MESH] --screenshot-dir DIR [--after SECONDS]"));
    return kLaunchExitUsage;
  }
  sc::app::Demo demo(sc::app::demoOptions(options));
  QObject::connect(&demo, &sc::app::Demo::failed, printError);
  sc::app::DemoScreenshotOptions shotOptions;
  shotOptions.directory = *options.screenshotDirectory;
  shotOptions.afterSeconds = options.afterSeconds;
  sc::app::DemoScreenshots screenshots(demo, shotOptions);
  QObject::connect(&screenshots, &sc::app::DemoScreenshots::finished, [](bool written, const QString& message) {
    if (!written) printError(message);
    QCoreApplication::exit(written ? 0 : kLaunchExitImageFailed);
  });
  if (!demo.start()) return kLaunchExitLoadFailed;
  screenshots.start();
  return QApplication::exec();
}
