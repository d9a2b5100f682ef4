#pragma once
// MainWindow: the application window. Wiring only: menus → mesh loading (sc::model) → MeshViewport and status bar;
// Session menu, lock toolbar and resolution selector → the current SessionController (HostController or
// ClientController, which owns the session). The frame path goes one way: the controller's displayLevelChanged and
// frameChanged go to the viewport's setDisplayLevel() and showFrame(); nothing is pulled back.

#include "app/gui/file_dialogs.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/port_reservation.h"
#include "app/gui/session_life.h"
#include "app/gui/session_settings.h"
#include "app/gui/watch_settings.h"

#include <QMainWindow>
#include <QPointer>
#include <QString>
#include <QStringList>

#include <utility>

class QCloseEvent;
class QDragEnterEvent;
class QDropEvent;
class QComboBox;
class QMenu;
class QLabel;
class QProgressBar;
class QToolButton;

namespace Ui {
class MainWindow;
}

namespace sc::model {
struct LoadedMesh;
}

namespace sc::app {

class MeshViewport;
class EditActions;
class SessionController;
class InteractiveProxyBuilder;
class SessionDocks;
class SessionPresence;
class NetworkConditionsDock;
class ViewActions;
class MeshLoading;

/// How openMeshAsking() reads the mesh: at once on the GUI thread, or on a worker (loadMeshInBackground()).
enum class MeshLoad { Now, Background };

/// The ShapeCast main window: File → Open…/Quit, View → Reset View, a MeshViewport as central widget and a status
/// bar with the mesh size (permanent, objectName "meshSizeLabel") and, briefly, the cleaning report.
class MainWindow : public QMainWindow {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(MainWindow)

 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Loads a mesh file with sc::model::loadMesh() on the GUI thread and shows it (ending a session first). Never
  /// throws. On success emits meshLoaded(), adds it to File → Open Recent and returns true. On failure keeps the
  /// current mesh and session, emits loadFailed() with the loader's message, shows it in a modal QMessageBox if
  /// error dialogs are enabled, and returns false. The menus and drops use loadMeshInBackground().
  bool openMesh(const QString& path);

  // --- files (main_window_files.cpp): File → Open…, Open Recent, drops, background loading, file questions
  /// A file the user gave (File → Open…, Open Recent, a drop on the window): a session file (.shapecast) opens
  /// the Host dialog with it, a mesh goes to openMeshAsking(path, MeshLoad::Background). False when nothing
  /// started (cancelled, or a file that is gone: then dropped from Open Recent with a message).
  bool openFileFromUser(const QString& path);
  /// Reads `path` on a worker thread (MeshLoading), progress and Cancel in the status bar; a load already running
  /// is cancelled. Once read, the session (if any) ends and the mesh is shown as by openMesh(); a broken file
  /// (loadFailed()) or Cancel (loadCancelled()) keeps the current mesh and session.
  void loadMeshInBackground(const QString& path);
  /// The Cancel button of a background load (no-op without one).
  void cancelMeshLoading();
  [[nodiscard]] bool meshLoadRunning() const;
  /// File → Open Recent's files, most recent first (QSettings, recent_files.h).
  [[nodiscard]] QStringList recentFiles() const;
  /// Who answers the file questions (default: chooseInFileDialog(), a QFileDialog in the folder last used).
  void setFileChooser(FileChooser chooser) { m_fileChooser = std::move(chooser); }

  /// Whether load errors also open a modal message box (default true). Off for tests and --screenshot runs,
  /// which observe loadFailed() instead.
  void setErrorDialogsEnabled(bool enabled) { m_errorDialogsEnabled = enabled; }
  [[nodiscard]] bool errorDialogsEnabled() const { return m_errorDialogsEnabled; }

  [[nodiscard]] MeshViewport* viewport() const;

