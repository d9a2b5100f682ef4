// TlsStream (session/net/tls_stream.h) against a real TLS server on 127.0.0.1: an owner that does not read holds at
// most the read limit (in bytes and in heap) while the host has more to send, every byte arrives once and in order
// when it reads, and what the connection reported (the host's address and certificate, its close) reaches the
// owner's thread.
#include "session/net/tls_stream.h"

#include "session/net/tls_identity.h"
#include "session/net/tls_server.h"

#include <gtest/gtest.h>
#include <malloc.h>

#include <QtNetwork/QSslSocket>
#include <QtTest/QTest>

#include "address_sanitizer.h"

#include <algorithm>
#include <optional>

namespace sc::session {
namespace {

/// Bytes the process holds from malloc now (glibc, all arenas: in use plus mmapped blocks).
qint64 heapInUse() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<qint64>(info.uordblks + info.hblkhd);
}

TEST(TlsStreamBuffer, AnOwnerThatDoesNotReadHoldsTheReadLimitThenGetsEveryByteInOrder) {
  const std::optional<TlsIdentity> identity = generateTlsIdentity(QStringLiteral("stream-test"));
  ASSERT_TRUE(identity.has_value());
  TlsServer server;
  server.setSslConfiguration(hostTlsConfiguration(identity->certificate, identity->privateKey));
  ASSERT_TRUE(server.listen(QHostAddress::LocalHost));

  constexpr qsizetype kPayload = 12 << 20;
  QByteArray payload(kPayload, Qt::Uninitialized);
  for (qsizetype i = 0; i < kPayload; ++i) payload[i] = static_cast<char>((i * 7) ^ (i >> 13));
  QSslSocket* sender = nullptr;
  qsizetype sent = 0;
  const auto sendMore = [&] {  // at most 1 MiB queued in the sender, so that its memory stays small
    while (sent < kPayload && sender->bytesToWrite() < (1 << 20)) {
      const qsizetype piece = std::min<qsizetype>(256 << 10, kPayload - sent);
      sender->write(payload.constData() + sent, piece);
      sent += piece;
    }
  };
  QObject::connect(&server, &QTcpServer::newConnection, [&] {
    sender = qobject_cast<QSslSocket*>(server.nextPendingConnection());
    QObject::connect(sender, &QSslSocket::encrypted, sendMore);
    QObject::connect(sender, &QSslSocket::encryptedBytesWritten, sendMore);
  });

  constexpr qint64 kLimit = 4 << 20;
  TlsStream stream(clientTlsConfiguration());
  stream.setBufferSizes(kLimit, 256 << 10);
  bool encrypted = false;
  bool disconnected = false;
  int readyReads = 0;
  QObject::connect(&stream, &TlsStream::encrypted, [&] { encrypted = true; });
  QObject::connect(&stream, &TlsStream::readyRead, [&] { ++readyReads; });
  QObject::connect(&stream, &TlsStream::disconnected, [&] { disconnected = true; });
  const qint64 heapBefore = heapInUse();
  stream.connectToHostEncrypted(QStringLiteral("127.0.0.1"), server.serverPort());

  ASSERT_TRUE(QTest::qWaitFor([&] { return stream.bytesAvailable() >= kLimit; }, 10000));
  EXPECT_TRUE(encrypted);
  EXPECT_EQ(stream.peerCertificate(), identity->certificate);
  EXPECT_EQ(stream.peerAddress(), QHostAddress(QHostAddress::LocalHost));
  QTest::qWait(300);  // the host still has megabytes to send; nothing is read here
  EXPECT_EQ(stream.bytesAvailable(), kLimit) << "never more than the read limit buffered";
  EXPECT_GE(readyReads, 1);
  // The buffer's heap is its bytes' (QSslSocket reads 4 KiB records; each read's own array would carry 16-32 KiB of
  // capacity: 38 MB measured for this limit). The rest, up to 5 MB: the sockets' buffers, the sender's queue (about
  // 1 MiB, plain and encrypted), TLS state (8.0-9.1 MB in all measured).
  if (!sc::testing::kAddressSanitizer) {
    EXPECT_LT(heapInUse() - heapBefore, 3 * kLimit) << "heap grown while the buffer holds the limit";
  }

  QByteArray received;
  ASSERT_TRUE(QTest::qWaitFor(
      [&] {
        received += stream.read(100'000);  // in pieces that cut across the stream's own chunks
        return received.size() >= kPayload;
      },
      20000));
  EXPECT_EQ(received.size(), kPayload);
  EXPECT_TRUE(received == payload) << "every byte once, in order";
  EXPECT_EQ(stream.bytesAvailable(), 0);

  ASSERT_NE(sender, nullptr);
  sender->disconnectFromHost();
  EXPECT_TRUE(QTest::qWaitFor([&] { return disconnected; }, 5000));
}

}  // namespace
}  // namespace sc::session
