#include "model/statistics_model.h"

#include <QLocale>

#include <cassert>
#include <cmath>

namespace sc::model {

StatisticsModel::StatisticsModel(QObject* parent, double windowSeconds) : QAbstractTableModel(parent) {
  if (std::isfinite(windowSeconds) && windowSeconds > 0.0) {
    m_window = windowSeconds;
  }
}

StatisticsModel::~StatisticsModel() = default;

bool StatisticsModel::append(const StatsSample& sample) {
  if (!std::isfinite(sample.t) || (!m_samples.empty() && sample.t < m_samples.back().t)) {
    return false;
  }
  dropOlderThan(sample.t - m_window);
  const int row = static_cast<int>(m_samples.size());
  beginInsertRows(QModelIndex(), row, row);
  m_samples.push_back(sample);
  endInsertRows();
  emit sampleAppended(sample);
  return true;
}

std::optional<StatsSample> StatisticsModel::latest() const {
  if (m_samples.empty()) {
    return std::nullopt;
  }
  return m_samples.back();
}

const StatsSample& StatisticsModel::sampleAt(int row) const {
  assert(row >= 0 && row < rowCount() && "sampleAt: row out of range");
  return m_samples[static_cast<std::size_t>(row)];
}

void StatisticsModel::clear() {
  beginResetModel();
  m_samples.clear();
  endResetModel();
}

void StatisticsModel::setWindow(double seconds) {
  if (!std::isfinite(seconds) || seconds <= 0.0) {
    return;
  }
  m_window = seconds;
  if (!m_samples.empty()) {
    dropOlderThan(m_samples.back().t - m_window);
  }
}

void StatisticsModel::setTitle(const QString& title) {
  if (title == m_title) {
    return;
  }
  m_title = title;
  emit titleChanged(m_title);
}

void StatisticsModel::dropOlderThan(double cutoff) {
  int count = 0;
  while (count < static_cast<int>(m_samples.size()) && m_samples[static_cast<std::size_t>(count)].t < cutoff) {
    ++count;
  }
  if (count == 0) {
    return;
  }
  beginRemoveRows(QModelIndex(), 0, count - 1);
  m_samples.erase(m_samples.begin(), m_samples.begin() + count);
  endRemoveRows();
}

QString StatisticsModel::columnName(int column) {
  switch (column) {
    case Time:
      return QStringLiteral("Time");
    case HdPct:
      return QStringLiteral("Distortion");
    case LossPct:
      return QStringLiteral("Loss");
    case KbpsIn:
      return QStringLiteral("In");
    case KbpsOut:
      return QStringLiteral("Out");
    case Fps:
      return QStringLiteral("Frame rate");
    case LatencyMs:
      return QStringLiteral("Latency");
    default:
      return {};
  }
}

QString StatisticsModel::columnToolTip(int column) {
  switch (column) {
    case HdPct:
      return QStringLiteral(
          "Shape error: Hausdorff distortion between the shape shown and the exact one at the last check, % of the "
          "bounding-box diagonal");
    case LossPct:
      return QStringLiteral("Coefficient datagrams lost in the last 10 s, % of those expected");
    case KbpsIn:
      return QStringLiteral("Coefficient stream received, payload kbit/s over the last second");
    case KbpsOut:
      return QStringLiteral("Coefficient stream sent to this peer, payload kbit/s over the last second");
    case Fps:
      return QStringLiteral("Frames shown per second (last second)");
    case LatencyMs:
      return QStringLiteral(
          "99th percentile of the one-way delay over the last 10 s: from the host sending a frame to this peer's app "
          "reading it, including time the app was busy drawing (one clock: valid on one machine)");
    default:
      return {};
  }
}

QString StatisticsModel::columnUnit(int column) {
  switch (column) {
    case Time:
      return QStringLiteral("s");
    case HdPct:
    case LossPct:
      return QStringLiteral("%");
    case KbpsIn:
    case KbpsOut:
      return QStringLiteral("kbit/s");
    case Fps:
      return QStringLiteral("fps");
    case LatencyMs:
      return QStringLiteral("ms");
    default:
      return {};
  }
}

int StatisticsModel::columnDecimals(int column) {
  switch (column) {
    case HdPct:
      return 3;
    case Time:
    case LossPct:
    case KbpsIn:
    case KbpsOut:
    case Fps:
    case LatencyMs:
      return 1;
    default:
      return 0;
  }
}

double StatisticsModel::value(const StatsSample& sample, int column) {
  switch (column) {
    case Time:
      return sample.t;
    case HdPct:
      return sample.hdPct;
    case LossPct:
      return sample.lossPct;
    case KbpsIn:
      return sample.kbpsIn;
    case KbpsOut:
      return sample.kbpsOut;
    case Fps:
      return sample.fps;
    case LatencyMs:
      return sample.latencyMs;
    default:
      assert(false && "value: column out of range");
      return 0.0;
  }
}

int StatisticsModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : static_cast<int>(m_samples.size());
}

int StatisticsModel::columnCount(const QModelIndex& parent) const { return parent.isValid() ? 0 : ColumnCount; }

QVariant StatisticsModel::data(const QModelIndex& index, int role) const {
  if (!checkIndex(index, CheckIndexOption::IndexIsValid | CheckIndexOption::ParentIsInvalid)) {
    return {};
  }
  const double v = value(m_samples[static_cast<std::size_t>(index.row())], index.column());
  switch (role) {
    case Qt::DisplayRole:
    case Qt::EditRole:
      return v;
    case Qt::ToolTipRole:
      return QLocale(QLocale::English, QLocale::UnitedStates).toString(v, 'f', columnDecimals(index.column())) +
             QLatin1Char(' ') + columnUnit(index.column());
    case Qt::TextAlignmentRole:
      return static_cast<int>(Qt::AlignRight | Qt::AlignVCenter);
    default:
      return {};
  }
}

QVariant StatisticsModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation == Qt::Horizontal && role == Qt::DisplayRole && section >= 0 && section < ColumnCount) {
    return columnName(section) + QStringLiteral(" (") + columnUnit(section) + QLatin1Char(')');
  }
  return QAbstractTableModel::headerData(section, orientation, role);
}

}  // namespace sc::model
