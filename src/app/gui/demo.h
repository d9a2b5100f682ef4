#pragma once
// `shapecast --demo`: the whole idea at once, in one process on loopback. A host window (hosting the default mesh,
// ready to drag as on first start: default handle and anchors, lock requested, Drag tool) and, once it is live, two
// client windows joining it: one at full resolution, one at the ≈5% level behind 10% emulated loss (its Network
// conditions dock shows and changes that). The three windows are arranged side by side on the primary screen.
// Errors (mesh, basis, port, join) show in each window as usual (dialogs unless disabled, sessionFailed()).

#include "app/gui/session_controller.h"

#include <QObject>
#include <QString>

#include <memory>
#include <vector>

namespace sc::app {

class MainWindow;

struct DemoOptions {
  QString meshPath;  ///< empty: defaultMeshOrGenerated(defaultMeshFolders())
  quint16 port = 0;  ///< host TCP port; 0 = any free port
  int m = 100;       ///< frequencies
  bool useBasisCache = true;
  double lowFraction = 0.05;  ///< the second client's resolution (fraction of the host's vertices)
  double lowLoss = 0.10;      ///< the second client's emulated loss
  bool errorDialogs = true;   ///< false in tests: failures only as MainWindow::sessionFailed()
};

class Demo final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(Demo)

 public:
  explicit Demo(DemoOptions options, QObject* parent = nullptr);
  /// Closes the three windows (clients leave, the host shuts down).
  ~Demo() override;

  /// Creates, arranges and shows the windows and starts hosting; the clients join once the host is live.
  /// False (and failed(reason)) when no mesh could be found or generated.
  bool start();

  [[nodiscard]] MainWindow* hostWindow() const { return m_host.get(); }
  [[nodiscard]] MainWindow* fullClientWindow() const { return m_fullClient.get(); }
  [[nodiscard]] MainWindow* lowClientWindow() const { return m_lowClient.get(); }
  /// Host, full client, low client (the clients are created by start()).
  [[nodiscard]] std::vector<MainWindow*> windows() const;
  [[nodiscard]] const QString& meshPath() const { return m_meshPath; }

 signals:
  /// The host is live on `port` and the clients are joining.
  void clientsJoining(quint16 port);
  /// A readable reason the demo could not start (the windows' own failures come as their sessionFailed()).
  void failed(const QString& reason);

 private:
  void joinClients(quint16 port);
  void arrange();

  DemoOptions m_options;
  QString m_meshPath;
  std::unique_ptr<MainWindow> m_host;
  std::unique_ptr<MainWindow> m_fullClient;
  std::unique_ptr<MainWindow> m_lowClient;
};

}  // namespace sc::app
