// Issue 16, plain words: what a user reads says it in everyday words ("Shape detail", "Error %", "Frame: 12 ms");
// the precise term ("Frequencies m", "Hausdorff distortion (HD max)", "99th percentile", "reconstruction +
// redraw") stays in the tooltip. Widgets built in this process; no session.

#include "app/gui/host_dialog.h"
#include "app/gui/statistics_dock.h"
#include "model/statistics_model.h"

#include <gtest/gtest.h>

#include <QLabel>
#include <QRegularExpression>

namespace sc::app {
namespace {

using model::StatisticsModel;

TEST(PlainWords, HostDialogSaysShapeDetailAndKeepsFrequenciesInTheTooltip) {
  HostDialog dialog;
  const auto* label = dialog.findChild<QLabel*>(QStringLiteral("frequenciesLabel"));
  ASSERT_NE(label, nullptr);
  EXPECT_FALSE(label->text().contains(QStringLiteral("Frequencies"))) << label->text().toStdString();
  EXPECT_FALSE(label->text().contains(QStringLiteral("(m)"))) << label->text().toStdString();
  EXPECT_TRUE(label->toolTip().contains(QStringLiteral("Frequencies m"))) << label->toolTip().toStdString();
}

TEST(PlainWords, StatisticsDockNamesArePlainAndTooltipsSayTheWindowAndTheTerm) {
  StatisticsDock dock;
  const QRegularExpression jargon(QStringLiteral("\\bHD\\b|p99|Hausdorff"));
  for (const QLabel* label : dock.findChildren<QLabel*>()) {
    EXPECT_FALSE(jargon.match(label->text()).hasMatch()) << label->text().toStdString();
  }
  const QLabel* latency = dock.valueLabel(StatisticsModel::LatencyMs);
  ASSERT_NE(latency, nullptr);
  EXPECT_TRUE(latency->toolTip().contains(QStringLiteral("99th percentile"))) << latency->toolTip().toStdString();
  EXPECT_TRUE(latency->toolTip().contains(QStringLiteral("last 10 s")));
  EXPECT_TRUE(dock.valueLabel(StatisticsModel::LossPct)->toolTip().contains(QStringLiteral("last 10 s")));
  EXPECT_TRUE(dock.valueLabel(StatisticsModel::HdPct)->toolTip().contains(QStringLiteral("Hausdorff distortion")));
}

}  // namespace
}  // namespace sc::app
