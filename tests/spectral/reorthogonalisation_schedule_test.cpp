// When block Lanczos re-orthogonalises against its whole basis: full passes in pairs, the interval between pairs
// grown by one after a small drift, shrunk after a large one, reset after a very large one, and capped.

#include "spectral/reorthogonalisation_schedule.h"

#include <gtest/gtest.h>

namespace sc::spectral {
namespace {

/// Runs one pair of full passes reporting `drift` for the first, then the skipped blocks until the next is due;
/// returns how many were skipped (at most 100).
int pairThenSkipped(detail::ReorthogonalisationSchedule& schedule, double drift) {
  EXPECT_TRUE(schedule.due());
  schedule.record(drift);
  EXPECT_TRUE(schedule.due()) << "the second block of a pair is re-orthogonalised too";
  schedule.record(1e-16);
  int skipped = 0;
  while (!schedule.due() && skipped < 100) {
    schedule.record(-1.0);
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
  for (int i = 0; i < 3; ++i) pairThenSkipped(schedule, 1e-15);  // interval 3
  EXPECT_EQ(pairThenSkipped(schedule, 1e-10), 3) << "between target/50 and the target: unchanged";
  EXPECT_EQ(pairThenSkipped(schedule, 2e-9), 2) << "above the target: one block fewer";
  EXPECT_EQ(pairThenSkipped(schedule, 2e-8), 0) << "above ten times the target: every block again";
}

TEST(ReorthogonalisationSchedule, NeverSkipsMoreThanEightBlocks) {
  detail::ReorthogonalisationSchedule schedule;
  int skipped = 0;
  for (int i = 0; i < 20; ++i) skipped = pairThenSkipped(schedule, 0.0);
  EXPECT_EQ(skipped, 8);
}

}  // namespace
}  // namespace sc::spectral
