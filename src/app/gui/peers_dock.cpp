#include "app/gui/peers_dock.h"

#include "app/gui/peer_colors.h"
#include "model/peer_table_model.h"

#include <QHeaderView>
#include <QItemSelectionModel>
#include <QSortFilterProxyModel>
#include <QTableView>

#include <algorithm>

namespace sc::app {

using sc::model::PeerTableModel;

namespace {

constexpr int kCellMargin = 8;  ///< px each side of a figure: the style's cell padding and some air

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
  m_view->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  m_view->horizontalHeader()->setStretchLastSection(true);
  m_view->setSortingEnabled(true);
  m_view->sortByColumn(PeerTableModel::Role, Qt::AscendingOrder);
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
