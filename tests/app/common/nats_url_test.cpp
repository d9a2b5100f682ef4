// Tests for src/app/common/nats_url.cpp: the NATS URL syntax shared by `shapecast --host … --nats`, `--watch`, the
// Host… dialog's relay group and `shapecast-cli host|watch --nats`.

#include "app/common/nats_url.h"

#include <gtest/gtest.h>

namespace sc::app {
namespace {

TEST(NatsUrl, AcceptsNatsAndTlsUrlsWithOrWithoutAPortAndLists) {
  for (const char* url : {"nats://127.0.0.1:4222", "tls://broker.example.org:4443", "nats://localhost",
                          "NATS://[::1]:4222", "nats://a:1,nats://b:2", "nats://a:1, tls://b:2", "nats://h:4222/"}) {
    EXPECT_TRUE(natsUrlProblem(QString::fromLatin1(url)).isEmpty())
        << url << ": " << natsUrlProblem(QString::fromLatin1(url)).toStdString();
  }
}

TEST(NatsUrl, RefusesWhatCnatsWouldNotReachWithReadableWords) {
  EXPECT_TRUE(natsUrlProblem({}).startsWith(QStringLiteral("Enter the NATS URL")));
  EXPECT_TRUE(natsUrlProblem(QStringLiteral("127.0.0.1:4222")).contains(QStringLiteral("nats:// or tls://")));
  EXPECT_TRUE(natsUrlProblem(QStringLiteral("http://h:4222")).contains(QStringLiteral("“http://h:4222”")));
  EXPECT_TRUE(natsUrlProblem(QStringLiteral("nats://u:p@h:4222")).contains(QStringLiteral("user or password")));
  EXPECT_TRUE(natsUrlProblem(QStringLiteral("nats://h:4222/x")).contains(QStringLiteral("only the server")));
  EXPECT_TRUE(natsUrlProblem(QStringLiteral("nats://h:0")).contains(QStringLiteral("port from 1 to 65535")));
  EXPECT_TRUE(natsUrlProblem(QStringLiteral("nats://h:99999")).contains(QStringLiteral("port from 1 to 65535")));
  EXPECT_FALSE(natsUrlProblem(QStringLiteral("nats://")).isEmpty());
  EXPECT_FALSE(natsUrlProblem(QStringLiteral("nats://a b:1")).isEmpty());
  // A list is refused for its first bad URL, named.
  EXPECT_TRUE(natsUrlProblem(QStringLiteral("nats://a:1,b:2")).contains(QStringLiteral("“b:2”")));
}

}  // namespace
}  // namespace sc::app
