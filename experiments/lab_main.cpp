// shapecast-lab: the paper experiments and benchmarks (lab_command.h). Usage: shapecast-lab <subcommand> [options].

#include "app/common/legacy_store.h"
#include "experiments/lab_command.h"
#include "session/net/nats_client.h"
#include "session/net/tls_identity.h"

#include <QCoreApplication>
#include <QGuiApplication>

#include <memory>

int main(int argc, char* argv[]) {
  sc::session::keepOpenSslStateUntilExit();  // before anything uses OpenSSL (the relay's TLS threads at exit)
  QStringList arguments;
  for (int i = 1; i < argc; ++i) arguments << QString::fromLocal8Bit(argv[i]);
  // The experiments run under a QGuiApplication (the loss experiment draws a PNG plot: QPainter text needs one),
  // headless, on the offscreen platform; table1 needs only Qt Core.
  const bool needsGui = sc::app::labCommandNeedsGui(arguments);
  if (needsGui && qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  const std::unique_ptr<QCoreApplication> app =
      needsGui ? std::make_unique<QGuiApplication>(argc, argv) : std::make_unique<QCoreApplication>(argc, argv);
  // The names that the settings and the host identity are kept under (shapecast-cli's and the desktop app's), and
  // their former store moved in first: the experiments' hosts load or create that identity.
  sc::app::nameApplication(QStringLiteral(SHAPECAST_VERSION));
  sc::app::migrateLegacyStoreIntoThisOne(sc::session::defaultTlsIdentityDirectory());
  arguments = QCoreApplication::arguments();
  arguments.removeFirst();
  return sc::app::runLabCommand(arguments);
}
