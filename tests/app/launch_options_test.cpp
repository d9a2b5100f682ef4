// Tests for src/app/gui/launch_options.cpp: shapecast's command line into LaunchOptions or a readable error (no
// QApplication, no windows).

#include "app/gui/launch_options.h"

#include <gtest/gtest.h>

#include <QFile>
#include <QTemporaryDir>

namespace sc::app {
namespace {

std::variant<LaunchOptions, LaunchError> parse(QStringList arguments) {
  arguments.prepend(QStringLiteral("shapecast"));
  return parseLaunchArguments(arguments);
}

LaunchOptions options(const QStringList& arguments) {
  const std::variant<LaunchOptions, LaunchError> parsed = parse(arguments);
  if (const auto* error = std::get_if<LaunchError>(&parsed)) {
    ADD_FAILURE() << arguments.join(QLatin1Char(' ')).toStdString() << ": " << error->message.toStdString();
    return {};
  }
  return std::get<LaunchOptions>(parsed);
}

/// The error of a command line that must not run (empty message when it unexpectedly parsed).
LaunchError error(const QStringList& arguments) {
  const std::variant<LaunchOptions, LaunchError> parsed = parse(arguments);
  if (const auto* problem = std::get_if<LaunchError>(&parsed)) return *problem;
  ADD_FAILURE() << arguments.join(QLatin1Char(' ')).toStdString() << " parsed";
  return {};
}

class LaunchOptionsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(m_dir.isValid());
    m_mesh = m_dir.filePath(QStringLiteral("mesh.off"));
    QFile file(m_mesh);
    ASSERT_TRUE(file.open(QIODevice::WriteOnly));  // validateHostSettings() only checks that it is a readable file
  }
  QTemporaryDir m_dir;
  QString m_mesh;
};

TEST_F(LaunchOptionsTest, NoArgumentsIsTheFirstStart) {
  const LaunchOptions none = options({});
  EXPECT_TRUE(none.firstStart());
  EXPECT_FALSE(none.demo || none.host || none.join || none.screenshotFile);
  EXPECT_FALSE(options({m_mesh}).firstStart());
  EXPECT_EQ(options({m_mesh}).meshPath, m_mesh);
}

TEST_F(LaunchOptionsTest, ScreenshotAndSize) {
  const LaunchOptions shot = options({m_mesh, QStringLiteral("--screenshot"), QStringLiteral("shot.png"),
                                      QStringLiteral("--size"), QStringLiteral("320x240")});
  ASSERT_TRUE(shot.screenshotFile.has_value());
  EXPECT_EQ(*shot.screenshotFile, QStringLiteral("shot.png"));
  EXPECT_EQ(shot.viewportSize, QSize(320, 240));
  EXPECT_EQ(options({}).viewportSize, QSize(1024, 768));
  for (const char* size : {"big", "0x10", "10x0", "100000x10", "10x", "-5x5"}) {
    EXPECT_TRUE(error({QStringLiteral("--size"), QString::fromLatin1(size)}).showHelp) << size;
  }
  EXPECT_TRUE(error({m_mesh, m_mesh}).showHelp) << "at most one MESH";
}

TEST_F(LaunchOptionsTest, HostSettingsFromTheCommandLine) {
  const LaunchOptions host =
      options({QStringLiteral("--host"), m_mesh, QStringLiteral("--port"), QStringLiteral("0"), QStringLiteral("--m"),
               QStringLiteral("30"), QStringLiteral("--name"), QStringLiteral("  alice ")});
  ASSERT_TRUE(host.host.has_value());
  EXPECT_EQ(host.host->meshPath, m_mesh);
  EXPECT_EQ(host.host->port, 0);
  EXPECT_EQ(host.host->m, 30);
  EXPECT_EQ(host.host->name, QStringLiteral("alice"));
  EXPECT_FALSE(host.firstStart());
  EXPECT_EQ(options({QStringLiteral("--host"), m_mesh}).host->name, QStringLiteral("host"));
  EXPECT_EQ(options({QStringLiteral("--host"), m_mesh}).host->port, 47100);

  EXPECT_TRUE(error({QStringLiteral("--host"), m_mesh, QStringLiteral("--port"), QStringLiteral("65536")})
                  .message.contains(QStringLiteral("--port")));
  EXPECT_TRUE(error({QStringLiteral("--host"), m_mesh, QStringLiteral("--m"), QStringLiteral("many")})
                  .message.contains(QStringLiteral("--m")));
  EXPECT_TRUE(error({QStringLiteral("--host"), m_dir.filePath(QStringLiteral("missing.off"))})
                  .message.contains(QStringLiteral("missing.off")));
  EXPECT_FALSE(
      error({QStringLiteral("--host"), m_mesh, QStringLiteral("--join"), QStringLiteral("a:1")}).message.isEmpty());
}

