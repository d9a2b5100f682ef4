// Hosting on a TCP port that is in use (issue 16): the error names the port and comes before the basis is
// computed, on the window path (MainWindow::hostSession, what the Host dialog calls) and in the controller; the
// session the window was in goes on. The command-line path (shapecast --host --port P) is in shapecast_exe_test.cpp.

#include "app/gui/main_window.h"
#include "app/gui/port_reservation.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QHostAddress>
#include <QSignalSpy>
#include <QTcpServer>

namespace sc::app {
namespace {

using State = SessionController::State;

class BusyPortTest : public sc::testing::TorusSessionTest {
 protected:
  void SetUp() override {
    sc::testing::TorusSessionTest::SetUp();
    if (IsSkipped()) return;
    ASSERT_TRUE(m_occupier.listen(QHostAddress::Any, 0)) << m_occupier.errorString().toStdString();
    m_busyPort = m_occupier.serverPort();
  }
  [[nodiscard]] HostSettings busySettings() const {
    HostSettings settings = sc::testing::loopbackHostSettings(m_meshPath, 20);
    settings.port = m_busyPort;
    return settings;
  }
  QTcpServer m_occupier;  ///< another program listening on the port
  quint16 m_busyPort = 0;
};

TEST_F(BusyPortTest, ReservationNamesTheBusyPortAndHoldsAFreeOne) {
  QString error;
  EXPECT_FALSE(PortReservation::take(m_busyPort, &error));
  EXPECT_TRUE(error.contains(QString::number(m_busyPort))) << error.toStdString();
  // A free port is held until released: nobody else can listen on it meanwhile.
  QTcpServer probe;
  ASSERT_TRUE(probe.listen(QHostAddress::Any, 0));
  const quint16 free = probe.serverPort();
  probe.close();
  std::optional<PortReservation> held = PortReservation::take(free);
  ASSERT_TRUE(held && held->holds());
  EXPECT_EQ(held->port(), free);
  QTcpServer other;
  EXPECT_FALSE(other.listen(QHostAddress::Any, free));
  held->release();
  EXPECT_TRUE(other.listen(QHostAddress::Any, free));
  // Port 0 (any free port) needs no reservation.
  std::optional<PortReservation> any = PortReservation::take(0);
  ASSERT_TRUE(any);
  EXPECT_FALSE(any->holds());
}

TEST_F(BusyPortTest, ControllerFailsInsideHostBeforeAnyPreparation) {
  HostController controller;
  QSignalSpy failed(&controller, &SessionController::failed);
  QSignalSpy progress(&controller, &SessionController::progress);
  EXPECT_FALSE(controller.host(busySettings()));
  // Inside host(), synchronously: no worker was started, so no basis was computed.
  EXPECT_EQ(controller.state(), State::Failed);
  EXPECT_FALSE(controller.preparationStarted());
  ASSERT_EQ(failed.count(), 1);
  const QString message = failed.front().front().toString();
  EXPECT_TRUE(message.contains(QStringLiteral("TCP port %1 is in use").arg(m_busyPort))) << message.toStdString();
  for (const QList<QVariant>& report : progress) {
    EXPECT_FALSE(report.at(1).toString().contains(QStringLiteral("basis"))) << report.at(1).toString().toStdString();
  }
}

TEST_F(BusyPortTest, WindowSaysWhichPortAndKeepsItsSession) {
  MainWindow window;
  sc::testing::showSessionWindow(window, QSize(480, 360));
  HostController* hosting = sc::testing::hostAndWait(window, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_EQ(hosting->state(), State::Live) << hosting->errorText().toStdString();
  const QString title = window.windowTitle();
  QSignalSpy failed(&window, &MainWindow::sessionFailed);
  QSignalSpy started(&window, &MainWindow::sessionStarted);
  EXPECT_FALSE(window.hostSession(busySettings()));
  ASSERT_EQ(failed.count(), 1);
  EXPECT_TRUE(failed.front().front().toString().contains(QString::number(m_busyPort)));
  // No new controller: the live session goes on, as it was.
  EXPECT_EQ(started.count(), 0);
  EXPECT_EQ(window.session(), hosting);
  EXPECT_EQ(hosting->state(), State::Live);
  EXPECT_EQ(window.windowTitle(), title);
}

TEST_F(BusyPortTest, WindowWithoutASessionFailsBeforeTheBasis) {
  MainWindow window;
  sc::testing::showSessionWindow(window, QSize(480, 360));
  QSignalSpy failed(&window, &MainWindow::sessionFailed);
  EXPECT_FALSE(window.hostSession(busySettings()));
  ASSERT_EQ(failed.count(), 1);  // at once, inside hostSession()
  EXPECT_TRUE(failed.front().front().toString().contains(QString::number(m_busyPort)));
  const auto* host = qobject_cast<const HostController*>(window.session());
  EXPECT_TRUE(host == nullptr || !host->preparationStarted());
}

}  // namespace
}  // namespace sc::app