  // --- sessions (Session menu; also used by main.cpp's --host/--join and by tests)
  /// Leaves any current session, then hosts `settings` (mesh load and basis run off the GUI thread; progress in
  /// the status bar with a Cancel button). Failures arrive as sessionFailed() (and a dialog if enabled). The TCP
  /// port is held first (`port` when it holds it, else taken here; port_reservation.h): a busy port is a
  /// sessionFailed() naming it before anything is computed, and the current session goes on. False then.
  bool hostSession(const HostSettings& settings, PortReservation port = {});
  /// Joins `settings`. Without a live session it becomes the current one at once. In a session, the new one
  /// connects beside it (pendingJoin(); its progress and Cancel in the status bar) and replaces it only once live:
  /// a join that fails or is cancelled leaves the session you were in as it was (sessionFailed() says both).
  void joinSession(const JoinSettings& settings);
  /// Watches a session relayed through NATS, read-only (viewer_controller.h): the current session leaves; the
  /// lock and the editing tools stay disabled and the lock label says "Watching SESSION through NATS".
  void watchSession(const WatchSettings& settings);
  /// A join still connecting beside the current session (nullptr when none).
  [[nodiscard]] SessionController* pendingJoin() const { return m_pendingJoin; }
  /// Leaves the current session, and drops a pending join (the last shape stays displayed).
  void leaveSession();
  /// The current session's controller (nullptr before the first Host/Join). Replaced by each host/join:
  /// sessionStarted() announces the new one (docks re-bind to it).
  [[nodiscard]] SessionController* session() const { return m_session; }
  /// The Peers and Statistics docks (bound to session()).
  [[nodiscard]] SessionDocks* docks() const { return m_docks; }
  /// The others' cameras and pointers, Follow (session_presence.h; bound to session()).
  [[nodiscard]] SessionPresence* presence() const { return m_presence; }
  /// The client's Network conditions dock (objectName "networkConditionsDock", bound to session()).
  [[nodiscard]] NetworkConditionsDock* networkConditionsDock() const { return m_networkDock; }
  /// Time of the last frame's reconstruction (the viewport's own: it reconstructs from K and Z) and of the rest of
  /// its redraw (normals, paint, composition: FrameTimes), ms.
  [[nodiscard]] double reconstructionMs() const;
  [[nodiscard]] double redrawMs() const { return m_redrawMs; }
  /// Undo/redo of the session's shared edit history (Edit menu; see edit_actions.h).
  [[nodiscard]] EditActions* editActions() const { return m_editActions; }
  /// View, Tools and Help menus: standard views, up axis, trackball, wireframe, panels, brush size, shortcuts, and
  /// what the viewer remembers (view_actions.h).
  [[nodiscard]] ViewActions* viewActions() const { return m_viewActions; }

  // --- session life (main_window_life.cpp): questions before a session ends, moderation, the invitation
  /// Who answers the questions asked before a session ends (quitting or leaving while hosting with people in the
  /// session, opening a mesh while hosting or joined). Default (none set): a QMessageBox (session_life.h) while
  /// error dialogs are enabled, else the answer End without asking (tests and --screenshot runs).
  void setSessionAsker(SessionAsker asker) { m_sessionAsker = std::move(asker); }
  /// File → Open… with a chosen `path`: while a session is active asks first (End the session and open / Host it
  /// instead / Cancel); never shows the mesh while still hosting or joined. True when the mesh was opened (or
  /// hosting it started; MeshLoad::Background: when its read started, the session ending once it is read).
  bool openMeshAsking(const QString& path, MeshLoad how = MeshLoad::Now);
  /// Session → Leave Session: a host with others in its session asks first. False when the user cancelled.
  bool leaveSessionAsking();
  /// The members of the hosted session other than this user (0 unless a live host).
  [[nodiscard]] int othersInSession() const;
  /// Session → Copy Invitation: the invitation (invitation.h) of this live host, also put on the clipboard. Empty
  /// (and the clipboard untouched) unless hosting live.
  QString copyInvitation();
  /// The Peers table's context menu for `peerId` (objectName "peerContextMenu", not shown): on a live host
  /// "Remove from session" (a member's row) and "Take back the lock" (the holder's row); nullptr when it would be
  /// empty. Owned by the window until the next call.
  QMenu* peerContextMenu(quint32 peerId);