TEST_F(LaunchOptionsTest, AHostRelaysThroughNatsWithAPasswordFile) {
  // Issue 18 item 3: --host … --nats URL --session ID --nats-user U --nats-password-file F.
  const QString secret = m_dir.filePath(QStringLiteral("host.pw"));
  QFile file(secret);
  ASSERT_TRUE(file.open(QIODevice::WriteOnly));
  file.write("s3cret\nignored\n");
  file.close();
  const QStringList relay{QStringLiteral("--nats"),      QStringLiteral("nats://127.0.0.1:4222"),
                          QStringLiteral("--session"),   QStringLiteral("lecture-1"),
                          QStringLiteral("--nats-user"), QStringLiteral("host")};
  const LaunchOptions host = options(QStringList{QStringLiteral("--host"), m_mesh} + relay +
                                     QStringList{QStringLiteral("--nats-password-file"), secret});
  ASSERT_TRUE(host.host.has_value());
  ASSERT_TRUE(host.host->relay.has_value());
  EXPECT_EQ(host.host->relay->url, QStringLiteral("nats://127.0.0.1:4222"));
  EXPECT_EQ(host.host->relay->sessionId, QStringLiteral("lecture-1"));
  EXPECT_EQ(host.host->relay->user, QStringLiteral("host"));
  EXPECT_EQ(host.host->relay->password, QStringLiteral("s3cret"));
  EXPECT_EQ(options(QStringList{QStringLiteral("--host"), m_mesh} + relay +
                    QStringList{QStringLiteral("--nats-password"), QStringLiteral("pw")})
                .host->relay->password,
            QStringLiteral("pw"));
  EXPECT_FALSE(options({QStringLiteral("--host"), m_mesh}).host->relay.has_value());

  EXPECT_TRUE(error(relay).message.contains(QStringLiteral("--host")));  // a relay needs a host
  EXPECT_TRUE(error({QStringLiteral("--host"), m_mesh, QStringLiteral("--session"), QStringLiteral("x")})
                  .message.contains(QStringLiteral("--nats")));
  EXPECT_TRUE(error({QStringLiteral("--host"), m_mesh, QStringLiteral("--nats"), QStringLiteral("nats://h:1")})
                  .message.contains(QStringLiteral("--session")));
  EXPECT_TRUE(error({QStringLiteral("--host"), m_mesh, QStringLiteral("--nats"), QStringLiteral("nats://h:1"),
                     QStringLiteral("--session"), QStringLiteral("a.b")})
                  .message.contains(QStringLiteral("--session")));  // a dot would split the subject
  EXPECT_TRUE(error(QStringList{QStringLiteral("--host"), m_mesh} + relay +
                    QStringList{QStringLiteral("--nats-password-file"), m_dir.filePath(QStringLiteral("none"))})
                  .message.contains(QStringLiteral("none")));
  EXPECT_FALSE(error(QStringList{QStringLiteral("--host"), m_mesh} + relay +
                     QStringList{QStringLiteral("--nats-password"), QStringLiteral("a"),
                                 QStringLiteral("--nats-password-file"), secret})
                   .message.isEmpty());
}

