// Seats and pending connections (docs/security.md, "Hostile member"): silent TCP connections do not take seats (a
// seat is counted only after the password proof), and pending connections from over-represented addresses make
// room for a newcomer from another address. Real TLS over loopback sockets (127.0.0.2 and 127.0.0.3 as "other
// addresses"). Fixture: security_fixture.h. Also the admission key that groups IPv6 addresses by /64.
#include "security_fixture.h"

#include "silent_connections.h"

#include <QtTest/QTest>

namespace sc::session {
namespace {

using testing::openSilentConnections;
using testing::stillOpen;

TEST_F(Security, SilentConnectionsDoNotTakeSeats) {
  SessionHostOptions options = hostOptions();
  options.maxPeers = 2;
  auto host = startHost(options);
  const auto sockets = openSilentConnections(QHostAddress(QStringLiteral("127.0.0.2")), host->tcpPort(), 4);
  ASSERT_TRUE(QTest::qWaitFor([&] { return stillOpen(sockets) == 4; }, kWaitMs));
  QTest::qWait(100);  // the host has accepted them
  auto first = start(clientOptions(host->tcpPort(), QStringLiteral("first")));
  EXPECT_TRUE(settle(*first)) << first->errorText().toStdString();
  auto second = start(clientOptions(host->tcpPort(), QStringLiteral("second")));
  EXPECT_TRUE(settle(*second)) << second->errorText().toStdString();
  auto third = start(clientOptions(host->tcpPort(), QStringLiteral("third")));
  EXPECT_FALSE(settle(*third)) << "two seats, two members";
  EXPECT_EQ(third->errorText(), QStringLiteral("the session is full"));
  EXPECT_EQ(members(*host), 2u);
}

TEST_F(Security, PendingConnectionsFromTwoAddressesDoNotLockOutAThird) {
  auto host = startHost();  // 16 pending in all, 8 per address
  const auto fromA = openSilentConnections(QHostAddress(QStringLiteral("127.0.0.2")), host->tcpPort(), 8);
  const auto fromB = openSilentConnections(QHostAddress(QStringLiteral("127.0.0.3")), host->tcpPort(), 8);
  ASSERT_TRUE(QTest::qWaitFor([&] { return stillOpen(fromA) + stillOpen(fromB) == 16; }, kWaitMs));
  QTest::qWait(100);
  int joined = 0;
  for (int i = 0; i < 3; ++i) {
    auto honest = start(clientOptions(host->tcpPort(), QStringLiteral("honest %1").arg(i)));
    if (settle(*honest)) ++joined;
  }
  EXPECT_EQ(joined, 3);
}

TEST(AdmissionAddressKey, GroupsIpv6ByTheirSlash64) {
  const auto key = [](const char* text) { return admissionAddressKey(QHostAddress(QString::fromLatin1(text))); };
  EXPECT_EQ(key("2001:db8:1:2::1"), key("2001:db8:1:2:ffff:eeee:dddd:cccc")) << "one /64: one address";
  EXPECT_EQ(key("2001:db8:1:2::1"), "2001:db8:1:2::/64");
  EXPECT_NE(key("2001:db8:1:2::1"), key("2001:db8:1:3::1")) << "another /64";
  EXPECT_EQ(key("127.0.0.2"), "127.0.0.2");
  EXPECT_EQ(key("::ffff:10.0.0.7"), "10.0.0.7") << "IPv4-mapped: the IPv4 address";
  EXPECT_NE(key("10.0.0.7"), key("10.0.0.8"));
}

}  // namespace
}  // namespace sc::session
