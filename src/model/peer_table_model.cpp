#include "model/peer_table_model.h"

#include <QLocale>

#include <cassert>
#include <limits>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace sc::model {

namespace {

const QLocale& english() {
  static const QLocale locale(QLocale::English, QLocale::UnitedStates);
  return locale;
}

QString unknownFigure() { return QString(QChar(0x2013)); }  // "–"

bool isNumericColumn(int column) {
  return column == PeerTableModel::LossPct || column == PeerTableModel::LatencyMs || column == PeerTableModel::KbpsIn ||
         column == PeerTableModel::HdMaxPct;
}

/// The first and last column whose displayed content differs between a and b, or {-1, -1}.
std::pair<int, int> changedColumns(const PeerRow& a, const PeerRow& b, bool fullCountMatters) {
  bool changed[PeerTableModel::ColumnCount] = {};
  changed[PeerTableModel::Name] = a.name != b.name;
  changed[PeerTableModel::Resolution] = a.vertexCount != b.vertexCount || fullCountMatters;
  changed[PeerTableModel::Role] = a.isHost != b.isHost || a.isSelf != b.isSelf || a.isAudience != b.isAudience;
  changed[PeerTableModel::Lock] =
      a.lock != b.lock || (a.lock == PeerRow::Lock::Queued && a.queuePosition != b.queuePosition);
  const bool statsFlag = a.hasStats != b.hasStats || a.figuresToolTip != b.figuresToolTip;
  changed[PeerTableModel::LossPct] = statsFlag || a.lossPct != b.lossPct;
  changed[PeerTableModel::LatencyMs] = statsFlag || a.latencyP99Ms != b.latencyP99Ms;
  changed[PeerTableModel::KbpsIn] = statsFlag || a.kbpsIn != b.kbpsIn;
  changed[PeerTableModel::HdMaxPct] = statsFlag || a.hdMaxPct != b.hdMaxPct;
  int first = -1;
  int last = -1;
  for (int c = 0; c < PeerTableModel::ColumnCount; ++c) {
    if (changed[c]) {
      first = first < 0 ? c : first;
      last = c;
    }
  }
  return {first, last};
}

}  // namespace

PeerTableModel::PeerTableModel(QObject* parent) : QAbstractTableModel(parent) {}

PeerTableModel::~PeerTableModel() = default;

void PeerTableModel::setPeers(std::vector<PeerRow> peers) {
  // Index the new list by id (first occurrence wins).
  std::unordered_map<std::uint32_t, std::size_t> incoming;
  incoming.reserve(peers.size());
  for (std::size_t i = 0; i < peers.size(); ++i) {
    incoming.emplace(peers[i].peerId, i);
  }

  // 1. Remove departed peers, in contiguous runs from the back so earlier row numbers stay valid.
  for (int row = static_cast<int>(m_rows.size()) - 1; row >= 0;) {
    if (incoming.contains(m_rows[static_cast<std::size_t>(row)].peerId)) {
      --row;
      continue;
    }
    int first = row;
    while (first > 0 && !incoming.contains(m_rows[static_cast<std::size_t>(first - 1)].peerId)) {
      --first;
    }
    beginRemoveRows(QModelIndex(), first, row);
    m_rows.erase(m_rows.begin() + first, m_rows.begin() + row + 1);
    endRemoveRows();
    row = first - 1;
  }

  // 2. Update the peers that stay, one dataChanged per changed row.
  std::unordered_set<std::uint32_t> present;
  present.reserve(m_rows.size());
  for (std::size_t row = 0; row < m_rows.size(); ++row) {
    PeerRow& current = m_rows[row];
    present.insert(current.peerId);
    PeerRow& next = peers[incoming.at(current.peerId)];
    const bool fullCountMatters =
        m_fullVertexCount != 0 && (current.vertexCount == m_fullVertexCount) != (next.vertexCount == m_fullVertexCount);
    const auto [first, last] = changedColumns(current, next, fullCountMatters);
    if (current == next) {
      continue;
    }
    current = std::move(next);
    if (first >= 0) {
      const int r = static_cast<int>(row);
      emit dataChanged(index(r, first), index(r, last));
    }
  }

  // 3. Append newcomers in the order given, skipping repeated ids.
  std::vector<PeerRow> added;
  for (std::size_t i = 0; i < peers.size(); ++i) {
    if (incoming.at(peers[i].peerId) == i && !present.contains(peers[i].peerId)) {
      added.push_back(std::move(peers[i]));
    }
  }
  if (!added.empty()) {
    const int first = static_cast<int>(m_rows.size());
    beginInsertRows(QModelIndex(), first, first + static_cast<int>(added.size()) - 1);
    for (PeerRow& peer : added) {
      m_rows.push_back(std::move(peer));
    }
    endInsertRows();
  }
}