TEST_F(LaunchOptionsTest, ARelayTakesATlsUrlAndTheBrokersCaAndRefusesBadValuesLikeTheDialog) {
  const QString ca = m_dir.filePath(QStringLiteral("ca.pem"));
  QFile file(ca);
  ASSERT_TRUE(file.open(QIODevice::WriteOnly));
  file.write("-----BEGIN CERTIFICATE-----\n");
  file.close();
  const QStringList host{QStringLiteral("--host"),          m_mesh,
                         QStringLiteral("--session"),       QStringLiteral("s1"),
                         QStringLiteral("--nats-user"),     QStringLiteral("host"),
                         QStringLiteral("--nats-password"), QStringLiteral("pw")};
  const LaunchOptions tls = options(host + QStringList{QStringLiteral("--nats"), QStringLiteral("tls://broker:4222"),
                                                       QStringLiteral("--nats-ca"), ca});
  ASSERT_TRUE(tls.host && tls.host->relay);
  EXPECT_EQ(tls.host->relay->url, QStringLiteral("tls://broker:4222"));
  EXPECT_EQ(tls.host->relay->caFile, ca);
  // The dialog's rule (checkHostRelaySettings), named by the option.
  EXPECT_TRUE(error(host + QStringList{QStringLiteral("--nats"), QStringLiteral("broker:4222")})
                  .message.startsWith(QStringLiteral("--nats: The NATS URL “broker:4222” must start with")));
  EXPECT_TRUE(error(host + QStringList{QStringLiteral("--nats"), QStringLiteral("tls://broker:4222"),
                                       QStringLiteral("--nats-ca"), m_dir.filePath(QStringLiteral("none.pem"))})
                  .message.startsWith(QStringLiteral("--nats-ca: ")));
  EXPECT_TRUE(
      error({QStringLiteral("--host"), m_mesh, QStringLiteral("--nats"), QStringLiteral("nats://h:1"),
             QStringLiteral("--session"), QStringLiteral("s"), QStringLiteral("--nats-user"), QStringLiteral("host")})
          .message.startsWith(QStringLiteral("--nats-password[-file]: ")));
  // A viewer's --nats-ca.
  const LaunchOptions watch =
      options({QStringLiteral("--watch"), QStringLiteral("tls://broker:4222"), QStringLiteral("--session"),
               QStringLiteral("s1"), QStringLiteral("--nats-ca"), ca});
  ASSERT_TRUE(watch.watch);
  EXPECT_EQ(watch.watch->caFile, ca);
  EXPECT_TRUE(
      error({QStringLiteral("--watch"), QStringLiteral("tls://h:0"), QStringLiteral("--session"), QStringLiteral("s1")})
          .message.contains(QStringLiteral("port from 1 to 65535")));
}

TEST_F(LaunchOptionsTest, JoinAddressesLevelsAndFingerprints) {
  const LaunchOptions join = options({QStringLiteral("--join"), QStringLiteral("[::1]:5000"), QStringLiteral("--name"),
                                      QStringLiteral("bob"), QStringLiteral("--level"), QStringLiteral("20%")});
  ASSERT_TRUE(join.join.has_value());
  EXPECT_EQ(join.join->host, QStringLiteral("::1"));
  EXPECT_EQ(join.join->port, 5000);
  EXPECT_EQ(join.join->name, QStringLiteral("bob"));
  ASSERT_TRUE(join.join->levelFraction.has_value());
  EXPECT_DOUBLE_EQ(*join.join->levelFraction, 0.2);
  const QString address = QStringLiteral("192.168.1.20:47100");
  EXPECT_EQ(options({QStringLiteral("--join"), address, QStringLiteral("--level"), QStringLiteral("1200")}).join->level,
            1200u);
  EXPECT_FALSE(options({QStringLiteral("--join"), address, QStringLiteral("--level"), QStringLiteral("100%")})
                   .join->levelFraction.has_value())
      << "100% is full resolution";
  EXPECT_FALSE(options({QStringLiteral("--join"), address}).join->name.isEmpty()) << "$USER or guest";

  for (const char* bad : {"localhost", "localhost:0", "host:99999", ":47100", "a b:1"}) {
    EXPECT_TRUE(
        error({QStringLiteral("--join"), QString::fromLatin1(bad)}).message.contains(QStringLiteral("HOST:PORT")))
        << bad;
  }
  for (const char* level : {"0%", "101%", "lots", "-3"}) {
    EXPECT_TRUE(error({QStringLiteral("--join"), address, QStringLiteral("--level"), QString::fromLatin1(level)})
                    .message.contains(QStringLiteral("--level")))
        << level;
  }
  EXPECT_TRUE(error({QStringLiteral("--join"), address, QStringLiteral("--fingerprint"), QStringLiteral("ab:cd:no")})
                  .message.contains(QStringLiteral("--fingerprint")));
  const QString hex = QStringLiteral("0123456789abcdef").repeated(4);
  EXPECT_EQ(options({QStringLiteral("--join"), address, QStringLiteral("--fingerprint"), hex}).join->fingerprint.size(),
            32);
}

