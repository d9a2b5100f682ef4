// Tests for src/app/gui/viewport/frame_policy.cpp: when MeshViewport lightens a frame (interactive, reduced scale,
// interactive proxy) and when it must repaint itself once idle. Pure rules: no GL, no widget.

#include "app/gui/viewport/frame_policy.h"

#include <gtest/gtest.h>

#include <QThread>

namespace {

using sc::app::FramePolicy;

FramePolicy::ProxyConditions allMet() {
  return {.singleSampled = true, .hasProxy = true, .wireframe = false, .painting = false, .showsSelection = true};
}

TEST(FramePolicy, TheFirstPaintIsFullAndNeedsNoRestore) {
  FramePolicy policy(true);
  policy.markMoved();
  const FramePolicy::Frame frame = policy.begin(true, true);
  EXPECT_FALSE(frame.interactive);
  EXPECT_FALSE(frame.proxy);
  EXPECT_EQ(frame.scale, 1.0);
  EXPECT_FALSE(policy.end(frame, 1.0));
}

TEST(FramePolicy, AMovingPaintRightAfterTheLastDrawsTheProxyAndAsksForTheIdleRestore) {
  FramePolicy policy(true);
  policy.painted();
  policy.markMoved();
  const FramePolicy::Frame moving = policy.begin(true, true);
  EXPECT_TRUE(moving.interactive);
  EXPECT_TRUE(moving.proxy);
  EXPECT_TRUE(policy.end(moving, 1.0)) << "a proxy frame is followed by a full one once idle";
  policy.painted();
  const FramePolicy::Frame still = policy.begin(true, true);
  EXPECT_TRUE(still.interactive);
  EXPECT_FALSE(still.proxy) << "nothing moved since the last paint";
  EXPECT_FALSE(policy.begin(false, true).proxy) << "not scalable: never the proxy";
}

TEST(FramePolicy, APaintAfterTheIdleDelayIsFull) {
  FramePolicy policy(true);
  policy.painted();
  QThread::msleep(FramePolicy::kIdleRestoreMs + 20);
  policy.markMoved();
  const FramePolicy::Frame frame = policy.begin(true, true);
  EXPECT_FALSE(frame.interactive);
  EXPECT_FALSE(frame.proxy);
  EXPECT_GE(policy.msSincePaint(), FramePolicy::kIdleRestoreMs);
}

TEST(FramePolicy, TheProxyNeedsAdaptiveResolutionAndEveryCondition) {
  FramePolicy policy(true);
  EXPECT_TRUE(policy.proxyMayDraw(allMet()));
  for (int broken = 0; broken < 5; ++broken) {
    FramePolicy::ProxyConditions c = allMet();
    c.singleSampled = broken != 0;
    c.hasProxy = broken != 1;
    c.wireframe = broken == 2;
    c.painting = broken == 3;
    c.showsSelection = broken != 4;
    EXPECT_FALSE(policy.proxyMayDraw(c)) << "condition " << broken;
  }
  policy.setAdaptive(false);
  EXPECT_FALSE(policy.proxyMayDraw(allMet()));
}

TEST(FramePolicy, SlowProxyFramesLowerTheProxyScaleOnly) {
  FramePolicy policy(true);
  policy.setPaintBudget(10.0);
  policy.painted();
  policy.markMoved();
  const FramePolicy::Frame proxy = policy.begin(true, true);
  ASSERT_TRUE(proxy.proxy);
  EXPECT_EQ(proxy.scale, 1.0);
  policy.end(proxy, 100.0);  // ten times the budget
  policy.painted();
  policy.markMoved();
  EXPECT_LT(policy.begin(true, true).scale, 1.0) << "the next proxy frame is reduced";
  policy.painted();
  policy.markMoved();
  EXPECT_EQ(policy.begin(true, false).scale, 1.0) << "frames of the mesh keep their own scale";
}

TEST(FramePolicy, AFrameSaysWhetherItMovedAndTheStandInIsAProxyFrameAtTheProxysScale) {
  FramePolicy policy(true);
  policy.setPaintBudget(10.0);
  policy.painted();
  policy.markMoved();
  const FramePolicy::Frame moving = policy.begin(true, true);
  EXPECT_TRUE(moving.moved);
  policy.end(moving, 100.0);  // the proxy's scale drops
  policy.painted();
  EXPECT_FALSE(policy.begin(true, true).moved) << "nothing moved since";
  const FramePolicy::Frame standIn = policy.standIn(true);
  EXPECT_TRUE(standIn.proxy);
  EXPECT_TRUE(standIn.interactive);
  EXPECT_LT(standIn.scale, 1.0) << "the proxy's own scale";
  EXPECT_EQ(policy.standIn(false).scale, 1.0) << "not scalable: full resolution";
}

}  // namespace
