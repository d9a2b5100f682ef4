#include "app/gui/view_actions.h"

#include "app/gui/mesh_viewport.h"
#include "app/gui/shortcuts_dialog.h"
#include "app/gui/window_layout.h"

#include <QAction>
#include <QActionGroup>
#include <QCoreApplication>
#include <QDockWidget>
#include <QFileInfo>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QSpinBox>
#include <QToolBar>

#include <algorithm>
#include <cmath>
#include <utility>

namespace sc::app {

namespace {
constexpr int kMinBrush = 2;    // pixels
constexpr int kMaxBrush = 300;  // pixels
}  // namespace

ViewActions::ViewActions(const Parts& parts)
    : QObject(parts.window), m_window(parts.window), m_viewport(parts.viewport) {
  // The View menu in order; the actions it had that are not rebuilt here (other features') stay after them.
  QMenu& menu = *parts.viewMenu;
  QList<QAction*> others = menu.actions();
  for (QAction* action : others) menu.removeAction(action);
  others.removeAll(parts.resetView);
  parts.resetView->setToolTip(tr("Frame the whole mesh from the default view"));
  addStandardViews(menu);
  menu.addSeparator();
  menu.addAction(parts.resetView);
  QAction* fit = makeAction(tr("&Fit"), QStringLiteral("actionFitView"), QKeySequence(Qt::Key_F));
  fit->setToolTip(tr("Frame the whole mesh, keeping the direction of view"));
  connect(fit, &QAction::triggered, m_viewport, &MeshViewport::fitToView);
  menu.addAction(fit);
  menu.addSeparator();
  addCameraOptions(menu);
  menu.addSeparator();
  const QMenu* panels = addPanelToggles(menu);
  bool separated = false;
  for (QAction* action : std::as_const(others)) {
    if (action->isSeparator() || panels->actions().contains(action)) continue;
    if (!std::exchange(separated, true)) menu.addSeparator();
    menu.addAction(action);
  }
  addToolsMenu(parts);
  addHelpMenu();
}

ViewActions::~ViewActions() = default;

QAction* ViewActions::makeAction(const QString& text, const QString& objectName, const QKeySequence& shortcut) {
  auto* action = new QAction(text, m_window);
  action->setObjectName(objectName);
  action->setShortcut(shortcut);
  m_window->addAction(action);  // the shortcut works whichever widget has the focus
  return action;
}

void ViewActions::addStandardViews(QMenu& menu) {
  // Blender's numeric-keypad layout on the number row: 1 front, 3 right, 7 top; with Ctrl the opposite side.
  struct Entry {
    QString text;
    const char* name;
    QKeySequence key;
    StandardView view;
  };
  const Entry entries[] = {
      {tr("Fr&ont"), "actionViewFront", QKeySequence(Qt::Key_1), StandardView::Front},
      {tr("&Back"), "actionViewBack", QKeySequence(Qt::CTRL | Qt::Key_1), StandardView::Back},
      {tr("&Right"), "actionViewRight", QKeySequence(Qt::Key_3), StandardView::Right},
      {tr("&Left"), "actionViewLeft", QKeySequence(Qt::CTRL | Qt::Key_3), StandardView::Left},
      {tr("&Top"), "actionViewTop", QKeySequence(Qt::Key_7), StandardView::Top},
      {tr("Botto&m"), "actionViewBottom", QKeySequence(Qt::CTRL | Qt::Key_7), StandardView::Bottom},
  };
  QMenu* views = menu.addMenu(tr("&Standard Views"));
  views->setObjectName(QStringLiteral("menuStandardViews"));
  for (const Entry& entry : entries) {
    QAction* action = makeAction(entry.text, QString::fromLatin1(entry.name), entry.key);
    connect(action, &QAction::triggered, m_viewport, [this, view = entry.view] { m_viewport->showView(view); });
    views->addAction(action);
  }
}

void ViewActions::addCameraOptions(QMenu& menu) {
  QMenu* up = menu.addMenu(tr("&Up Axis"));
  up->setObjectName(QStringLiteral("menuUpAxis"));
  m_upAxisGroup = new QActionGroup(this);
  m_yUp = makeAction(tr("&Y Up"), QStringLiteral("actionYUp"), QKeySequence(Qt::Key_Y));
  m_zUp = makeAction(tr("&Z Up"), QStringLiteral("actionZUp"), QKeySequence(Qt::Key_Z));
  for (QAction* action : {m_yUp, m_zUp}) {
    action->setCheckable(true);
    m_upAxisGroup->addAction(action);
    up->addAction(action);
  }
  m_yUp->setChecked(m_viewport->upAxis() == UpAxis::Y);
  m_zUp->setChecked(m_viewport->upAxis() == UpAxis::Z);
  connect(m_yUp, &QAction::triggered, this, [this] { setUpAxis(UpAxis::Y); });
  connect(m_zUp, &QAction::triggered, this, [this] { setUpAxis(UpAxis::Z); });

  QAction* trackball =
      makeAction(tr("&Trackball Rotation"), QStringLiteral("actionTrackball"), QKeySequence(Qt::Key_T));
  trackball->setCheckable(true);
  trackball->setToolTip(tr("Orbit freely (the view may roll) instead of turning about the up axis"));
  connect(trackball, &QAction::toggled, m_viewport,
          [this](bool on) { m_viewport->setRotationMode(on ? RotationMode::Trackball : RotationMode::Turntable); });
  menu.addAction(trackball);

  QAction* wireframe = makeAction(tr("&Wireframe"), QStringLiteral("actionWireframe"), QKeySequence(Qt::Key_W));
  wireframe->setCheckable(true);
  wireframe->setChecked(m_viewport->wireframe());
  connect(wireframe, &QAction::toggled, m_viewport, &MeshViewport::setWireframe);
  menu.addAction(wireframe);
}

QMenu* ViewActions::addPanelToggles(QMenu& menu) {
  QMenu* panels = menu.addMenu(tr("&Panels"));
  panels->setObjectName(QStringLiteral("menuPanels"));
  for (QDockWidget* dock : m_window->findChildren<QDockWidget*>(Qt::FindDirectChildrenOnly)) {
    panels->addAction(dock->toggleViewAction());
  }
  for (QToolBar* bar : m_window->findChildren<QToolBar*>(Qt::FindDirectChildrenOnly)) {
    QAction* toggle = bar->toggleViewAction();
    toggle->setText(tr("%1 Toolbar").arg(bar->windowTitle()));
    panels->addAction(toggle);
  }
  return panels;
}

void ViewActions::addToolsMenu(const Parts& parts) {
  auto* menu = new QMenu(tr("&Tools"), m_window);
  menu->setObjectName(QStringLiteral("menuTools"));
  const std::array<Qt::Key, 4> keys{Qt::Key_O, Qt::Key_H, Qt::Key_A, Qt::Key_D};
  for (std::size_t i = 0; i < keys.size(); ++i) {
    parts.tools[i]->setShortcut(QKeySequence(keys[i]));
    menu->addAction(parts.tools[i]);
  }
  menu->addSeparator();
  QAction* larger =
      makeAction(tr("&Larger Brush"), QStringLiteral("actionBrushLarger"), QKeySequence(Qt::Key_BracketRight));
  QAction* smaller =
      makeAction(tr("&Smaller Brush"), QStringLiteral("actionBrushSmaller"), QKeySequence(Qt::Key_BracketLeft));
  connect(larger, &QAction::triggered, this, [this] { setBrushRadius(m_viewport->brushRadius() * kBrushStep); });
  connect(smaller, &QAction::triggered, this, [this] { setBrushRadius(m_viewport->brushRadius() / kBrushStep); });
  menu->addAction(larger);
  menu->addAction(smaller);
  QMenuBar* bar = m_window->menuBar();
  const QList<QAction*> menus = bar->actions();
  const qsizetype viewAt = menus.indexOf(parts.viewMenu->menuAction());
  bar->insertMenu(viewAt >= 0 && viewAt + 1 < menus.size() ? menus[viewAt + 1] : nullptr, menu);

  // The brush size beside the tools.
  m_brushBox = new QSpinBox(m_window);
  m_brushBox->setObjectName(QStringLiteral("brushSizeSpinBox"));
  m_brushBox->setRange(kMinBrush, kMaxBrush);
  m_brushBox->setPrefix(tr("Brush "));
  m_brushBox->setSuffix(tr(" px"));
  m_brushBox->setToolTip(tr("Brush radius of the Handle and Anchors tools ([ and ] change it)"));
  m_brushBox->setValue(static_cast<int>(std::lround(m_viewport->brushRadius())));
  connect(m_brushBox, &QSpinBox::valueChanged, this, [this](int pixels) { m_viewport->setBrushRadius(pixels); });
  const QList<QAction*> barActions = parts.toolBar->actions();
  const qsizetype dragAt = barActions.indexOf(parts.tools[3]);
  parts.toolBar->insertWidget(dragAt >= 0 && dragAt + 1 < barActions.size() ? barActions[dragAt + 1] : nullptr,
                              m_brushBox);
}

void ViewActions::setBrushRadius(double pixels) {
  const int rounded = std::clamp(static_cast<int>(std::lround(pixels)), kMinBrush, kMaxBrush);
  // A step always changes the size by at least a pixel.
  const int current = m_brushBox->value();
  m_brushBox->setValue(
      rounded == current ? std::clamp(pixels > current ? current + 1 : current - 1, kMinBrush, kMaxBrush) : rounded);
}

void ViewActions::addHelpMenu() {
  QMenu* help = m_window->menuBar()->addMenu(tr("&Help"));
  help->setObjectName(QStringLiteral("menuHelp"));
  QAction* keys = makeAction(tr("&Keyboard Shortcuts…"), QStringLiteral("actionShortcuts"), QKeySequence(Qt::Key_F1));
  connect(keys, &QAction::triggered, this, &ViewActions::showShortcuts);
  help->addAction(keys);
  QAction* about = makeAction(tr("&About ShapeCast"), QStringLiteral("actionAbout"), QKeySequence());
  connect(about, &QAction::triggered, this, &ViewActions::showAbout);
  help->addAction(about);
}

QWidget* ViewActions::showShortcuts() {
  delete m_shortcuts;  // built again: the menus may have changed since
  m_shortcuts = new ShortcutsDialog(*m_window->menuBar(), m_window);
  m_shortcuts->show();
  m_shortcuts->raise();
  return m_shortcuts;
}

QWidget* ViewActions::showAbout() {
  const QString version = QCoreApplication::applicationVersion();
  auto* box = new QMessageBox(QMessageBox::NoIcon, tr("About ShapeCast"),
                              tr("<b>ShapeCast</b> %1<p>Collaborative spectral mesh deformation over a real network: "
                                 "one person hosts a mesh, others join, and everybody deforms the same shape.</p>"
                                 "<p>Built with Qt %2.</p>")
                                  .arg(version.toHtmlEscaped(), QString::fromLatin1(qVersion())),
                              QMessageBox::Ok, m_window);
  box->setObjectName(QStringLiteral("aboutBox"));
  box->setAttribute(Qt::WA_DeleteOnClose);
  box->open();
  return box;
}

void ViewActions::rememberUpAxes(const QString& settingsFile) { m_upAxes.emplace(settingsFile); }

void ViewActions::rememberLayout(const QString& settingsFile) {
  delete m_layout;
  m_layout = new WindowLayout(*m_window, settingsFile);
}

void ViewActions::showingFile(const QString& path) {
  m_file = path;
  if (!m_upAxes) return;
  showUpAxis(m_upAxes->recall(path).value_or(UpAxis::Y));
}

void ViewActions::setUpAxis(UpAxis axis) {
  showUpAxis(axis);
  if (m_upAxes && !m_file.isEmpty()) m_upAxes->remember(m_file, axis);
}

void ViewActions::showUpAxis(UpAxis axis) {
  m_viewport->setUpAxis(axis);
  (axis == UpAxis::Z ? m_zUp : m_yUp)->setChecked(true);
}

}  // namespace sc::app
