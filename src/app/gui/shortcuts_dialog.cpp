#include "app/gui/shortcuts_dialog.h"

#include <QAction>
#include <QDialogButtonBox>
#include <QHeaderView>
#include <QLabel>
#include <QMenu>
#include <QMenuBar>
#include <QTableWidget>
#include <QVBoxLayout>

namespace sc::app {

namespace {

QString plainText(QString text) {
  text.replace(QStringLiteral("&&"), QStringLiteral("\\x01"));
  text.remove(QLatin1Char('&'));
  text.replace(QStringLiteral("\\x01"), QStringLiteral("&"));
  if (text.endsWith(QStringLiteral("…"))) text.chop(1);
  if (text.endsWith(QStringLiteral("..."))) text.chop(3);
  return text;
}

void collect(const QList<QAction*>& actions, const QString& path, std::vector<ShortcutRow>& rows) {
  for (const QAction* action : actions) {
    if (action->isSeparator()) continue;
    if (const QMenu* sub = action->menu()) {
      const QString subPath =
          path.isEmpty() ? plainText(sub->title()) : path + QStringLiteral(" ▸ ") + plainText(sub->title());
      collect(sub->actions(), subPath, rows);
      continue;
    }
    if (action->shortcut().isEmpty()) continue;
    QStringList keys;
    for (const QKeySequence& key : action->shortcuts()) keys << key.toString(QKeySequence::NativeText);
    rows.push_back({path, plainText(action->text()), keys.join(QStringLiteral(", "))});
  }
}

}  // namespace

std::vector<ShortcutRow> shortcutRows(const QMenuBar& bar) {
  std::vector<ShortcutRow> rows;
  collect(bar.actions(), QString(), rows);
  return rows;
}

ShortcutsDialog::ShortcutsDialog(const QMenuBar& bar, QWidget* parent) : QDialog(parent) {
  setObjectName(QStringLiteral("shortcutsDialog"));
  setWindowTitle(tr("Keyboard Shortcuts"));
  const std::vector<ShortcutRow> rows = shortcutRows(bar);
  auto* table = new QTableWidget(static_cast<int>(rows.size()), 3, this);
  table->setObjectName(QStringLiteral("shortcutsTable"));
  table->setHorizontalHeaderLabels({tr("Action"), tr("Shortcut"), tr("Menu")});
  table->verticalHeader()->hide();
  table->setEditTriggers(QAbstractItemView::NoEditTriggers);
  table->setSelectionMode(QAbstractItemView::NoSelection);
  for (int r = 0; r < static_cast<int>(rows.size()); ++r) {
    const ShortcutRow& row = rows[static_cast<std::size_t>(r)];
    table->setItem(r, 0, new QTableWidgetItem(row.action));
    table->setItem(r, 1, new QTableWidgetItem(row.shortcut));
    table->setItem(r, 2, new QTableWidgetItem(row.menu));
  }
  table->resizeColumnsToContents();
  table->horizontalHeader()->setStretchLastSection(true);
  auto* mouse = new QLabel(tr("<b>Mouse</b> in the 3D view: left drag orbits (in the Handle, Anchors and Drag tools "
                              "it paints or drags; Alt+left drag orbits there), right or middle drag pans, the "
                              "wheel zooms, Shift+left drag erases paint, Ctrl+left drag rotates the handle, a "
                              "double click on the mesh makes that point the centre of rotation (off the mesh: "
                              "Reset View)."),
                           this);
  mouse->setWordWrap(true);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close, this);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(table);
  layout->addWidget(mouse);
  layout->addWidget(buttons);
  resize(560, 560);
}

ShortcutsDialog::~ShortcutsDialog() = default;

}  // namespace sc::app
