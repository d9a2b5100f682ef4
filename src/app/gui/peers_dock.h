#pragma once
// PeersDock: the dock that lists a session's peers (sc::model::PeerTableModel) in a sortable table.

#include <QDockWidget>
#include <QPointer>

#include <optional>

class QMenu;
class QSortFilterProxyModel;
class QTableView;

namespace sc::model {
class PeerTableModel;
}

namespace sc::app {

/// A QDockWidget (objectName "peersDock", title "Peers") holding a QTableView (objectName "peersTable") on a
/// QSortFilterProxyModel over a PeerTableModel. Clicking a header sorts on PeerTableModel::SortRole (numbers as
/// numbers, unknown figures first ascending); the initial order is by Role (host first), then arrival order.
/// Rows are selected whole, one at a time; the selection follows its peer through model updates and re-sorting.
///
/// The dock does not own the model: it observes it and forgets it if it is destroyed. View only: no session or
/// protocol logic; the app's controller feeds the model and listens to currentPeerChanged(). Each row's Name shows
/// the peer's colour (peerColor()) as a swatch (Qt::DecorationRole, added by the proxy). Text columns are sized to
/// their contents, figure columns to fixed widths (issue 16: short cells, details in tooltips).
///
/// Columns: the side dock holds Name, Role, Lock and Loss % by default, so the table never scrolls sideways in the
/// default window; "Shows", "Delay ms", "kbit/s" and "Error %" are a right-click on the header away (the header's
/// context menu lists every column with a check box; Name cannot be hidden). The choice is kept in QSettings
/// ("peers/hiddenColumns", column titles) and applies to every PeersDock opened afterwards. The selected peer's
/// figures are all in the Statistics dock whatever the table shows.
class PeersDock : public QDockWidget {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(PeersDock)

 public:
  /// @param[in] model  the peers to show, or nullptr for an empty table (setModel() later).
  explicit PeersDock(sc::model::PeerTableModel* model = nullptr, QWidget* parent = nullptr);
  ~PeersDock() override;

  /// Shows model instead of the current one (nullptr: an empty table). Clears the selection.
  void setModel(sc::model::PeerTableModel* model);
  [[nodiscard]] sc::model::PeerTableModel* model() const;

  /// The table and the sorting proxy between it and the model (for tests and for the window's layout).
  [[nodiscard]] QTableView* view() const { return m_view; }
  [[nodiscard]] QSortFilterProxyModel* proxy() const { return m_proxy; }

  /// Whether a column (sc::model::PeerTableModel::Column) is shown; setColumnShown() shows or hides it and stores
  /// the choice (Name is always shown).
  [[nodiscard]] bool columnShown(int column) const;
  void setColumnShown(int column, bool shown);
  /// The header's context menu: one checkable action per column, titled as the column (caller owns it).
  [[nodiscard]] QMenu* makeColumnMenu(QWidget* parent);

  /// The peerId of the selected row, or nullopt if none is selected.
  [[nodiscard]] std::optional<quint32> selectedPeerId() const;
  /// Selects the row of peerId (and scrolls to it); returns false, leaving the selection, if it is not listed.
  bool selectPeer(quint32 peerId);

 signals:
  /// The selected peer changed to peerId (the host then shows that peer's statistics).
  void currentPeerChanged(quint32 peerId);
  /// The selection became empty.
  void currentPeerCleared();

 private:
  /// Gives the figure columns fixed widths that hold any value, so that changing figures never change the table's
  /// size hint (and re-lay out the window). Needs the model's columns.
  void fixFigureWidths();
  void onCurrentRowChanged(const QModelIndex& current);
  /// Hides the columns stored in QSettings (or the default ones) and shows the others.
  void restoreColumns();

  QTableView* m_view = nullptr;
  QSortFilterProxyModel* m_proxy = nullptr;
  QPointer<sc::model::PeerTableModel> m_model;
};

}  // namespace sc::app
