// Issue 16: in the default 1100 × 800 window no text is cut off. A host and a client on loopback (two MainWindows in
// this process): every visible one-line label shows its whole text, every Peers cell its whole figure, the status
// bar's message fits beside its permanent fields and the progress bar's text fits the bar. Each window is
// saved as a PNG (QWidget::grab) into $SHAPECAST_TEST_SCREENSHOTS when that is set, to look at.

#include "app/gui/first_start.h"
#include "app/gui/main_window.h"
#include "app/gui/peers_dock.h"
#include "app/gui/repaint_batch.h"
#include "app/gui/session_docks.h"
#include "app/gui/statistics_dock.h"
#include "model/statistics_model.h"
#include "session_windows.h"

#include <gtest/gtest.h>

#include <QDir>
#include <QLabel>
#include <QProgressBar>
#include <QScrollBar>
#include <QSizeGrip>
#include <QStatusBar>
#include <QTableView>
#include <QTest>

#include <algorithm>
#include <string>

namespace sc::app {
namespace {

constexpr QSize kDefaultWindow{1100, 800};

/// Every visible, one-line, plain-text label of `window` whose text is wider than its contents or whose contents are
/// partly hidden by an ancestor: "name: text".
std::vector<std::string> clippedLabels(const QWidget& window) {
  std::vector<std::string> clipped;
  for (const QLabel* label : window.findChildren<QLabel*>()) {
    if (!label->isVisibleTo(&window) || label->wordWrap() || label->text().isEmpty() || label->text().contains('\n') ||
        Qt::mightBeRichText(label->text()))
      continue;
    // Wide enough, and not cut off by an ancestor (a scroll area's viewport, a dock narrower than its content).
    if (label->fontMetrics().horizontalAdvance(label->text()) > label->contentsRect().width() ||
        !label->visibleRegion().boundingRect().contains(label->contentsRect()))
      clipped.push_back(label->objectName().toStdString() + ": \"" + label->text().toStdString() + "\" needs " +
                        std::to_string(label->fontMetrics().horizontalAdvance(label->text())) + " px, has " +
                        std::to_string(label->contentsRect().width()));
  }
  return clipped;
}

/// Room for the status bar's message: up to the leftmost visible field beside it (size grip aside).
int messageRoom(const QStatusBar& bar) {
  int right = bar.width();
  for (const QWidget* child : bar.findChildren<QWidget*>(Qt::FindDirectChildrenOnly)) {
    if (child->isVisible() && qobject_cast<const QSizeGrip*>(child) == nullptr) right = std::min(right, child->x());
  }
  return right - 8;  // QStatusBar's message margin
}

void expectMessageFits(const MainWindow& window) {
  const QStatusBar& bar = *window.statusBar();
  const QString message = bar.currentMessage();
  EXPECT_LE(bar.fontMetrics().horizontalAdvance(message), messageRoom(bar)) << message.toStdString();
}

void save(MainWindow& window, const QString& name) {
  const QString dir = qEnvironmentVariable("SHAPECAST_TEST_SCREENSHOTS");
  if (dir.isEmpty()) return;
  window.docks()->repaintBatch()->releaseNow();  // grab() draws nothing of widgets whose painting is held
  QDir().mkpath(dir);
  EXPECT_TRUE(window.grabWindow().save(QDir(dir).filePath(name)));
}

class WindowTextFitTest : public sc::testing::TorusSessionTest {};

TEST_F(WindowTextFitTest, DocksAndStatusBarShowWholeTextsInTheDefaultWindow) {
  MainWindow hostWindow;
  MainWindow clientWindow;
  const LiveSession live = hostAndJoin(hostWindow, clientWindow, kDefaultWindow, kDefaultWindow);
  ASSERT_EQ(live.host->state(), SessionController::State::Live) << live.host->errorText().toStdString();
  ASSERT_NE(live.client, nullptr);
  ASSERT_EQ(live.client->state(), SessionController::State::Live) << live.client->errorText().toStdString();
  for (MainWindow* window : {&hostWindow, &clientWindow}) {
    const QLabel* latency = window->docks()->statisticsDock()->valueLabel(model::StatisticsModel::LatencyMs);
    ASSERT_TRUE(QTest::qWaitFor([latency] { return latency->text().endsWith(QStringLiteral(" ms")); }, 15000))
        << "figures arrive once a second";
  }
  // Two rows in each Peers table with their figures, then one more second for the layouts to settle.
  QTest::qWait(1500);
  for (MainWindow* window : {&hostWindow, &clientWindow}) {
    SCOPED_TRACE(window == &hostWindow ? "host" : "client");
    // Every shown Peers cell shows its whole text, and the table does not scroll sideways.
    const QTableView* peers = window->docks()->peersDock()->view();
    EXPECT_EQ(peers->model()->rowCount(), 2);
    EXPECT_EQ(peers->horizontalScrollBar()->maximum(), 0) << "the Peers table scrolls sideways";
    for (int column = 0; column < peers->model()->columnCount(); ++column) {
      if (peers->isColumnHidden(column)) continue;
      const QAbstractItemView* cells = peers;  // QTableView hides sizeHintForColumn()
      EXPECT_GE(peers->columnWidth(column), cells->sizeHintForColumn(column)) << "column " << column;
    }
    const std::vector<std::string> clipped = clippedLabels(*window);
    EXPECT_TRUE(clipped.empty()) << clipped.front();
    expectMessageFits(*window);
  }
  save(hostWindow, QStringLiteral("text-fit-host.png"));
  save(clientWindow, QStringLiteral("text-fit-client.png"));
}

TEST_F(WindowTextFitTest, FirstStartHintAndProgressFitTheDefaultWindow) {
  MainWindow window;
  sc::testing::showSessionWindow(window, kDefaultWindow);
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  const auto* progress = window.findChild<QProgressBar*>(QStringLiteral("sessionProgress"));
  ASSERT_NE(progress, nullptr);
  bool progressSeen = false;
  QObject::connect(progress, &QProgressBar::valueChanged, &window, [&] {
    if (!progress->isVisible()) return;
    progressSeen = true;
    EXPECT_LE(progress->fontMetrics().horizontalAdvance(progress->text()), progress->contentsRect().width() - 8)
        << progress->text().toStdString();
    expectMessageFits(window);
  });
  hostReadyToDrag(window, sc::testing::loopbackHostSettings(m_meshPath, 20));
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return window.statusBar()->currentMessage().contains(QStringLiteral("Session → Join")); },
                      sc::testing::kSessionLiveTimeoutMs));
  EXPECT_TRUE(progressSeen);
  QTest::qWait(200);
  expectMessageFits(window);
  const std::vector<std::string> clipped = clippedLabels(window);
  EXPECT_TRUE(clipped.empty()) << clipped.front();
  save(window, QStringLiteral("text-fit-first-start.png"));
}

}  // namespace
}  // namespace sc::app
