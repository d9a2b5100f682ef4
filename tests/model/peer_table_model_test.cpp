// Tests for src/model/peer_table_model.cpp.

#include "model/peer_table_model.h"

#include <gtest/gtest.h>

#include <QAbstractItemModelTester>
#include <QSignalSpy>
#include <QSortFilterProxyModel>

#include <vector>

using sc::model::PeerRow;
using sc::model::PeerTableModel;

namespace {

PeerRow peer(std::uint32_t id, const char* name, std::uint32_t vertices) {
  PeerRow row;
  row.peerId = id;
  row.name = QString::fromUtf8(name);
  row.vertexCount = vertices;
  return row;
}

PeerRow withStats(PeerRow row, double loss, double latency, double kbps, double hd) {
  row.hasStats = true;
  row.lossPct = loss;
  row.latencyP99Ms = latency;
  row.kbpsIn = kbps;
  row.hdMaxPct = hd;
  return row;
}

QString text(const PeerTableModel& model, int row, int column, int role = Qt::DisplayRole) {
  return model.data(model.index(row, column), role).toString();
}

/// Records the structural signals of a model.
struct Recorder {
  explicit Recorder(QAbstractItemModel* model)
      : inserted(model, &QAbstractItemModel::rowsInserted),
        removed(model, &QAbstractItemModel::rowsRemoved),
        changed(model, &QAbstractItemModel::dataChanged),
        reset(model, &QAbstractItemModel::modelReset) {}
  void clear() {
    inserted.clear();
    removed.clear();
    changed.clear();
    reset.clear();
  }
  QSignalSpy inserted, removed, changed, reset;
};

}  // namespace

TEST(PeerTableModel, PassesModelTesterThroughInsertsUpdatesAndRemovals) {
  PeerTableModel model;
  QAbstractItemModelTester tester(&model, QAbstractItemModelTester::FailureReportingMode::Fatal);
  model.setFullVertexCount(22982);

  PeerRow host = peer(1, "ada", 22982);
  host.isHost = true;
  host.isSelf = true;
  host.lock = PeerRow::Lock::Holder;
  model.setPeers({host, peer(2, "bob", 1719), peer(3, "cy", 5000)});
  ASSERT_EQ(model.rowCount(), 3);
  model.setPeers(
      {host, withStats(peer(2, "bob", 1719), 2.5, 31.25, 42.0, 0.125), peer(3, "cy", 5000), peer(4, "dee", 22982)});
  model.setPeers({peer(4, "dee", 22982), host});
  model.setPeers({});
  EXPECT_EQ(model.rowCount(), 0);
  model.setPeers({host, peer(5, "eve", 100)});
  model.setFullVertexCount(100);
  EXPECT_EQ(model.rowCount(), 2);
}

