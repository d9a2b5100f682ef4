// Issue 16, idle CPU: with nothing moving, the host still sends its unchanged shape about once a second (still
// frames) and every member its unchanged view (presence, ~2 per second). Neither may repaint a viewport: on a
// software rasteriser each repaint of the 3D view costs a full frame. A host and a client on loopback in this
// process; the test counts the repaints the viewports ask for (MeshViewport::repaintRequestCount()) while still
// frames arrive.

#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QSignalSpy>
#include <QTest>

namespace sc::app {
namespace {

class IdleRepaintTest : public sc::testing::TorusSessionTest {};

TEST_F(IdleRepaintTest, StillFramesAndUnchangedPresenceDoNotRepaintTheViewports) {
  MainWindow hostWindow;
  MainWindow clientWindow;
  const LiveSession live = hostAndJoin(hostWindow, clientWindow, {640, 480}, {640, 480});
  ASSERT_EQ(live.host->state(), SessionController::State::Live) << live.host->errorText().toStdString();
  ASSERT_NE(live.client, nullptr);
  ASSERT_EQ(live.client->state(), SessionController::State::Live) << live.client->errorText().toStdString();
  QSignalSpy clientFrames(live.client, &SessionController::frameChanged);
  ASSERT_TRUE(QTest::qWaitFor([&] { return clientFrames.count() >= 1; }, 5000)) << "the first still frame";
  QTest::qWait(1500);  // the first picture, the presence of both, the full redraw after any moving frame
  // Repaints the application asks for: an X server shared with other test processes also exposes the viewports'
  // native windows (another process's window closing over them), which paints them without any request.
  const int hostPaints = hostWindow.viewport()->repaintRequestCount();
  const int clientPaints = clientWindow.viewport()->repaintRequestCount();
  const qsizetype framesBefore = clientFrames.count();
  ASSERT_TRUE(QTest::qWaitFor([&] { return clientFrames.count() >= framesBefore + 2; }, 10000))
      << "still frames keep arriving about once a second";
  QTest::qWait(200);
  EXPECT_EQ(hostWindow.viewport()->repaintRequestCount(), hostPaints) << "the host's view did not ask to repaint";
  EXPECT_EQ(clientWindow.viewport()->repaintRequestCount(), clientPaints) << "the client's view did not ask to repaint";
}

}  // namespace
}  // namespace sc::app
