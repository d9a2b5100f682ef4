// Tests for src/model/statistics_model.cpp.

#include "model/statistics_model.h"

#include <gtest/gtest.h>

#include <QAbstractItemModelTester>
#include <QSignalSpy>

#include <limits>

using sc::model::StatisticsModel;
using sc::model::StatsSample;

namespace {

StatsSample sampleAt(double t) {
  StatsSample s;
  s.t = t;
  s.hdPct = 0.01 * t;
  s.lossPct = 5.0;
  s.kbpsIn = 40.0 + t;
  s.kbpsOut = 2.0;
  s.fps = 60.0;
  s.latencyMs = 12.5;
  return s;
}

}  // namespace

TEST(StatisticsModel, KeepsTheLastWindowOfSamples) {
  StatisticsModel model;
  QAbstractItemModelTester tester(&model, QAbstractItemModelTester::FailureReportingMode::Fatal);
  EXPECT_DOUBLE_EQ(model.window(), 60.0);
  EXPECT_FALSE(model.latest().has_value());

  QSignalSpy removed(&model, &QAbstractItemModel::rowsRemoved);
  QSignalSpy reset(&model, &QAbstractItemModel::modelReset);
  QSignalSpy appended(&model, &StatisticsModel::sampleAppended);
  // Two samples a second for 100 s: 0, 0.5, ..., 99.5.
  for (int i = 0; i < 200; ++i) {
    ASSERT_TRUE(model.append(sampleAt(0.5 * i)));
  }
  EXPECT_EQ(appended.count(), 200);
  EXPECT_EQ(reset.count(), 0);
  // Kept: t >= 99.5 - 60 = 39.5, i.e. 39.5 ... 99.5 = 121 samples, oldest first.
  ASSERT_EQ(model.rowCount(), 121);
  EXPECT_DOUBLE_EQ(model.sampleAt(0).t, 39.5);
  EXPECT_DOUBLE_EQ(model.sampleAt(120).t, 99.5);
  EXPECT_EQ(model.latest(), sampleAt(99.5));
  // Every removal was from the front.
  for (const auto& args : removed) {
    EXPECT_EQ(args.at(1).toInt(), 0);
  }

  // A gap longer than the window drops everything older in one removal.
  removed.clear();
  ASSERT_TRUE(model.append(sampleAt(500.0)));
  EXPECT_EQ(removed.count(), 1);
  EXPECT_EQ(model.rowCount(), 1);

  model.clear();
  EXPECT_EQ(model.rowCount(), 0);
  EXPECT_EQ(reset.count(), 1);
  EXPECT_TRUE(model.append(sampleAt(1.0)));  // a fresh clock after clear() is fine
}

TEST(StatisticsModel, RejectsOutOfOrderAndNonFiniteTimes) {
  StatisticsModel model;
  QAbstractItemModelTester tester(&model, QAbstractItemModelTester::FailureReportingMode::Fatal);
  ASSERT_TRUE(model.append(sampleAt(10.0)));
  EXPECT_FALSE(model.append(sampleAt(9.0)));
  EXPECT_FALSE(model.append(sampleAt(std::numeric_limits<double>::quiet_NaN())));
  EXPECT_FALSE(model.append(sampleAt(std::numeric_limits<double>::infinity())));
  EXPECT_TRUE(model.append(sampleAt(10.0)));  // equal times are accepted
  EXPECT_EQ(model.rowCount(), 2);
}

TEST(StatisticsModel, ShorterWindowDropsAtOnce) {
  StatisticsModel model(nullptr, 10.0);
  QAbstractItemModelTester tester(&model, QAbstractItemModelTester::FailureReportingMode::Fatal);
  for (int t = 0; t <= 10; ++t) {
    model.append(sampleAt(t));
  }
  EXPECT_EQ(model.rowCount(), 11);
  model.setWindow(4.0);
  EXPECT_EQ(model.rowCount(), 5);  // 6 ... 10
  EXPECT_DOUBLE_EQ(model.sampleAt(0).t, 6.0);
  model.setWindow(-1.0);  // ignored
  EXPECT_DOUBLE_EQ(model.window(), 4.0);
}

TEST(StatisticsModel, DataAndMetadata) {
  StatisticsModel model;
  QSignalSpy titles(&model, &StatisticsModel::titleChanged);
  model.setTitle(QStringLiteral("bob"));
  model.setTitle(QStringLiteral("bob"));
  EXPECT_EQ(titles.count(), 1);
  EXPECT_EQ(model.title(), QStringLiteral("bob"));

  model.append(sampleAt(2.0));
  EXPECT_EQ(model.columnCount(), StatisticsModel::ColumnCount);
  EXPECT_DOUBLE_EQ(model.data(model.index(0, StatisticsModel::KbpsIn)).toDouble(), 42.0);
  EXPECT_DOUBLE_EQ(model.data(model.index(0, StatisticsModel::Time)).toDouble(), 2.0);
  EXPECT_EQ(model.data(model.index(0, StatisticsModel::LatencyMs), Qt::ToolTipRole).toString(),
            QStringLiteral("12.5 ms"));
  EXPECT_EQ(model.headerData(StatisticsModel::KbpsOut, Qt::Horizontal).toString(), QStringLiteral("Out (kbit/s)"));
  EXPECT_EQ(StatisticsModel::columnName(StatisticsModel::HdPct), QStringLiteral("Distortion"));
  EXPECT_EQ(StatisticsModel::columnUnit(StatisticsModel::Fps), QStringLiteral("fps"));
  EXPECT_TRUE(StatisticsModel::columnName(StatisticsModel::ColumnCount).isEmpty());
  for (int c = 0; c < StatisticsModel::ColumnCount; ++c) {
    EXPECT_FALSE(StatisticsModel::columnName(c).isEmpty());
    EXPECT_FALSE(StatisticsModel::columnUnit(c).isEmpty());
  }
}
