#include "app/gui/peers_dock.h"

#include "app/gui/peer_colors.h"
#include "model/peer_table_model.h"

#include <QHeaderView>
#include <QItemSelectionModel>
#include <QMenu>
#include <QSettings>
#include <QSortFilterProxyModel>
#include <QTableView>

#include <algorithm>

namespace sc::app {

using sc::model::PeerTableModel;

namespace {

constexpr int kCellMargin = 8;  ///< px each side of a figure: the style's cell padding and some air
const QString kHiddenColumnsKey = QStringLiteral("peers/hiddenColumns");

/// The columns a side dock of the default window cannot hold beside Name, Role, Lock and Loss %.
QStringList defaultHiddenColumns() {
  return {PeerTableModel::columnTitle(PeerTableModel::Resolution),
          PeerTableModel::columnTitle(PeerTableModel::LatencyMs), PeerTableModel::columnTitle(PeerTableModel::KbpsIn),
          PeerTableModel::columnTitle(PeerTableModel::HdMaxPct)};
}

/// The sorting proxy, plus each peer's colour (peerColor()) as the Name column's decoration: a swatch per row.
class ColouredPeerProxy final : public QSortFilterProxyModel {
 public:
  using QSortFilterProxyModel::QSortFilterProxyModel;
  [[nodiscard]] QVariant data(const QModelIndex& index, int role) const override {
    if (role == Qt::DecorationRole && index.column() == PeerTableModel::Name) {
      return peerColor(index.data(PeerTableModel::PeerIdRole).toUInt());
    }
    return QSortFilterProxyModel::data(index, role);
  }
};

}  // namespace

PeersDock::PeersDock(PeerTableModel* model, QWidget* parent) : QDockWidget(tr("Peers"), parent) {
  setObjectName(QStringLiteral("peersDock"));

  m_proxy = new ColouredPeerProxy(this);
  m_proxy->setSortRole(PeerTableModel::SortRole);
  m_proxy->setSortCaseSensitivity(Qt::CaseInsensitive);
  m_proxy->setDynamicSortFilter(true);

  m_view = new QTableView(this);
  m_view->setObjectName(QStringLiteral("peersTable"));
  m_view->setModel(m_proxy);
  m_view->setSelectionBehavior(QAbstractItemView::SelectRows);
  m_view->setSelectionMode(QAbstractItemView::SingleSelection);
  m_view->setEditTriggers(QAbstractItemView::NoEditTriggers);
  m_view->setAlternatingRowColors(true);
  m_view->setWordWrap(false);
  m_view->verticalHeader()->hide();
  // Name takes what the other columns leave (its tooltip has the whole name): a longer Lock or Role text narrows
  // the names instead of pushing the table into sideways scrolling.
  m_view->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  m_view->horizontalHeader()->setStretchLastSection(false);
  m_view->setSortingEnabled(true);
  m_view->sortByColumn(PeerTableModel::Role, Qt::AscendingOrder);
  m_view->horizontalHeader()->setContextMenuPolicy(Qt::CustomContextMenu);
  m_view->horizontalHeader()->setToolTip(tr("Click to sort; right-click to choose the columns"));
  connect(m_view->horizontalHeader(), &QWidget::customContextMenuRequested, this, [this](const QPoint& at) {
    QMenu* menu = makeColumnMenu(this);
    menu->setAttribute(Qt::WA_DeleteOnClose);
    menu->popup(m_view->horizontalHeader()->mapToGlobal(at));
  });
  setWidget(m_view);

  connect(m_view->selectionModel(), &QItemSelectionModel::currentRowChanged, this,
          [this](const QModelIndex& current, const QModelIndex&) { onCurrentRowChanged(current); });

  setModel(model);
}

PeersDock::~PeersDock() = default;

void PeersDock::setModel(PeerTableModel* model) {
  if (model == m_model) {
    return;
  }
  m_view->clearSelection();
  m_model = model;
  m_proxy->setSourceModel(model);  // QSortFilterProxyModel drops a destroyed source itself.
  fixFigureWidths();
  if (m_view->horizontalHeader()->count() > PeerTableModel::Name)
    m_view->horizontalHeader()->setSectionResizeMode(PeerTableModel::Name, QHeaderView::Stretch);
  restoreColumns();
}

bool PeersDock::columnShown(int column) const { return !m_view->isColumnHidden(column); }

void PeersDock::setColumnShown(int column, bool shown) {
  if (column <= PeerTableModel::Name || column >= PeerTableModel::ColumnCount) return;
  m_view->setColumnHidden(column, !shown);
  QStringList hidden;
  for (int c = 0; c < PeerTableModel::ColumnCount; ++c)
    if (m_view->isColumnHidden(c)) hidden << PeerTableModel::columnTitle(c);
  QSettings().setValue(kHiddenColumnsKey, hidden);
}

void PeersDock::restoreColumns() {
  const QStringList hidden = QSettings().value(kHiddenColumnsKey, defaultHiddenColumns()).toStringList();
  for (int column = PeerTableModel::Name + 1; column < PeerTableModel::ColumnCount; ++column)
    m_view->setColumnHidden(column, hidden.contains(PeerTableModel::columnTitle(column)));
}

QMenu* PeersDock::makeColumnMenu(QWidget* parent) {
  auto* menu = new QMenu(tr("Columns"), parent);
  for (int column = PeerTableModel::Name; column < PeerTableModel::ColumnCount; ++column) {
    QAction* action = menu->addAction(PeerTableModel::columnTitle(column));
    action->setCheckable(true);
    action->setChecked(columnShown(column));
    action->setEnabled(column != PeerTableModel::Name);
    action->setToolTip(PeerTableModel::columnToolTip(column));
    connect(action, &QAction::toggled, this, [this, column](bool shown) { setColumnShown(column, shown); });
  }
  return menu;
}

void PeersDock::fixFigureWidths() {
  // Figures get fixed widths that hold the values they show: columns that followed each second's digits changed
  // the table's size hint, re-laid out the window and repainted it once more a second (issue 16, idle CPU).
  const QFontMetrics metrics = m_view->fontMetrics();
  const QFontMetrics headerMetrics = m_view->horizontalHeader()->fontMetrics();
  // The widest value each figure shows in practice (loss ≤ 100 %; latency and kbit/s with a group separator).
  const std::pair<int, const char*> widest[] = {{PeerTableModel::LossPct, "100.0"},
                                                {PeerTableModel::LatencyMs, "9,999.9"},
                                                {PeerTableModel::KbpsIn, "99,999.9"},
                                                {PeerTableModel::HdMaxPct, "99.999"}};
  for (const auto& [column, sample] : widest) {
    const int text = std::max(metrics.horizontalAdvance(QString::fromLatin1(sample)),
                              headerMetrics.horizontalAdvance(PeerTableModel::columnTitle(column)));
    if (column >= m_view->horizontalHeader()->count()) continue;  // no model (yet)
    m_view->horizontalHeader()->setSectionResizeMode(column, QHeaderView::Fixed);
    m_view->horizontalHeader()->resizeSection(column, text + 2 * kCellMargin);
  }
}

PeerTableModel* PeersDock::model() const { return m_model; }

std::optional<quint32> PeersDock::selectedPeerId() const {
  const QModelIndexList rows = m_view->selectionModel()->selectedRows();
  if (rows.isEmpty()) {
    return std::nullopt;
  }
  return rows.first().data(PeerTableModel::PeerIdRole).toUInt();
}

bool PeersDock::selectPeer(quint32 peerId) {
  if (m_model == nullptr) {
    return false;
  }
  const int sourceRow = m_model->rowOfPeer(peerId);
  if (sourceRow < 0) {
    return false;
  }
  const QModelIndex index = m_proxy->mapFromSource(m_model->index(sourceRow, 0));
  m_view->selectionModel()->setCurrentIndex(index, QItemSelectionModel::ClearAndSelect | QItemSelectionModel::Rows);
  m_view->scrollTo(index);
  return true;
}

void PeersDock::onCurrentRowChanged(const QModelIndex& current) {
  if (!current.isValid()) {
    emit currentPeerCleared();
    return;
  }
  emit currentPeerChanged(current.data(PeerTableModel::PeerIdRole).toUInt());
}

}  // namespace sc::app
