// Tests for src/app/gui/viewport/progressive_picture.cpp and MeshViewport's use of it: the full picture of a large
// mesh drawn in slices between paints equals the mesh drawn whole, a change of view starts it over, and meshes below
// the threshold are drawn as before (needs an X server with GL). A small mesh stands in for a large one by lowering
// the threshold and capping the slices.

#include "app/gui/mesh_viewport.h"

#include "app_test_support.h"
#include "synthetic_basis.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QTest>

#include <algorithm>
#include <numeric>
#include <utility>
#include <vector>

namespace {

using sc::app::MeshViewport;
using sc::app::ReconstructionPath;

constexpr int kSliceLimit = 3000;  // triangles per slice: the 20,480-triangle sphere takes seven slices

/// Pixels whose colour differs by more than one step in a channel.
int differingPixels(const QImage& a, const QImage& b) { return sc::testing::countDifferentPixels(a, b, 1); }

class MeshViewportProgressivePicture : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sc::testing::openGlAvailable()) GTEST_SKIP() << "no OpenGL 3.3 context (run under xvfb-run)";
    const auto sphere = sc::testing::icosphere(5, 1.0, Eigen::Vector3d::Zero());
    viewport.resize(400, 300);
    viewport.setMesh(sphere.V, sphere.F);
    viewport.setAdaptiveResolution(true);
    viewport.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&viewport));
  }
  /// Waits until the complete picture is that of the current view (slices run on the event loop).
  bool waitForCurrentPicture() {
    return QTest::qWaitFor([this] { return viewport.progressivePictureCurrent(); }, 20000);
  }

  /// The whole mesh drawn in one pass at full resolution: a grab (never sliced) with adaptive resolution off, since
  /// under ctest -j2 another test's window can expose this one and make the grab an interactive, reduced frame.
  QImage wholeMesh() {
    viewport.setAdaptiveResolution(false);
    QImage image = viewport.grabFramebuffer();
    EXPECT_EQ(viewport.frameTimes().renderScale, 1.0);
    viewport.setAdaptiveResolution(true);
    return image;
  }

  MeshViewport viewport;
};

TEST_F(MeshViewportProgressivePicture, AStillPictureIsDrawnInSlicesAndEqualsTheMeshDrawnWhole) {
  for (const bool wireframe : {false, true}) {
    SCOPED_TRACE(wireframe ? "wireframe" : "shaded");
    viewport.setWireframe(wireframe);
    viewport.setProgressivePicture(1000, kSliceLimit);
    // a new mesh: its picture's slices are drawn between paints (once a mesh was shown whole, a still paint without a
    // proxy would draw the rest of its picture at once). Set after an idle pause, so that its first paint is not an
    // interactive frame of a moving shape (one soon after the last paint or grab), which draws the mesh whole.
    ASSERT_TRUE(waitForCurrentPicture());
    QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
    const auto sphere = sc::testing::icosphere(5, 1.0, Eigen::Vector3d(wireframe ? 0.1 : 0.0, 0.0, 0.0));
    viewport.setMesh(sphere.V, sphere.F);
    // a still paint in the middle (an expose: a loaded machine's, another window's) shows the slices so far
    ASSERT_TRUE(QTest::qWaitFor([this] { return viewport.progressivePicture().slices() >= 2; }, 20000));
    viewport.repaint();
    ASSERT_TRUE(waitForCurrentPicture());
    EXPECT_GE(viewport.progressivePicture().slices(), viewport.triangleCount() / kSliceLimit)
        << "drawn a slice at a time";
    QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);  // the paint that shows it, and the restore timer's
    const int requests = viewport.repaintRequestCount();
    QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 3);
    EXPECT_EQ(viewport.repaintRequestCount(), requests) << "a complete picture asks for no more paints";
    EXPECT_TRUE(viewport.progressivePictureCurrent());
    const QImage picture = viewport.progressivePictureImage();
    const QImage whole = wholeMesh();
    ASSERT_FALSE(picture.isNull());
    EXPECT_EQ(picture.size(), whole.size());
    EXPECT_EQ(differingPixels(picture, whole), 0) << "slices drawn in order over one depth buffer: the same picture";
  }
}

