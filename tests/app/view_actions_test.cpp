// Tests for the viewer habits of issue 16 (src/app/gui/view_actions.cpp, shortcuts_dialog.cpp, window_layout.cpp,
// up_axis_memory.cpp, app_theme.cpp): every shortcut is unique and listed in the menus and in Help → Keyboard
// Shortcuts; the keys drive the view; View → Panels hides and shows the docks; the window layout and the up axis
// per file come back in a second window reading the same settings; the dark palette decision.

#include "app/gui/view_actions.h"
#include "app/gui/app_theme.h"
#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/shortcuts_dialog.h"
#include "app/gui/window_layout.h"
#include "app_test_support.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QDockWidget>
#include <QMenu>
#include <QMenuBar>
#include <QSettings>
#include <QSpinBox>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>

#include <map>
#include <set>

namespace sc::app {
namespace {

QAction* action(const QWidget& window, const char* name) {
  return window.findChild<QAction*>(QString::fromLatin1(name));
}

// Every action reachable from the menu bar (submenus included).
void menuActions(const QList<QAction*>& actions, std::set<const QAction*>& out) {
  for (const QAction* a : actions) {
    out.insert(a);
    if (const QMenu* menu = a->menu()) menuActions(menu->actions(), out);
  }
}

class ViewActionsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(m_dir.isValid());
    m_settings = m_dir.filePath(QStringLiteral("settings.ini"));
  }
  QString writeSphere(const char* name) {
    const QString path = m_dir.filePath(QString::fromLatin1(name));
    const auto sphere = sc::testing::icosphere(2);
    EXPECT_TRUE(sc::testing::writeOff(path, sphere.V, sphere.F));
    return path;
  }
  QTemporaryDir m_dir;
  QString m_settings;
};

TEST_F(ViewActionsTest, EveryToolViewAndWireframeHasAUniqueShortcutListedInTheMenusAndTheHelpDialog) {
  MainWindow window;
  const char* const required[] = {"actionToolOrbit",   "actionToolHandle",   "actionToolAnchors", "actionToolDrag",
                                  "actionViewFront",   "actionViewBack",     "actionViewLeft",    "actionViewRight",
                                  "actionViewTop",     "actionViewBottom",   "actionResetView",   "actionFitView",
                                  "actionWireframe",   "actionTrackball",    "actionYUp",         "actionZUp",
                                  "actionBrushLarger", "actionBrushSmaller", "actionShortcuts"};
  for (const char* name : required) {
    const QAction* a = action(window, name);
    ASSERT_NE(a, nullptr) << name;
    EXPECT_FALSE(a->shortcut().isEmpty()) << name << " has no shortcut";
  }
  ASSERT_NE(action(window, "actionAbout"), nullptr);

  std::set<const QAction*> inMenus;
  menuActions(window.menuBar()->actions(), inMenus);
  std::map<QKeySequence, QString> owners;
  int withShortcut = 0;
  for (const QAction* a : window.findChildren<QAction*>()) {
    for (const QKeySequence& key : a->shortcuts()) {
      ++withShortcut;
      const auto [it, inserted] = owners.emplace(key, a->objectName());
      EXPECT_TRUE(inserted) << key.toString().toStdString() << " is taken by both " << it->second.toStdString()
                            << " and " << a->objectName().toStdString();
      EXPECT_TRUE(inMenus.count(a) == 1) << a->objectName().toStdString() << " (" << key.toString().toStdString()
                                         << ") is in no menu";
    }
  }
  EXPECT_GE(withShortcut, static_cast<int>(std::size(required)));

  // Help → Keyboard Shortcuts lists each of them, with the shortcut's text.
  action(window, "actionShortcuts")->trigger();
  auto* dialog = window.findChild<QDialog*>(QStringLiteral("shortcutsDialog"));
  ASSERT_NE(dialog, nullptr);
  EXPECT_TRUE(dialog->isVisible());
  auto* table = dialog->findChild<QTableWidget*>(QStringLiteral("shortcutsTable"));
  ASSERT_NE(table, nullptr);
  std::set<QString> listed;
  for (int r = 0; r < table->rowCount(); ++r) {
    for (const QString& key : table->item(r, 1)->text().split(QStringLiteral(", "))) listed.insert(key);
  }
  EXPECT_EQ(listed.size(), owners.size());
  for (const auto& [key, name] : owners) {
    EXPECT_EQ(listed.count(key.toString(QKeySequence::NativeText)), 1u)
        << name.toStdString() << " (" << key.toString().toStdString() << ") is not listed";
  }
  const std::vector<ShortcutRow> rows = shortcutRows(*window.menuBar());
  const auto wireframe = std::find_if(rows.begin(), rows.end(),
                                      [](const ShortcutRow& row) { return row.action == QStringLiteral("Wireframe"); });
  ASSERT_NE(wireframe, rows.end());
  EXPECT_EQ(wireframe->menu, QStringLiteral("View"));
  EXPECT_EQ(wireframe->shortcut, QStringLiteral("W"));
  dialog->close();

  action(window, "actionAbout")->trigger();
  auto* about = window.findChild<QWidget*>(QStringLiteral("aboutBox"));
  ASSERT_NE(about, nullptr);
  about->close();
}

