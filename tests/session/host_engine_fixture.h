#pragma once
// Shared by the HostEngine suites (host_engine_*_test.cpp): a small host model (an icosphere with a 12-function
// harmonic basis, built once), a fake clock, and filters over the engine's actions. No sockets, no timers: every
// event gets the fake clock's reading and the test advances it by hand (tickUntil() follows the engine's wake-ups).

#include "harmonic_host_model.h"
#include "session/engine/host_engine.h"
#include "session/wire/handle_transforms.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

namespace sc::session::testing {

using namespace std::chrono_literals;

/// Every action of type T in `actions`, in order.
template <typename T>
std::vector<T> actionsOf(const HostActions& actions) {
  std::vector<T> found;
  for (const HostAction& action : actions.list) {
    if (const T* a = std::get_if<T>(&action)) found.push_back(*a);
  }
  return found;
}

/// The messages of type M sent to `peer` (SendToPeer) in `actions`.
template <typename M>
std::vector<M> sentTo(const HostActions& actions, PeerId peer) {
  std::vector<M> found;
  for (const SendToPeer& send : actionsOf<SendToPeer>(actions)) {
    if (send.peer == peer && std::holds_alternative<M>(send.message)) found.push_back(std::get<M>(send.message));
  }
  return found;
}

/// The messages of type M sent to everybody (SendToAll) in `actions`.
template <typename M>
std::vector<M> sentToAll(const HostActions& actions) {
  std::vector<M> found;
  for (const SendToAll& send : actionsOf<SendToAll>(actions)) {
    if (std::holds_alternative<M>(send.message)) found.push_back(std::get<M>(send.message));
  }
  return found;
}

class HostEngineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { s_model = harmonicHostModel(sc::testing::icosphere(2), 12); }
  static void TearDownTestSuite() { s_model.reset(); }

  /// A started engine with `options` and the ladder `targets`, its clock at 1 s.
  void startEngine(HostEngineOptions options = {}, std::vector<std::uint32_t> targets = {}) {
    m_engine = std::make_unique<HostEngine>(s_model, std::move(options), targets);
    m_actions = m_engine->start(m_now);
  }

  HostEngine& engine() { return *m_engine; }
  Micros now() const { return m_now; }
  void advance(Micros by) { m_now += by; }

  /// Advances the clock to `until`, ticking at every wake-up the engine asks for on the way (and at `until`);
  /// returns every action of those ticks, in order.
  HostActions tickUntil(Micros until) {
    HostActions all;
    while (true) {
      const std::optional<Micros> wake = m_engine->nextWakeUp();
      const bool stop = !wake || *wake > until;
      m_now = stop ? until : std::max(m_now, *wake);
      HostActions step = m_engine->tick(m_now);
      all.list.insert(all.list.end(), step.list.begin(), step.list.end());
      all.wakeAt = step.wakeAt;
      if (stop) return all;
    }
  }
  HostActions tickFor(Micros duration) { return tickUntil(m_now + duration); }

  /// Admits and welcomes a peer named `name` from `address`; returns its id.
  PeerId join(const QString& name, const std::string& address = "10.0.0.1") {
    const Admission admission = m_engine->onConnectionAttempt(address, m_now);
    EXPECT_NE(admission.peer, kNoPeer) << "a join within the limits is admitted";
    m_actions = m_engine->onWelcomed(admission.peer, name, m_now);
    return admission.peer;
  }

  /// Factors every PrepareConstraints of `actions` as the adapter's worker would and hands the result back;
  /// returns the engine's answers, in order.
  HostActions completeConstraints(const HostActions& actions) {
    HostActions all;
    for (const PrepareConstraints& job : actionsOf<PrepareConstraints>(actions)) {
      HostActions step =
          m_engine->onConstraintsPrepared(job.ticket, m_engine->deformer().prepare(*job.constraints), m_now);
      all.list.insert(all.list.end(), step.list.begin(), step.list.end());
    }
    return all;
  }

  /// Vertex ids of the model whose rest position satisfies `predicate`.
  static std::vector<std::uint32_t> where(const std::function<bool(const Eigen::Vector3d&)>& predicate) {
    std::vector<std::uint32_t> ids;
    for (Eigen::Index i = 0; i < s_model->V.rows(); ++i) {
      if (predicate(s_model->V.row(i).transpose())) ids.push_back(static_cast<std::uint32_t>(i));
    }
    return ids;
  }

  /// The host's own user takes the lock and sets a cap handle (z > 0.8) over anchors (z < −0.5).
  void holdLockWithCap() {
    bool sent = false;
    m_engine->requestLock(m_now, &sent);
    ASSERT_TRUE(sent);
    ASSERT_EQ(m_engine->arbiter().holder(), kHostPeer);
    spectral::ConstraintSet set;
    set.handles.emplace_back();
    for (Eigen::Index i = 0; i < s_model->V.rows(); ++i) {
      if (s_model->V(i, 2) > 0.8) set.handles[0].vertices.push_back(static_cast<int>(i));
      if (s_model->V(i, 2) < -0.5) set.anchors.push_back(static_cast<int>(i));
    }
    bool accepted = false;
    m_engine->setConstraints(set, m_now, &accepted);
    ASSERT_TRUE(accepted);
  }

  /// The host's own user drags the cap to height `dz`; returns the engine's actions.
  HostActions lift(double dz) {
    spectral::HandleTransform pose;
    pose.translation = Eigen::Vector3d(0.0, 0.0, dz);
    bool accepted = false;
    HostActions actions = m_engine->drag(std::span(&pose, 1), m_now, &accepted);
    EXPECT_TRUE(accepted);
    return actions;
  }

  static inline std::shared_ptr<const HostModel> s_model;
  std::unique_ptr<HostEngine> m_engine;
  HostActions m_actions;  ///< of the last start() or join()
  Micros m_now{1'000'000};
};

}  // namespace sc::session::testing