TEST_F(MeshViewportProgressivePicture, AChangeOfViewStartsThePictureOverAndItShowsTheNewView) {
  viewport.setProgressivePicture(1000, kSliceLimit);
  ASSERT_TRUE(waitForCurrentPicture());
  const QImage before = viewport.progressivePictureImage();
  const int completed = viewport.progressivePicture().completed();
  viewport.lookFrom({3.0f, 1.0f, 0.5f}, {0.2f, 0.0f, 0.0f});
  EXPECT_FALSE(viewport.progressivePictureCurrent()) << "the picture of the old view is not shown for the new one";
  ASSERT_TRUE(waitForCurrentPicture());
  EXPECT_GT(viewport.progressivePicture().completed(), completed);
  const QImage after = viewport.progressivePictureImage();
  EXPECT_GT(differingPixels(before, after), 100) << "the view changed";
  EXPECT_EQ(differingPixels(after, wholeMesh()), 0);
}

// A display level's frames on either reconstruction path: a new Z (CPU: new positions; GPU: the shader's uniforms)
// makes the picture stale, and the picture drawn for it equals the frame drawn whole.
TEST_F(MeshViewportProgressivePicture, AFrameOfANewZStartsThePictureOverOnEitherPath) {
  const auto sphere = sc::testing::icosphere(5, 1.0, Eigen::Vector3d::Zero());
  const int m = 24;
  viewport.setDisplayLevel(
      sc::spectral::makeDisplayLevel({sphere.V, sphere.F, {}, sc::testing::syntheticBasis(sphere.V, m, 0.08f)}));
  viewport.setProgressivePicture(1000, kSliceLimit);
  for (const ReconstructionPath path : {ReconstructionPath::Cpu, ReconstructionPath::Gpu}) {
    viewport.setReconstructionPath(path);
    if (viewport.reconstructionPath() != path) {  // only where this context cannot draw the basis
      EXPECT_FALSE(viewport.gpuReconstructionAvailable());
      continue;
    }
    SCOPED_TRACE(path == ReconstructionPath::Gpu ? "gpu" : "cpu");
    for (const unsigned seed : {1U, 2U}) {
      viewport.showFrame(
          {seed + (path == ReconstructionPath::Gpu ? 10U : 0U), sc::testing::randomCoefficients(m, 1.0f, seed)});
      EXPECT_FALSE(viewport.progressivePictureCurrent()) << "the shape changed";
      ASSERT_TRUE(waitForCurrentPicture());
      EXPECT_EQ(differingPixels(viewport.progressivePictureImage(), wholeMesh()), 0);
    }
  }
}

TEST_F(MeshViewportProgressivePicture, ABrushStrokeReadsTheCompletePicturesDepthAndPaintsWhatADepthPassWould) {
  // A big sphere under a small one: a dab on the small one, off the middle of the view, lands elsewhere on the
  // shape (or off it) if the depth's rows were read upside down.
  const auto shape = sc::testing::joined(sc::testing::icosphere(5, 1.0, Eigen::Vector3d::Zero()),
                                         sc::testing::icosphere(4, 0.45, Eigen::Vector3d(0.0, 1.5, 0.0)));
  viewport.setMesh(shape.V, shape.F);
  viewport.setTool(sc::app::ViewportTool::HandleBrush);
  viewport.setBrushRadius(12.0);
  static constexpr QPoint kDab(200, 45);
  // a dab on the small sphere, from an empty selection (its tints start a new picture: waited for when `progressive`)
  const auto stroke = [this](bool progressive) {
    viewport.setSelection({}, {});
    EXPECT_TRUE(!progressive || waitForCurrentPicture());
    QTest::mousePress(&viewport, Qt::LeftButton, {}, kDab);
    QTest::mouseRelease(&viewport, Qt::LeftButton, {}, kDab);
    return viewport.handles();
  };
  viewport.setProgressivePicture(1000, kSliceLimit);
  const std::vector<int> fromPicture = stroke(true);
  EXPECT_EQ(viewport.progressivePicture().depthReads(), 1) << "the stroke's depth was read back, not drawn";
  viewport.setProgressivePicture(0);  // off: a depth pass over the whole mesh
  const std::vector<int> drawn = stroke(false);
  EXPECT_EQ(viewport.progressivePicture().depthReads(), 1);
  EXPECT_GT(drawn.size(), 10U) << "the dab covers visible vertices";
  const int bigSphere = static_cast<int>(sc::testing::icosphere(5).V.rows());
  EXPECT_TRUE(std::all_of(drawn.begin(), drawn.end(), [bigSphere](int v) { return v >= bigSphere; }))
      << "all on the small sphere";
  EXPECT_EQ(fromPicture, drawn);
  viewport.setProgressivePicture(1000, kSliceLimit);
  viewport.setWireframe(true);  // the picture's fill is pushed back under its edges: not a picking depth
  EXPECT_EQ(stroke(true), drawn);
  EXPECT_EQ(viewport.progressivePicture().depthReads(), 1);
  // a stroke before the picture is complete (a new mesh here, as soon after an orbit): the press completes the
  // picture and reads its depth, and the paint after the dab patches it
  viewport.setWireframe(false);
  viewport.setMesh(shape.V, shape.F);
  viewport.repaint();
  const int completed = viewport.progressivePicture().completed();
  const int patches = viewport.progressivePicture().patches();
  QTest::mousePress(&viewport, Qt::LeftButton, {}, kDab);
  QTest::mouseRelease(&viewport, Qt::LeftButton, {}, kDab);
  EXPECT_EQ(viewport.handles(), drawn);
  EXPECT_EQ(viewport.progressivePicture().depthReads(), 2);
  EXPECT_EQ(viewport.progressivePicture().completed(), completed + 1) << "completed by the press";
  viewport.repaint();
  EXPECT_EQ(viewport.progressivePicture().patches(), patches + 1);
  EXPECT_TRUE(viewport.progressivePictureCurrent());
  EXPECT_EQ(differingPixels(viewport.progressivePictureImage(), wholeMesh()), 0);
}

