#include "app/gui/statistics_dock.h"

#include "model/statistics_model.h"

#include <QChart>
#include <QChartView>
#include <QGridLayout>
#include <QLabel>
#include <QLegend>
#include <QLineSeries>
#include <QLocale>
#include <QPainter>
#include <QScrollArea>
#include <QVBoxLayout>
#include <QValueAxis>

#include <algorithm>
#include <cmath>

namespace sc::app {

using sc::model::StatisticsModel;

namespace {

QString unknownFigure() { return QString(QChar(0x2013)); }  // "–"

QString valueLabelName(int column) {
  switch (column) {
    case StatisticsModel::HdPct:
      return QStringLiteral("hdPctValueLabel");
    case StatisticsModel::LossPct:
      return QStringLiteral("lossPctValueLabel");
    case StatisticsModel::KbpsIn:
      return QStringLiteral("kbpsInValueLabel");
    case StatisticsModel::KbpsOut:
      return QStringLiteral("kbpsOutValueLabel");
    case StatisticsModel::Fps:
      return QStringLiteral("fpsValueLabel");
    case StatisticsModel::LatencyMs:
      return QStringLiteral("latencyMsValueLabel");
    default:
      return {};
  }
}

QPointF pointOf(const sc::model::StatsSample& sample, int column) {
  return {sample.t, StatisticsModel::value(sample, column)};
}

}  // namespace

StatisticsDock::StatisticsDock(StatisticsModel* model, QWidget* parent) : QDockWidget(tr("Statistics"), parent) {
  setObjectName(QStringLiteral("statisticsDock"));

  auto* content = new QWidget;
  auto* layout = new QVBoxLayout(content);
  layout->setContentsMargins(6, 6, 6, 6);

  m_sourceLabel = new QLabel(content);
  m_sourceLabel->setObjectName(QStringLiteral("statisticsSourceLabel"));
  QFont bold = m_sourceLabel->font();
  bold.setBold(true);
  m_sourceLabel->setFont(bold);
  layout->addWidget(m_sourceLabel);

  m_relayLabel = new QLabel(content);
  m_relayLabel->setObjectName(QStringLiteral("relayAudienceLabel"));
  m_relayLabel->setWordWrap(true);
  m_relayLabel->setVisible(false);
  layout->addWidget(m_relayLabel);

  // Latest figures: one (name, value) pair per row, so that they fit a narrow dock (issue 16: two pairs a row were
  // clipped at the default window size).
  auto* figures = new QGridLayout;
  figures->setHorizontalSpacing(12);
  m_valueLabels.assign(StatisticsModel::ColumnCount, nullptr);
  for (int column = StatisticsModel::HdPct; column < StatisticsModel::ColumnCount; ++column) {
    const int index = column - StatisticsModel::HdPct;
    auto* name = new QLabel(StatisticsModel::columnName(column) + QLatin1Char(':'), content);
    name->setToolTip(StatisticsModel::columnToolTip(column));
    auto* value = new QLabel(unknownFigure(), content);
    value->setToolTip(StatisticsModel::columnToolTip(column));
    value->setObjectName(valueLabelName(column));
    value->setAlignment(Qt::AlignRight | Qt::AlignVCenter);
    // Not selectable: a selectable label lays its text out again (and repaints) at every layout pass of the dock.
    value->setMinimumWidth(value->fontMetrics().horizontalAdvance(QStringLiteral("00,000.0 kbit/s")));
    figures->addWidget(name, index, 0);
    figures->addWidget(value, index, 1);
    m_valueLabels[static_cast<std::size_t>(column)] = value;
  }
  layout->addLayout(figures);

  auto chartTitle = [](int column) -> QString {  // QString, not a QStringBuilder of temporaries
    return StatisticsModel::columnName(column) + QStringLiteral(" (") + StatisticsModel::columnUnit(column) +
           QLatin1Char(')');
  };
  addChart(chartTitle(StatisticsModel::HdPct), {StatisticsModel::HdPct});
  addChart(tr("Loss in the last 10 s (%)"), {StatisticsModel::LossPct});
  addChart(tr("Bandwidth (kbit/s)"), {StatisticsModel::KbpsIn, StatisticsModel::KbpsOut});
  addChart(tr("Latency, 99th percentile of 10 s (ms)"), {StatisticsModel::LatencyMs});
  for (const Chart& chart : m_charts) {
    layout->addWidget(chart.view);
  }
  layout->addStretch(1);

  auto* scroll = new QScrollArea(this);
  scroll->setWidgetResizable(true);
  scroll->setFrameShape(QFrame::NoFrame);
  scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  scroll->setWidget(content);
  setWidget(scroll);

  setModel(model);
}

StatisticsDock::~StatisticsDock() {
  if (m_model != nullptr) {
    disconnect(m_model, nullptr, this, nullptr);
  }
}

void StatisticsDock::addChart(const QString& title, std::vector<int> columns) {
  Chart chart;
  chart.chart = new QChart;
  chart.chart->setTitle(title);
  chart.chart->setMargins(QMargins(2, 2, 2, 2));
  chart.chart->setBackgroundRoundness(0);
  QFont titleFont = chart.chart->titleFont();
  titleFont.setPointSizeF(std::max(7.0, titleFont.pointSizeF() - 1.0));
  chart.chart->setTitleFont(titleFont);

  chart.x = new QValueAxis;
  chart.x->setLabelFormat(QStringLiteral("%.0f"));
  chart.x->setTickCount(7);
  chart.y = new QValueAxis;
  chart.y->setLabelFormat(QStringLiteral("%g"));
  chart.chart->addAxis(chart.x, Qt::AlignBottom);
  chart.chart->addAxis(chart.y, Qt::AlignLeft);

  for (int column : columns) {
    auto* series = new QLineSeries;
    series->setName(StatisticsModel::columnName(column));
    chart.chart->addSeries(series);  // the chart owns the series
    series->attachAxis(chart.x);
    series->attachAxis(chart.y);
    chart.series.emplace_back(column, series);
  }
  chart.chart->legend()->setVisible(columns.size() > 1);
  chart.chart->legend()->setAlignment(Qt::AlignRight);

  chart.view = new QChartView(chart.chart);  // the view owns the chart; the layout parents the view
  chart.view->setRenderHint(QPainter::Antialiasing);
  chart.view->setMinimumHeight(150);
  m_charts.push_back(chart);
}

void StatisticsDock::setModel(StatisticsModel* model) {
  if (m_model != nullptr) {
    disconnect(m_model, nullptr, this, nullptr);
  }
  m_model = model;
  if (model != nullptr) {
    connect(model, &QAbstractItemModel::rowsInserted, this,
            [this](const QModelIndex&, int first, int last) { onRowsInserted(first, last); });
    connect(model, &QAbstractItemModel::rowsRemoved, this,
            [this](const QModelIndex&, int first, int last) { onRowsRemoved(first, last); });
    connect(model, &QAbstractItemModel::modelReset, this, &StatisticsDock::rebuild);
    connect(model, &StatisticsModel::titleChanged, this, &StatisticsDock::updateLabels);
    // The QPointer is already null when destroyed() arrives: rebuild() then shows nothing.
    connect(model, &QObject::destroyed, this, &StatisticsDock::rebuild);
  }
  rebuild();
}

StatisticsModel* StatisticsDock::model() const { return m_model; }

QLabel* StatisticsDock::valueLabel(int column) const {
  if (column < 0 || column >= static_cast<int>(m_valueLabels.size())) {
    return nullptr;
  }
  return m_valueLabels[static_cast<std::size_t>(column)];
}

QLineSeries* StatisticsDock::series(int column) const {
  for (const Chart& chart : m_charts) {
    for (const auto& [c, series] : chart.series) {
      if (c == column) {
        return series;
      }
    }
  }
  return nullptr;
}

std::vector<QChartView*> StatisticsDock::chartViews() const {
  std::vector<QChartView*> views;
  for (const Chart& chart : m_charts) {
    views.push_back(chart.view);
  }
  return views;
}

void StatisticsDock::onRowsInserted(int first, int last) {
  if (m_model == nullptr) {
    return;
  }
  for (Chart& chart : m_charts) {
    for (const auto& [column, series] : chart.series) {
      QList<QPointF> points;
      points.reserve(last - first + 1);
      for (int row = first; row <= last; ++row) {
        points.append(pointOf(m_model->sampleAt(row), column));
      }
      if (first >= series->count()) {
        series->append(points);
      } else {
        for (int i = 0; i < points.size(); ++i) {
          series->insert(first + i, points[i]);
        }
      }
    }
  }
  updateAxes();
  updateLabels();
}

void StatisticsDock::onRowsRemoved(int first, int last) {
  for (Chart& chart : m_charts) {
    for (const auto& [column, series] : chart.series) {
      const int count = std::min(last, series->count() - 1) - first + 1;
      if (count > 0) {
        series->removePoints(first, count);
      }
    }
  }
  updateAxes();
  updateLabels();
}

void StatisticsDock::rebuild() {
  const int rows = m_model != nullptr ? m_model->rowCount() : 0;
  for (Chart& chart : m_charts) {
    for (const auto& [column, series] : chart.series) {
      QList<QPointF> points;
      points.reserve(rows);
      for (int row = 0; row < rows; ++row) {
        points.append(pointOf(m_model->sampleAt(row), column));
      }
      series->replace(points);
    }
  }
  updateAxes();
  updateLabels();
}

void StatisticsDock::updateAxes() {
  const double window = m_model != nullptr ? m_model->window() : StatisticsModel::kDefaultWindowSeconds;
  const int rows = m_model != nullptr ? m_model->rowCount() : 0;
  // Fill from the left until a window's worth of samples exists, then scroll with the newest one.
  double xEnd = window;
  if (rows > 0) {
    const double tFirst = m_model->sampleAt(0).t;
    const double tLast = m_model->sampleAt(rows - 1).t;
    xEnd = std::max(tLast, tFirst + window);
  }
  for (Chart& chart : m_charts) {
    chart.x->setRange(xEnd - window, xEnd);
    double yMax = 0.0;
    for (const auto& [column, series] : chart.series) {
      for (const QPointF& p : series->points()) {
        if (std::isfinite(p.y())) {
          yMax = std::max(yMax, p.y());
        }
      }
    }
    // 10% head room, rounded up to 1, 2, 4, 6, 8 or 10 times a power of ten, with at most 5 ticks at round values
    // (more do not fit a chart this small: Qt Charts elides their labels). An all-zero chart spans [0, 1].
    struct Top {
      double mantissa;
      int ticks;
    };
    static constexpr Top kTops[] = {{1.0, 3}, {2.0, 5}, {4.0, 5}, {6.0, 4}, {8.0, 5}, {10.0, 3}};
    Top chosen = kTops[0];
    double magnitude = 1.0;
    if (yMax > 0.0) {
      const double target = yMax * 1.1;
      magnitude = std::pow(10.0, std::floor(std::log10(target)));
      const double mantissa = target / magnitude;
      // mantissa is in [1, 10) up to rounding: the last entry catches it.
      chosen = *std::find_if(std::begin(kTops), std::end(kTops) - 1,
                             [mantissa](const Top& top) { return mantissa <= top.mantissa; });
    }
    chart.y->setRange(0.0, chosen.mantissa * magnitude);
    chart.y->setTickCount(chosen.ticks);
  }
}

void StatisticsDock::setRelayAudience(const QString& text) {
  if (m_relayLabel->text() == text) return;
  m_relayLabel->setText(text);
  m_relayLabel->setVisible(!text.isEmpty());
}

void StatisticsDock::updateLabels() {
  if (m_model == nullptr) {
    m_sourceLabel->setText(tr("No statistics"));
  } else {
    m_sourceLabel->setText(m_model->title());
  }
  m_sourceLabel->setVisible(!m_sourceLabel->text().isEmpty());

  const auto latest = m_model != nullptr ? m_model->latest() : std::nullopt;
  const QLocale english(QLocale::English, QLocale::UnitedStates);
  for (int column = StatisticsModel::HdPct; column < StatisticsModel::ColumnCount; ++column) {
    QLabel* label = m_valueLabels[static_cast<std::size_t>(column)];
    if (!latest) {
      label->setText(unknownFigure());
      continue;
    }
    label->setText(
        english.toString(StatisticsModel::value(*latest, column), 'f', StatisticsModel::columnDecimals(column)) +
        QLatin1Char(' ') + StatisticsModel::columnUnit(column));
  }
}

}  // namespace sc::app
