// Tests for src/session/engine/host_engine_edits.cpp (issue 15, "edits that accumulate"): a new constraint set starts
// from the current shape, every committed stroke is a step with its author, and undo / redo of one author's steps
// keep everybody else's. Socket-free: a fake clock, members driven by their messages.
#include "host_engine_fixture.h"

namespace sc::session::testing {
namespace {

class HostEngineEdits : public HostEngineTest {
 protected:
  /// The host's user lifts its cap by `dz` in one stroke and releases the lock.
  void hostLiftsCapAndReleases(double dz) {
    holdLockWithCap();
    lift(dz);
    tickFor(20ms);
    bool accepted = false;
    engine().endStroke(now(), &accepted);
    ASSERT_TRUE(accepted);
    engine().releaseLock(now());
  }

  /// `member` takes the lock, sets a handle at x > 0.8 over anchors at x < −0.5 (factored as the adapter would),
  /// drags it by `dy` and ends the stroke.
  void memberDragsSide(PeerId member, double dy) {
    const std::vector<LockNotice> granted =
        sentToAll<LockNotice>(engine().onMessage(member, LockMessage{LockRequestKind::Request, kNoEpoch}, now()));
    ASSERT_FALSE(granted.empty());
    const LockEpoch epoch = engine().arbiter().epoch();
    ASSERT_EQ(engine().arbiter().holder(), member);
    Constraints constraints;
    constraints.epoch = epoch;
    constraints.groups.push_back(where([](const Eigen::Vector3d& x) { return x.x() > 0.8; }));
    constraints.anchors = where([](const Eigen::Vector3d& x) { return x.x() < -0.5; });
    const Eigen::MatrixXd before = engine().coefficients();
    completeConstraints(engine().onMessage(member, constraints, now()));
    EXPECT_EQ(engine().coefficients(), before) << "new constraints change nothing by themselves";
    spectral::HandleTransform pose;
    pose.translation = Eigen::Vector3d(0.0, dy, 0.0);
    const std::vector<HandleTransform> handles{toWire(0, pose)};
    advance(20ms);
    engine().onMessage(member, Drag{epoch, handles}, now());
    advance(20ms);
    engine().onMessage(member, StrokeEnd{epoch}, now());
  }

