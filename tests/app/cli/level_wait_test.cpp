// Tests levelWaitTimeout() (src/app/cli/session_setup.h): how long join and drive wait for a level grows with the
// session's size n·m above the 100k dragon at m = 100, so that a million-vertex full level is not cut off by a
// deadline set for smaller meshes.

#include "app/cli/session_setup.h"

#include <gtest/gtest.h>

#include <chrono>

namespace sc::app {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

TEST(LevelWaitTimeout, TheFloorHoldsUpToTheHundredThousandVertexDragon) {
  EXPECT_EQ(levelWaitTimeout(7529, 100, seconds(120)), seconds(120));
  EXPECT_EQ(levelWaitTimeout(100000, 100, seconds(120)), seconds(120));
  EXPECT_EQ(levelWaitTimeout(200000, 50, seconds(120)), seconds(120));
}

TEST(LevelWaitTimeout, GrowsWithVerticesTimesRows) {
  EXPECT_EQ(levelWaitTimeout(999922, 100, seconds(120)), milliseconds(1199907));  // ⌈120 s · 9.99922⌉
  EXPECT_EQ(levelWaitTimeout(1000000, 200, seconds(120)), seconds(2400));
  EXPECT_EQ(levelWaitTimeout(1000000, 100, seconds(3600)), seconds(36000)) << "a rated join's floor scales too";
}

}  // namespace
}  // namespace sc::app
