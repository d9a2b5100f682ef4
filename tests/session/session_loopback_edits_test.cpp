// Loopback tests of the shared edit history over real sockets (issue 15): a client's drag after the host's keeps the
// host's shape, each user's strokes reach everybody's EditLog with their author, and a client's undo takes out only
// its own step, on every screen. Fixture: session_loopback_fixture.h.
#include "session_loopback_fixture.h"

#include <QtTest/QTest>

namespace sc::session {
namespace {

/// Vertex ids of the suite's icosphere satisfying `predicate`.
template <typename Predicate>
std::vector<std::uint32_t> verticesWhere(const HostModel& model, Predicate predicate) {
  std::vector<std::uint32_t> ids;
  for (Eigen::Index i = 0; i < model.V.rows(); ++i) {
    if (predicate(model.V.row(i))) ids.push_back(static_cast<std::uint32_t>(i));
  }
  return ids;
}

TEST_F(SessionLoopback, AClientsUndoTakesOutOnlyItsOwnStepOnEveryScreen) {
  auto host = startHost();
  auto bob = join(*host, QStringLiteral("bob"));
  auto carol = join(*host, QStringLiteral("carol"));

  // The host raises the cap in one stroke and lets go of the lock.
  ASSERT_TRUE(host->requestLock());
  const auto [cap, bottom] = capConstraints();
  spectral::ConstraintSet hostSet;
  hostSet.handles.push_back({std::vector<int>(cap.begin(), cap.end())});
  hostSet.anchors.assign(bottom.begin(), bottom.end());
  ASSERT_TRUE(host->setConstraints(hostSet));
  spectral::HandleTransform up;
  up.translation = Eigen::Vector3d(0.0, 0.0, 0.3);
  ASSERT_TRUE(host->drag(std::span(&up, 1)));
  QTest::qWait(30);
  ASSERT_TRUE(host->endStroke());
  ASSERT_TRUE(host->releaseLock());
  const Eigen::MatrixXd hostShape = host->coefficients();
  ASSERT_GT(hostShape.norm(), 1e-3);

  // bob takes the lock, anchors the raised cap and drags the side (+x) sideways.
  ASSERT_TRUE(bob->requestLock());
  ASSERT_TRUE(QTest::qWaitFor([&] { return bob->lock()->canDrag(); }, kWaitMs));
  const std::vector<std::uint32_t> side =
      verticesWhere(*s_model, [](const auto& x) { return x(0) > 0.8 && x(2) < 0.8 && x(2) > -0.5; });
  ASSERT_FALSE(side.empty());
  ASSERT_TRUE(bob->sendConstraints({side}, cap));
  spectral::HandleTransform sideways;
  sideways.translation = Eigen::Vector3d(0.0, 0.25, 0.0);
  QTest::qWait(50);  // the host factors bob's constraints off its network thread
  ASSERT_TRUE(bob->sendDrag({toWire(0, sideways)}));
  ASSERT_TRUE(bob->endStroke());
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->history().steps().size() == 2; }, kWaitMs));
  const Eigen::MatrixXd both = host->coefficients();
  const Eigen::MatrixXd bobDelta = host->history().steps()[1].delta;
  EXPECT_LT((both - (hostShape + bobDelta)).cwiseAbs().maxCoeff(), 1e-12);
  // the cap stayed raised: bob anchored it where the host left it (from rest it would have dropped back)
  const Eigen::MatrixXd capRows = s_model->basis.vectors(std::vector<int>(cap.begin(), cap.end()), Eigen::all);
  const double raised = (capRows * hostShape).col(2).mean();
  ASSERT_GT(raised, 0.1);
  EXPECT_GT((capRows * both).col(2).mean(), 0.8 * raised);

  // Everybody's EditLog lists both steps with their authors.
  for (SessionClient* client : {bob.get(), carol.get()}) {
    ASSERT_TRUE(QTest::qWaitFor([&] { return client->editLog().steps.size() == 2; }, kWaitMs));
    EXPECT_EQ(client->editLog().steps[0].author, kHostPeer);
    EXPECT_EQ(client->editLog().steps[0].authorName, QStringLiteral("Hostess"));
    EXPECT_EQ(client->editLog().steps[1].author, bob->peerId());
    EXPECT_EQ(client->editLog().steps[1].authorName, QStringLiteral("bob"));
  }

  // carol has nothing to undo: her request changes nothing
  ASSERT_TRUE(carol->requestEdit(EditAction::Undo));
  QTest::qWait(100);
  EXPECT_EQ(host->coefficients(), both);
  EXPECT_EQ(host->counters().editsRefused, 1u);

  // bob undoes his own step: the host's raised cap stays, on the host and on carol's screen
  ASSERT_TRUE(bob->requestEdit(EditAction::Undo));
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return (host->coefficients() - hostShape).cwiseAbs().maxCoeff() < 1e-12; }, kWaitMs));
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        const Eigen::MatrixXd shown = carol->channel().coefficients();
        return shown.rows() == hostShape.rows() && (shown - hostShape).cwiseAbs().maxCoeff() < 1e-3;
      },
      kWaitMs));
  ASSERT_TRUE(QTest::qWaitFor([&] { return carol->editLog().steps[1].undoneBy == bob->peerId(); }, kWaitMs));
  EXPECT_EQ(carol->editLog().steps[0].undoneBy, kNoPeer);
  // and redoes it
  ASSERT_TRUE(bob->requestEdit(EditAction::Redo));
  ASSERT_TRUE(QTest::qWaitFor([&] { return (host->coefficients() - both).cwiseAbs().maxCoeff() < 1e-12; }, kWaitMs));
}

}  // namespace
}  // namespace sc::session
