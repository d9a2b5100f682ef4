// Tests src/session/engine/frame_assembler.cpp: latest-wins application, concealment and drop counters.
#include "session/engine/frame_assembler.h"

#include <gtest/gtest.h>

#include <random>

namespace {

using namespace sc::session;

const QByteArray kAssemblerKey = QByteArrayLiteral("assembler-key");
constexpr std::uint16_t kAssemblerPeer = 3;
constexpr int kAssemblerM = 100;

Eigen::MatrixXd frameZ(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd Z(kAssemblerM, 3);
  for (int k = 0; k < kAssemblerM; ++k)
    for (int c = 0; c < 3; ++c) Z(k, c) = uniform(rng) / (1.0 + k);
  return Z;
}

/// Rows part j carries beyond the protected ones (same rule as the wire format).
bool inPart(int k, int j, int parts, int protectedRows) {
  return k >= protectedRows && (k - protectedRows) % parts == j;
}

/// The exact dequantised frame as a lossless receiver sees it.
Eigen::MatrixXd losslessView(const std::vector<QByteArray>& parts) {
  FrameAssembler reference(kAssemblerKey, kAssemblerPeer, kAssemblerM);
  for (const QByteArray& p : parts) EXPECT_EQ(reference.receive(p), DecodeError::None);
  return reference.z();
}

struct LossCase {
  int parts;
  Concealment concealment;
};

class FrameAssemblerLoss : public ::testing::TestWithParam<LossCase> {};

TEST_P(FrameAssemblerLoss, LosingAnyOneDatagramConcealsOnlyItsRows) {
  const auto [parts, concealment] = GetParam();
  CodecOptions options;
  options.partsPerFrame = parts;
  for (int lost = 0; lost < parts; ++lost) {
    CoefficientEncoder encoder(kAssemblerKey, kAssemblerPeer, options);
    FrameAssembler assembler(kAssemblerKey, kAssemblerPeer, kAssemblerM, concealment);
    const auto first = encoder.encodeFrame(1, frameZ(1));
    const auto second = encoder.encodeFrame(2, frameZ(2));
    ASSERT_EQ(static_cast<int>(second.size()), parts);
    for (const QByteArray& p : first) ASSERT_EQ(assembler.receive(p), DecodeError::None);
    for (int j = 0; j < parts; ++j) {
      if (j == lost) continue;
      ASSERT_EQ(assembler.receive(second[static_cast<std::size_t>(j)]), DecodeError::None);
    }

    const Eigen::MatrixXd before = losslessView(first), now = losslessView(second);
    int concealedRows = 0;
    for (int k = 0; k < kAssemblerM; ++k) {
      const bool concealed = inPart(k, lost, parts, options.protectedRows);
      concealedRows += concealed;
      Eigen::RowVector3d expected = now.row(k);
      if (concealed)
        expected = concealment == Concealment::HoldLast ? Eigen::RowVector3d(before.row(k))
                                                        : Eigen::RowVector3d::Zero().eval();
      EXPECT_EQ(assembler.z().row(k), expected) << "row " << k << " lost part " << lost;
    }
    EXPECT_EQ(assembler.counts().frame, 2u);
    EXPECT_EQ(assembler.counts().rowsConcealed, concealedRows);
    EXPECT_EQ(assembler.counts().rowsReceived, kAssemblerM - concealedRows);
  }
}

INSTANTIATE_TEST_SUITE_P(PartsAndConcealment, FrameAssemblerLoss,
                         ::testing::Values(LossCase{2, Concealment::HoldLast}, LossCase{3, Concealment::HoldLast},
                                           LossCase{2, Concealment::ZeroFill}, LossCase{4, Concealment::ZeroFill}));

TEST(FrameAssembler, StartsAtRestAndAppliesWholeFrames) {
  CoefficientEncoder encoder(kAssemblerKey, kAssemblerPeer);
  FrameAssembler assembler(kAssemblerKey, kAssemblerPeer, kAssemblerM);
  EXPECT_FALSE(assembler.hasFrame());
  EXPECT_TRUE(assembler.z().isZero());
  EXPECT_EQ(assembler.counts().rowsConcealed, kAssemblerM);
  const Eigen::MatrixXd Z = frameZ(9);
  for (const QByteArray& p : encoder.encodeFrame(5, Z)) EXPECT_EQ(assembler.receive(p), DecodeError::None);
  EXPECT_LE((assembler.z() - Z).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_EQ(assembler.counts().rowsReceived, kAssemblerM);
  EXPECT_EQ(assembler.accepted(), 2u);
}

TEST(FrameAssembler, LateFrameIsDroppedNotMixedIn) {
  CoefficientEncoder encoder(kAssemblerKey, kAssemblerPeer);
  FrameAssembler assembler(kAssemblerKey, kAssemblerPeer, kAssemblerM);
  const auto old = encoder.encodeFrame(1, frameZ(1));
  const auto current = encoder.encodeFrame(2, frameZ(2));
  for (const QByteArray& p : current) EXPECT_EQ(assembler.receive(p), DecodeError::None);
  const Eigen::MatrixXd shown = assembler.z();
  EXPECT_EQ(assembler.receive(old[0]), DecodeError::Stale);
  EXPECT_EQ(assembler.assemblyDrops(AssemblyDrop::Late), 1u);
  EXPECT_EQ(assembler.z(), shown);
}

TEST(FrameAssembler, FrameNumberWrapsAt32Bits) {
  CoefficientEncoder encoder(kAssemblerKey, kAssemblerPeer);
  FrameAssembler assembler(kAssemblerKey, kAssemblerPeer, kAssemblerM);
  for (const QByteArray& p : encoder.encodeFrame(0xffffffffu, frameZ(1)))
    EXPECT_EQ(assembler.receive(p), DecodeError::None);
  for (const QByteArray& p : encoder.encodeFrame(0u, frameZ(2))) EXPECT_EQ(assembler.receive(p), DecodeError::None);
  EXPECT_EQ(assembler.counts().frame, 0u);
  EXPECT_EQ(assembler.counts().rowsReceived, kAssemblerM);
}

TEST(FrameAssembler, CountsDropsByReason) {
  CoefficientEncoder encoder(kAssemblerKey, kAssemblerPeer);
  CoefficientEncoder stranger(QByteArrayLiteral("someone-else"), kAssemblerPeer);
  CoefficientEncoder wrongM(kAssemblerKey, kAssemblerPeer);
  FrameAssembler assembler(kAssemblerKey, kAssemblerPeer, kAssemblerM);
  const auto parts = encoder.encodeFrame(1, frameZ(1));
  EXPECT_EQ(assembler.receive(parts[0]), DecodeError::None);
  EXPECT_EQ(assembler.receive(parts[0]), DecodeError::Replayed);
  EXPECT_EQ(assembler.receive(parts[1].left(10)), DecodeError::Truncated);
  EXPECT_EQ(assembler.receive(stranger.encodeFrame(1, frameZ(1))[0]), DecodeError::BadTag);
  wrongM.setNextSequence(500);
  EXPECT_EQ(assembler.receive(wrongM.encodeFrame(2, Eigen::MatrixXd::Ones(50, 3))[0]), DecodeError::Malformed);
  EXPECT_EQ(assembler.decodeDrops(DecodeError::Replayed), 1u);
  EXPECT_EQ(assembler.decodeDrops(DecodeError::Truncated), 1u);
  EXPECT_EQ(assembler.decodeDrops(DecodeError::BadTag), 1u);
  EXPECT_EQ(assembler.assemblyDrops(AssemblyDrop::WrongLength), 1u);
  EXPECT_EQ(assembler.totalDrops(), 4u);
  EXPECT_EQ(assembler.accepted(), 1u);
}

TEST(FrameAssembler, SeedIsExactAndMakesOlderFramesLate) {
  CoefficientEncoder encoder(kAssemblerKey, kAssemblerPeer);
  FrameAssembler assembler(kAssemblerKey, kAssemblerPeer, kAssemblerM);
  EXPECT_FALSE(assembler.seed(5, Eigen::MatrixXd::Ones(kAssemblerM - 1, 3)));  // wrong shape
  ASSERT_TRUE(assembler.seed(5, frameZ(5)));
  EXPECT_TRUE(assembler.hasFrame());
  EXPECT_EQ(assembler.frame(), 5u);
  EXPECT_EQ(assembler.z(), frameZ(5));
  EXPECT_EQ(assembler.counts().rowsReceived, kAssemblerM);
  EXPECT_FALSE(assembler.seed(4, frameZ(4)));  // older than the seed
  for (const QByteArray& p : encoder.encodeFrame(5, frameZ(6))) EXPECT_EQ(assembler.receive(p), DecodeError::Stale);
  EXPECT_EQ(assembler.assemblyDrops(AssemblyDrop::Late), 2u);
  EXPECT_EQ(assembler.authenticated(), 2u);
  EXPECT_EQ(assembler.lastHeader().frame, 5u);
  EXPECT_EQ(assembler.lastHeader().sequence, 1u);
  const auto parts = encoder.encodeFrame(6, frameZ(6), 1234u);
  EXPECT_EQ(assembler.receive(parts[0]), DecodeError::None);
  EXPECT_EQ(assembler.frame(), 6u);
  EXPECT_EQ(assembler.lastHeader().timestamp, 1234u);
  EXPECT_FALSE(assembler.seed(7, frameZ(7)));  // ignored once a datagram was applied
  EXPECT_EQ(assembler.frame(), 6u);
}

}  // namespace
