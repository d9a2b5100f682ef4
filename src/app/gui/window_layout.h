#pragma once
// WindowLayout: a main window's geometry and its docks' and toolbars' layout, restored when it is made and saved
// whenever the window closes (QSettings group "window": QWidget::saveGeometry, QMainWindow::saveState; the docks
// and toolbars need an objectName, which every one of ShapeCast's has).

#include <QObject>
#include <QString>

class QMainWindow;

namespace sc::app {

class WindowLayout final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(WindowLayout)

 public:
  /// Restores the layout saved last (if any) into `window`, whose docks and toolbars must exist by now, and saves
  /// it on each close. `settingsFile` empty: the application's QSettings; otherwise that INI file (tests).
  WindowLayout(QMainWindow& window, QString settingsFile);

  /// Saves the window's layout now (also done on close).
  void save() const;
  /// Whether the constructor found and applied a saved layout.
  [[nodiscard]] bool restored() const { return m_restored; }

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  QMainWindow& m_window;
  QString m_file;
  bool m_restored = false;
};

}  // namespace sc::app