TEST_F(ViewActionsTest, KeysDriveTheToolsTheViewsTheWireframeAndTheBrush) {
  if (!sc::testing::openGlAvailable()) GTEST_SKIP() << "no OpenGL 3.3 context (run under xvfb-run)";
  MainWindow window;
  window.setErrorDialogsEnabled(false);
  ASSERT_TRUE(window.openMesh(writeSphere("sphere.off")));
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  // Shortcuts go to the active window (no window manager under Xvfb: activate it).
  window.activateWindow();
  (void)QTest::qWaitForWindowActive(&window, 1000);  // no window manager: may not become active by itself
  QApplication::setActiveWindow(&window);
  ASSERT_EQ(QApplication::activeWindow(), &window);
  MeshViewport* view = window.viewport();
  view->setFocus();
  QTest::keyClick(view, Qt::Key_W);
  EXPECT_TRUE(view->wireframe());
  EXPECT_TRUE(action(window, "actionWireframe")->isChecked());
  QTest::keyClick(view, Qt::Key_H);
  EXPECT_EQ(view->tool(), ViewportTool::HandleBrush);
  QTest::keyClick(view, Qt::Key_A);
  EXPECT_EQ(view->tool(), ViewportTool::AnchorBrush);
  QTest::keyClick(view, Qt::Key_D);
  EXPECT_EQ(view->tool(), ViewportTool::Drag);
  QTest::keyClick(view, Qt::Key_O);
  EXPECT_EQ(view->tool(), ViewportTool::Orbit);
  QTest::keyClick(view, Qt::Key_3);  // Right: the eye on +x
  const QVector3D right = (view->camera().eye() - view->camera().target()).normalized();
  EXPECT_NEAR(right.x(), 1.0f, 1e-4f);
  QTest::keyClick(view, Qt::Key_Z);  // z up: the view turns to Home about +z
  EXPECT_EQ(view->upAxis(), UpAxis::Z);
  EXPECT_TRUE(action(window, "actionZUp")->isChecked());
  EXPECT_GT(view->camera().up().z(), 0.9f);
  QTest::keyClick(view, Qt::Key_T);
  EXPECT_EQ(view->rotationMode(), RotationMode::Trackball);
  const double brush = view->brushRadius();
  QTest::keyClick(view, Qt::Key_BracketRight);
  EXPECT_NEAR(view->brushRadius(), std::round(brush * ViewActions::kBrushStep), 0.5);
  EXPECT_EQ(window.viewActions()->brushSizeBox()->value(), static_cast<int>(view->brushRadius()));
  window.viewActions()->brushSizeBox()->setValue(12);
  EXPECT_EQ(view->brushRadius(), 12.0);
}

TEST_F(ViewActionsTest, ViewPanelsHideAndShowTheDocks) {
  MainWindow window;
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  auto* panels = window.findChild<QMenu*>(QStringLiteral("menuPanels"));
  ASSERT_NE(panels, nullptr);
  const QList<QDockWidget*> docks = window.findChildren<QDockWidget*>(Qt::FindDirectChildrenOnly);
  ASSERT_GE(docks.size(), 3);  // peers, statistics, network conditions
  for (QDockWidget* dock : docks) {
    QAction* toggle = dock->toggleViewAction();
    EXPECT_TRUE(panels->actions().contains(toggle)) << dock->objectName().toStdString();
    const bool shown = dock->isVisible();
    toggle->trigger();
    EXPECT_EQ(dock->isVisible(), !shown) << dock->objectName().toStdString();
    toggle->trigger();
    EXPECT_EQ(dock->isVisible(), shown) << dock->objectName().toStdString();
  }
}

