// Tests src/app/gui/event_loop_stalls.cpp: a GUI thread that blocks is reported as a stall of at least the time it
// blocked; a turning loop's gaps are counted in the longest gap.

#include "app/gui/event_loop_stalls.h"

#include <gtest/gtest.h>

#include <QTest>

#include <chrono>
#include <thread>
#include <vector>

namespace sc::app {
namespace {

TEST(EventLoopStalls, ABlockedThreadIsReportedAsAStallOfAtLeastTheBlockedTime) {
  EventLoopStalls stalls(std::chrono::milliseconds(200));
  std::vector<double> reported;
  QObject::connect(&stalls, &EventLoopStalls::stalled, [&reported](double ms) { reported.push_back(ms); });
  QTest::qWait(50);                                             // the timer turns
  std::this_thread::sleep_for(std::chrono::milliseconds(400));  // the work a step would do on the GUI thread
  ASSERT_TRUE(QTest::qWaitFor([&reported] { return !reported.empty(); }, 5000));
  EXPECT_GE(reported.back(), 400.0);
  EXPECT_GE(stalls.stalls(), 1);
  EXPECT_GE(stalls.longestMs(), 400.0);
}

}  // namespace
}  // namespace sc::app