TEST(PeerTableModel, FormatsEveryColumn) {
  PeerTableModel model;
  model.setFullVertexCount(22982);
  PeerRow host = peer(1, "ada", 22982);
  host.isHost = true;
  host.lock = PeerRow::Lock::Holder;
  PeerRow client = withStats(peer(2, "bob", 1719), 2.5, 31.25, 1234.56, 0.125);
  client.isSelf = true;
  client.lock = PeerRow::Lock::Queued;
  client.queuePosition = 2;
  model.setPeers({host, client});

  EXPECT_EQ(text(model, 0, PeerTableModel::Name), QStringLiteral("ada"));
  EXPECT_EQ(text(model, 0, PeerTableModel::Resolution), QStringLiteral("full"));
  EXPECT_EQ(text(model, 1, PeerTableModel::Resolution), QStringLiteral("1,719"));
  EXPECT_EQ(text(model, 0, PeerTableModel::Role), QStringLiteral("host"));
  EXPECT_EQ(text(model, 1, PeerTableModel::Role), QStringLiteral("client (you)"));
  EXPECT_EQ(text(model, 0, PeerTableModel::Lock), QStringLiteral("holds lock"));
  EXPECT_EQ(text(model, 1, PeerTableModel::Lock), QStringLiteral("waits #2"));
  EXPECT_EQ(text(model, 0, PeerTableModel::LossPct), QStringLiteral("\u2013"));
  EXPECT_EQ(text(model, 0, PeerTableModel::HdMaxPct), QStringLiteral("\u2013"));
  EXPECT_EQ(text(model, 1, PeerTableModel::LossPct), QStringLiteral("2.5"));
  EXPECT_EQ(text(model, 1, PeerTableModel::LatencyMs), QStringLiteral("31.3"));
  EXPECT_EQ(text(model, 1, PeerTableModel::KbpsIn), QStringLiteral("1,234.6"));
  EXPECT_EQ(text(model, 1, PeerTableModel::HdMaxPct), QStringLiteral("0.125"));
  EXPECT_FALSE(text(model, 1, PeerTableModel::Lock, Qt::ToolTipRole).isEmpty());
  EXPECT_EQ(text(model, 0, PeerTableModel::LossPct, Qt::ToolTipRole), QStringLiteral("No statistics received yet"));

  // Numbers right-aligned, text left-aligned.
  const int right = model.data(model.index(1, PeerTableModel::KbpsIn), Qt::TextAlignmentRole).toInt();
  const int left = model.data(model.index(1, PeerTableModel::Name), Qt::TextAlignmentRole).toInt();
  EXPECT_TRUE(right & Qt::AlignRight);
  EXPECT_TRUE(left & Qt::AlignLeft);

  // Raw values for sorting; unknown figures are -1.
  EXPECT_DOUBLE_EQ(model.data(model.index(1, PeerTableModel::KbpsIn), PeerTableModel::SortRole).toDouble(), 1234.56);
  EXPECT_DOUBLE_EQ(model.data(model.index(0, PeerTableModel::KbpsIn), PeerTableModel::SortRole).toDouble(), -1.0);
  EXPECT_EQ(model.data(model.index(1, PeerTableModel::Resolution), PeerTableModel::SortRole).toULongLong(), 1719u);
  EXPECT_EQ(model.data(model.index(1, PeerTableModel::Name), PeerTableModel::PeerIdRole).toUInt(), 2u);
  EXPECT_EQ(model.headerData(PeerTableModel::LossPct, Qt::Horizontal).toString(), QStringLiteral("Loss %"));

  EXPECT_EQ(model.peerAt(1).name, QStringLiteral("bob"));
  EXPECT_EQ(model.rowOfPeer(2), 1);
  EXPECT_EQ(model.rowOfPeer(99), -1);
}

// Issue 16: plain words in the headers, the precise terms in their tooltips.
TEST(PeerTableModel, HeadersUsePlainWordsAndTooltipsKeepThePreciseTerms) {
  PeerTableModel model;
  for (int column = 0; column < PeerTableModel::ColumnCount; ++column) {
    const QString title = model.headerData(column, Qt::Horizontal).toString();
    EXPECT_FALSE(title.contains(QStringLiteral("HD"))) << title.toStdString();
    EXPECT_FALSE(title.contains(QStringLiteral("p99"))) << title.toStdString();
  }
  EXPECT_EQ(model.headerData(PeerTableModel::HdMaxPct, Qt::Horizontal).toString(), QStringLiteral("Error %"));
  EXPECT_TRUE(model.headerData(PeerTableModel::HdMaxPct, Qt::Horizontal, Qt::ToolTipRole)
                  .toString()
                  .contains(QStringLiteral("Hausdorff distortion (HD max)")));
  const QString latency = model.headerData(PeerTableModel::LatencyMs, Qt::Horizontal, Qt::ToolTipRole).toString();
  EXPECT_TRUE(latency.contains(QStringLiteral("99th percentile"))) << latency.toStdString();
  EXPECT_TRUE(latency.contains(QStringLiteral("last 10 s"))) << latency.toStdString();
  EXPECT_TRUE(model.headerData(PeerTableModel::LossPct, Qt::Horizontal, Qt::ToolTipRole)
                  .toString()
                  .contains(QStringLiteral("last 10 s")));
  EXPECT_FALSE(model.headerData(PeerTableModel::Name, Qt::Horizontal, Qt::ToolTipRole).isValid());
}

