// Tests for src/app/common/host_address.cpp: the HOST:PORT syntax of `shapecast --join` and `shapecast-cli
// join|drive`.

#include "app/common/host_address.h"

#include <gtest/gtest.h>

namespace sc::app {
namespace {

TEST(HostAddress, NamesAndIpv4Addresses) {
  const std::optional<HostAddress> ip = parseHostAddress(QStringLiteral("192.168.1.20:47100"));
  ASSERT_TRUE(ip.has_value());
  EXPECT_EQ(ip->host, QStringLiteral("192.168.1.20"));
  EXPECT_EQ(ip->port, 47100);
  const std::optional<HostAddress> name = parseHostAddress(QStringLiteral("studio-3.example.org:1"));
  ASSERT_TRUE(name.has_value());
  EXPECT_EQ(name->host, QStringLiteral("studio-3.example.org"));
  EXPECT_EQ(name->port, 1);
  EXPECT_EQ(parseHostAddress(QStringLiteral("localhost:65535"))->port, 65535);
}

TEST(HostAddress, Ipv6BracketedOrBare) {
  const std::optional<HostAddress> bracketed = parseHostAddress(QStringLiteral("[::1]:47100"));
  ASSERT_TRUE(bracketed.has_value());
  EXPECT_EQ(bracketed->host, QStringLiteral("::1")) << "the brackets are removed";
  EXPECT_EQ(bracketed->port, 47100);
  const std::optional<HostAddress> bare = parseHostAddress(QStringLiteral("fe80::1:8080"));
  ASSERT_TRUE(bare.has_value());
  EXPECT_EQ(bare->host, QStringLiteral("fe80::1")) << "the last colon separates the port";
  EXPECT_EQ(bare->port, 8080);
}

TEST(HostAddress, RejectsWhatIsNotHostColonPort) {
  for (const char* text :
       {"", "localhost", "localhost:", ":47100", "localhost:0", "localhost:65536", "host:99999", "host:123456",
        "host:+80", "host:80 ", " host:80", "a b:80", "host:8o", "[::1:80", "::1]:80", "[]:80", "[::1]x:80"}) {
    EXPECT_FALSE(parseHostAddress(QString::fromLatin1(text)).has_value()) << '"' << text << '"';
  }
}

}  // namespace
}  // namespace sc::app
