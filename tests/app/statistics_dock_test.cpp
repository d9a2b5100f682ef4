// Tests for src/app/gui/statistics_dock.cpp.

#include "app/gui/statistics_dock.h"
#include "model/statistics_model.h"

#include "app_test_support.h"

#include <gtest/gtest.h>

#include <QChartView>
#include <QImage>
#include <QLabel>
#include <QLineSeries>
#include <QValueAxis>

#include <cmath>
#include <memory>

using sc::app::StatisticsDock;
using sc::model::StatisticsModel;
using sc::model::StatsSample;

namespace {

StatsSample sampleAt(double t) {
  StatsSample s;
  s.t = t;
  s.hdPct = 0.125 + 0.001 * t;
  s.lossPct = 10.0 + std::fmod(t, 7.0);
  s.kbpsIn = 40.0 + t;
  s.kbpsOut = 1.5;
  s.fps = 60.0;
  s.latencyMs = 12.0 + std::fmod(t, 3.0);
  return s;
}

QString labelText(const StatisticsDock& dock, const char* name) {
  const auto* label = dock.findChild<QLabel*>(QString::fromLatin1(name));
  return label != nullptr ? label->text() : QStringLiteral("<missing>");
}

}  // namespace

TEST(StatisticsDock, ShowsLatestFiguresAndChartsTheWindow) {
  StatisticsModel model;
  model.setTitle(QStringLiteral("bob"));
  StatisticsDock dock(&model);
  EXPECT_EQ(dock.objectName(), QStringLiteral("statisticsDock"));
  EXPECT_EQ(labelText(dock, "statisticsSourceLabel"), QStringLiteral("bob"));
  EXPECT_EQ(labelText(dock, "hdPctValueLabel"), QStringLiteral("\u2013"));
  ASSERT_EQ(dock.chartViews().size(), 4u);
  ASSERT_NE(dock.series(StatisticsModel::KbpsIn), nullptr);
  ASSERT_NE(dock.series(StatisticsModel::KbpsOut), nullptr);
  EXPECT_EQ(dock.series(StatisticsModel::Fps), nullptr);
  EXPECT_EQ(dock.series(StatisticsModel::Time), nullptr);
  EXPECT_EQ(dock.series(StatisticsModel::KbpsIn)->count(), 0);

  for (int t = 0; t < 10; ++t) {
    model.append(sampleAt(t));
  }
  for (int column : {StatisticsModel::HdPct, StatisticsModel::LossPct, StatisticsModel::KbpsIn,
                     StatisticsModel::KbpsOut, StatisticsModel::LatencyMs}) {
    EXPECT_EQ(dock.series(column)->count(), 10) << column;
  }
  EXPECT_EQ(labelText(dock, "hdPctValueLabel"), QStringLiteral("0.134 %"));
  EXPECT_EQ(labelText(dock, "lossPctValueLabel"), QStringLiteral("12.0 %"));
  EXPECT_EQ(labelText(dock, "kbpsInValueLabel"), QStringLiteral("49.0 kbit/s"));
  EXPECT_EQ(labelText(dock, "kbpsOutValueLabel"), QStringLiteral("1.5 kbit/s"));
  EXPECT_EQ(labelText(dock, "fpsValueLabel"), QStringLiteral("60.0 fps"));
  EXPECT_EQ(labelText(dock, "latencyMsValueLabel"), QStringLiteral("12.0 ms"));
  const QPointF last = dock.series(StatisticsModel::KbpsIn)->at(9);
  EXPECT_DOUBLE_EQ(last.x(), 9.0);
  EXPECT_DOUBLE_EQ(last.y(), 49.0);

  // 100 s at 1 Hz: the model keeps 61 samples (t in [39, 99]) and the series mirror it point for point.
  for (int t = 10; t < 100; ++t) {
    model.append(sampleAt(t));
  }
  ASSERT_EQ(model.rowCount(), 61);
  EXPECT_EQ(dock.series(StatisticsModel::LatencyMs)->count(), 61);
  EXPECT_EQ(dock.series(StatisticsModel::KbpsOut)->count(), 61);
  EXPECT_DOUBLE_EQ(dock.series(StatisticsModel::HdPct)->at(0).x(), 39.0);
  EXPECT_DOUBLE_EQ(dock.series(StatisticsModel::HdPct)->at(60).x(), 99.0);
  // The x axis scrolled to the last 60 s; the y axis covers the data.
  const auto xAxes = dock.series(StatisticsModel::KbpsIn)->attachedAxes();
  ASSERT_EQ(xAxes.size(), 2);
  for (QAbstractAxis* axis : xAxes) {
    auto* value = qobject_cast<QValueAxis*>(axis);
    ASSERT_NE(value, nullptr);
    if (axis->orientation() == Qt::Horizontal) {
      EXPECT_DOUBLE_EQ(value->min(), 39.0);
      EXPECT_DOUBLE_EQ(value->max(), 99.0);
    } else {
      EXPECT_DOUBLE_EQ(value->min(), 0.0);
      EXPECT_GE(value->max(), 139.0);
    }
  }

  model.clear();
  EXPECT_EQ(dock.series(StatisticsModel::KbpsIn)->count(), 0);
  EXPECT_EQ(labelText(dock, "kbpsInValueLabel"), QStringLiteral("\u2013"));
}