TEST(PeerTableModel, UnknownFullCountShowsVertexCounts) {
  PeerTableModel model;
  model.setPeers({peer(1, "solo", 1)});
  EXPECT_EQ(text(model, 0, PeerTableModel::Resolution), QStringLiteral("1"));
  QSignalSpy changed(&model, &QAbstractItemModel::dataChanged);
  model.setFullVertexCount(1);
  EXPECT_EQ(changed.count(), 1);
  EXPECT_EQ(text(model, 0, PeerTableModel::Resolution), QStringLiteral("full"));
}

TEST(PeerTableModel, UpdatesMinimally) {
  PeerTableModel model;
  Recorder signals_(&model);
  model.setPeers({peer(1, "a", 10), peer(2, "b", 10), peer(3, "c", 10)});
  EXPECT_EQ(signals_.inserted.count(), 1);
  EXPECT_EQ(signals_.reset.count(), 0);

  // Same content again: nothing at all.
  signals_.clear();
  model.setPeers({peer(1, "a", 10), peer(2, "b", 10), peer(3, "c", 10)});
  EXPECT_EQ(signals_.inserted.count() + signals_.removed.count() + signals_.changed.count(), 0);

  // One peer's figures change: one dataChanged over that row's statistics columns only.
  signals_.clear();
  model.setPeers({peer(1, "a", 10), withStats(peer(2, "b", 10), 1.0, 2.0, 3.0, 4.0), peer(3, "c", 10)});
  ASSERT_EQ(signals_.changed.count(), 1);
  const auto topLeft = signals_.changed.at(0).at(0).value<QModelIndex>();
  const auto bottomRight = signals_.changed.at(0).at(1).value<QModelIndex>();
  EXPECT_EQ(topLeft.row(), 1);
  EXPECT_EQ(bottomRight.row(), 1);
  EXPECT_EQ(topLeft.column(), PeerTableModel::LossPct);
  EXPECT_EQ(bottomRight.column(), PeerTableModel::HdMaxPct);
  EXPECT_EQ(signals_.inserted.count() + signals_.removed.count(), 0);

  // The middle peer leaves and a new one arrives (in the middle of the list): one removal, one append at the end.
  signals_.clear();
  model.setPeers({peer(1, "a", 10), peer(4, "d", 10), peer(3, "c", 10)});
  ASSERT_EQ(signals_.removed.count(), 1);
  EXPECT_EQ(signals_.removed.at(0).at(1).toInt(), 1);
  EXPECT_EQ(signals_.removed.at(0).at(2).toInt(), 1);
  ASSERT_EQ(signals_.inserted.count(), 1);
  EXPECT_EQ(signals_.inserted.at(0).at(1).toInt(), 2);
  EXPECT_EQ(signals_.changed.count(), 0);
  ASSERT_EQ(model.rowCount(), 3);
  EXPECT_EQ(model.peerAt(0).peerId, 1u);
  EXPECT_EQ(model.peerAt(1).peerId, 3u);
  EXPECT_EQ(model.peerAt(2).peerId, 4u);

  // Two adjacent departures are one removal; the reset never happens.
  signals_.clear();
  model.setPeers({peer(4, "d", 10)});
  EXPECT_EQ(signals_.removed.count(), 1);
  EXPECT_EQ(model.rowCount(), 1);
  EXPECT_EQ(signals_.reset.count(), 0);
}