// Without a proxy, a new mesh shows its slices as they come; once the window has shown it whole, a still change that
// cannot be patched (wireframe here) draws the rest of its new picture in a still paint, as it would the whole mesh,
// rather than show the slices so far (an interactive paint draws the whole mesh, reduced); that picture equals the
// whole draw.
TEST_F(MeshViewportProgressivePicture, WithoutAProxyOnlyANewMeshShowsItsSlicesSoFar) {
  viewport.setProgressivePicture(1000, kSliceLimit);
  // The first paint of a new mesh, not an interactive one (a moving frame draws whole): under ctest -j2 another
  // test's window can expose this one just before, so try again a few times.
  bool slicesSoFar = false;
  for (int attempt = 0; attempt < 20 && !slicesSoFar; ++attempt) {
    const auto sphere = sc::testing::icosphere(5, 1.0, Eigen::Vector3d(0.5 + 0.01 * attempt, 0.0, 0.0));
    QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
    viewport.setMesh(sphere.V, sphere.F);
    viewport.repaint();
    slicesSoFar = viewport.frameTimes().pictureSlices >= 1;
  }
  EXPECT_TRUE(slicesSoFar) << "the new mesh's slices so far";
  ASSERT_TRUE(waitForCurrentPicture());
  QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
  viewport.repaint();
  EXPECT_EQ(viewport.frameTimes().pictureSlices, viewport.progressivePicture().slices()) << "the complete picture";
  // a still paint (as above, another test's window may make one interactive: then the mesh is drawn whole, reduced)
  bool completedInThePaint = false;
  for (int attempt = 0; attempt < 20 && !completedInThePaint; ++attempt) {
    QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
    const int completed = viewport.progressivePicture().completed();
    viewport.setWireframe(!viewport.wireframe());
    viewport.repaint();
    completedInThePaint = viewport.progressivePicture().completed() == completed + 1;
    if (!completedInThePaint) {
      EXPECT_EQ(viewport.frameTimes().pictureSlices, 0) << "drawn whole";
    }
  }
  ASSERT_TRUE(completedInThePaint) << "the new picture completed in the paint";
  EXPECT_EQ(viewport.frameTimes().pictureSlices, viewport.progressivePicture().slices()) << "and shown";
  EXPECT_LE(viewport.progressivePicture().slices(), 2) << "its first slice (the paint's) and the rest";
  EXPECT_TRUE(viewport.progressivePictureCurrent());
  EXPECT_EQ(differingPixels(viewport.progressivePictureImage(), wholeMesh()), 0);
}

