// PresenceSchedule (sender pacing) and PresenceBoard (others' latest presence) on a fake clock: no sockets.
#include "session/engine/presence_board.h"
#include "session/engine/presence_schedule.h"

#include <gtest/gtest.h>

namespace sc::session {
namespace {

using namespace std::chrono_literals;

Presence at(double x, bool pointerOn = false) {
  Presence p{kNoPeer, {x, 0.0, 5.0}, {0.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, pointerOn, {}, false};
  if (pointerOn) p.pointer = {0.1, 0.2, 0.3};
  return p;
}

/// Offers `value(t)` every `step` for `duration` from `start`; returns how many offers said "send".
template <typename ValueAt>
int sendsOver(PresenceSchedule& schedule, Micros start, Micros duration, Micros step, ValueAt value) {
  int sends = 0;
  for (Micros t = start; t < start + duration; t += step) sends += schedule.offer(value(t), t) ? 1 : 0;
  return sends;
}

TEST(PresenceSchedule, MovingIsPacedAtThirtyPerSecond) {
  PresenceSchedule schedule;
  // The camera moves every millisecond for 2 s: ~30 sends per second, no more.
  const int sends = sendsOver(schedule, Micros{0}, 2s, 1ms, [](Micros t) { return at(double(t.count())); });
  EXPECT_GE(sends, 58);
  EXPECT_LE(sends, 61);
}

TEST(PresenceSchedule, IdleSendsTwicePerSecondAtMost) {
  PresenceSchedule schedule;
  ASSERT_TRUE(schedule.offer(at(1.0), Micros{0}));  // the first value goes at once
  // Nothing changes; offered every millisecond for 3 s: a keep-alive every 500 ms only.
  const int sends = sendsOver(schedule, 1ms, 3s, 1ms, [](Micros) { return at(1.0); });
  EXPECT_EQ(sends, 6);
  EXPECT_FALSE(schedule.pending());
}

TEST(PresenceSchedule, AChangeTooSoonWaitsForItsSlot) {
  PresenceSchedule schedule;
  ASSERT_TRUE(schedule.offer(at(1.0), Micros{0}));
  EXPECT_EQ(schedule.nextDue(), Micros{500'000});  // idle: the keep-alive
  EXPECT_FALSE(schedule.offer(at(2.0), Micros{10'000}));
  EXPECT_TRUE(schedule.pending());
  EXPECT_EQ(schedule.nextDue(), Micros{33'333});  // the changed value's slot
  EXPECT_TRUE(schedule.offer(at(2.0), Micros{33'333}));
  EXPECT_FALSE(schedule.pending());
  EXPECT_TRUE(schedule.offer(at(2.0, true), Micros{70'000})) << "the pointer appearing is a change";
  schedule.reset();
  EXPECT_TRUE(schedule.offer(at(2.0, true), Micros{70'001})) << "after reset the next offer goes at once";
}

PeerList members() {
  return PeerList{
      {{1, 100, QStringLiteral("host")}, {2, 100, QStringLiteral("alice")}, {3, 50, QStringLiteral("bob")}}};
}

Presence from(PeerId author, bool dragging = false) {
  Presence p = at(double(author));
  p.author = author;
  p.dragging = dragging;
  return p;
}

TEST(PresenceBoard, KeepsTheLatestOfEachOtherMember) {
  PresenceBoard board;
  board.setPeers(members(), 2);
  EXPECT_TRUE(board.update(from(1), Micros{10}));
  EXPECT_TRUE(board.update(from(3, true), Micros{20}));
  Presence later = from(3);
  later.eye[1] = 7.0;
  EXPECT_TRUE(board.update(later, Micros{30}));
  ASSERT_EQ(board.entries().size(), 2u);
  const RemotePresence* bob = board.find(3);
  ASSERT_NE(bob, nullptr);
  EXPECT_EQ(bob->presence, later);
  EXPECT_EQ(bob->name, QStringLiteral("bob"));
  EXPECT_EQ(bob->receivedAt, Micros{30});
  EXPECT_TRUE(board.dragging().empty());
  board.update(from(1, true), Micros{40});
  EXPECT_EQ(board.dragging(), std::vector<PeerId>{1});
}

TEST(PresenceBoard, IgnoresStrangersAndItself) {
  PresenceBoard board;
  board.setPeers(members(), 2);
  EXPECT_FALSE(board.update(from(2), Micros{1})) << "our own presence is never shown";
  EXPECT_FALSE(board.update(from(9), Micros{1})) << "not a member";
  EXPECT_FALSE(board.update(from(kNoPeer), Micros{1}));
  for (PeerId id = 10; id < 1000; ++id) board.update(from(id), Micros{1});
  EXPECT_TRUE(board.entries().empty()) << "a host cannot make the board grow beyond the PeerList";
}

TEST(PresenceBoard, EntriesLeaveWithTheirPeer) {
  PresenceBoard board;
  board.setPeers(members(), 2);
  board.update(from(1), Micros{1});
  board.update(from(3), Micros{1});
  PeerList without = members();
  without.peers.pop_back();  // bob left
  board.setPeers(without, 2);
  EXPECT_EQ(board.find(3), nullptr);
  EXPECT_NE(board.find(1), nullptr);
  EXPECT_FALSE(board.update(from(3), Micros{2}));
  board.clear();
  EXPECT_TRUE(board.entries().empty());
}

}  // namespace
}  // namespace sc::session
