// Tests src/session/engine/still_frame_schedule.cpp: when the host's still frame is due after a moving frame (measured
// interval, clamped), with injected time.
#include "session/engine/still_frame_schedule.h"

#include <gtest/gtest.h>

namespace {

using namespace sc::session;
using namespace std::chrono_literals;

TEST(StillFrameSchedule, BeforeAnIntervalTheStillFrameComesAfterTheLongestDelay) {
  StillFrameSchedule s;
  const std::optional<Micros> due = s.onFrame(1'000'000us, true);
  ASSERT_TRUE(due.has_value());
  EXPECT_EQ(*due, 1'000'000us + StillFrameSchedule::kMaxDelay);
  EXPECT_EQ(s.interval(), Micros{0});
}

TEST(StillFrameSchedule, DelayFollowsTheMeasuredInterval) {
  StillFrameSchedule s;
  Micros at{0};
  std::optional<Micros> due;
  for (int i = 0; i < 10; ++i, at += 33'000us) due = s.onFrame(at, true);
  EXPECT_EQ(s.interval(), 33'000us);
  ASSERT_TRUE(due.has_value());
  EXPECT_EQ(*due - (at - 33'000us), Micros{41'250});  // 1.25 × 33 ms after the last moving frame
}

TEST(StillFrameSchedule, DelayIsClamped) {
  StillFrameSchedule fast;
  for (Micros at{0}; at < 100'000us; at += 5'000us) (void)fast.onFrame(at, true);
  EXPECT_EQ(fast.interval(), 5'000us);
  EXPECT_EQ(fast.delay(), StillFrameSchedule::kMinDelay);
  StillFrameSchedule slow;
  for (Micros at{0}; at < 2'000'000us; at += 200'000us) (void)slow.onFrame(at, true);
  EXPECT_EQ(slow.interval(), 200'000us);
  EXPECT_EQ(slow.delay(), StillFrameSchedule::kMaxDelay);
}

TEST(StillFrameSchedule, AFrameThatDidNotMoveSchedulesNothing) {
  StillFrameSchedule s;
  (void)s.onFrame(0us, true);
  (void)s.onFrame(30'000us, true);
  EXPECT_FALSE(s.onFrame(70'000us, false).has_value());     // the still frame itself
  EXPECT_FALSE(s.onFrame(1'070'000us, false).has_value());  // an idle refresh
  // A pause is no interval sample: the next drag's first spacing starts after a moving frame only.
  (void)s.onFrame(2'000'000us, true);
  EXPECT_EQ(s.interval(), 30'000us);
  (void)s.onFrame(2'040'000us, true);
  EXPECT_EQ(s.interval(), 30'000us + (40'000us - 30'000us) / 8);
}

}  // namespace
