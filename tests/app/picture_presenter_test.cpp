// PicturePresenter's decisions without GL: a fake view that never lets it draw (pictureScene() throws), so each test
// follows a path that decides before any slice is drawn. The GL paths (slices, patches, depth) are covered through
// MeshViewport in mesh_viewport_progressive_test.cpp.

#include "app/gui/viewport/picture_presenter.h"

#include <QCoreApplication>

#include <gtest/gtest.h>

#include <stdexcept>

namespace sc::app {
namespace {

ProgressivePicture::Key keyWith(unsigned shape, unsigned tints) {
  ProgressivePicture::Key key;
  key.shared = shape;
  key.tints = tints;
  key.size = QSize(64, 48);
  return key;
}

class FakeView final : public PicturePresenter::Host {
 public:
  bool possible = true;
  int triangles = 1000;
  bool proxy = false;
  ProgressivePicture::Key key = keyWith(1, 1);
  int repaints = 0;
  int contextRequests = 0;  // a slice asks for the context first

  [[nodiscard]] bool picturesPossible() const override { return possible; }
  [[nodiscard]] int pictureTriangles() const override { return triangles; }
  ProgressivePicture::Key currentPictureKey() override { return key; }
  [[nodiscard]] bool proxyMayDraw() const override { return proxy; }
  PictureScene pictureScene() override { throw std::logic_error("this test has no GL: nothing may be drawn"); }
  [[nodiscard]] bool pictureExposed() const override { return true; }
  QOpenGLFunctions_3_3_Core& pictureGl() override { throw std::logic_error("this test has no GL"); }
  bool makePictureCurrent() override {
    ++contextRequests;
    return false;
  }
  void releasePictureContext() override {}
  [[nodiscard]] bool pictureShapeLagging() const override { return false; }
  void repaintPicture() override { ++repaints; }
};

/// A presenter over a FakeView of 1000 triangles, active from 1000 on, and a paint's clock and times.
class PicturePresenterTest : public ::testing::Test {
 protected:
  PicturePresenterTest() { presenter.setMinimumTriangles(1000, 0); }
  /// A still (or `interactive`) window paint into framebuffer 0.
  PicturePresenter::Paint paint(bool interactive = false) { return presenter.show(0, interactive, stages, times); }

  FakeView view;
  PicturePresenter presenter{view};
  StageClock stages;
  FrameTimes times;
};

TEST_F(PicturePresenterTest, ActiveOnlyFromTheThresholdUpAndWhereTheViewCanDrawPictures) {
  EXPECT_TRUE(presenter.active());
  view.triangles = 999;
  EXPECT_FALSE(presenter.active());
  view.triangles = 5000;
  view.possible = false;  // e.g. multisampled, or adaptive resolution off
  EXPECT_FALSE(presenter.active());
  view.possible = true;
  presenter.setMinimumTriangles(0, 0);
  EXPECT_FALSE(presenter.active()) << "0 means never";
}

TEST_F(PicturePresenterTest, WhileTheProxyMayDrawAStillPaintStartsThePictureAndLetsTheProxyStandIn) {
  view.proxy = true;
  EXPECT_EQ(paint(), PicturePresenter::Paint::Proxy);
  EXPECT_TRUE(presenter.picture().drawing(view.key));
  EXPECT_EQ(presenter.picture().slices(), 0) << "the slices follow between paints";
  EXPECT_EQ(times.pictureSlices, 0);
  EXPECT_FALSE(presenter.current());
}

TEST_F(PicturePresenterTest, WithoutAProxyAnInteractivePaintDrawsAMeshShownWholeBeforeWhole) {
  presenter.windowPainted(false, false);  // the window showed the mesh whole (e.g. wireframe on)
  EXPECT_EQ(paint(true), PicturePresenter::Paint::Whole);
  EXPECT_TRUE(presenter.picture().drawing(view.key)) << "the picture is started for the still paints after it";
  // a new mesh was not shown whole: an interactive paint of it shows the slices so far, which needs GL here
  presenter.meshReplaced();
  EXPECT_THROW(paint(true), std::logic_error);
}

TEST_F(PicturePresenterTest, TheIdleRestoreRepaintsWhenInactiveStartsThePictureElseAndLeavesNewTintsToThePaint) {
  view.triangles = 10;
  presenter.continuePicture();
  EXPECT_EQ(view.repaints, 1) << "a small mesh is drawn whole by the repaint";
  view.triangles = 5000;
  presenter.continuePicture();
  EXPECT_EQ(view.repaints, 1);
  EXPECT_TRUE(presenter.picture().drawing(view.key)) << "the slices start; the window keeps its frame meanwhile";
  view.key = keyWith(1, 2);  // a brush dab: only the tints changed
  presenter.continuePicture();
  EXPECT_EQ(view.repaints, 2) << "the paint patches the picture rather than starting it over";
  EXPECT_FALSE(presenter.picture().drawing(view.key));
  view.key = keyWith(2, 2);  // a new shape: started over
  presenter.continuePicture();
  EXPECT_EQ(view.repaints, 2);
  EXPECT_TRUE(presenter.picture().drawing(view.key));
}

TEST_F(PicturePresenterTest, TheNextSliceWaitsForATurnOfTheEventLoop) {
  view.proxy = true;
  ASSERT_EQ(paint(), PicturePresenter::Paint::Proxy);
  EXPECT_EQ(view.contextRequests, 0) << "not within the paint";
  QCoreApplication::processEvents();
  EXPECT_EQ(view.contextRequests, 1) << "a slice was attempted on the next turn (no context here: none drawn)";
  EXPECT_TRUE(presenter.picture().drawing(view.key));
}

TEST_F(PicturePresenterTest, PickingDepthIsNotThePicturesWhenInactiveOrWithWireframe) {
  view.triangles = 10;
  EXPECT_FALSE(presenter.depthForPicking().has_value());
  view.triangles = 5000;
  view.key.wireframe = true;
  EXPECT_FALSE(presenter.depthForPicking().has_value());
  EXPECT_FALSE(presenter.picture().drawing()) << "nothing was started for it";
}

}  // namespace
}  // namespace sc::app
