// Loopback tests of the still frame after a drag stops (src/session/engine/still_frame_schedule.h, session_host.cpp)
// and of what an extrapolating client (frame_predictor.h) shows around it: one still frame after the last drag and then
// only the idle refresh; the last real frame shown after the drag stops; without the still frame the prediction is
// withdrawn in time. Real sockets on 127.0.0.1. Fixture: session_loopback_fixture.h.
#include "session_loopback_fixture.h"

#include "session/engine/session_clock.h"
#include "session/net/client_datagram_channel.h"
#include "session/net/host_datagram_channel.h"

#include <QtTest/QTest>

#include <span>

namespace sc::session {
namespace {

class StillFrameLoopback : public SessionLoopback {
 protected:
  static constexpr int kDragSpacingMs = 50;  ///< drag poses this far apart: one frame each (above `coalesce`)
  static constexpr int kDragSteps = 12;

  /// The host's own user takes the lock, sets the cap constraints and drags the cap up in kDragSteps poses
  /// kDragSpacingMs apart, then stops. Returns the frame number of the last drag's frame (0 on failure).
  static std::uint32_t dragThenStop(SessionHost& host) {
    if (!host.requestLock() || host.lockHolder() != kHostPeer) return 0;
    const auto [handle, anchors] = capConstraints();
    spectral::ConstraintSet set;
    set.handles.push_back({std::vector<int>(handle.begin(), handle.end())});
    set.anchors.assign(anchors.begin(), anchors.end());
    if (!host.setConstraints(set)) return 0;
    QTest::qWait(kDragSpacingMs);
    for (int step = 1; step <= kDragSteps; ++step) {
      spectral::HandleTransform pose;
      pose.translation = Eigen::Vector3d(0.0, 0.0, 0.03 * step);
      if (!host.drag(std::span(&pose, 1))) return 0;
      if (step < kDragSteps) QTest::qWait(kDragSpacingMs);
    }
    return host.currentFrame();
  }

  /// What an extrapolating client displayed, one entry per frameUpdated.
  struct Shown {
    std::uint32_t frame = 0;     ///< currentFrame(): a predicted frame number included
    std::uint32_t received = 0;  ///< receivedFrame()
    Micros at{0};
    Eigen::MatrixXd Z;
  };
  /// Records every frameUpdated of `client`'s channel from now on.
  static std::shared_ptr<std::vector<Shown>> record(SessionClient& client) {
    auto shown = std::make_shared<std::vector<Shown>>();
    ClientDatagramChannel* channel = &client.channel();
    QObject::connect(channel, &ClientDatagramChannel::frameUpdated, channel, [shown, channel](std::uint32_t frame) {
      shown->push_back({frame, channel->receivedFrame(), sessionNow(), channel->coefficients()});
    });
    return shown;
  }
  /// Index of the entry showing the complete received frame `frame` (its last datagram, before anything else was
  /// shown: a predicted frame or the next one); -1 when none.
  static int lastOf(const std::vector<Shown>& shown, std::uint32_t frame) {
    int found = -1;
    for (int i = 0; i < static_cast<int>(shown.size()); ++i) {
      const Shown& entry = shown[static_cast<std::size_t>(i)];
      const bool real = entry.frame == frame && entry.received == frame;
      if (real) found = i;
      if (!real && found >= 0) break;
    }
    return found;
  }
  /// Arrival of frame `frame`'s first datagram (when FramePredictor's overdue schedule starts); 0 when none.
  static Micros arrivalOf(const std::vector<Shown>& shown, std::uint32_t frame) {
    for (const Shown& entry : shown) {
      if (entry.received == frame) return entry.at;
    }
    return Micros{0};
  }
};

TEST_F(StillFrameLoopback, OneStillFrameFollowsTheLastDragThenOnlyTheIdleRefresh) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(400);
  auto host = startHost(options);
  std::vector<std::pair<std::uint32_t, Micros>> sent;
  QObject::connect(host.get(), &SessionHost::frameSent, host.get(),
                   [&sent](std::uint32_t frame) { sent.emplace_back(frame, sessionNow()); });
  const std::uint32_t last = dragThenStop(*host);
  ASSERT_GT(last, 0u);
  const Eigen::MatrixXd dragged = host->coefficients();
  const Micros lastAt = sent.back().second;
  ASSERT_EQ(sent.back().first, last);
  EXPECT_EQ(host->counters().stillFramesSent, 0u);
  // Past the still frame and one idle refresh, short of a second refresh.
  QTest::qWait(options.idleRefresh.count() + 250);

