#include "app/gui/demo.h"

#include "app/gui/first_start.h"
#include "app/gui/main_window.h"

#include <QGuiApplication>
#include <QScreen>

#include <cmath>

namespace sc::app {

Demo::Demo(DemoOptions options, QObject* parent) : QObject(parent), m_options(std::move(options)) {}

Demo::~Demo() {
  // Clients first, so that the host sees them leave rather than vanish.
  m_lowClient.reset();
  m_fullClient.reset();
  m_host.reset();
}

std::vector<MainWindow*> Demo::windows() const {
  std::vector<MainWindow*> out;
  for (MainWindow* window : {m_host.get(), m_fullClient.get(), m_lowClient.get()}) {
    if (window != nullptr) out.push_back(window);
  }
  return out;
}

bool Demo::start() {
  if (m_host) return false;
  m_meshPath = m_options.meshPath;
  if (m_meshPath.isEmpty()) {
    QString error;
    m_meshPath = defaultMeshOrGenerated(defaultMeshFolders(), &error);
    if (m_meshPath.isEmpty()) {
      emit failed(tr("No mesh for the demo: %1").arg(error));
      return false;
    }
  }
  m_host = std::make_unique<MainWindow>();
  m_fullClient = std::make_unique<MainWindow>();
  m_lowClient = std::make_unique<MainWindow>();
  for (MainWindow* window : windows()) window->setErrorDialogsEnabled(m_options.errorDialogs);
  arrange();
  for (MainWindow* window : windows()) window->show();

  HostSettings settings;
  settings.meshPath = m_meshPath;
  settings.port = m_options.port;
  settings.m = m_options.m;
  settings.name = QStringLiteral("host");
  settings.useBasisCache = m_options.useBasisCache;
  hostReadyToDrag(*m_host, settings);
  m_host->setWindowTitle(tr("Demo host — ShapeCast"));
  connect(m_host->session(), &SessionController::hostingStarted, this, &Demo::joinClients, Qt::SingleShotConnection);
  m_fullClient->setWindowTitle(tr("Demo client, full resolution — waiting for the host"));
  m_lowClient->setWindowTitle(
      tr("Demo client, %1% resolution — waiting for the host").arg(std::round(100.0 * m_options.lowFraction)));
  return true;
}

void Demo::joinClients(quint16 port) {
  JoinSettings full;
  full.host = QStringLiteral("127.0.0.1");
  full.port = port;
  full.name = QStringLiteral("full");
  full.fingerprint = m_host->session()->hostFingerprint();  // in-process clients pin their own host
  m_fullClient->joinSession(full);
  m_fullClient->setWindowTitle(tr("Demo client, full resolution — ShapeCast"));

  JoinSettings low = full;
  low.name = QStringLiteral("low-lossy");
  low.levelFraction = m_options.lowFraction;
  session::ImpairmentSettings impairment;
  impairment.loss = m_options.lowLoss;
  impairment.seed = 5;
  low.impairment = impairment;
  m_lowClient->joinSession(low);
  m_lowClient->setWindowTitle(tr("Demo client, %1% resolution, %2% loss — ShapeCast")
                                  .arg(std::round(100.0 * m_options.lowFraction))
                                  .arg(std::round(100.0 * m_options.lowLoss)));
  emit clientsJoining(port);
}

void Demo::arrange() {
  const QScreen* screen = QGuiApplication::primaryScreen();
  const QRect area = screen != nullptr ? screen->availableGeometry() : QRect(0, 0, 1920, 1080);
  const int width = area.width() / 3;
  const int height = std::min(area.height(), std::max(480, width * 4 / 3));
  int x = area.x();
  for (MainWindow* window : windows()) {
    window->resize(width - 8, height - 40);  // room for the window frame
    window->move(x, area.y());
    x += width;
  }
}

}  // namespace sc::app