  // --- export (File menu; also used by tests)
  /// Writes the displayed mesh (the session's current positions at this peer's resolution with that level's
  /// faces; without a session the mesh last opened) to `path`, OBJ or PLY by its extension (model::writeMesh).
  /// False with a readable `error` when there is no mesh, the extension is neither, or the write fails.
  bool exportDeformedMesh(const QString& path, QString* error = nullptr);
  /// Saves the viewport's framebuffer as a PNG image. False with `error` on failure.
  bool saveScreenshot(const QString& path, QString* error = nullptr);
  /// The whole window as shown: QWidget::grab() with the viewport's frame (MeshViewport::grabFramebuffer()) drawn
  /// where the viewport is, since grab() cannot see the viewport's window surface.
  [[nodiscard]] QImage grabWindow();
  /// File → Save Session…: writes the hosted session (mesh, m, mode, current shape, undo history) to `path`
  /// (session_snapshot.h). False with a readable `error` unless this window is a live host or when writing fails.
  bool saveSession(const QString& path, QString* error = nullptr);

 public slots:
  void showHostDialog();
  void showJoinDialog();

 signals:
  /// A new session controller was created (before it starts); the previous one is being deleted.
  void sessionStarted(sc::app::SessionController* controller);
  /// A session failed (readable text: unreachable, wrong password, version mismatch, host gone, …).
  void sessionFailed(const QString& message);
  /// The current session ended (Left or Failed): the title, the host identity, the docks and the figures were
  /// reset to no session (the last shape stays displayed).
  void sessionEnded();
  /// A mesh was loaded from path and is shown.
  void meshLoaded(const QString& path, int vertexCount, int triangleCount);
  /// Loading path failed; message names the file and the problem.
  void loadFailed(const QString& path, const QString& message);
  /// A background load of path was cancelled (the current mesh stays).
  void loadCancelled(const QString& path);

 private slots:
  void chooseAndOpenMesh();
  void chooseAndExportMesh();
  void chooseAndSaveScreenshot();
  void chooseAndSaveSession();
  void chooseAndOpenSession();

 protected:
  /// A live host with others in its session asks first; ending it sends Leave{HostEnded} and closes the window
  /// once the Leaves are written (kLeaveFlushMs later).
  void closeEvent(QCloseEvent* event) override;
  /// Drops of local files (meshes, session files): the first one goes to openFileFromUser().
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;

 private:
  static constexpr int kStatusMessageMs = 10000;  ///< how long transient status bar messages stay
  static constexpr int kLeaveFlushMs = 300;       ///< the event loop writes the Leaves before the window closes

