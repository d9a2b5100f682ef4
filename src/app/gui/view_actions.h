#pragma once
// ViewActions: the viewer habits of the main window's menus (issue 16). View → Standard Views (Front, Back, Left,
// Right, Top, Bottom), Reset View, Fit, Up Axis (Y or Z, remembered per file: UpAxisMemory), Trackball Rotation,
// Wireframe and a toggle for every dock and toolbar; Tools → the four tools and the brush size (also a spin box in
// the toolbar); Help → Keyboard Shortcuts (a dialog built from the menus' actions: shortcuts_dialog.h) and About.
// Every tool, view and the wireframe has a keyboard shortcut shown in its menu (the list is in README "Using it").

#include "app/gui/orbit_camera.h"
#include "app/gui/up_axis_memory.h"

#include <QObject>
#include <QString>

#include <array>
#include <optional>

class QAction;
class QActionGroup;
class QMainWindow;
class QMenu;
class QSpinBox;
class QToolBar;

namespace sc::app {

class MeshViewport;
class WindowLayout;

class ViewActions final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(ViewActions)

 public:
  /// What the window already has (made by its form): the View menu with Reset View, the four tool actions (in
  /// ViewportTool order: Orbit, Handle, Anchors, Drag) and the toolbar they sit in.
  struct Parts {
    QMainWindow* window = nullptr;
    MeshViewport* viewport = nullptr;
    QMenu* viewMenu = nullptr;
    QAction* resetView = nullptr;
    std::array<QAction*, 4> tools{};
    QToolBar* toolBar = nullptr;
  };
  static constexpr double kBrushStep = 1.25;  ///< Larger / Smaller Brush multiply / divide the radius by this.

  /// Builds the menus; call once every dock and toolbar of the window exists (the View menu lists them).
  explicit ViewActions(const Parts& parts);
  ~ViewActions() override;

  /// Remembers the up axis per file from now on (UpAxisMemory on `settingsFile`; empty: the application's).
  void rememberUpAxes(const QString& settingsFile = {});
  /// Restores the window layout saved last and saves it on close from now on (WindowLayout on `settingsFile`).
  void rememberLayout(const QString& settingsFile = {});
  [[nodiscard]] WindowLayout* layout() const { return m_layout; }

  /// The file now shown (a mesh opened, a mesh or session file hosted): its remembered up axis applies (with
  /// rememberUpAxes() on), and a later change of the axis is remembered for it.
  void showingFile(const QString& path);
  /// Chooses the up axis (the View menu's; remembered for the file shown, see showingFile()).
  void setUpAxis(UpAxis axis);

  /// The dialog of Help → Keyboard Shortcuts (made on first use, owned by the window; shown non-modally).
  QWidget* showShortcuts();
  /// The About box of Help → About ShapeCast (shown non-modally).
  QWidget* showAbout();

  [[nodiscard]] QSpinBox* brushSizeBox() const { return m_brushBox; }

 private:
  void addStandardViews(QMenu& menu);
  void addCameraOptions(QMenu& menu);
  QMenu* addPanelToggles(QMenu& menu);
  void addToolsMenu(const Parts& parts);
  void addHelpMenu();
  QAction* makeAction(const QString& text, const QString& objectName, const QKeySequence& shortcut);
  void setBrushRadius(double pixels);
  void showUpAxis(UpAxis axis);

  QMainWindow* m_window = nullptr;
  MeshViewport* m_viewport = nullptr;
  QActionGroup* m_upAxisGroup = nullptr;
  QAction* m_yUp = nullptr;
  QAction* m_zUp = nullptr;
  QSpinBox* m_brushBox = nullptr;
  QWidget* m_shortcuts = nullptr;
  std::optional<UpAxisMemory> m_upAxes;
  WindowLayout* m_layout = nullptr;
  QString m_file;
};

}  // namespace sc::app
