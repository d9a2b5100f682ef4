#pragma once
// Help → Keyboard Shortcuts: every action of the menu bar that has a shortcut (read from the actions themselves,
// so the list cannot drift from what the keys do), with its menu, plus the mouse gestures of the 3D view.

#include <QDialog>
#include <QString>

#include <vector>

class QMenuBar;

namespace sc::app {

/// One row of the list: the menu path ("View ▸ Standard Views"), the action's text without its mnemonic and
/// ellipsis, and its shortcuts in the platform's native text (several: joined by ", ").
struct ShortcutRow {
  QString menu;
  QString action;
  QString shortcut;
};

/// The rows for `bar`'s menus, depth first in menu order; actions without a shortcut are left out. Pure (reads the
/// actions only). Cost: O(#actions).
[[nodiscard]] std::vector<ShortcutRow> shortcutRows(const QMenuBar& bar);

/// A dialog with the rows in a table (objectName "shortcutsTable": Action, Shortcut, Menu) and the mouse gestures
/// below it.
class ShortcutsDialog final : public QDialog {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(ShortcutsDialog)

 public:
  ShortcutsDialog(const QMenuBar& bar, QWidget* parent);
  ~ShortcutsDialog() override;
};

}  // namespace sc::app