TEST_F(LaunchOptionsTest, DemoAndItsScreenshots) {
  const LaunchOptions demo = options({QStringLiteral("--demo"), m_mesh});
  EXPECT_TRUE(demo.demo);
  EXPECT_FALSE(demo.firstStart());
  EXPECT_FALSE(demo.screenshotDirectory.has_value());
  EXPECT_EQ(demoOptions(demo).meshPath, m_mesh);
  EXPECT_TRUE(demoOptions(demo).errorDialogs);

  const LaunchOptions shots = options({QStringLiteral("--demo"), QStringLiteral("--screenshot-dir"),
                                       QStringLiteral("shots"), QStringLiteral("--after"), QStringLiteral("5")});
  ASSERT_TRUE(shots.screenshotDirectory.has_value());
  EXPECT_EQ(*shots.screenshotDirectory, QStringLiteral("shots"));
  EXPECT_DOUBLE_EQ(shots.afterSeconds, 5.0);
  EXPECT_FALSE(demoOptions(shots).errorDialogs) << "screenshot runs report on stderr";
  EXPECT_DOUBLE_EQ(options({QStringLiteral("--demo")}).afterSeconds, 20.0);

  EXPECT_TRUE(
      error({QStringLiteral("--screenshot-dir"), QStringLiteral("shots")}).message.contains(QStringLiteral("--demo")));
  for (const char* after : {"soon", "0.5", "601"}) {
    EXPECT_TRUE(error({QStringLiteral("--demo"), QStringLiteral("--after"), QString::fromLatin1(after)})
                    .message.contains(QStringLiteral("--after")))
        << after;
  }
  EXPECT_FALSE(error({QStringLiteral("--demo"), QStringLiteral("--host"), m_mesh}).message.isEmpty());
  EXPECT_FALSE(
      error({QStringLiteral("--demo"), QStringLiteral("--screenshot"), QStringLiteral("x.png")}).message.isEmpty());
}

TEST_F(LaunchOptionsTest, UnknownOptionsAndMissingValuesAreErrors) {
  EXPECT_TRUE(error({QStringLiteral("--bogus")}).message.contains(QStringLiteral("bogus")));
  EXPECT_FALSE(error({QStringLiteral("--join")}).message.isEmpty());
}

TEST_F(LaunchOptionsTest, WatchThroughNats) {
  const QString pin = QStringLiteral("ab").repeated(32);
  const QString passwordFile = m_dir.filePath(QStringLiteral("viewer.password"));
  QFile file(passwordFile);
  ASSERT_TRUE(file.open(QIODevice::WriteOnly));
  file.write("viewer-secret\nignored\n");
  file.close();
  const LaunchOptions watch =
      options({QStringLiteral("--watch"), QStringLiteral("nats://127.0.0.1:4222"), QStringLiteral("--session"),
               QStringLiteral("lecture-1"), QStringLiteral("--nats-user"), QStringLiteral("viewer"),
               QStringLiteral("--nats-password-file"), passwordFile, QStringLiteral("--pin"), pin,
               QStringLiteral("--level"), QStringLiteral("20%")});
  ASSERT_TRUE(watch.watch.has_value());
  EXPECT_FALSE(watch.firstStart());
  EXPECT_FALSE(watch.host || watch.join || watch.demo);
  EXPECT_EQ(watch.watch->url, QStringLiteral("nats://127.0.0.1:4222"));
  EXPECT_EQ(watch.watch->sessionId, QStringLiteral("lecture-1"));
  EXPECT_EQ(watch.watch->user, QStringLiteral("viewer"));
  EXPECT_EQ(watch.watch->password, QStringLiteral("viewer-secret"));  // the first line only
  EXPECT_EQ(watch.watch->pin, QByteArray::fromHex(pin.toLatin1()));
  ASSERT_TRUE(watch.watch->levelFraction.has_value());
  EXPECT_DOUBLE_EQ(*watch.watch->levelFraction, 0.2);
  // The defaults: full level, trust on first use; a password on the command line is taken as well.
  const LaunchOptions plain =
      options({QStringLiteral("--watch"), QStringLiteral("nats://h:1"), QStringLiteral("--session"),
               QStringLiteral("s"), QStringLiteral("--nats-password"), QStringLiteral("pw")});
  ASSERT_TRUE(plain.watch.has_value());
  EXPECT_EQ(plain.watch->level, 0u);
  EXPECT_FALSE(plain.watch->levelFraction);
  EXPECT_TRUE(plain.watch->pin.isEmpty());
  EXPECT_EQ(plain.watch->password, QStringLiteral("pw"));
}

