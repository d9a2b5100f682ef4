// Tests for several people dragging at once (issue 15, item 2; host_engine_lock.cpp, host_engine_edits.cpp,
// shared_constraints.h): each holder of a lease moves its own handle groups, the host solves every group in one
// subspace solve, overlapping sets are refused with the holder named, and a lease's end takes its set out while the
// other drags go on. Socket-free: a fake clock, members driven by their messages.
#include "host_engine_fixture.h"

namespace sc::session::testing {
namespace {

class HostEngineCoediting : public HostEngineTest {
 protected:
  static std::vector<std::uint32_t> east() {
    return where([](const Eigen::Vector3d& x) { return x.x() > 0.8; });
  }
  static std::vector<std::uint32_t> west() {
    return where([](const Eigen::Vector3d& x) { return x.x() < -0.8; });
  }
  static std::vector<std::uint32_t> south() {
    return where([](const Eigen::Vector3d& x) { return x.z() < -0.8; });
  }

  /// Three editors at once; bob and carol join and each takes a lease.
  void startWithTwoEditors() {
    HostEngineOptions options;
    options.maxEditors = 3;
    startEngine(options);
    m_bob = join(QStringLiteral("bob"));
    m_carol = join(QStringLiteral("carol"), "10.0.0.2");
    m_dave = join(QStringLiteral("dave"), "10.0.0.3");  // watches
    engine().onMessage(m_bob, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
    engine().onMessage(m_carol, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
    m_bobEpoch = engine().arbiter().epochOf(m_bob);
    m_carolEpoch = engine().arbiter().epochOf(m_carol);
    ASSERT_NE(m_bobEpoch, kNoEpoch);
    ASSERT_NE(m_carolEpoch, kNoEpoch) << "two leases at once";
  }

  /// Bob's handle is the east cap, carol's the west cap, both over the south cap; both sets installed.
  void bothSetTheirEnds() {
    completeConstraints(engine().onMessage(m_bob, Constraints{m_bobEpoch, {east()}, south()}, now()));
    completeConstraints(engine().onMessage(m_carol, Constraints{m_carolEpoch, {west()}, south()}, now()));
  }

  /// Bob drags his end by `bobY` along y, carol hers by `carolZ` along z, 10 ms apart; the frames go out.
  void bothDrag(double bobY, double carolZ) {
    advance(10ms);
    drag(m_bob, m_bobEpoch, {0.0, bobY, 0.0});
    advance(10ms);
    drag(m_carol, m_carolEpoch, {0.0, 0.0, carolZ});
    tickFor(20ms);
  }

  HostActions drag(PeerId member, LockEpoch epoch, const Eigen::Vector3d& t) {
    spectral::HandleTransform pose;
    pose.translation = t;
    return engine().onMessage(member, Drag{epoch, {toWire(0, pose)}}, now());
  }

  static spectral::HandleTransform moved(const Eigen::Vector3d& t) {
    spectral::HandleTransform pose;
    pose.translation = t;
    return pose;
  }

  static std::vector<int> ints(const std::vector<std::uint32_t>& ids) { return {ids.begin(), ids.end()}; }

  PeerId m_bob = kNoPeer;
  PeerId m_carol = kNoPeer;
  PeerId m_dave = kNoPeer;
  LockEpoch m_bobEpoch = kNoEpoch;
  LockEpoch m_carolEpoch = kNoEpoch;
};

TEST_F(HostEngineCoediting, TwoSimultaneousDragsGiveTheShapeOfOneSolveWithBothGroupsOnEveryScreen) {
  startWithTwoEditors();
  bothSetTheirEnds();
  ASSERT_EQ(engine().deformer().constraints().handles.size(), 2u) << "both groups in one union";
  // both drag, interleaved, several frames each
  HostActions frames;
  for (int i = 1; i <= 5; ++i) {
    advance(10ms);
    HostActions a = drag(m_bob, m_bobEpoch, {0.0, 0.04 * i, 0.0});
    advance(10ms);
    HostActions b = drag(m_carol, m_carolEpoch, {0.0, 0.0, 0.05 * i});
    frames.list.insert(frames.list.end(), a.list.begin(), a.list.end());
    frames.list.insert(frames.list.end(), b.list.begin(), b.list.end());
  }
  HostActions rest = tickFor(50ms);
  frames.list.insert(frames.list.end(), rest.list.begin(), rest.list.end());
  const std::vector<SendFrame> sent = actionsOf<SendFrame>(frames);
  ASSERT_FALSE(sent.empty()) << "frames go to everybody (dave included): SendFrame is a broadcast";

  // one solve of a deformer that has both groups and the shared anchors, from rest
  spectral::SpectralDeformer reference(s_model->basis, s_model->operators, s_model->V);
  ASSERT_TRUE(reference.setConstraints({{{ints(east())}, {ints(west())}}, ints(south())}));
  const spectral::HandleTransform both[] = {moved({0.0, 0.2, 0.0}), moved({0.0, 0.0, 0.25})};
  const Eigen::MatrixXd expected = reference.solve(both);
  EXPECT_LT((*sent.back().Z - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff());
  EXPECT_LT((engine().coefficients() - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff());
}

TEST_F(HostEngineCoediting, ASetOverlappingAnotherHoldersIsRefusedWithTheHolderNamed) {
  startWithTwoEditors();
  completeConstraints(engine().onMessage(m_bob, Constraints{m_bobEpoch, {east()}, south()}, now()));
  const std::uint64_t factored = static_cast<std::uint64_t>(engine().deformer().factorizationCount());
  // carol's handle takes in bob's anchors (the south cap)
  const HostActions refused = engine().onMessage(m_carol, Constraints{m_carolEpoch, {south()}, {}}, now());
  const std::vector<LockNotice> notices = sentTo<LockNotice>(refused, m_carol);
  ASSERT_EQ(notices.size(), 1u);
  EXPECT_EQ(notices[0].kind, LockNoticeKind::Refused);
  EXPECT_EQ(notices[0].epoch, m_carolEpoch);
  EXPECT_EQ(notices[0].waiting, std::vector<PeerId>{m_bob});
  EXPECT_TRUE(actionsOf<PrepareConstraints>(refused).empty()) << "nothing is factored for a refused set";
  EXPECT_EQ(static_cast<std::uint64_t>(engine().deformer().factorizationCount()), factored);
  EXPECT_EQ(engine().counters().constraintsOverlapping, 1u);
  // anchors shared with bob's anchors are no conflict
  const HostActions accepted = engine().onMessage(m_carol, Constraints{m_carolEpoch, {west()}, south()}, now());
  EXPECT_TRUE(sentTo<LockNotice>(accepted, m_carol).empty());
  EXPECT_EQ(actionsOf<PrepareConstraints>(accepted).size(), 1u);
  // the host's own user gets the same refusal (its LockClient keeps it for the window)
  bool sent = false;
  engine().requestLock(now(), &sent);
  spectral::ConstraintSet overlapping{{{ints(east())}}, {}};
  bool ok = true;
  engine().setConstraints(overlapping, now(), &ok);
  EXPECT_FALSE(ok);
  ASSERT_TRUE(engine().localLock().lastRefusal().has_value());
  EXPECT_EQ(engine().localLock().lastRefusal()->holders, std::vector<PeerId>{m_bob});
}

TEST_F(HostEngineCoediting, EachDraggersStrokeIsItsOwnStepAndUndoingOneKeepsTheOther) {
  startWithTwoEditors();
  bothSetTheirEnds();
  bothDrag(0.2, 0.25);
  engine().onMessage(m_bob, StrokeEnd{m_bobEpoch}, now());  // bob lets go; carol still holds her pose
  advance(10ms);
  drag(m_carol, m_carolEpoch, {0.0, 0.0, 0.3});  // and carries on from where she was
  tickFor(20ms);
  engine().onMessage(m_carol, StrokeEnd{m_carolEpoch}, now());
  const auto& steps = engine().history().steps();
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].author, m_bob);
  EXPECT_EQ(steps[1].author, m_carol);
  const Eigen::MatrixXd Z = engine().coefficients();
  EXPECT_LT((steps[0].delta + steps[1].delta - Z).cwiseAbs().maxCoeff(), 1e-9 * Z.cwiseAbs().maxCoeff())
      << "the shares add up to the shape";

  spectral::SpectralDeformer reference(s_model->basis, s_model->operators, s_model->V);
  ASSERT_TRUE(reference.setConstraints({{{ints(east())}, {ints(west())}}, ints(south())}));
  const spectral::HandleTransform both[] = {moved({0.0, 0.2, 0.0}), moved({0.0, 0.0, 0.3})};
  const spectral::HandleTransform carolAlone[] = {spectral::HandleTransform{}, moved({0.0, 0.0, 0.3})};
  EXPECT_LT((Z - reference.solve(both)).cwiseAbs().maxCoeff(), 1e-6 * Z.cwiseAbs().maxCoeff())
      << "carol's drag went on from where it was, not from the start (no jump at bob's release)";

  engine().onMessage(m_bob, EditRequest{EditAction::Undo}, now());
  const Eigen::MatrixXd afterUndo = engine().coefficients();
  EXPECT_LT((afterUndo - reference.solve(carolAlone)).cwiseAbs().maxCoeff(), 1e-6 * Z.cwiseAbs().maxCoeff())
      << "bob's undo takes out his drag only; carol's stays";
}

TEST_F(HostEngineCoediting, ALeaseThatEndsTakesItsSetOutAndTheOtherDragGoesOnWithoutAJump) {
  startWithTwoEditors();
  bothSetTheirEnds();
  bothDrag(0.2, 0.2);
  const Eigen::MatrixXd before = engine().coefficients();
  // bob vanishes mid-drag: his stroke is a step, his lease and set go
  const HostActions gone = engine().onClosed(m_bob, now());
  ASSERT_EQ(engine().history().steps().size(), 1u);
  EXPECT_EQ(engine().history().steps()[0].author, m_bob);
  EXPECT_EQ(engine().arbiter().epochOf(m_bob), kNoEpoch);
  completeConstraints(gone);
  ASSERT_EQ(engine().deformer().constraints().handles.size(), 1u) << "only carol's group is left";
  EXPECT_EQ(engine().coefficients(), before) << "taking a set out moves nothing by itself";
  // carol's next pose is a small step from her last one: the shape moves a little, not by her whole drag again
  advance(10ms);
  drag(m_carol, m_carolEpoch, {0.0, 0.0, 0.21});
  tickFor(20ms);
  const double step = (engine().coefficients() - before).cwiseAbs().maxCoeff();
  EXPECT_GT(step, 0.0);
  EXPECT_LT(step, 0.2 * before.cwiseAbs().maxCoeff());
}

TEST_F(HostEngineCoediting, WithOneEditorTheSecondRequestWaitsAsWithTheSingleLock) {
  startEngine();  // maxEditors = 1 (the default of the engine; the app asks for more)
  const PeerId bob = join(QStringLiteral("bob"));
  const PeerId carol = join(QStringLiteral("carol"), "10.0.0.2");
  engine().onMessage(bob, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  const HostActions queued = engine().onMessage(carol, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  ASSERT_EQ(sentTo<LockNotice>(queued, carol).size(), 1u);
  EXPECT_EQ(sentTo<LockNotice>(queued, carol)[0].kind, LockNoticeKind::Queued);
}

TEST_F(HostEngineCoediting, ANewcomerIsToldEveryCurrentLease) {
  startWithTwoEditors();
  const Admission erin = engine().onConnectionAttempt("10.0.0.9", now());
  const std::vector<LockNotice> grants =
      sentTo<LockNotice>(engine().onWelcomed(erin.peer, QStringLiteral("erin"), now()), erin.peer);
  ASSERT_EQ(grants.size(), 2u);
  EXPECT_EQ(grants[0], (LockNotice{LockNoticeKind::Granted, m_bob, m_bobEpoch}));
  EXPECT_EQ(grants[1], (LockNotice{LockNoticeKind::Granted, m_carol, m_carolEpoch}));
}

}  // namespace
}  // namespace sc::session::testing