void PeerTableModel::setFullVertexCount(std::uint32_t count) {
  if (count == m_fullVertexCount) {
    return;
  }
  m_fullVertexCount = count;
  if (!m_rows.empty()) {
    emit dataChanged(index(0, Resolution), index(static_cast<int>(m_rows.size()) - 1, Resolution));
  }
}

const PeerRow& PeerTableModel::peerAt(int row) const {
  assert(row >= 0 && row < rowCount() && "peerAt: row out of range");
  return m_rows[static_cast<std::size_t>(row)];
}

int PeerTableModel::rowOfPeer(std::uint32_t peerId) const {
  for (std::size_t row = 0; row < m_rows.size(); ++row) {
    if (m_rows[row].peerId == peerId) {
      return static_cast<int>(row);
    }
  }
  return -1;
}

QString PeerTableModel::columnTitle(int column) {
  switch (column) {
    case Name:
      return QStringLiteral("Name");
    case Resolution:
      return QStringLiteral("Shows");
    case Role:
      return QStringLiteral("Role");
    case Lock:
      return QStringLiteral("Lock");
    case LossPct:
      return QStringLiteral("Loss %");
    case LatencyMs:
      return QStringLiteral("Delay ms");
    case KbpsIn:
      return QStringLiteral("kbit/s");
    case HdMaxPct:
      return QStringLiteral("Error %");
    default:
      return {};
  }
}

QString PeerTableModel::columnToolTip(int column) {
  switch (column) {
    case Resolution:
      return QStringLiteral("Vertices the peer displays (\"full\": the host's whole mesh)");
    case LossPct:
      return QStringLiteral("Loss: coefficient datagrams lost in the last 10 s, % of those expected");
    case LatencyMs:
      return QStringLiteral(
          "Latency: 99th percentile of the one-way delay over the last 10 s, in ms, from the host sending a frame to "
          "the peer's app reading it (includes time that app was busy drawing; one clock, so valid on one machine)");
    case KbpsIn:
      return QStringLiteral("Coefficient stream received, payload kbit/s over the last second");
    case HdMaxPct:
      return QStringLiteral(
          "Shape error: largest Hausdorff distortion (HD max) between the shape shown and the exact one, % of the "
          "bounding-box diagonal");
    default:
      return {};
  }
}

int PeerTableModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : static_cast<int>(m_rows.size());
}

int PeerTableModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant PeerTableModel::data(const QModelIndex& index, int role) const {
  if (!checkIndex(index, CheckIndexOption::IndexIsValid | CheckIndexOption::ParentIsInvalid)) {
    return {};
  }
  const PeerRow& peer = m_rows[static_cast<std::size_t>(index.row())];
  switch (role) {
    case Qt::DisplayRole:
      return displayText(peer, index.column());
    case Qt::ToolTipRole:
      return toolTip(peer, index.column());
    case Qt::TextAlignmentRole:
      return static_cast<int>((isNumericColumn(index.column()) ? Qt::AlignRight : Qt::AlignLeft) | Qt::AlignVCenter);
    case SortRole:
      return sortValue(peer, index.column());
    case PeerIdRole:
      return QVariant::fromValue(static_cast<quint32>(peer.peerId));
    default:
      return {};
  }
}

QVariant PeerTableModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || section < 0 || section >= ColumnCount) {
    return QAbstractTableModel::headerData(section, orientation, role);
  }
  if (role == Qt::DisplayRole) {
    return columnTitle(section);
  }
  if (role == Qt::ToolTipRole) {
    const QString tip = columnToolTip(section);
    return tip.isEmpty() ? QVariant() : QVariant(tip);
  }
  if (role == Qt::TextAlignmentRole) {
    return static_cast<int>((isNumericColumn(section) ? Qt::AlignRight : Qt::AlignLeft) | Qt::AlignVCenter);
  }
  return {};
}