TEST_F(LaunchOptionsTest, WatchErrorsAreReadable) {
  const QStringList base = {QStringLiteral("--watch"), QStringLiteral("nats://127.0.0.1:4222"),
                            QStringLiteral("--session"), QStringLiteral("s1")};
  EXPECT_TRUE(error({QStringLiteral("--watch"), QStringLiteral("127.0.0.1:4222"), QStringLiteral("--session"),
                     QStringLiteral("s1")})
                  .message.contains(QStringLiteral("NATS URL")));
  EXPECT_TRUE(
      error({QStringLiteral("--watch"), QStringLiteral("nats://h:1")}).message.contains(QStringLiteral("--session")));
  EXPECT_TRUE(error({QStringLiteral("--watch"), QStringLiteral("nats://h:1"), QStringLiteral("--session"),
                     QStringLiteral("a.b")})
                  .message.contains(QStringLiteral("--session")));
  EXPECT_TRUE(error(base + QStringList{QStringLiteral("--pin"), QStringLiteral("xyz")})
                  .message.contains(QStringLiteral("--pin")));
  EXPECT_TRUE(error(base + QStringList{QStringLiteral("--level"), QStringLiteral("lots")})
                  .message.contains(QStringLiteral("--level")));
  EXPECT_TRUE(error(base + QStringList{QStringLiteral("--nats-password-file"), m_dir.filePath(QStringLiteral("none"))})
                  .message.contains(QStringLiteral("--nats-password-file")));
  EXPECT_TRUE(error(base + QStringList{QStringLiteral("--join"), QStringLiteral("127.0.0.1:47100")})
                  .message.contains(QStringLiteral("--watch")));
  EXPECT_TRUE(error(base + QStringList{QStringLiteral("--demo")}).message.contains(QStringLiteral("--watch")));
}

TEST(ShieldedArguments, NameWithASpaceIsJoinedToItsValueAndTheRestIsKept) {
  std::vector<std::string> given = {"shapecast", "--join", "127.0.0.1:47100", "--name", "bob", "--level", "full"};
  std::vector<char*> argv;
  for (std::string& argument : given) argv.push_back(argument.data());
  EXPECT_EQ(shieldedArguments(argv),
            (std::vector<std::string>{"shapecast", "--join", "127.0.0.1:47100", "--name=bob", "--level", "full"}));
  // Already joined, or a trailing --name without a value (the parser then says what is missing): unchanged.
  std::vector<std::string> other = {"shapecast", "--name=alice", "mesh.ply", "--name"};
  std::vector<char*> otherArgv;
  for (std::string& argument : other) otherArgv.push_back(argument.data());
  EXPECT_EQ(shieldedArguments(otherArgv), other);
}

TEST(ShieldedArguments, SessionIsJoinedToItsValueBeforeQGuiApplicationTakesIt) {
  // QGuiApplication consumes "-session ID" / "--session ID" (X11 session management): the relay's --session
  // (issue 18) reaches our parser only as --session=ID.
  std::vector<std::string> given = {"shapecast", "--host", "m.ply", "--nats", "nats://h:1", "--session", "lecture"};
  std::vector<char*> argv;
  for (std::string& argument : given) argv.push_back(argument.data());
  EXPECT_EQ(shieldedArguments(argv),
            (std::vector<std::string>{"shapecast", "--host", "m.ply", "--nats", "nats://h:1", "--session=lecture"}));
}

}  // namespace
}  // namespace sc::app
