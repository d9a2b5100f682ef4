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

TEST(PicturePresenter, ActiveOnlyFromTheThresholdUpAndWhereTheViewCanDrawPictures) {
  FakeView view;
  PicturePresenter presenter(view);
  presenter.setMinimumTriangles(1000, 0);
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

TEST(PicturePresenter, WhileTheProxyMayDrawAStillPaintStartsThePictureAndLetsTheProxyStandIn) {
  FakeView view;
  view.proxy = true;
  PicturePresenter presenter(view);
  presenter.setMinimumTriangles(1000, 0);
  StageClock stages;
  FrameTimes times;
  EXPECT_EQ(presenter.show(0, false, stages, times), PicturePresenter::Paint::Proxy);
  EXPECT_TRUE(presenter.picture().drawing(view.key));
  EXPECT_EQ(presenter.picture().slices(), 0) << "the slices follow between paints";
  EXPECT_EQ(times.pictureSlices, 0);
  EXPECT_FALSE(presenter.current());
}

TEST(PicturePresenter, WithoutAProxyAnInteractivePaintDrawsAMeshShownWholeBeforeWhole) {
  FakeView view;
  PicturePresenter presenter(view);
  presenter.setMinimumTriangles(1000, 0);
  presenter.windowPainted(false, false);  // the window showed the mesh whole (e.g. wireframe on)
  StageClock stages;
  FrameTimes times;
  EXPECT_EQ(presenter.show(0, true, stages, times), PicturePresenter::Paint::Whole);
  EXPECT_TRUE(presenter.picture().drawing(view.key)) << "the picture is started for the still paints after it";
  // a new mesh was not shown whole: an interactive paint of it shows the slices so far, which needs GL here
  presenter.meshReplaced();
  EXPECT_THROW(presenter.show(0, true, stages, times), std::logic_error);
}

TEST(PicturePresenter, TheIdleRestoreRepaintsWhenInactiveStartsThePictureElseAndLeavesNewTintsToThePaint) {
  FakeView view;
  PicturePresenter presenter(view);
  presenter.setMinimumTriangles(1000, 0);
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

TEST(PicturePresenter, TheNextSliceWaitsForATurnOfTheEventLoop) {
  FakeView view;
  view.proxy = true;
  PicturePresenter presenter(view);
  presenter.setMinimumTriangles(1000, 0);
  StageClock stages;
  FrameTimes times;
  ASSERT_EQ(presenter.show(0, false, stages, times), PicturePresenter::Paint::Proxy);
  EXPECT_EQ(view.contextRequests, 0) << "not within the paint";
  QCoreApplication::processEvents();
  EXPECT_EQ(view.contextRequests, 1) << "a slice was attempted on the next turn (no context here: none drawn)";
  EXPECT_TRUE(presenter.picture().drawing(view.key));
}

TEST(PicturePresenter, PickingDepthIsNotThePicturesWhenInactiveOrWithWireframe) {
  FakeView view;
  PicturePresenter presenter(view);
  presenter.setMinimumTriangles(1000, 0);
  view.triangles = 10;
  EXPECT_FALSE(presenter.depthForPicking().has_value());
  view.triangles = 5000;
  view.key.wireframe = true;
  EXPECT_FALSE(presenter.depthForPicking().has_value());
  EXPECT_FALSE(presenter.picture().drawing()) << "nothing was started for it";
}

}  // namespace
}  // namespace sc::app
