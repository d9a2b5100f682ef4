#pragma once
// StatisticsDock: the dock that shows one peer's session figures (sc::model::StatisticsModel) as numbers and as
// scrolling line charts over the model's window (60 s by default).

#include <QDockWidget>
#include <QPointer>

#include <vector>

class QChart;
class QChartView;
class QLabel;
class QLineSeries;
class QValueAxis;

namespace sc::model {
class StatisticsModel;
}

namespace sc::app {

/// A QDockWidget (objectName "statisticsDock", title "Statistics") that observes a StatisticsModel:
/// - a source label (objectName "statisticsSourceLabel"): the model's title(), "No statistics" without a model;
/// - one value label per metric with the latest figure and its unit, e.g. "0.125 %", "42.0 kbit/s", or "–" while
///   the model is empty, name and value with StatisticsModel::columnToolTip() (the precise figure: window,
///   percentile, term); objectNames "hdPctValueLabel", "lossPctValueLabel", "kbpsInValueLabel",
///   "kbpsOutValueLabel", "fpsValueLabel", "latencyMsValueLabel" (decimals from StatisticsModel::columnDecimals());
/// - four Qt Charts line charts: distortion %, loss %, bandwidth (in and out, two series) and latency. Series
///   point i is model row i (x = t in seconds, y = the metric), kept in step incrementally from rowsInserted /
///   rowsRemoved (a full rebuild only on modelReset and setModel()). The x axis spans the model's window and
///   scrolls with the newest sample; the y axis runs from 0 to a rounded maximum of the visible points.
///
/// - a relay section (objectName "relayAudienceLabel", hidden while empty): the host's viewers through NATS as one
///   aggregate (setRelayAudience(), relay_audience_view.h), whichever peer the figures below belong to;
///
/// The dock does not own the model: setModel() switches to another one (the host picks a client), and a destroyed
/// model is forgotten. View only; GUI thread.
class StatisticsDock : public QDockWidget {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(StatisticsDock)

 public:
  /// @param[in] model  the figures to show, or nullptr for none yet.
  explicit StatisticsDock(sc::model::StatisticsModel* model = nullptr, QWidget* parent = nullptr);
  ~StatisticsDock() override;

  /// Observes model instead of the current one (nullptr: none) and redraws everything from it.
  void setModel(sc::model::StatisticsModel* model);
  [[nodiscard]] sc::model::StatisticsModel* model() const;

  /// The relay section's text (empty: hidden). Repaints only when it changed.
  void setRelayAudience(const QString& text);
  [[nodiscard]] QLabel* relayAudienceLabel() const { return m_relayLabel; }

  /// The value label of a StatisticsModel::Column (nullptr for Time or out of range).
  [[nodiscard]] QLabel* valueLabel(int column) const;
  /// The chart series of a StatisticsModel::Column (nullptr for Time, Fps — shown as a number only — or out of
  /// range).
  [[nodiscard]] QLineSeries* series(int column) const;
  /// The four chart views, top to bottom: distortion, loss, bandwidth, latency.
  [[nodiscard]] std::vector<QChartView*> chartViews() const;

 private:
  struct Chart {
    QChartView* view = nullptr;
    QChart* chart = nullptr;
    QValueAxis* x = nullptr;
    QValueAxis* y = nullptr;
    std::vector<std::pair<int, QLineSeries*>> series;  ///< (StatisticsModel::Column, series)
  };

  void addChart(const QString& title, std::vector<int> columns);
  void onRowsInserted(int first, int last);
  void onRowsRemoved(int first, int last);
  void rebuild();
  void updateAxes();
  void updateLabels();

  QPointer<sc::model::StatisticsModel> m_model;
  QLabel* m_sourceLabel = nullptr;
  QLabel* m_relayLabel = nullptr;
  std::vector<QLabel*> m_valueLabels;  ///< indexed by StatisticsModel::Column; nullptr for Time.
  std::vector<Chart> m_charts;
};

}  // namespace sc::app
