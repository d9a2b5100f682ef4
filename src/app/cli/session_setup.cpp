#include "app/cli/session_setup.h"

#include "session/wire/handle_transforms.h"

#include <QCoreApplication>
#include <QDeadlineTimer>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QTimer>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

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

std::chrono::milliseconds levelWaitTimeout(std::uint32_t vertices, std::uint16_t rows,
                                           std::chrono::milliseconds floor) {
  constexpr double kFloorSize = 1e7;  // n·m of the 100k dragon at m = 100
  const double scale = std::max(1.0, static_cast<double>(vertices) * static_cast<double>(rows) / kFloorSize);
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(static_cast<double>(floor.count()) * scale)));
}

bool joinAndWait(const SubcommandParser& command, session::SessionClient& client, std::chrono::milliseconds timeout) {
  using State = session::SessionClient::State;
  client.start();
  QElapsedTimer clock;
  clock.start();
  const auto limit = [&client, timeout] {
    const std::optional<session::Welcome>& welcome = client.session();
    return welcome ? levelWaitTimeout(welcome->vertexCount, welcome->rowCount, timeout) : timeout;
  };
  const auto ended = [&client] {
    const State s = client.state();
    return s == State::Ready || s == State::Failed || s == State::Left;
  };
  // The deadline grows once the Welcome tells the session's size: the predicate reads it at every turn.
  const bool finished =
      waitUntil([&] { return ended() || clock.elapsed() > limit().count(); }, std::chrono::hours(24 * 365)) && ended();
  if (client.state() == State::Ready) return true;
  if (!finished) {
    command.error(
        QStringLiteral("no model from the host within %1 s").arg(static_cast<double>(limit().count()) / 1000.0));
  } else {
    command.error(QStringLiteral("session failed: %1").arg(client.errorText()));
  }
  return false;
}

WireConstraints wireConstraints(const spectral::ConstraintSet& constraints) {
  WireConstraints wire;
  for (const spectral::HandleGroup& group : constraints.handles)
    wire.groups.emplace_back(group.vertices.begin(), group.vertices.end());
  wire.anchors.assign(constraints.anchors.begin(), constraints.anchors.end());
  return wire;
}

int playDragScript(session::SessionClient& client, const DragScript& script, std::size_t groups, double diagonal) {
  const std::vector<double> times = frameTimes(script);
  QElapsedTimer clock;
  clock.start();
  int sent = 0;
  const auto lockHeld = [&client] { return client.lock() != nullptr && client.lock()->canDrag(); };
  for (double t : times) {
    const double due = (t - times.front()) * 1000.0;
    waitUntil([&] { return static_cast<double>(clock.nsecsElapsed()) / 1e6 >= due || !lockHeld(); },
              std::chrono::milliseconds(static_cast<int>(std::ceil(due - static_cast<double>(clock.elapsed()))) + 50));
    if (!lockHeld()) break;
    const spectral::HandleTransform pose = transformAt(poseAt(script, t), diagonal);
    std::vector<session::HandleTransform> handles;
    for (std::size_t g = 0; g < groups; ++g) handles.push_back(session::toWire(static_cast<std::uint16_t>(g), pose));
    if (client.sendDrag(std::move(handles))) ++sent;
  }
  return sent;
}

}  // namespace sc::app
