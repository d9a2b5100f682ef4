// A hostile member's Constraints (docs/security.md, "Hostile member"): a burst of the largest valid Constraints
// (every vertex of a 10,242-vertex model at m = 100) costs the host's event-loop thread less than a frame interval
// of CPU time in all (so no stall of its loop can be longer), because each accepted set (about 10–15 ms of work) is
// factored on a worker thread. CPU time, not wall gaps: the shared test machine's scheduling noise alone makes
// 15 ms gaps. Real TLS over loopback sockets, host and test in one thread. Fixture: security_fixture.h.
#include "address_sanitizer.h"
#include "security_fixture.h"

#include "raw_control_peer.h"

#include <QtTest/QTest>

#include <ctime>
#include <numeric>

namespace sc::session {
namespace {

class HostileConstraints : public Security {
 protected:
  static void SetUpTestSuite() {
    Security::SetUpTestSuite();
    s_large = testing::harmonicHostModel(sc::testing::icosphere(5), 100);
  }
  static void TearDownTestSuite() {
    s_large.reset();
    Security::TearDownTestSuite();
  }
  static inline std::shared_ptr<const HostModel> s_large;
};

/// CPU time of the calling thread (the one that runs the host's event loop), in milliseconds.
double threadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) / 1e6;
}

/// CPU time this thread spends while the event loop runs for `ms`.
double cpuMsOverEventLoop(int ms) {
  const double before = threadCpuMs();
  QTest::qWait(ms);
  return threadCpuMs() - before;
}

TEST_F(HostileConstraints, ABurstOfTheLargestConstraintsDoesNotStallTheHost) {
  SessionHostOptions options = hostOptions(std::nullopt);
  auto host = testing::startHost(s_large, options);
  testing::RawControlPeer member(host->tcpPort());
  const std::optional<Welcome> welcome = member.join(QStringLiteral("solver"));
  ASSERT_TRUE(welcome);
  const LockEpoch epoch = member.acquireLock(welcome->peerId);
  ASSERT_NE(epoch, kNoEpoch);
  const auto n = static_cast<std::uint32_t>(s_large->vertexCount());
  std::vector<std::uint32_t> all(n);
  std::iota(all.begin(), all.end(), 0u);
  const double idleMs = cpuMsOverEventLoop(1000);  // the host's own cadences (frames, heartbeats)
  const double before = threadCpuMs();
  for (std::uint32_t i = 0; i < 8; ++i) {  // each a different handle: nothing to deduplicate
    std::vector<std::uint32_t> handle(all.begin() + i * 10, all.begin() + i * 10 + 10);
    std::vector<std::uint32_t> anchors(all.begin(), all.begin() + i * 10);
    anchors.insert(anchors.end(), all.begin() + i * 10 + 10, all.end());
    member.send(Constraints{epoch, {handle}, anchors});
  }
  QTest::qWait(1000);
  const double burstMs = threadCpuMs() - before;
  const std::uint64_t accepted = host->counters().constraintsAccepted;
  RecordProperty("extraCpuMs", std::to_string(burstMs - idleMs));
  EXPECT_GE(accepted, 5u) << "the burst and at least one deferred set were factored";
  EXPECT_GT(host->counters().requestsThrottled, 0u);
  // Every stall of the host's loop is at most the extra CPU time its thread spent: under one frame interval (16 ms;
  // 5-8 ms measured, 29-31 ms with the factorisation on this thread). Not under the sanitisers: ASan's allocator
  // (quarantine, fresh mappings for each 41 KB message) makes it a measure of page faults, 2,650 of them and 37-42 ms
  // of system time of the 50-80 ms measured on this VM, on the same commit that measured 22 ms two days before.
  if (!sc::testing::kAddressSanitizer) {
    EXPECT_LT(burstMs - idleMs, 16.0) << "the host's thread spent " << burstMs - idleMs << " ms more than idle on "
                                      << accepted << " sets (idle " << idleMs << " ms)";
  }
  EXPECT_EQ(host->lockHolder(), welcome->peerId);
}

}  // namespace
}  // namespace sc::session
