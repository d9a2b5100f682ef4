// When block Lanczos re-orthogonalises against its whole basis: full passes in pairs, the interval between pairs
// grown by one after a small drift, shrunk after a large one, reset after a very large one, and capped; the first
// pass of a pair covers every column, the second the head its first found drifting.

#include "spectral/reorthogonalisation_schedule.h"

#include <gtest/gtest.h>

namespace sc::spectral {
namespace {

/// Runs one pair of full passes reporting `drift` for the first, then the skipped blocks until the next is due;
/// returns how many were skipped (at most 100).
int pairThenSkipped(detail::ReorthogonalisationSchedule& schedule, double drift) {
  EXPECT_TRUE(schedule.due());
  schedule.record({drift, 0});
  EXPECT_TRUE(schedule.due()) << "the second block of a pair is re-orthogonalised too";
  schedule.record({1e-16, 0});
  int skipped = 0;
  while (!schedule.due() && skipped < 100) {
    schedule.recordSkipped();
    ++skipped;
  }
  return skipped;
}

TEST(ReorthogonalisationSchedule, StartsWithEveryBlockAndGrowsByOneAfterSmallDrifts) {
  detail::ReorthogonalisationSchedule schedule;
  EXPECT_TRUE(schedule.due());
  EXPECT_EQ(pairThenSkipped(schedule, 1e-15), 1);
  EXPECT_EQ(pairThenSkipped(schedule, 1e-15), 2);
  EXPECT_EQ(pairThenSkipped(schedule, 1e-15), 3);
}

TEST(ReorthogonalisationSchedule, KeepsItsIntervalBetweenTheBoundsAndShrinksAboveTheTarget) {
  detail::ReorthogonalisationSchedule schedule;
  constexpr double target = detail::ReorthogonalisationSchedule::kDriftTarget;
  for (int i = 0; i < 3; ++i) pairThenSkipped(schedule, 1e-15);  // interval 3
  EXPECT_EQ(pairThenSkipped(schedule, target / 10), 3) << "between target/50 and the target: unchanged";
  EXPECT_EQ(pairThenSkipped(schedule, 2 * target), 2) << "above the target: one block fewer";
  EXPECT_EQ(pairThenSkipped(schedule, 20 * target), 0) << "above ten times the target: every block again";
}

TEST(ReorthogonalisationSchedule, NeverSkipsMoreThanEightBlocks) {
  detail::ReorthogonalisationSchedule schedule;
  int skipped = 0;
  for (int i = 0; i < 20; ++i) skipped = pairThenSkipped(schedule, 0.0);
  EXPECT_EQ(skipped, 8);
}

TEST(ReorthogonalisationSchedule, TheSecondPassOfAPairCoversTwiceTheDriftingHeadPlusAMargin) {
  detail::ReorthogonalisationSchedule schedule;
  ASSERT_TRUE(schedule.due());
  EXPECT_EQ(schedule.reach(284), 284) << "the first pass of a pair covers every column";
  schedule.record({6e-9, 30});
  ASSERT_TRUE(schedule.due());
  EXPECT_EQ(schedule.reach(288), 76) << "twice the 30 drifting columns plus 16";
  schedule.record({5e-12, 3});
  while (!schedule.due()) schedule.recordSkipped();
  EXPECT_EQ(schedule.reach(300), 300) << "the next pair starts over every column, whatever the second pass found";
  schedule.record({1e-9, 150});
  EXPECT_EQ(schedule.reach(304), 304) << "a head past half the basis: every column";
  schedule.record({1e-12, 0});
  while (!schedule.due()) schedule.recordSkipped();
  schedule.record({1e-15, 0});
  EXPECT_EQ(schedule.reach(320), 16) << "nothing drifting: the margin";
}

TEST(ReorthogonalisationSchedule, APassIsCutShortWhenItsLastBlockDrifts) {
  using Schedule = detail::ReorthogonalisationSchedule;
  EXPECT_FALSE(Schedule::cutShort({1e-11, 72}, 76, 288, 4)) << "the drift ends before the last block";
  EXPECT_TRUE(Schedule::cutShort({1e-11, 73}, 76, 288, 4)) << "drift in columns 72–75";
  EXPECT_FALSE(Schedule::cutShort({1e-11, 288}, 288, 288, 4)) << "a pass over every column is never short";
}

TEST(ReorthogonalisationSchedule, AColumnDriftsAboveTheFloorAndAThousandthOfTheLargestDrift) {
  using Schedule = detail::ReorthogonalisationSchedule;
  Eigen::VectorXd drift(8);
  drift << 6e-9, 3e-10, 7e-12, 5e-12, 1e-13, 4e-12, 1e-15, 0.0;
  detail::DriftProfile profile = Schedule::profile(drift);
  EXPECT_EQ(profile.drift, 6e-9);
  EXPECT_EQ(profile.drifting, 3) << "the last column above 6e-12 is the third";
  drift << 3e-12, 1e-15, 2e-13, 1e-15, 5e-14, 0.0, 0.0, 0.0;
  EXPECT_EQ(Schedule::profile(drift).drifting, 3) << "below a small head the floor 1e-13 decides";
  drift.setConstant(1e-16);
  EXPECT_EQ(Schedule::profile(drift).drifting, 0);
  EXPECT_EQ(Schedule::profile(Eigen::VectorXd()).drifting, 0);
}

}  // namespace
}  // namespace sc::spectral