TEST(StatisticsDock, SwitchesModelsAndForgetsDestroyedOnes) {
  StatisticsModel first;
  auto second = std::make_unique<StatisticsModel>();
  second->setTitle(QStringLiteral("cy"));
  for (int t = 0; t < 5; ++t) {
    first.append(sampleAt(t));
  }
  for (int t = 0; t < 3; ++t) {
    second->append(sampleAt(100 + t));
  }
  StatisticsDock dock(&first);
  EXPECT_EQ(dock.series(StatisticsModel::LossPct)->count(), 5);

  dock.setModel(second.get());
  EXPECT_EQ(dock.model(), second.get());
  EXPECT_EQ(dock.series(StatisticsModel::LossPct)->count(), 3);
  EXPECT_EQ(labelText(dock, "statisticsSourceLabel"), QStringLiteral("cy"));
  EXPECT_EQ(labelText(dock, "kbpsInValueLabel"), QStringLiteral("142.0 kbit/s"));

  // The old model no longer drives the dock.
  first.append(sampleAt(5));
  EXPECT_EQ(dock.series(StatisticsModel::LossPct)->count(), 3);

  second.reset();
  EXPECT_EQ(dock.model(), nullptr);
  EXPECT_EQ(dock.series(StatisticsModel::LossPct)->count(), 0);
  EXPECT_EQ(labelText(dock, "statisticsSourceLabel"), QStringLiteral("No statistics"));
  EXPECT_EQ(labelText(dock, "fpsValueLabel"), QStringLiteral("\u2013"));
}

TEST(StatisticsDock, RendersChartsNotBlank) {
  StatisticsModel model;
  StatisticsDock empty(&model);
  empty.resize(420, 900);
  const QImage blankish = empty.grab().toImage();

  for (int t = 0; t < 60; ++t) {
    model.append(sampleAt(t));
  }
  StatisticsDock dock(&model);
  dock.resize(420, 900);
  const QImage image = dock.grab().toImage();
  ASSERT_FALSE(image.isNull());
  EXPECT_GT(sc::testing::pixelStdDev(image), std::sqrt(50.0));  // grey-level variance above 50
  // The lines drew something: the image differs from the empty dock's in many pixels.
  ASSERT_EQ(image.size(), blankish.size());
  int different = 0;
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      different += image.pixel(x, y) != blankish.pixel(x, y) ? 1 : 0;
    }
  }
  EXPECT_GT(different, 500);
  if (qEnvironmentVariableIsSet("SHAPECAST_SAVE_DOCK_IMAGES")) {
    image.save(QStringLiteral("/tmp/statistics_dock.png"));
  }
}
