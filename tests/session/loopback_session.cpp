#include "loopback_session.h"

#include <gtest/gtest.h>

#include <QtTest/QTest>

#include <utility>

namespace sc::session::testing {

std::unique_ptr<SessionHost> startHost(std::shared_ptr<const HostModel> model, SessionHostOptions options) {
  auto host = std::make_unique<SessionHost>(std::move(model), std::move(options));
  QString error;
  EXPECT_TRUE(host->start(&error)) << error.toStdString();
  return host;
}

SessionClientOptions clientOptions(quint16 port, const QString& name, std::optional<QString> password) {
  SessionClientOptions options;
  options.host = QStringLiteral("127.0.0.1");
  options.port = port;
  options.name = name;
  options.password = std::move(password);
  options.minPbkdf2Iterations = kTestPbkdf2Iterations;  // the fixtures' hosts derive fast
  options.keepLevelPayload = true;                      // the tests compare what arrived with what was sent
  return options;
}

std::unique_ptr<SessionClient> startClient(SessionClientOptions options) {
  auto client = std::make_unique<SessionClient>(std::move(options));
  client->start();
  return client;
}

bool settle(SessionClient& client) {
  (void)QTest::qWaitFor(
      [&] {
        const auto s = client.state();
        return s == SessionClient::State::Ready || s == SessionClient::State::Failed || s == SessionClient::State::Left;
      },
      kWaitMs);
  return client.state() == SessionClient::State::Ready;
}

}  // namespace sc::session::testing
