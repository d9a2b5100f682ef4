// The client's rule for fitting a constraint set under the host's work bound (session/engine/constraint_work.h).

#include "session/engine/constraint_work.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <vector>

namespace sc::session {
namespace {

std::vector<std::uint32_t> iota(std::size_t count, std::uint32_t first) {
  std::vector<std::uint32_t> ids(count);
  std::iota(ids.begin(), ids.end(), first);
  return ids;
}

TEST(ConstraintWork, TheBoundInIdsIsTheWorkOverMSquared) {
  EXPECT_EQ(maxConstraintIds(128), 30000u);
  EXPECT_EQ(maxConstraintIds(100), 49152u);  // ⌊30000 · 128² / 100²⌋
  EXPECT_EQ(maxConstraintIds(10, 1000.0), 10u);
  EXPECT_EQ(maxConstraintIds(10, 999.0), 9u);
}

TEST(ConstraintWork, ASetWithinTheBoundIsKeptAsItIs) {
  std::vector<std::uint32_t> anchors = iota(7, 100);
  EXPECT_EQ(thinAnchors(anchors, 3, 10), 1u);
  EXPECT_EQ(anchors, iota(7, 100));
}

TEST(ConstraintWork, AnchorsAreThinnedEvenlyWithTheSmallestStrideThatFits) {
  // A million-vertex drag: a 5% sphere handle and everything beyond 40% of the diagonal anchored (m = 100).
  const std::size_t handles = 12000, given = 480000, maxIds = maxConstraintIds(100);
  std::vector<std::uint32_t> anchors = iota(given, 1000000 - static_cast<std::uint32_t>(given));
  const std::size_t k = thinAnchors(anchors, handles, maxIds);
  EXPECT_EQ(k, 13u);  // room 37152: ⌈480000 / 37152⌉
  EXPECT_LE(handles + anchors.size(), maxIds);
  EXPECT_GT(handles + (given + k - 2) / (k - 1), maxIds) << "a stride of k − 1 would not fit";
  ASSERT_FALSE(anchors.empty());
  for (std::size_t i = 0; i < anchors.size(); ++i) ASSERT_EQ(anchors[i], 1000000 - given + i * k) << i;
}

TEST(ConstraintWork, HandlesThatFillTheBoundLeaveNoAnchors) {
  std::vector<std::uint32_t> anchors = iota(5, 0);
  EXPECT_EQ(thinAnchors(anchors, 10, 10), 0u);
  EXPECT_TRUE(anchors.empty());
  std::vector<std::uint32_t> none;
  EXPECT_EQ(thinAnchors(none, 4, 10), 1u);
}

}  // namespace
}  // namespace sc::session