TEST(PeerTableModel, IgnoresRepeatedIds) {
  PeerTableModel model;
  QAbstractItemModelTester tester(&model, QAbstractItemModelTester::FailureReportingMode::Fatal);
  model.setPeers({peer(7, "first", 1), peer(7, "second", 2)});
  ASSERT_EQ(model.rowCount(), 1);
  EXPECT_EQ(model.peerAt(0).name, QStringLiteral("first"));
  model.setPeers({peer(7, "third", 3), peer(7, "fourth", 4), peer(8, "x", 1), peer(8, "y", 1)});
  ASSERT_EQ(model.rowCount(), 2);
  EXPECT_EQ(model.peerAt(0).name, QStringLiteral("third"));
  EXPECT_EQ(model.peerAt(1).name, QStringLiteral("x"));
}

TEST(PeerTableModel, SortsOnRawRoleThroughProxy) {
  PeerTableModel model;
  QSortFilterProxyModel proxy;
  proxy.setSourceModel(&model);
  proxy.setSortRole(PeerTableModel::SortRole);
  QAbstractItemModelTester tester(&proxy, QAbstractItemModelTester::FailureReportingMode::Fatal);
  // "9.0" sorts after "10.0" as text; the raw role sorts numerically.
  model.setPeers(
      {withStats(peer(1, "a", 1), 0, 0, 10.0, 0), withStats(peer(2, "b", 1), 0, 0, 9.0, 0), peer(3, "c", 1)});
  proxy.sort(PeerTableModel::KbpsIn, Qt::AscendingOrder);
  auto idAt = [&](int row) { return proxy.data(proxy.index(row, 0), PeerTableModel::PeerIdRole).toUInt(); };
  EXPECT_EQ(idAt(0), 3u);  // no stats first
  EXPECT_EQ(idAt(1), 2u);
  EXPECT_EQ(idAt(2), 1u);
  // A figure changes: the proxy re-sorts dynamically.
  model.setPeers(
      {withStats(peer(1, "a", 1), 0, 0, 10.0, 0), withStats(peer(2, "b", 1), 0, 0, 90.0, 0), peer(3, "c", 1)});
  EXPECT_EQ(idAt(1), 1u);
  EXPECT_EQ(idAt(2), 2u);
}

TEST(PeerTableModel, AnAudienceRowShowsViewersAndItsDistributionsInTheFigureTooltips) {
  // Issue 18 item 3: the viewers through NATS are one row, whatever their number.
  PeerTableModel model;
  model.setFullVertexCount(1000);
  PeerRow audience = withStats(peer(0xFFFFFFFFu, "250 viewers through NATS", 0), 0.5, 12.0, 0.0, 0.0);
  audience.isAudience = true;
  audience.figuresToolTip = QStringLiteral("loss median 0.50 %, max 2.00 %");
  model.setPeers({peer(1, "alice", 1000), audience});
  EXPECT_EQ(text(model, 1, PeerTableModel::Role), QStringLiteral("viewers"));
  EXPECT_EQ(text(model, 1, PeerTableModel::Resolution), QString(QChar(0x2013)));
  EXPECT_EQ(text(model, 1, PeerTableModel::LossPct), QStringLiteral("0.5"));
  EXPECT_EQ(text(model, 1, PeerTableModel::LossPct, Qt::ToolTipRole), audience.figuresToolTip);
  EXPECT_EQ(text(model, 1, PeerTableModel::LatencyMs, Qt::ToolTipRole), audience.figuresToolTip);
  EXPECT_EQ(text(model, 1, PeerTableModel::Name, Qt::ToolTipRole), audience.name);
  EXPECT_EQ(text(model, 0, PeerTableModel::Role), QStringLiteral("client"));  // a peer's row is unchanged

  Recorder recorder(&model);
  audience.figuresToolTip = QStringLiteral("loss median 0.50 %, max 3.00 %");  // only the distribution changed
  model.setPeers({peer(1, "alice", 1000), audience});
  ASSERT_EQ(recorder.changed.size(), 1);
  EXPECT_EQ(text(model, 1, PeerTableModel::HdMaxPct, Qt::ToolTipRole), audience.figuresToolTip);
}
