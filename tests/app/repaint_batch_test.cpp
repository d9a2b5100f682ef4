// Tests src/app/gui/repaint_batch.cpp: painting of the batch's widgets (and their children) waits while held and
// comes back on, for all of them, once the batch has settled; destroyed widgets are skipped.

#include "app/gui/repaint_batch.h"

#include <gtest/gtest.h>

#include <QLabel>
#include <QTest>

#include <memory>

namespace sc::app {
namespace {

TEST(RepaintBatch, HoldsPaintingOfEveryWidgetUntilItSettles) {
  QWidget first;
  auto* child = new QLabel(QStringLiteral("figure"), &first);
  auto second = std::make_unique<QWidget>();
  auto gone = std::make_unique<QWidget>();
  RepaintBatch batch;
  batch.add(&first);
  batch.add(second.get());
  batch.add(gone.get());
  gone.reset();
  EXPECT_TRUE(first.updatesEnabled());
  batch.hold();
  EXPECT_TRUE(batch.holding());
  EXPECT_FALSE(first.updatesEnabled());
  EXPECT_FALSE(child->updatesEnabled()) << "children wait with their parent";
  EXPECT_FALSE(second->updatesEnabled());
  child->setText(QStringLiteral("changed"));  // text changes meanwhile; only painting waits
  EXPECT_EQ(child->text(), QStringLiteral("changed"));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !batch.holding(); }, 5000));
  EXPECT_TRUE(first.updatesEnabled());
  EXPECT_TRUE(child->updatesEnabled());
  EXPECT_TRUE(second->updatesEnabled());

  batch.hold();
  batch.releaseNow();  // before a grab
  EXPECT_FALSE(batch.holding());
  EXPECT_TRUE(first.updatesEnabled());
}

}  // namespace
}  // namespace sc::app
