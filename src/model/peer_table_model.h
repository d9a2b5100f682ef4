#pragma once
// PeerTableModel: the people in a session as a Qt table model, for the desktop's peers dock.
// Plain data in through setPeers() (an app-side controller translates session events into PeerRow values);
// this module knows nothing of src/session.

#include <QAbstractTableModel>
#include <QString>
#include <QVariant>

#include <cstdint>
#include <vector>

namespace sc::model {

/// One peer of a session as the views show it. Figures are the latest ones the observer knows of.
struct PeerRow {
  /// Who holds or waits for the edit lock.
  enum class Lock {
    None,    ///< neither holds nor waits.
    Holder,  ///< holds the lock (may drag).
    Queued,  ///< waits; queuePosition says where.
  };

  std::uint32_t peerId = 0;       ///< the session's id for this peer; unique within one setPeers() call.
  QString name;                   ///< display name.
  std::uint32_t vertexCount = 0;  ///< vertices of the resolution level it displays.
  bool isHost = false;            ///< this peer hosts the session.
  bool isSelf = false;            ///< this peer is the local instance ("(you)").
  Lock lock = Lock::None;
  int queuePosition = 0;      ///< 1-based place in the lock queue when lock == Queued; ignored otherwise.
  double lossPct = 0.0;       ///< datagrams lost, in percent [0, 100].
  double latencyP99Ms = 0.0;  ///< 99th-percentile one-way latency, in milliseconds.
  double kbpsIn = 0.0;        ///< received bandwidth, in kbit/s.
  double hdMaxPct = 0.0;      ///< largest normalised Hausdorff distortion, in percent of the bbox diagonal.
  bool hasStats = false;      ///< false: the four figures above are unknown and shown as "–".
  /// Not a peer but one row for a whole audience (issue 18: the viewers through NATS, however many): Role shows
  /// "viewers", Resolution "–", and the figure columns' tooltip is figuresToolTip (the distributions).
  bool isAudience = false;
  QString figuresToolTip;

  friend bool operator==(const PeerRow&, const PeerRow&) = default;
};

/// A table of PeerRow values, one row per peer, eight columns (see Column).
///
/// setPeers() updates minimally: rows are matched by peerId; departed peers are removed (beginRemoveRows), peers
/// whose fields changed get one dataChanged() over the changed columns of their row, and newcomers are appended
/// (beginInsertRows) in the order given. Rows that stay keep their relative order, so row order is arrival order;
/// views sort through a QSortFilterProxyModel on SortRole. Never resets, so selections and scroll positions survive
/// the once-a-second refresh.
///
/// Roles: Qt::DisplayRole (text, "–" for unknown figures), Qt::ToolTipRole (also on the header: columnToolTip()),
/// Qt::TextAlignmentRole (int: numeric columns right-aligned, others left, all vertically centred), SortRole (the raw
/// value: QString for Name, a number otherwise, -1 for unknown figures so they sort first ascending) and PeerIdRole
/// (quint32, any column). Numbers are formatted in English (group separator ",", decimal point "."), independent of the
/// system locale. Read-only; not thread-safe (GUI thread).
class PeerTableModel : public QAbstractTableModel {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(PeerTableModel)

 public:
  /// Column indices. A plain enum: the values are column numbers for the Qt API.
  enum Column : int {
    Name,        ///< display name.
    Resolution,  ///< header "Shows": "full" at the full level (see setFullVertexCount()), else the vertex count.
    Role,        ///< "host" / "client", with " (you)" for the local peer.
    Lock,        ///< "holds lock" / "waits #k" / empty.
    LossPct,     ///< loss in percent, one decimal.
    LatencyMs,   ///< p99 latency (the peer's last 10 s) in ms, one decimal; header "Delay ms".
    KbpsIn,      ///< received kbit/s, one decimal.
    HdMaxPct,    ///< Hausdorff maximum in percent of the diagonal, three decimals; header "Error %".
    ColumnCount
  };

  enum ItemRole : int {
    SortRole = Qt::UserRole + 1,  ///< raw value for sorting (see the class comment).
    PeerIdRole,                   ///< the row's peerId as quint32.
  };

  explicit PeerTableModel(QObject* parent = nullptr);
  ~PeerTableModel() override;

  /// Replaces the table's content by peers, minimally (see the class comment). Later entries whose peerId
  /// repeats an earlier one are ignored. Cost: O(#rows + #peers) with hashing.
  void setPeers(std::vector<PeerRow> peers);

  /// The host's full vertex count: a peer whose vertexCount equals it shows "full (N)" as resolution. 0 (the
  /// default) means unknown: every peer shows "N vertices". Emits dataChanged() on the Resolution column.
  void setFullVertexCount(std::uint32_t count);
  [[nodiscard]] std::uint32_t fullVertexCount() const { return m_fullVertexCount; }

  /// The peer shown in row. @pre 0 <= row < rowCount().
  [[nodiscard]] const PeerRow& peerAt(int row) const;

  /// The row of peerId, or -1 if no such peer is listed.
  [[nodiscard]] int rowOfPeer(std::uint32_t peerId) const;

  /// The header text of column (English, plain words), e.g. "Loss %". Empty for an out-of-range column.
  [[nodiscard]] static QString columnTitle(int column);
  /// The header's tooltip: what the column's figure is precisely (window, percentile, term), e.g. HdMaxPct's names
  /// the Hausdorff distortion. Empty for columns that need none (headerData() then gives no tooltip).
  [[nodiscard]] static QString columnToolTip(int column);

  int rowCount(const QModelIndex& parent = QModelIndex()) const override;
  int columnCount(const QModelIndex& parent = QModelIndex()) const override;
  QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

 private:
  [[nodiscard]] QString displayText(const PeerRow& peer, int column) const;
  [[nodiscard]] QVariant sortValue(const PeerRow& peer, int column) const;
  [[nodiscard]] QString toolTip(const PeerRow& peer, int column) const;

  std::vector<PeerRow> m_rows;
  std::uint32_t m_fullVertexCount = 0;
};

}  // namespace sc::model
