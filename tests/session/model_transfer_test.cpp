#include "session/wire/model_transfer.h"

#include <gtest/gtest.h>

namespace sc::session {
namespace {

QByteArray payload(int size) {
  QByteArray bytes(size, '\0');
  for (int i = 0; i < size; ++i) bytes[i] = static_cast<char>((i * 131) ^ (i >> 8));
  return bytes;
}

TEST(ModelTransfer, ChunksReassembleBitExactly) {
  const QByteArray bytes = payload(100000);
  ModelSender sender(3, TransferKind::Level, 500, bytes, 4096);
  EXPECT_EQ(sender.begin().totalSize, 100000u);
  EXPECT_EQ(sender.begin().sha256, sha256(bytes));
  ModelReceiver receiver;
  receiver.begin(sender.begin());
  int chunks = 0;
  ModelReceiver::Status status = ModelReceiver::Status::InProgress;
  while (auto chunk = sender.nextChunk()) {
    ASSERT_EQ(status, ModelReceiver::Status::InProgress);
    // Every chunk survives the wire codec.
    const QByteArray frame = encodeControlMessage(*chunk);
    ASSERT_FALSE(frame.isEmpty());
    status = receiver.add(*chunk);
    ++chunks;
    EXPECT_EQ(receiver.receivedBytes(), sender.sentBytes());
  }
  EXPECT_EQ(chunks, (100000 + 4095) / 4096);
  ASSERT_EQ(status, ModelReceiver::Status::Complete);
  EXPECT_TRUE(sender.finished());
  EXPECT_EQ(receiver.take(), bytes);
  EXPECT_FALSE(receiver.active());
}

TEST(ModelTransfer, CorruptedChunkFailsTheChecksum) {
  ModelSender sender(1, TransferKind::FullModel, 10, payload(10000), 3000);
  ModelReceiver receiver;
  receiver.begin(sender.begin());
  ModelReceiver::Status status = ModelReceiver::Status::InProgress;
  while (auto chunk = sender.nextChunk()) {
    if (chunk->offset == 3000) chunk->bytes[7] = static_cast<char>(chunk->bytes[7] ^ 1);
    status = receiver.add(*chunk);
  }
  EXPECT_EQ(status, ModelReceiver::Status::BadChecksum);
  EXPECT_FALSE(receiver.active());
  EXPECT_TRUE(receiver.take().isEmpty());
}

TEST(ModelTransfer, GapsForeignIdsAndSizeDisagreementsAreRejected) {
  ModelSender sender(5, TransferKind::Level, 10, payload(9000), 3000);
  ModelReceiver receiver;
  const ModelChunk first = *sender.nextChunk();
  EXPECT_EQ(receiver.add(first), ModelReceiver::Status::UnknownTransfer);  // no begin yet
  receiver.begin(sender.begin());
  ModelChunk foreign = first;
  foreign.transferId = 6;
  EXPECT_EQ(receiver.add(foreign), ModelReceiver::Status::UnknownTransfer);
  EXPECT_TRUE(receiver.active());
  const ModelChunk second = *sender.nextChunk();
  EXPECT_EQ(receiver.add(second), ModelReceiver::Status::OutOfOrder);  // gap: offset 3000 before 0
  EXPECT_FALSE(receiver.active());
  receiver.begin(sender.begin());
  ModelChunk lying = first;
  lying.totalSize = 8999;
  EXPECT_EQ(receiver.add(lying), ModelReceiver::Status::OutOfOrder);
}

TEST(ModelTransfer, ANewBeginAbandonsTheUnfinishedTransfer) {
  ModelSender a(1, TransferKind::Level, 10, payload(5000), 1000);
  ModelSender b(2, TransferKind::FullModel, 20, payload(2500), 1000);
  ModelReceiver receiver;
  receiver.begin(a.begin());
  EXPECT_EQ(receiver.add(*a.nextChunk()), ModelReceiver::Status::InProgress);
  receiver.begin(b.begin());
  EXPECT_EQ(receiver.add(*a.nextChunk()), ModelReceiver::Status::UnknownTransfer);
  ModelReceiver::Status status{};
  while (auto chunk = b.nextChunk()) status = receiver.add(*chunk);
  EXPECT_EQ(status, ModelReceiver::Status::Complete);
  EXPECT_EQ(receiver.take(), payload(2500));
}

TEST(ModelTransfer, PrecomputedDigestAnnouncesTheSameBegin) {
  const QByteArray bytes = payload(7000);
  ModelSender hashing(9, TransferKind::Level, 40, bytes, 2000);
  ModelSender precomputed(9, TransferKind::Level, 40, bytes, sha256(bytes), 2000);
  EXPECT_EQ(precomputed.begin(), hashing.begin());
  while (auto chunk = hashing.nextChunk()) {
    const std::optional<ModelChunk> other = precomputed.nextChunk();
    ASSERT_TRUE(other.has_value());
    EXPECT_EQ(*other, *chunk);
  }
  EXPECT_FALSE(precomputed.nextChunk().has_value());
}

TEST(ModelTransfer, UncheckedCompletionLeavesTheChecksumToTheCaller) {
  // Intact: Complete without hashing; the payload verifies against the announced digest.
  ModelSender sender(4, TransferKind::FullModel, 10, payload(10000), 3000);
  ModelReceiver receiver;
  receiver.begin(sender.begin());
  ModelReceiver::Status status = ModelReceiver::Status::InProgress;
  while (auto chunk = sender.nextChunk()) status = receiver.addUnchecked(*chunk);
  ASSERT_EQ(status, ModelReceiver::Status::Complete);
  ASSERT_TRUE(receiver.current().has_value());
  const QByteArray expected = receiver.current()->sha256;
  const QByteArray bytes = receiver.take();
  EXPECT_FALSE(receiver.active());
  EXPECT_EQ(bytes, payload(10000));
  EXPECT_TRUE(checksumMatches(bytes, expected));

  // Corrupted: still Complete (not hashed), and the caller's check catches it.
  ModelSender again(5, TransferKind::FullModel, 10, payload(10000), 3000);
  receiver.begin(again.begin());
  while (auto chunk = again.nextChunk()) {
    if (chunk->offset == 6000) chunk->bytes[0] = static_cast<char>(chunk->bytes[0] ^ 0x40);
    status = receiver.addUnchecked(*chunk);
  }
  ASSERT_EQ(status, ModelReceiver::Status::Complete);
  const QByteArray digest = receiver.current()->sha256;
  EXPECT_FALSE(checksumMatches(receiver.take(), digest));
  EXPECT_FALSE(checksumMatches(payload(10000), QByteArray()));  // a digest of the wrong size never matches

  // The ordering rules are those of add().
  ModelSender third(6, TransferKind::Level, 10, payload(9000), 3000);
  receiver.begin(third.begin());
  (void)third.nextChunk();
  EXPECT_EQ(receiver.addUnchecked(*third.nextChunk()), ModelReceiver::Status::OutOfOrder);
  EXPECT_FALSE(receiver.active());
}

}  // namespace
}  // namespace sc::session
