#pragma once
// StatisticsModel: a sliding time series of one peer's session figures (distortion, loss, bandwidth, frame rate,
// latency), for the statistics dock's numbers and charts. Plain samples in through append(); one model per
// observed peer (a host keeps one per client). Knows nothing of src/session.

#include <QAbstractTableModel>
#include <QString>
#include <QVariant>

#include <deque>
#include <optional>

namespace sc::model {

/// The figures of one peer at one instant.
struct StatsSample {
  double t = 0.0;          ///< time of the sample in seconds, on any clock that only moves forward.
  double hdPct = 0.0;      ///< normalised Hausdorff distortion, in percent of the rest bbox diagonal.
  double lossPct = 0.0;    ///< datagrams lost, in percent [0, 100].
  double kbpsIn = 0.0;     ///< received bandwidth, kbit/s.
  double kbpsOut = 0.0;    ///< sent bandwidth, kbit/s.
  double fps = 0.0;        ///< frames shown (or sent, on the host) per second.
  double latencyMs = 0.0;  ///< one-way latency, milliseconds.

  friend bool operator==(const StatsSample&, const StatsSample&) = default;
};

/// Rows are samples in time order (row 0 oldest), columns are Time and the six metrics (see Column).
///
/// Only the last window() seconds are kept: append(s) first removes, with one beginRemoveRows() from row 0, every
/// sample older than s.t - window(), then appends s with beginInsertRows() at the end. Rows are therefore only ever
/// inserted at the end and removed from the front (a view can mirror the model with append/pop-front); clear() and
/// setWindow() are the only other mutators. No resets except clear().
///
/// Roles: Qt::DisplayRole and Qt::EditRole give the raw double; Qt::ToolTipRole the value with its unit;
/// Qt::TextAlignmentRole right-aligned (int). Header: "name (unit)". Read-only; not thread-safe (GUI thread).
class StatisticsModel : public QAbstractTableModel {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(StatisticsModel)

 public:
  /// Column indices; a plain enum because the values are column numbers for the Qt API.
  enum Column : int { Time, HdPct, LossPct, KbpsIn, KbpsOut, Fps, LatencyMs, ColumnCount };

  static constexpr double kDefaultWindowSeconds = 60.0;

  /// @param[in] windowSeconds  how much history to keep, > 0 (default 60 s).
  explicit StatisticsModel(QObject* parent = nullptr, double windowSeconds = kDefaultWindowSeconds);
  ~StatisticsModel() override;

  /// Appends sample at the end, after dropping samples older than sample.t - window(). Returns false and changes
  /// nothing when sample.t is not finite or earlier than latest()->t (samples must come in time order; equal
  /// times are accepted). Emits sampleAppended() after the rows signals.
  bool append(const StatsSample& sample);

  /// The newest sample, or nullopt while the model is empty.
  [[nodiscard]] std::optional<StatsSample> latest() const;

  /// The sample in row. @pre 0 <= row < rowCount().
  [[nodiscard]] const StatsSample& sampleAt(int row) const;

  /// Removes every sample (one model reset); window and title stay.
  void clear();

  /// History kept, in seconds. setWindow() drops samples that fall out of a shorter window at once (relative to
  /// the newest sample). @pre seconds > 0 and finite; other values are ignored.
  [[nodiscard]] double window() const { return m_window; }
  void setWindow(double seconds);

  /// Whose figures these are, e.g. a peer's name ("" by default); views show it. Emits titleChanged() on change.
  [[nodiscard]] QString title() const { return m_title; }
  void setTitle(const QString& title);

  /// Column metadata: short English name ("Distortion", "Loss", "In", "Out", "Frame rate", "Latency", "Time") and
  /// unit ("%", "%", "kbit/s", "kbit/s", "fps", "ms", "s"). Empty strings for an out-of-range column.
  [[nodiscard]] static QString columnName(int column);
  [[nodiscard]] static QString columnUnit(int column);
  /// What the column's figure is precisely (window, percentile, the term behind the plain name), for tooltips;
  /// empty for Time or out of range.
  [[nodiscard]] static QString columnToolTip(int column);
  /// Decimals used when the column's value is shown as text (e.g. 3 for distortion, 1 for bandwidth).
  [[nodiscard]] static int columnDecimals(int column);
  /// The field of sample that column holds (Time → t). @pre 0 <= column < ColumnCount.
  [[nodiscard]] static double value(const StatsSample& sample, int column);

  int rowCount(const QModelIndex& parent = QModelIndex()) const override;
  int columnCount(const QModelIndex& parent = QModelIndex()) const override;
  QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

 signals:
  /// A sample was appended (after rowsInserted and any rowsRemoved).
  void sampleAppended(const sc::model::StatsSample& sample);
  void titleChanged(const QString& title);

 private:
  /// Removes samples with t < cutoff from the front.
  void dropOlderThan(double cutoff);

  std::deque<StatsSample> m_samples;
  double m_window = kDefaultWindowSeconds;
  QString m_title;
};

}  // namespace sc::model
