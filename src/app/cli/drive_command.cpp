#include "app/cli/drive_command.h"

#include "app/cli/drag_script.h"
#include "app/cli/peer_arguments.h"
#include "app/cli/session_setup.h"
#include "app/common/password_memory.h"
#include "session/engine/constraint_work.h"
#include "session/wire/handle_transforms.h"
#include "spectral/hausdorff.h"

#include <QJsonObject>
#include <QTextStream>
#include <QTimer>

namespace sc::app {
int runDriveCommand(const QStringList& arguments) {
  SubcommandParser command(QStringLiteral("drive"),
                           QStringLiteral("Take the edit lock of a session and play a drag script."),
                           SubcommandKind::Peer);
  const QCommandLineOption scriptOption(QStringLiteral("script"), QStringLiteral("drag script (docs/drag-script.md)"),
                                        QStringLiteral("file"));
  const PeerArguments peer(command, QStringLiteral("driver"));
  command.parser().addOption(scriptOption);
  int exitCode = kExitOk;
  if (!command.parse(arguments, exitCode)) return exitCode;
  if (!command.parser().isSet(scriptOption)) {
    command.error(QStringLiteral("--script is required"));
    return kExitUsage;
  }
  const std::variant<DragScript, QString> parsed = readDragScript(command.parser().value(scriptOption));
  if (const QString* error = std::get_if<QString>(&parsed)) {
    command.error(*error);
    return kExitUsage;
  }
  const DragScript& script = std::get<DragScript>(parsed);

  session::SessionClientOptions options;
  if (!peer.apply(command, options)) return kExitUsage;
  session::SessionClient client(options);
  forgetPassword(options.password);  // the client keeps its own copy until its proof
  if (!joinAndWait(command, client, std::chrono::seconds(120))) return kExitNetwork;
  const Eigen::MatrixXd& rest = client.level()->restV;
  const std::variant<spectral::ConstraintSet, QString> resolved = resolveConstraints(script, rest);
  if (const QString* error = std::get_if<QString>(&resolved)) {
    command.error(*error);
    client.leave();
    return kExitUsage;
  }
  spectral::ConstraintSet constraints = std::get<spectral::ConstraintSet>(resolved);

  QTextStream out(stderr);  // progress; stdout carries only the report (one JSON line with --json)
  // Within the host's work bound (constraint_work.h): on a dense mesh the script's anchors are thinned evenly.
  std::size_t handleIds = 0;
  for (const spectral::HandleGroup& group : constraints.handles) handleIds += group.vertices.size();
  const std::size_t anchorsGiven = constraints.anchors.size();
  const std::size_t stride =
      session::thinAnchors(constraints.anchors, handleIds, session::maxConstraintIds(client.session()->rowCount));
  if (stride != 1) {
    out << QStringLiteral(
               "%1 handle and %2 anchor vertices: keeping one anchor in %3 (%4) within the host's work "
               "bound\n")
               .arg(handleIds)
               .arg(anchorsGiven)
               .arg(stride)
               .arg(constraints.anchors.size());
  }
  out << "waiting for the lock\n";
  out.flush();
  client.requestLock();
  const bool held = waitUntil(
      [&client] { return client.lock()->canDrag() || client.state() != session::SessionClient::State::Ready; },
      std::chrono::minutes(10));
  if (!held || !client.lock()->canDrag()) {
    command.error(QStringLiteral("did not get the lock: %1").arg(client.errorText()));
    return kExitNetwork;
  }
  WireConstraints wire = wireConstraints(constraints);
  const std::size_t groups = wire.groups.size();
  client.sendConstraints(std::move(wire.groups), std::move(wire.anchors));
  out << QStringLiteral("lock held (epoch %1): playing %2 frames\n")
             .arg(client.lock()->heldEpoch())
             .arg(frameTimes(script).size());
  out.flush();
  const int sent = playDragScript(client, script, groups, spectral::boundingBoxDiagonal(rest));
  const bool complete = sent == static_cast<int>(frameTimes(script).size());
  client.releaseLock();
  waitUntil([] { return false; }, std::chrono::milliseconds(100));  // let the release go out
  client.leave();
  const QJsonObject report{{QStringLiteral("frames_sent"), sent},
                           {QStringLiteral("frames"), static_cast<qint64>(frameTimes(script).size())},
                           {QStringLiteral("complete"), complete}};
  printReport(command, report, [](const QJsonObject& r) {
    QTextStream(stdout) << QStringLiteral("sent %1 of %2 frames\n")
                               .arg(r[QStringLiteral("frames_sent")].toInt())
                               .arg(r[QStringLiteral("frames")].toInt());
  });
  if (!complete) command.error(QStringLiteral("lost the lock during the drag"));
  return complete ? kExitOk : kExitNetwork;
}

}  // namespace sc::app