// New tints alone (a brush dab, a selection) patch the complete picture: only the triangles around the vertices whose
// tint changed are redrawn over it, and it equals the mesh drawn whole with those tints, on either reconstruction
// path; tints over a quarter of the mesh start the picture over instead.
TEST_F(MeshViewportProgressivePicture, NewTintsPatchTheCompletePictureAndItEqualsTheMeshDrawnWhole) {
  const auto sphere = sc::testing::icosphere(5, 1.0, Eigen::Vector3d::Zero());
  const int m = 24;
  viewport.setDisplayLevel(
      sc::spectral::makeDisplayLevel({sphere.V, sphere.F, {}, sc::testing::syntheticBasis(sphere.V, m, 0.08f)}));
  viewport.showFrame({1U, sc::testing::randomCoefficients(m, 1.0f, 1U)});
  viewport.setProgressivePicture(1000, kSliceLimit);
  const int n = static_cast<int>(sphere.V.rows());
  // vertices near +z (facing the default camera or not, whichever: the test compares pictures) and near +x
  std::vector<int> handles;
  std::vector<int> anchors;
  for (int v = 0; v < n; ++v) {
    if (sphere.V(v, 2) > 0.9) handles.push_back(v);
    if (sphere.V(v, 0) > 0.9) anchors.push_back(v);
  }
  ASSERT_GT(handles.size(), 20U);
  ASSERT_GT(anchors.size(), 20U);
  for (const ReconstructionPath path : {ReconstructionPath::Cpu, ReconstructionPath::Gpu}) {
    viewport.setReconstructionPath(path);
    if (viewport.reconstructionPath() != path) {
      EXPECT_FALSE(viewport.gpuReconstructionAvailable());
      continue;
    }
    SCOPED_TRACE(path == ReconstructionPath::Gpu ? "gpu" : "cpu");
    viewport.setSelection({}, {});
    ASSERT_TRUE(waitForCurrentPicture());
    for (const auto& [h, a] : {std::pair{handles, std::vector<int>{}}, std::pair{handles, anchors},
                               std::pair{std::vector<int>{}, anchors}}) {
      const int completed = viewport.progressivePicture().completed();
      const int patches = viewport.progressivePicture().patches();
      const QImage before = viewport.progressivePictureImage();
      viewport.setSelection(h, a);
      viewport.repaint();
      EXPECT_EQ(viewport.progressivePicture().patches(), patches + 1) << "patched in the paint";
      EXPECT_TRUE(viewport.progressivePictureCurrent());
      EXPECT_EQ(viewport.progressivePicture().completed(), completed) << "not drawn again";
      EXPECT_EQ(viewport.frameTimes().pictureSlices, viewport.progressivePicture().slices()) << "the picture shown";
      const QImage after = viewport.progressivePictureImage();
      EXPECT_GT(differingPixels(before, after), 100) << "the changed tints are in view";
      EXPECT_EQ(differingPixels(after, wholeMesh()), 0);
    }
  }
  // new tints while the picture of a new mesh is being drawn: the slices so far are patched, the rest draw the new
  // tints, and the picture is not started over. The first paint of the mesh draws its first slice (not when it is an
  // interactive paint: under ctest -j2 another test's window can expose this one just before, so try again).
  bool drawing = false;
  for (int attempt = 0; attempt < 20 && !drawing; ++attempt) {
    QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
    viewport.setMesh(sphere.V, sphere.F);
    viewport.repaint();
    drawing = viewport.progressivePicture().slices() == 1 && !viewport.progressivePictureCurrent();
  }
  ASSERT_TRUE(drawing) << "the new mesh's first slice";
  const int patchCount = viewport.progressivePicture().patches();
  const int completedCount = viewport.progressivePicture().completed();
  viewport.setSelection(handles, anchors);
  viewport.repaint();
  EXPECT_EQ(viewport.progressivePicture().patches(), patchCount + 1) << "the first slice patched";
  EXPECT_EQ(viewport.progressivePicture().slices(), 1) << "not started over";
  ASSERT_TRUE(waitForCurrentPicture());
  EXPECT_EQ(viewport.progressivePicture().patches(), patchCount + 1) << "the paints of later slices patch nothing";
  EXPECT_EQ(viewport.progressivePicture().completed(), completedCount + 1);
  EXPECT_GT(viewport.progressivePicture().slices(), 1) << "the same picture went on";
  EXPECT_EQ(differingPixels(viewport.progressivePictureImage(), wholeMesh()), 0);

  std::vector<int> most(static_cast<std::size_t>(n / 2));
  std::iota(most.begin(), most.end(), 0);
  const int patches = viewport.progressivePicture().patches();
  viewport.setSelection(most, {});
  viewport.repaint();
  EXPECT_EQ(viewport.progressivePicture().patches(), patches) << "half the mesh: started over, not patched";
  ASSERT_TRUE(waitForCurrentPicture());
  EXPECT_EQ(differingPixels(viewport.progressivePictureImage(), wholeMesh()), 0);
}

TEST_F(MeshViewportProgressivePicture, AMeshBelowTheThresholdIsDrawnWholeInEachPaint) {
  viewport.repaint();
  QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
  viewport.repaint();
  EXPECT_EQ(viewport.progressivePicture().slices(), 0);
  EXPECT_EQ(viewport.progressivePicture().completed(), 0);
  EXPECT_EQ(viewport.frameTimes().triangles, viewport.triangleCount());
}

}  // namespace