TEST_F(ViewActionsTest, WindowGeometryAndDockLayoutComeBackInASecondWindow) {
  {
    MainWindow first;
    first.viewActions()->rememberLayout(m_settings);
    EXPECT_FALSE(first.viewActions()->layout()->restored());
    first.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&first));
    first.resize(900, 640);
    auto* statistics = first.findChild<QDockWidget*>(QStringLiteral("statisticsDock"));
    ASSERT_NE(statistics, nullptr);
    statistics->toggleViewAction()->trigger();
    ASSERT_FALSE(statistics->isVisible());
    auto* peers = first.findChild<QDockWidget*>(QStringLiteral("peersDock"));
    first.addDockWidget(Qt::LeftDockWidgetArea, peers);
    QTest::qWait(50);
    first.close();  // saves
  }
  QSettings written(m_settings, QSettings::IniFormat);
  EXPECT_FALSE(written.value(QStringLiteral("window/state")).toByteArray().isEmpty());

  MainWindow second;
  second.viewActions()->rememberLayout(m_settings);
  EXPECT_TRUE(second.viewActions()->layout()->restored());
  second.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&second));
  EXPECT_EQ(second.size(), QSize(900, 640));
  EXPECT_FALSE(second.findChild<QDockWidget*>(QStringLiteral("statisticsDock"))->isVisible());
  EXPECT_EQ(second.dockWidgetArea(second.findChild<QDockWidget*>(QStringLiteral("peersDock"))), Qt::LeftDockWidgetArea);
}

TEST_F(ViewActionsTest, TheUpAxisIsRememberedPerFile) {
  const QString a = writeSphere("a.off");
  const QString b = writeSphere("b.off");
  {
    MainWindow window;
    window.setErrorDialogsEnabled(false);
    window.viewActions()->rememberUpAxes(m_settings);
    ASSERT_TRUE(window.openMesh(a));
    EXPECT_EQ(window.viewport()->upAxis(), UpAxis::Y) << "the default";
    action(window, "actionZUp")->trigger();
    EXPECT_EQ(window.viewport()->upAxis(), UpAxis::Z);
    ASSERT_TRUE(window.openMesh(b));
    EXPECT_EQ(window.viewport()->upAxis(), UpAxis::Y) << "another file: its own (the default)";
    EXPECT_TRUE(action(window, "actionYUp")->isChecked());
    ASSERT_TRUE(window.openMesh(a));
    EXPECT_EQ(window.viewport()->upAxis(), UpAxis::Z);
  }
  MainWindow again;
  again.setErrorDialogsEnabled(false);
  again.viewActions()->rememberUpAxes(m_settings);
  ASSERT_TRUE(again.openMesh(a));
  EXPECT_EQ(again.viewport()->upAxis(), UpAxis::Z) << "remembered between runs";
  EXPECT_TRUE(action(again, "actionZUp")->isChecked());
  EXPECT_GT(again.viewport()->camera().up().z(), 0.9f);
}

TEST(AppTheme, DarkWhenToldOrWhenTheSystemIsDark) {
  const QColor light(239, 239, 239);
  const QColor dark(40, 40, 40);
  EXPECT_EQ(chooseColorScheme({}, {}, std::nullopt, light), ColorScheme::Light);
  EXPECT_EQ(chooseColorScheme({}, {}, std::nullopt, dark), ColorScheme::Dark);
  EXPECT_EQ(chooseColorScheme(QStringLiteral("dark"), {}, std::nullopt, light), ColorScheme::Dark);
  EXPECT_EQ(chooseColorScheme(QStringLiteral("Light"), {}, std::nullopt, dark), ColorScheme::Light);
  EXPECT_EQ(chooseColorScheme({}, QStringLiteral("Adwaita:dark"), std::nullopt, light), ColorScheme::Dark);
  EXPECT_EQ(chooseColorScheme({}, QStringLiteral("Adwaita-dark"), std::nullopt, light), ColorScheme::Dark);
  EXPECT_EQ(chooseColorScheme({}, QStringLiteral("Adwaita"), std::nullopt, light), ColorScheme::Light);
  EXPECT_EQ(chooseColorScheme({}, QStringLiteral("Adwaita:dark"), false, light), ColorScheme::Light)
      << "the platform's own scheme wins over GTK_THEME";
  EXPECT_EQ(chooseColorScheme({}, {}, true, light), ColorScheme::Dark);
  const QPalette palette = darkPalette();
  EXPECT_LT(palette.color(QPalette::Window).lightness(), 80);
  EXPECT_LT(palette.color(QPalette::Base).lightness(), 80);
  EXPECT_GT(palette.color(QPalette::WindowText).lightness(), 180);
  EXPECT_GT(palette.color(QPalette::Text).lightness(), 180);
  EXPECT_LT(palette.color(QPalette::Disabled, QPalette::Text).lightness(),
            palette.color(QPalette::Active, QPalette::Text).lightness());
}

}  // namespace
}  // namespace sc::app
