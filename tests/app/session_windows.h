#pragma once
// The loopback session set-up the app's session tests share: a MainWindow made ready for a test, a mesh hosted by it
// on any free port of 127.0.0.1, another MainWindow joining it, each step waiting until the session is live; and a
// fixture holding a generated torus written as an OFF file in a temporary folder.

#include "app/gui/client_controller.h"
#include "app/gui/host_controller.h"
#include "app/gui/main_window.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QSize>
#include <QString>
#include <QTemporaryDir>

namespace sc::testing {

/// How long hosting (the basis of a small mesh) or joining (handshake, level transfer) may take in a test.
inline constexpr int kSessionLiveTimeoutMs = 60000;

/// Turns `window`'s error dialogs off (a failure must not block a test on a modal box), resizes it to `size` and
/// shows it. Does not wait for it to be exposed. Cost: one show.
void showSessionWindow(app::MainWindow& window, QSize size);

/// Settings that host `meshPath` (mesh or session file) on any free port with `m` frequencies, as "alice", without
/// the basis cache (a test neither reads nor writes the user's cache) and without a password.
app::HostSettings loopbackHostSettings(const QString& meshPath, int m);

/// Settings that join 127.0.0.1:`port` as "bob" with no password, trusting on first use with the known hosts kept
/// in `knownHostsFile` (a temporary INI file, never the user's settings).
app::JoinSettings loopbackJoinSettings(quint16 port, const QString& knownHostsFile);

/// Hosts with `settings` in `window` and processes events until the preparation has ended, at most
/// kSessionLiveTimeoutMs. Returns window.session() (never null), a host: Live when hosting worked, Failed (errorText()
/// says why) when it did not, still Preparing after the timeout. Asserts nothing: the caller checks the state.
app::HostController* hostAndWait(app::MainWindow& window, const app::HostSettings& settings);

/// Joins with `settings` in `window` and processes events until the session is Live with its requested level (a
/// progressive join shows the smallest one first) or Failed, at most
/// kSessionLiveTimeoutMs. Returns the joining client in the state it reached (window.session() unless the window
/// was in a session: then its pendingJoin(), nullptr once a failed one was deleted). Asserts nothing.
app::ClientController* joinAndWait(app::MainWindow& window, const app::JoinSettings& settings);

/// Fixture of the two-window session tests: a 48 × 24 torus (m_mesh) written to m_meshPath in a temporary folder
/// (m_dir). Skips the test without an OpenGL 3.3 context (the windows' viewports need one).
class TorusSessionTest : public ::testing::Test {
 protected:
  void SetUp() override;

  /// A known-hosts INI file in the temporary folder (for loopbackJoinSettings).
  [[nodiscard]] QString knownHostsFile() const;

  /// Writes a `shapecast-cli drive` script into the temporary folder and returns its path: a handle around vertex 0
  /// (8% of the diagonal), anchors farther than 40% from it, lifted by 15% over 1 s and held for 0.5 s.
  [[nodiscard]] QString writeLiftScript() const;

  /// The two windows of a session: what hostAndJoin() returns.
  struct LiveSession {
    app::HostController* host = nullptr;
    app::ClientController* client = nullptr;
  };
  /// Shows `hostWindow` and `clientWindow` at the given sizes, hosts the torus (m = 20) in the first and joins it
  /// from the second, waiting for each (hostAndWait, joinAndWait). Returns both controllers in the states they
  /// reached; the caller asserts Live (the join is not tried when hosting failed: client stays nullptr).
  LiveSession hostAndJoin(app::MainWindow& hostWindow, app::MainWindow& clientWindow, QSize hostSize = {900, 700},
                          QSize clientSize = {900, 700});

  QTemporaryDir m_dir;
  GeneratedMesh m_mesh;
  QString m_meshPath;
};

}  // namespace sc::testing