  /// The mean z of the cap (z > 0.8) in the shape `Z` gives, minus at rest.
  static double capLift(const Eigen::MatrixXd& Z) {
    const std::vector<std::uint32_t> cap = where([](const Eigen::Vector3d& x) { return x.z() > 0.8; });
    double sum = 0.0;
    for (std::uint32_t v : cap) sum += (s_model->basis.vectors.row(v) * Z)(2);
    return sum / static_cast<double>(cap.size());
  }
};

TEST_F(HostEngineEdits, ASecondUsersNewConstraintsKeepTheFirstUsersShape) {
  startEngine();
  const PeerId bob = join(QStringLiteral("bob"));
  hostLiftsCapAndReleases(0.4);
  const Eigen::MatrixXd afterHost = engine().coefficients();
  ASSERT_GT(capLift(afterHost), 0.2);
  memberDragsSide(bob, 0.3);
  EXPECT_GT(capLift(engine().coefficients()), 0.8 * capLift(afterHost))
      << "the host's raised cap must not snap back when bob drags another part";
  EXPECT_NE(engine().coefficients(), afterHost) << "bob's drag moved the shape";
}

TEST_F(HostEngineEdits, EveryStrokeIsAStepWithItsAuthorAndTheLogGoesToEverybody) {
  startEngine();
  const PeerId bob = join(QStringLiteral("bob"));
  holdLockWithCap();
  lift(0.2);
  tickFor(20ms);
  bool accepted = false;
  const HostActions ended = engine().endStroke(now(), &accepted);
  ASSERT_TRUE(accepted);
  const std::vector<EditLog> logs = sentToAll<EditLog>(ended);
  ASSERT_EQ(logs.size(), 1u);
  ASSERT_EQ(logs[0].steps.size(), 1u);
  EXPECT_EQ(logs[0].steps[0].author, kHostPeer);
  EXPECT_EQ(logs[0].steps[0].authorName, QStringLiteral("host"));
  EXPECT_EQ(actionsOf<EditHistoryChanged>(ended).size(), 1u);
  // a second stroke with the same constraints is a second step; it starts from the first one's shape
  lift(0.1);
  tickFor(20ms);
  engine().endStroke(now());
  ASSERT_EQ(engine().history().steps().size(), 2u);
  EXPECT_NEAR(capLift(engine().history().steps()[0].delta + engine().history().steps()[1].delta),
              capLift(engine().coefficients()), 1e-12);
  engine().releaseLock(now());
  memberDragsSide(bob, 0.2);
  ASSERT_EQ(engine().history().steps().size(), 3u);
  EXPECT_EQ(engine().history().steps()[2].author, bob);
  EXPECT_EQ(engine().history().steps()[2].authorName, QStringLiteral("bob"));
  // a newcomer gets the log with its Welcome's other facts
  const Admission carol = engine().onConnectionAttempt("10.0.0.9", now());
  const std::vector<EditLog> toCarol =
      sentTo<EditLog>(engine().onWelcomed(carol.peer, QStringLiteral("carol"), now()), carol.peer);
  ASSERT_EQ(toCarol.size(), 1u);
  EXPECT_EQ(toCarol[0].steps.size(), 3u);
}

TEST_F(HostEngineEdits, UndoAndRedoOfEachAuthorsStepsKeepTheOthersWork) {
  startEngine();
  const PeerId bob = join(QStringLiteral("bob"));
  hostLiftsCapAndReleases(0.4);
  const Eigen::MatrixXd hostShape = engine().coefficients();
  memberDragsSide(bob, 0.3);
  const Eigen::MatrixXd bothShape = engine().coefficients();
  const Eigen::MatrixXd bobDelta = bothShape - hostShape;

  // bob undoes his own step: the host's lift stays
  const HostActions undone = engine().onMessage(bob, EditRequest{EditAction::Undo}, now());
  EXPECT_LT((engine().coefficients() - hostShape).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_EQ(actionsOf<SendFrame>(undone).size(), 1u) << "everybody sees the undo";
  EXPECT_EQ(sentToAll<EditLog>(undone).size(), 1u);
  // bob has nothing more of his own to undo: a second undo changes nothing
  engine().onMessage(bob, EditRequest{EditAction::Undo}, now());
  EXPECT_LT((engine().coefficients() - hostShape).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(engine().counters().editsRefused, 1u);
  // bob redoes it
  engine().onMessage(bob, EditRequest{EditAction::Redo}, now());
  EXPECT_LT((engine().coefficients() - bothShape).cwiseAbs().maxCoeff(), 1e-12);

  // the host undoes the latest step of anybody (bob's), then its own: bob's work is never silently dropped
  bool applied = false;
  engine().edit(EditAction::Undo, now(), &applied);
  ASSERT_TRUE(applied);
  EXPECT_LT((engine().coefficients() - hostShape).cwiseAbs().maxCoeff(), 1e-12);
  engine().edit(EditAction::Undo, now(), &applied);
  ASSERT_TRUE(applied);
  EXPECT_LT(engine().coefficients().cwiseAbs().maxCoeff(), 1e-12) << "both undone: rest";
  // redo by the host brings back what the HOST undid last (its own lift); bob's step stays undone, listed
  engine().edit(EditAction::Redo, now(), &applied);
  ASSERT_TRUE(applied);
  EXPECT_LT((engine().coefficients() - hostShape).cwiseAbs().maxCoeff(), 1e-12);
  const EditLog log = engine().history().log();
  ASSERT_EQ(log.steps.size(), 2u);
  EXPECT_EQ(log.steps[1].undoneBy, kHostPeer);
  EXPECT_TRUE(log.steps[1].redoable);
  engine().edit(EditAction::Redo, now(), &applied);
  EXPECT_LT((engine().coefficients() - (hostShape + bobDelta)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST_F(HostEngineEdits, UndoingAnotherStepWhileSomeoneDragsKeepsTheDragGoingFromTheNewShape) {
  startEngine();
  const PeerId bob = join(QStringLiteral("bob"));
  hostLiftsCapAndReleases(0.4);
  const Eigen::MatrixXd hostShape = engine().coefficients();
  memberDragsSide(bob, 0.3);  // bob still holds the lock with his handle
  const LockEpoch epoch = engine().arbiter().epoch();
  const Eigen::MatrixXd bobStep = engine().coefficients() - hostShape;
  // bob starts a second stroke, then the host undoes its own (older) lift under him
  spectral::HandleTransform pose;
  pose.translation = Eigen::Vector3d(0.0, 0.1, 0.0);
  advance(20ms);
  engine().onMessage(bob, Drag{epoch, {toWire(0, pose)}}, now());
  const Eigen::MatrixXd midStroke = engine().coefficients();
  // host's undo takes bob's stroke going on as a step first, then undoes that latest step (bob's)
  engine().edit(EditAction::Undo, now());
  EXPECT_LT((engine().coefficients() - (hostShape + bobStep)).cwiseAbs().maxCoeff(), 1e-12);
  engine().edit(EditAction::Undo, now());  // and bob's first stroke
  engine().edit(EditAction::Undo, now());  // and the host's lift
  EXPECT_LT(engine().coefficients().cwiseAbs().maxCoeff(), 1e-12);
  // bob drags on: his pose acts from the shape as it is now (rest), not from what was undone
  pose.translation = Eigen::Vector3d(0.0, 0.05, 0.0);
  advance(20ms);
  engine().onMessage(bob, Drag{epoch, {toWire(0, pose)}}, now());
  EXPECT_LT(capLift(engine().coefficients()), 0.05) << "the undone lift does not come back";
  EXPECT_NE(midStroke, engine().coefficients());
}

TEST_F(HostEngineEdits, ALockThatEndsEndsTheStrokeAndUndoNeedsNoLock) {
  startEngine();
  const PeerId bob = join(QStringLiteral("bob"));
  holdLockWithCap();
  lift(0.3);
  tickFor(20ms);
  engine().releaseLock(now());  // no endStroke: the release ends the stroke
  ASSERT_EQ(engine().history().steps().size(), 1u);
  EXPECT_EQ(engine().history().steps()[0].author, kHostPeer);
  // bob takes the lock; the host (not holding it) can still undo
  engine().onMessage(bob, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  ASSERT_EQ(engine().arbiter().holder(), bob);
  bool applied = false;
  engine().edit(EditAction::Undo, now(), &applied);
  EXPECT_TRUE(applied);
  EXPECT_LT(engine().coefficients().cwiseAbs().maxCoeff(), 1e-12);
}

TEST_F(HostEngineEdits, AMemberWhoVanishesMidStrokeLeavesItsStrokeAsAStepUnderItsName) {
  startEngine();
  const PeerId bob = join(QStringLiteral("bob"));
  engine().onMessage(bob, LockMessage{LockRequestKind::Request, kNoEpoch}, now());
  const LockEpoch epoch = engine().arbiter().epoch();
  Constraints constraints;
  constraints.epoch = epoch;
  constraints.groups.push_back(where([](const Eigen::Vector3d& x) { return x.z() > 0.8; }));
  completeConstraints(engine().onMessage(bob, constraints, now()));
  spectral::HandleTransform pose;
  pose.translation = Eigen::Vector3d(0.0, 0.0, 0.2);
  advance(20ms);
  engine().onMessage(bob, Drag{epoch, {toWire(0, pose)}}, now());
  const Eigen::MatrixXd shape = engine().coefficients();
  engine().onClosed(bob, now());  // no StrokeEnd, no Leave
  ASSERT_EQ(engine().history().steps().size(), 1u);
  EXPECT_EQ(engine().history().steps()[0].authorName, QStringLiteral("bob"));
  EXPECT_EQ(engine().coefficients(), shape) << "what bob did stays";
  // and the host may still undo it
  bool applied = false;
  engine().edit(EditAction::Undo, now(), &applied);
  EXPECT_TRUE(applied);
}

TEST_F(HostEngineEdits, EditRequestsOverTheirRateAreIgnored) {
  startEngine();
  const PeerId bob = join(QStringLiteral("bob"));
  for (int i = 0; i < 20; ++i) engine().onMessage(bob, EditRequest{EditAction::Undo}, now());
  EXPECT_GE(engine().counters().requestsThrottled, 10u);
  EXPECT_NE(engine().arbiter().holder(), bob);
}

TEST(EditHistory, KeepsAtMostItsCapacityAndForgetsTheOldest) {
  EditHistory history(3);
  for (int i = 1; i <= 5; ++i)
    EXPECT_TRUE(history.commit(2, QStringLiteral("bob"), Eigen::MatrixXd::Constant(4, 3, i)));
  EXPECT_FALSE(history.commit(2, QStringLiteral("bob"), Eigen::MatrixXd::Zero(4, 3)))
      << "a stroke that changed nothing";
  ASSERT_EQ(history.steps().size(), 3u);
  EXPECT_EQ(history.steps().front().id, 3u);
  EXPECT_EQ(history.log().steps.size(), 3u);
}

TEST(EditHistory, ALongAuthorNameIsCutToWholeCharactersAndTheLogStillEncodes) {
  EditHistory history;
  QString name;
  for (int i = 0; i < 40; ++i) name += QString::fromUtf8("🦆");  // 4 UTF-8 bytes, two UTF-16 units each
  history.commit(2, name, Eigen::MatrixXd::Constant(2, 3, 1.0));
  const EditLog log = history.log();
  ASSERT_EQ(log.steps.size(), 1u);
  EXPECT_LE(log.steps[0].authorName.toUtf8().size(), kMaxNameBytes);
  EXPECT_EQ(log.steps[0].authorName, name.left(32));  // 16 ducks
  EXPECT_FALSE(encodeControlMessage(log).isEmpty());
}

TEST(EditLogReading, EachMemberFindsWhatItsUndoAndRedoWouldDo) {
  const EditLog log{{{1, 1, 0, false, QStringLiteral("host")},
                     {2, 2, 0, false, QStringLiteral("bob")},
                     {3, 3, 2, true, QStringLiteral("carol")},
                     {4, 3, 0, false, QStringLiteral("carol")}}};
  EXPECT_EQ(undoableIn(log, 2, false)->step, 2u) << "bob: his own latest applied step";
  EXPECT_EQ(undoableIn(log, 3, false)->step, 4u);
  EXPECT_EQ(undoableIn(log, 1, true)->step, 4u) << "the host: anybody's latest";
  EXPECT_FALSE(undoableIn(log, 9, false).has_value());
  EXPECT_EQ(redoableIn(log, 2)->step, 3u) << "bob undid carol's step 3 and may redo it";
  EXPECT_FALSE(redoableIn(log, 3).has_value());
}

TEST(EditHistory, ANewStepEndsItsAuthorsRedoButNotOthers) {
  EditHistory history;
  history.commit(2, QStringLiteral("bob"), Eigen::MatrixXd::Constant(2, 3, 1.0));
  history.commit(3, QStringLiteral("carol"), Eigen::MatrixXd::Constant(2, 3, 2.0));
  ASSERT_NE(history.undo(2, false), nullptr);
  ASSERT_NE(history.undo(3, false), nullptr);
  history.commit(2, QStringLiteral("bob"), Eigen::MatrixXd::Constant(2, 3, 3.0));
  EXPECT_EQ(history.redoable(2), nullptr) << "bob made a new edit: his undone step stays undone";
  ASSERT_NE(history.redoable(3), nullptr) << "carol's redo is hers";
  EXPECT_EQ(history.redo(3)->author, 3u);
  EXPECT_EQ(history.undoable(2, false)->delta(0, 0), 3.0);
}

}  // namespace
}  // namespace sc::session::testing