QString PeerTableModel::displayText(const PeerRow& peer, int column) const {
  const QLocale& locale = english();
  switch (column) {
    case Name:
      return peer.name;
    case Resolution:
      if (peer.isAudience) return unknownFigure();
      if (m_fullVertexCount != 0 && peer.vertexCount == m_fullVertexCount) {
        return QStringLiteral("full");  // the counts are in the tooltip: the table fits a side dock (issue 16)
      }
      return locale.toString(peer.vertexCount);
    case Role: {
      if (peer.isAudience) return QStringLiteral("viewers");
      QString text = peer.isHost ? QStringLiteral("host") : QStringLiteral("client");
      return peer.isSelf ? text + QStringLiteral(" (you)") : text;
    }
    case Lock:
      switch (peer.lock) {
        case PeerRow::Lock::Holder:
          return QStringLiteral("holds lock");
        case PeerRow::Lock::Queued:
          return QStringLiteral("waits #") + QString::number(peer.queuePosition);
        case PeerRow::Lock::None:
          return {};
      }
      return {};
    case LossPct:
      return peer.hasStats ? locale.toString(peer.lossPct, 'f', 1) : unknownFigure();
    case LatencyMs:
      return peer.hasStats ? locale.toString(peer.latencyP99Ms, 'f', 1) : unknownFigure();
    case KbpsIn:
      return peer.hasStats ? locale.toString(peer.kbpsIn, 'f', 1) : unknownFigure();
    case HdMaxPct:
      return peer.hasStats ? locale.toString(peer.hdMaxPct, 'f', 3) : unknownFigure();
    default:
      return {};
  }
}

QVariant PeerTableModel::sortValue(const PeerRow& peer, int column) const {
  switch (column) {
    case Name:
      return peer.name;
    case Resolution:
      return static_cast<qulonglong>(peer.vertexCount);
    case Role:
      return peer.isHost ? 0 : 1;  // host first
    case Lock:
      switch (peer.lock) {
        case PeerRow::Lock::Holder:
          return 0;
        case PeerRow::Lock::Queued:
          return peer.queuePosition;
        case PeerRow::Lock::None:
          return std::numeric_limits<int>::max();
      }
      return std::numeric_limits<int>::max();
    case LossPct:
      return peer.hasStats ? peer.lossPct : -1.0;
    case LatencyMs:
      return peer.hasStats ? peer.latencyP99Ms : -1.0;
    case KbpsIn:
      return peer.hasStats ? peer.kbpsIn : -1.0;
    case HdMaxPct:
      return peer.hasStats ? peer.hdMaxPct : -1.0;
    default:
      return {};
  }
}

QString PeerTableModel::toolTip(const PeerRow& peer, int column) const {
  const QLocale& locale = english();
  switch (column) {
    case Name:
      if (peer.isAudience) return peer.name;
      return peer.name + QStringLiteral(" (peer #") + QString::number(peer.peerId) + QLatin1Char(')');
    case Resolution:
      return QStringLiteral("Displays ") + locale.toString(peer.vertexCount) + QStringLiteral(" vertices") +
             (m_fullVertexCount != 0 ? QStringLiteral(" of ") + locale.toString(m_fullVertexCount) : QString());
    case Role:
      if (peer.isAudience) return QStringLiteral("Watch through NATS without connecting to this host");
      return peer.isHost ? QStringLiteral("Hosts the session: owns the mesh and the deformation")
                         : QStringLiteral("Joined the session");
    case Lock:
      switch (peer.lock) {
        case PeerRow::Lock::Holder:
          return QStringLiteral("Holds the edit lock: may drag");
        case PeerRow::Lock::Queued:
          return QStringLiteral("Waits for the edit lock, place ") + QString::number(peer.queuePosition) +
                 QStringLiteral(" in the queue");
        case PeerRow::Lock::None:
          return QStringLiteral("Neither holds nor waits for the edit lock");
      }
      return {};
    default:
      break;
  }
  if (!peer.hasStats) {
    return QStringLiteral("No statistics received yet");
  }
  if (!peer.figuresToolTip.isEmpty() && isNumericColumn(column)) return peer.figuresToolTip;
  switch (column) {
    case LossPct:
      return QStringLiteral("Datagrams lost in the last 10 s: ") + locale.toString(peer.lossPct, 'f', 2) +
             QStringLiteral(" %");
    case LatencyMs:
      return QStringLiteral("Latency, 99th percentile of the last 10 s: ") +
             locale.toString(peer.latencyP99Ms, 'f', 2) + QStringLiteral(" ms");
    case KbpsIn:
      return QStringLiteral("Received: ") + locale.toString(peer.kbpsIn, 'f', 2) + QStringLiteral(" kbit/s");
    case HdMaxPct:
      return QStringLiteral("Shape error, largest Hausdorff distortion: ") + locale.toString(peer.hdMaxPct, 'f', 4) +
             QStringLiteral(" % of the bounding-box diagonal");
    default:
      return {};
  }
}

}  // namespace sc::model
