#include "app/cli/session_setup.h"

#include <QCoreApplication>
#include <QDeadlineTimer>
#include <QEventLoop>
#include <QTimer>

namespace sc::app {

std::shared_ptr<const session::HostModel> loadHostModel(const SubcommandParser& command, const QString& meshPath,
                                                        int& exitCode) {
  std::optional<model::LoadedMesh> mesh = loadMeshOrReport(command, meshPath);
  if (!mesh) {
    exitCode = kExitMeshError;
    return nullptr;
  }
  spectral::BasisComputation basis = basisOrReport(command, *mesh);
  if (!basis.result.ok()) {
    exitCode = kExitBasisError;
    return nullptr;
  }
  auto model = std::make_shared<session::HostModel>();
  model->V = std::move(mesh->V);
  model->F = std::move(mesh->F);
  model->basis = std::move(basis.result.basis);
  model->operators = std::move(basis.operators);
  exitCode = kExitOk;
  return model;
}

bool waitUntil(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  QDeadlineTimer deadline(timeout);
  QTimer wakeUp;  // bounds each wait, so the deadline is seen even when nothing happens
  wakeUp.start(10);
  while (!done() && !deadline.hasExpired()) QCoreApplication::processEvents(QEventLoop::WaitForMoreEvents);
  return done();
}

bool joinAndWait(const SubcommandParser& command, session::SessionClient& client, std::chrono::milliseconds timeout) {
  using State = session::SessionClient::State;
  client.start();
  const bool finished = waitUntil(
      [&client] {
        const State s = client.state();
        return s == State::Ready || s == State::Failed || s == State::Left;
      },
      timeout);
  if (client.state() == State::Ready) return true;
  if (!finished) {
    command.error(QStringLiteral("no model from the host within %1 s").arg(timeout.count() / 1000.0));
  } else {
    command.error(QStringLiteral("session failed: %1").arg(client.errorText()));
  }
  return false;
}

}  // namespace sc::app