  /// Makes `controller` (new, not started) the current session: the previous one leaves and is deleted later.
  void adoptSession(SessionController* controller);
  void setUpEditAndExport();
  void setUpSessionFileActions();
  void setUpSessionControls();
  void setUpSessionStatusBar();
  void connectViewportToSession();
  void setUpSessionDocks();
  void setUpSessionLife();
  void setUpViewActions();
  void setUpFiles();
  void rebuildRecentMenu();
  /// Adds `path` to Open Recent and its folder as the dialogs' start.
  void rememberFile(const QString& path);
  /// Shows a mesh read from `path` (ends the session first): viewport, proxy, labels, title, meshLoaded().
  void showMesh(const QString& path, const model::LoadedMesh& mesh);
  /// Opens the Host dialog with the session file `path`; true when hosting started.
  bool openSessionFile(const QString& path);
  /// Asks m_fileChooser (or a QFileDialog); remembers the folder of a chosen file.
  QString chooseFile(const FileRequest& request, QString* selectedFilter = nullptr);
  /// The name files of this window are suggested from: the hosted mesh's, else the opened mesh's base name.
  [[nodiscard]] QString suggestedBaseName() const;
  SessionAnswer ask(const SessionQuestion& question);
  /// A session is preparing, connecting or live.
  [[nodiscard]] bool sessionActive() const;
  void onSessionLevel(const spectral::SharedDisplayLevel& level);
  /// Shows a frame of the session in the viewport (the per-frame path) and starts the redraw timing.
  void onSessionFrame(const spectral::DisplayFrame& frame);
  void onSessionMesh();
  /// Shows the session's handle and anchors (its displayed ids) in the viewport.
  void showSessionSelection();
  void updateLockControls();
  void updateLevelCombo();
  void updateSessionActions();
  void updateTimingLabel();
  void onSessionFailed(const QString& message);
  /// The current session reached Left or Failed: nothing of it stays on show but its last shape.
  void onSessionEnded();
  /// Makes a pending join that went live the current session and shows what it already received.
  void adoptPendingJoin(const QString& title);
  /// Leaves and deletes a pending join (no-op without one).
  void dropPendingJoin();
  /// The status bar, sessionFailed() and (if enabled) a plain-text dialog for a failure of `controller`
  /// (nullptr: a failure before any controller, e.g. a busy port).
  void reportSessionFailure(const SessionController* controller, const QString& message);
  /// The Join form again, filled in with `retry` and showing `message`, the password field to type in; OK joins.
  void askPasswordAndJoin(const JoinSettings& retry, const QString& message);
  void onProgress(int percent, const QString& what);
  /// SessionController::levelDownload: the status bar's progress bar shows "<name> N%" (percent < 0: hidden).
  void onLevelDownload(int percent, const QString& name);

  Ui::MainWindow* ui;
  QLabel* m_meshSizeLabel = nullptr;
  QLabel* m_lockLabel = nullptr;
  QComboBox* m_levelCombo = nullptr;
  QLabel* m_timingLabel = nullptr;
  QProgressBar* m_progressBar = nullptr;
  bool m_levelDownloading = false;  ///< m_progressBar shows a level streaming behind the shown one
  QToolButton* m_cancelButton = nullptr;
  SessionController* m_session = nullptr;
  SessionController* m_pendingJoin = nullptr;  ///< a join connecting beside m_session (joinSession())
  SessionDocks* m_docks = nullptr;
  NetworkConditionsDock* m_networkDock = nullptr;
  bool m_redrawPending = false;
  // SHAPECAST_STALL_MS set: say each level install's GUI-thread time and its first paint's stages on stderr.
  bool m_reportLevelInstalls = qEnvironmentVariableIsSet("SHAPECAST_STALL_MS");
  bool m_installPaintPending = false;
  double m_viewReconstructMs = 0.0;
  double m_redrawMs = 0.0;
  FrameTimes m_labelFrame;  ///< the viewport frame the timing label describes
  QString m_lastDirectory;
  QString m_openedPath;  ///< the mesh file last shown by openMesh()/loadMeshInBackground()
  FileChooser m_fileChooser;
  QPointer<MeshLoading> m_meshLoading;
  QMenu* m_recentMenu = nullptr;
  bool m_errorDialogsEnabled = true;
  EditActions* m_editActions = nullptr;
  ViewActions* m_viewActions = nullptr;
  SessionPresence* m_presence = nullptr;
  SessionAsker m_sessionAsker;
  bool m_closeConfirmed = false;  ///< the session was ended for the close: the next closeEvent closes
  QMenu* m_peerMenu = nullptr;
  InteractiveProxyBuilder* m_proxyBuilder = nullptr;  ///< the viewport's proxy while a dense mesh moves
  Eigen::MatrixXd m_openedV;  ///< the mesh last opened with openMesh() (exported when not in a session)
  Eigen::MatrixXi m_openedF;
};

}  // namespace sc::app