  ASSERT_GE(sent.size(), 2u + kDragSteps);
  std::vector<std::pair<std::uint32_t, Micros>> after;
  for (const auto& entry : sent) {
    if (entry.second > lastAt) after.push_back(entry);
  }
  // Exactly one still frame, the next frame number, within about two drag intervals (1.25 × the measured one).
  EXPECT_EQ(host->counters().stillFramesSent, 1u);
  ASSERT_GE(after.size(), 2u);
  EXPECT_EQ(after[0].first, last + 1);
  const Micros stillGap = after[0].second - lastAt;
  EXPECT_GE(stillGap, StillFrameSchedule::kMinDelay - Micros{1000});
  EXPECT_LE(stillGap, Micros{2 * kDragSpacingMs * 1000});
  EXPECT_EQ(host->coefficients(), dragged);  // the same Z under the new number
  // Then only the idle refresh: a second frame no sooner than idleRefresh after the still frame (the housekeeping
  // tick checks every 100 ms), and nothing else.
  EXPECT_EQ(after.size(), 2u);
  EXPECT_EQ(after[1].first, last + 2);
  const Micros refreshGap = after[1].second - after[0].second;
  EXPECT_GE(refreshGap, std::chrono::duration_cast<Micros>(options.idleRefresh) - Micros{1000});
  EXPECT_LE(refreshGap, std::chrono::duration_cast<Micros>(options.idleRefresh) + Micros{150'000});
}

TEST_F(StillFrameLoopback, ExtrapolatingClientShowsTheLastRealFrameAfterTheDragStops) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(60000);  // only the drag's frames and the still frame
  auto host = startHost(options);
  auto viewer = join(*host, QStringLiteral("viewer"));
  ASSERT_NE(viewer->channel().predictor(), nullptr) << "Extrapolate is the default";
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->channel().pathOpen(viewer->peerId()); }, kWaitMs));
  const std::shared_ptr<std::vector<Shown>> shown = record(*viewer);
  const std::uint32_t last = dragThenStop(*host);
  ASSERT_GT(last, 0u);
  QTest::qWait(250);  // the still frame, and the ~200 ms a withdrawn prediction would have taken

  const int real = lastOf(*shown, last);
  ASSERT_GE(real, 0);
  const Eigen::MatrixXd lastReal = (*shown)[static_cast<std::size_t>(real)].Z;
  EXPECT_LT((lastReal - host->coefficients()).cwiseAbs().maxCoeff(), 1e-3 * host->coefficients().cwiseAbs().maxCoeff());
  // After the last real frame: only the still frame, showing exactly its Z; no predicted frame, no withdrawal.
  ASSERT_GT(shown->size(), static_cast<std::size_t>(real) + 1);
  for (std::size_t i = static_cast<std::size_t>(real) + 1; i < shown->size(); ++i) {
    EXPECT_EQ((*shown)[i].frame, last + 1) << i;
    EXPECT_EQ((*shown)[i].received, last + 1) << i;
    EXPECT_EQ((*shown)[i].Z, lastReal) << i;
  }
  EXPECT_EQ(viewer->channel().currentFrame(), last + 1);
  EXPECT_EQ(viewer->channel().coefficients(), lastReal);
  EXPECT_EQ(viewer->channel().predictor()->withdrawals(), 0u);
  EXPECT_FALSE(viewer->channel().predictor()->nextDue().has_value());
}

TEST_F(StillFrameLoopback, WithoutTheStillFrameThePredictionIsWithdrawnInTime) {
  SessionHostOptions options = hostOptions();
  options.idleRefresh = std::chrono::milliseconds(60000);
  options.stillFrame = false;  // as if the still frame were lost on the way
  auto host = startHost(options);
  auto viewer = join(*host, QStringLiteral("viewer"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return host->channel().pathOpen(viewer->peerId()); }, kWaitMs));
  const std::shared_ptr<std::vector<Shown>> shown = record(*viewer);
  std::optional<Micros> withdrawnAt;
  QObject::connect(&viewer->channel(), &ClientDatagramChannel::predictionWithdrawn, viewer.get(),
                   [&withdrawnAt](std::uint32_t) { withdrawnAt = sessionNow(); });
  const std::uint32_t last = dragThenStop(*host);
  ASSERT_GT(last, 0u);
  ASSERT_TRUE(QTest::qWaitFor([&] { return withdrawnAt.has_value(); }, 2000));
  QTest::qWait(50);

  const int real = lastOf(*shown, last);
  ASSERT_GE(real, 0);
  const Shown& lastReal = (*shown)[static_cast<std::size_t>(real)];
  // Predicted frames last+1..last+4 were shown (the overshoot the still frame avoids), then frame `last` again,
  // (overdueFactor + maxFrames) = 5.5 intervals after it arrived (the documented bound), a timer's slack allowed.
  const Micros interval = viewer->channel().predictor()->interval();
  ASSERT_GT(interval.count(), 0);
  EXPECT_EQ(shown->back().frame, last);
  EXPECT_EQ(shown->back().Z, lastReal.Z);
  EXPECT_EQ(viewer->channel().coefficients(), lastReal.Z);
  EXPECT_GE(viewer->channel().predictor()->framesPredicted(), 4u);
  const Micros withdrawal = *withdrawnAt - arrivalOf(*shown, last);
  const PredictorSettings settings;
  const auto bound = Micros{
      static_cast<Micros::rep>((settings.overdueFactor + settings.maxFrames) * static_cast<double>(interval.count()))};
  EXPECT_GE(withdrawal, bound - Micros{2000});
  EXPECT_LE(withdrawal, bound + Micros{30'000});
}

}  // namespace
}  // namespace sc::session
