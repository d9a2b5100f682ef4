// Tests for src/app/gui/peers_dock.cpp.

#include "app/gui/peers_dock.h"
#include "model/peer_table_model.h"

#include "app_test_support.h"

#include <gtest/gtest.h>

#include <cmath>

#include <QHeaderView>
#include <QImage>
#include <QMenu>
#include <QSettings>
#include <QSignalSpy>
#include <QSortFilterProxyModel>
#include <QTableView>

#include <memory>

using sc::app::PeersDock;
using sc::model::PeerRow;
using sc::model::PeerTableModel;

namespace {

PeerRow peer(std::uint32_t id, const char* name, std::uint32_t vertices, bool host = false) {
  PeerRow row;
  row.peerId = id;
  row.name = QString::fromUtf8(name);
  row.vertexCount = vertices;
  row.isHost = host;
  return row;
}

}  // namespace

TEST(PeersDock, ShowsTheModelSortedWithHostFirst) {
  PeerTableModel model;
  model.setFullVertexCount(22982);
  PeersDock dock(&model);
  EXPECT_EQ(dock.objectName(), QStringLiteral("peersDock"));
  EXPECT_EQ(dock.model(), &model);

  PeerRow self = peer(2, "bob", 1719);
  self.isSelf = true;
  model.setPeers({self, peer(1, "ada", 22982, true), peer(3, "cy", 5000)});
  QAbstractItemModel* shown = dock.view()->model();
  ASSERT_EQ(shown->rowCount(), 3);
  EXPECT_EQ(shown->index(0, PeerTableModel::Name).data().toString(), QStringLiteral("ada"));
  EXPECT_EQ(shown->index(0, PeerTableModel::Resolution).data().toString(), QStringLiteral("full"));
  EXPECT_EQ(shown->headerData(PeerTableModel::LatencyMs, Qt::Horizontal).toString(), QStringLiteral("Delay ms"));

  // Sorting by resolution uses the raw vertex count (1,719 < 5,000 < 22,982).
  dock.view()->sortByColumn(PeerTableModel::Resolution, Qt::AscendingOrder);
  EXPECT_EQ(shown->index(0, PeerTableModel::Name).data().toString(), QStringLiteral("bob"));
  EXPECT_EQ(shown->index(1, PeerTableModel::Name).data().toString(), QStringLiteral("cy"));
  EXPECT_EQ(shown->index(2, PeerTableModel::Name).data().toString(), QStringLiteral("ada"));
}

TEST(PeersDock, SelectionFollowsThePeerAndSignals) {
  PeerTableModel model;
  PeersDock dock(&model);
  QSignalSpy changed(&dock, &PeersDock::currentPeerChanged);
  model.setPeers({peer(1, "ada", 10, true), peer(2, "bob", 10), peer(3, "cy", 10)});
  EXPECT_FALSE(dock.selectedPeerId().has_value());

  ASSERT_TRUE(dock.selectPeer(3));
  ASSERT_EQ(changed.count(), 1);
  EXPECT_EQ(changed.at(0).at(0).toUInt(), 3u);
  EXPECT_EQ(dock.selectedPeerId(), 3u);
  EXPECT_FALSE(dock.selectPeer(42));

  // An update that re-sorts and removes another peer keeps the selection on the same peer.
  dock.view()->sortByColumn(PeerTableModel::Name, Qt::DescendingOrder);
  model.setPeers({peer(1, "ada", 10, true), peer(3, "cy", 20)});
  EXPECT_EQ(dock.selectedPeerId(), 3u);

  // Switching the model clears the selection.
  PeerTableModel other;
  dock.setModel(&other);
  EXPECT_FALSE(dock.selectedPeerId().has_value());
  EXPECT_EQ(dock.view()->model()->rowCount(), 0);
}

TEST(PeersDock, ForgetsADestroyedModel) {
  auto model = std::make_unique<PeerTableModel>();
  PeersDock dock(model.get());
  model->setPeers({peer(1, "ada", 10, true)});
  model.reset();
  EXPECT_EQ(dock.model(), nullptr);
  EXPECT_EQ(dock.view()->model()->rowCount(), 0);
}

TEST(PeersDock, RendersNotBlank) {
  PeerTableModel model;
  model.setFullVertexCount(22982);
  PeerRow client = peer(2, "bob", 1719);
  client.hasStats = true;
  client.lossPct = 9.5;
  client.kbpsIn = 41.0;
  client.lock = PeerRow::Lock::Queued;
  client.queuePosition = 1;
  PeerRow host = peer(1, "ada", 22982, true);
  host.lock = PeerRow::Lock::Holder;
  model.setPeers({host, client});
  PeersDock dock(&model);
  dock.resize(720, 200);
  const QImage image = dock.grab().toImage();
  ASSERT_FALSE(image.isNull());
  EXPECT_GT(sc::testing::pixelStdDev(image), std::sqrt(50.0));  // grey-level variance above 50
}

TEST(PeersDock, SideDockColumnsByDefaultAndTheHeaderMenuShowsTheRestAndRemembers) {
  QSettings().remove(QStringLiteral("peers/hiddenColumns"));
  PeerTableModel model;
  {
    PeersDock dock(&model);
    for (const int column : {PeerTableModel::Name, PeerTableModel::Role, PeerTableModel::Lock, PeerTableModel::LossPct})
      EXPECT_TRUE(dock.columnShown(column)) << column;
    for (const int column :
         {PeerTableModel::Resolution, PeerTableModel::LatencyMs, PeerTableModel::KbpsIn, PeerTableModel::HdMaxPct})
      EXPECT_FALSE(dock.columnShown(column)) << column;
    EXPECT_EQ(dock.view()->horizontalHeader()->contextMenuPolicy(), Qt::CustomContextMenu);

    // The header's menu lists every column, checked as shown; Name cannot be hidden.
    std::unique_ptr<QMenu> menu(dock.makeColumnMenu(nullptr));
    const QList<QAction*> actions = menu->actions();
    ASSERT_EQ(actions.size(), PeerTableModel::ColumnCount);
    EXPECT_EQ(actions[PeerTableModel::LatencyMs]->text(), QStringLiteral("Delay ms"));
    EXPECT_FALSE(actions[PeerTableModel::Name]->isEnabled());
    EXPECT_FALSE(actions[PeerTableModel::LatencyMs]->isChecked());
    actions[PeerTableModel::LatencyMs]->trigger();  // show Delay ms
    actions[PeerTableModel::Lock]->trigger();       // hide Lock
    EXPECT_TRUE(dock.columnShown(PeerTableModel::LatencyMs));
    EXPECT_FALSE(dock.columnShown(PeerTableModel::Lock));
    dock.setColumnShown(PeerTableModel::Name, false);
    EXPECT_TRUE(dock.columnShown(PeerTableModel::Name));
  }
  // The next dock (the next session, the next start) shows what the user chose.
  PeersDock next(&model);
  EXPECT_TRUE(next.columnShown(PeerTableModel::LatencyMs));
  EXPECT_FALSE(next.columnShown(PeerTableModel::Lock));
  EXPECT_FALSE(next.columnShown(PeerTableModel::KbpsIn));
  QSettings().remove(QStringLiteral("peers/hiddenColumns"));
}
