// shapecast-cli: headless ShapeCast tool. Usage: shapecast-cli <subcommand> [options]; see --help.

#include "app/cli/basis_command.h"
#include "app/cli/deform_command.h"
#include "app/cli/drive_command.h"
#include "app/cli/host_command.h"
#include "app/cli/join_command.h"
#include "app/cli/lab_alias.h"
#include "app/cli/watch_command.h"
#include "app/common/legacy_store.h"
#include "session/net/nats_client.h"
#include "session/net/tls_identity.h"

#include <QCoreApplication>
#include <QTextStream>

#include <span>
#include <vector>

namespace {

constexpr const char* kUsage =
    "usage: shapecast-cli <subcommand> [options]\n"
    "\n"
    "subcommands:\n"
    "  basis MESH [--m 100] [--no-cache] [--cache-dir DIR] [--json]\n"
    "      compute (or load from the cache) the manifold harmonic basis of MESH and print its figures\n"
    "  deform MESH --script DRAG.json [--mode linear|rigid] [--level N] [--out FILE] [--m 100] [--no-cache]\n"
    "         [--cache-dir DIR] [--json]\n"
    "      replay a drag script (docs/drag-script.md) with the spectral deformer and write the deformed mesh\n"
    "  host MESH [--port 47100] [--password-file F] [--mode linear|rigid] [--m 100] [--seconds T]\n"
    "      host a session: clients join, one at a time holds the edit lock and drags\n"
    "  join HOST:PORT [--name N] [--password-file F] [--level full|N] [--loss P] [--burst L] [--seconds T]\n"
    "       [--stats-json FILE]\n"
    "      join a session headless and report loss, bandwidth, latency and Hausdorff distortion\n"
    "  drive HOST:PORT --script DRAG.json [--name N] [--password-file F]\n"
    "      take the edit lock, play a drag script, release\n"
    "  watch --nats URL --session ID --nats-user U --nats-password-file F [--pin FINGERPRINT] [--seconds T]\n"
    "      watch a session relayed through NATS (host --nats ...) headless: frames, loss, latency\n"
    "\n"
    "the paper's experiments and benchmarks, run by shapecast-lab (next to shapecast-cli; see 'shapecast-lab "
    "--help'):\n"
    "  bench table1 [MESH...] [--m 100] [--low-fraction 0.05] [--frames 200] [--json] [--markdown FILE]\n"
    "      reproduce the paper's Table 1 on this machine and write it to docs/benchmarks.md\n"
    "  experiment loss [--mesh MESH] [--loss 0,0.02,...] [--burst] [--json]\n"
    "      reproduce the paper's Figures 3 and 4 on loopback and write them to docs/benchmarks.md\n"
    "  experiment load --clients N --seconds T [--mesh MESH] [--markdown FILE] [--json]\n"
    "      one host process, N headless clients and a 30 fps drag: host CPU, per-client loss and latency\n"
    "\n"
    "run 'shapecast-cli <subcommand> --help' for the options of a subcommand\n";

}  // namespace

int main(int argc, char* argv[]) {
  sc::session::keepOpenSslStateUntilExit();  // before anything uses OpenSSL (the relay's TLS threads at exit)
  // argv as given (QCoreApplication may take out the options it knows) for the shapecast-lab alias.
  const std::vector<char*> given(argv + 1, argv + argc);
  const QCoreApplication app(argc, argv);
  // one store of known hosts and host identity with the desktop app
  sc::app::nameApplication(QStringLiteral(SHAPECAST_VERSION));
  sc::app::migrateLegacyStoreIntoThisOne(sc::session::defaultTlsIdentityDirectory());
  QStringList arguments = QCoreApplication::arguments();
  arguments.removeFirst();
  const QString subcommand = arguments.isEmpty() ? QString() : arguments.takeFirst();
  if (subcommand == QLatin1String("basis")) return sc::app::runBasisCommand(arguments);
  if (subcommand == QLatin1String("deform")) return sc::app::runDeformCommand(arguments);
  if (subcommand == QLatin1String("host")) {
    const int code = sc::app::runHostCommand(arguments);
    sc::session::natsShutdown();  // cnats' threads, if the relay was used (harmless otherwise)
    return code;
  }
  if (subcommand == QLatin1String("join")) return sc::app::runJoinCommand(arguments);
  if (subcommand == QLatin1String("drive")) return sc::app::runDriveCommand(arguments);
  if (subcommand == QLatin1String("watch")) {
    const int code = sc::app::runWatchCommand(arguments);
    sc::session::natsShutdown();
    return code;
  }
  if (sc::app::isLabCommand(QStringList(subcommand) + arguments)) return sc::app::runLabAlias(given);

  QTextStream err(stderr);
  if (subcommand.isEmpty() || subcommand == QLatin1String("--help") || subcommand == QLatin1String("-h")) {
    QTextStream(stdout) << kUsage;
    return subcommand.isEmpty() ? 2 : 0;
  }
  err << "shapecast-cli: unknown subcommand '" << subcommand << "'\n\n" << kUsage;
  return 2;
}
