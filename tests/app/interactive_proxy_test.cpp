// Tests for the interactive proxy: MeshViewport draws it in interactive frames and the full mesh once idle
// (src/app/gui/mesh_viewport_render.cpp), and InteractiveProxyBuilder computes it off the GUI thread and applies
// it only to the mesh it was built for (src/app/gui/interactive_proxy.cpp). Needs an X server with GL.

#include "app/gui/interactive_proxy.h"
#include "app/gui/mesh_viewport.h"
#include "model/mesh_proxy.h"
#include "spectral/reconstruction_kernel.h"

#include "app_test_support.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QSignalSpy>
#include <QTest>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace {

using sc::app::InteractiveProxyBuilder;
using sc::app::MeshViewport;

/// Pixels of `image` that differ from `background`, as a mask.
std::vector<bool> coverage(const QImage& image, const QImage& background) {
  std::vector<bool> mask;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) mask.push_back(image.pixel(x, y) != background.pixel(x, y));
  return mask;
}

class InteractiveProxyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!sc::testing::openGlAvailable()) GTEST_SKIP() << "no OpenGL 3.3 context (run under xvfb-run)";
  }
};

// Frames painted right after each other draw the proxy's triangles; the idle restore draws the mesh's. Both
// pictures cover the same pixels (the proxy follows the surface).
TEST_F(InteractiveProxyTest, InteractiveFramesDrawTheProxyAndTheIdleFrameTheMesh) {
  const auto sphere = sc::testing::icosphere(5);  // 20,480 triangles
  MeshViewport viewport;
  viewport.resize(320, 240);
  viewport.setMesh(sphere.V, sphere.F);
  viewport.setAdaptiveResolution(true);
  viewport.setPaintBudget(1e6);  // keeps every frame at full pixel resolution: only the triangles change
  viewport.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&viewport));
  QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
  const QImage full = viewport.grabFramebuffer();
  EXPECT_EQ(viewport.frameTimes().triangles, sphere.F.rows());

  viewport.setInteractiveProxy(sc::model::proxyTriangles(sphere.V, sphere.F, 2000));
  ASSERT_GT(viewport.proxyTriangleCount(), 1500);
  ASSERT_LT(viewport.proxyTriangleCount(), 2500);
  QImage interactive;
  for (int i = 0; i < 3; ++i) {  // frames of a moving shape, right after each other
    viewport.setPositions(sphere.V);
    interactive = viewport.grabFramebuffer();
  }
  EXPECT_EQ(viewport.frameTimes().triangles, viewport.proxyTriangleCount());
  EXPECT_EQ(viewport.frameTimes().renderScale, 1.0);
  // A paint right after, but nothing moved (e.g. a brush hovering): the mesh itself.
  static_cast<void>(viewport.grabFramebuffer());
  EXPECT_EQ(viewport.frameTimes().triangles, sphere.F.rows());

  const int painted = viewport.paintCount();
  QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 3);
  EXPECT_GT(viewport.paintCount(), painted) << "the view redrew itself in full once idle";
  EXPECT_EQ(viewport.frameTimes().triangles, sphere.F.rows());

  const QImage background = [] {
    MeshViewport empty;
    empty.resize(320, 240);
    empty.show();
    EXPECT_TRUE(QTest::qWaitForWindowExposed(&empty));
    return empty.grabFramebuffer();
  }();
  const std::vector<bool> a = coverage(full, background), b = coverage(interactive, background);
  ASSERT_EQ(a.size(), b.size());
  std::size_t covered = 0, disagree = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    covered += a[i] ? 1 : 0;
    disagree += a[i] != b[i] ? 1 : 0;
  }
  EXPECT_GT(covered, a.size() / 10) << "the sphere is on screen";
  EXPECT_LT(static_cast<double>(disagree), 0.03 * static_cast<double>(covered)) << "the proxy has the mesh's outline";
}

/// Triangles drawn by a frame of a moving shape right after another one.
int trianglesOfAMovingFrame(MeshViewport& viewport, const Eigen::MatrixXd& V) {
  for (int i = 0; i < 2; ++i) {
    viewport.setPositions(V);
    static_cast<void>(viewport.grabFramebuffer());  // a paint
  }
  return viewport.frameTimes().triangles;
}

TEST_F(InteractiveProxyTest, TheMeshItselfWithoutAdaptiveResolutionInWireframeOrWhenASelectionWouldVanish) {
  const auto sphere = sc::testing::icosphere(4);
  MeshViewport viewport;
  viewport.resize(200, 150);
  viewport.setMesh(sphere.V, sphere.F);
  viewport.setAdaptiveResolution(true);
  const Eigen::MatrixXi proxy = sc::model::proxyTriangles(sphere.V, sphere.F, 500);
  viewport.setInteractiveProxy(proxy);
  viewport.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&viewport));
  const auto full = static_cast<int>(sphere.F.rows());
  ASSERT_EQ(trianglesOfAMovingFrame(viewport, sphere.V), viewport.proxyTriangleCount());

  viewport.setWireframe(true);
  EXPECT_EQ(trianglesOfAMovingFrame(viewport, sphere.V), full) << "wireframe shows the real edges";
  viewport.setWireframe(false);

  // A one-vertex handle the proxy does not use would vanish: the mesh is drawn; one it uses shows: the proxy.
  std::vector<bool> used(static_cast<std::size_t>(sphere.V.rows()), false);
  for (Eigen::Index i = 0; i < proxy.size(); ++i) used[static_cast<std::size_t>(proxy(i))] = true;
  const auto notUsed = static_cast<int>(std::find(used.begin(), used.end(), false) - used.begin());
  const auto usedVertex = static_cast<int>(std::find(used.begin(), used.end(), true) - used.begin());
  ASSERT_LT(notUsed, sphere.V.rows());
  viewport.setSelection({notUsed}, {});
  EXPECT_EQ(trianglesOfAMovingFrame(viewport, sphere.V), full);
  viewport.setSelection({notUsed, usedVertex}, {});
  EXPECT_EQ(trianglesOfAMovingFrame(viewport, sphere.V), viewport.proxyTriangleCount());

  viewport.setAdaptiveResolution(false);
  EXPECT_EQ(trianglesOfAMovingFrame(viewport, sphere.V), full);
}

TEST_F(InteractiveProxyTest, ANewMeshDropsTheProxy) {
  const auto sphere = sc::testing::icosphere(4);
  MeshViewport viewport;
  viewport.setMesh(sphere.V, sphere.F);
  viewport.setInteractiveProxy(sc::model::proxyTriangles(sphere.V, sphere.F, 500));
  ASSERT_GT(viewport.proxyTriangleCount(), 0);
  viewport.setMesh(sphere.V, sphere.F);
  EXPECT_EQ(viewport.proxyTriangleCount(), 0);
  viewport.setInteractiveProxy(sc::model::proxyTriangles(sphere.V, sphere.F, 500));
  viewport.clearMesh();
  EXPECT_EQ(viewport.proxyTriangleCount(), 0);
}

// A client's frames on the CPU path (showFrame()): interactive frames draw the proxy, the mesh's positions
// follow when asked for (hostPositions()), and the idle frame draws the mesh at the latest coefficients: the
// same picture as a viewport that never had a proxy.
TEST_F(InteractiveProxyTest, CoefficientFramesDrawTheProxyAndTheIdleFrameTheMeshAtTheLatestCoefficients) {
  const auto sphere = sc::testing::icosphere(5);
  constexpr int m = 8;
  Eigen::MatrixXd values(sphere.V.rows(), m);
  for (Eigen::Index i = 0; i < values.rows(); ++i)
    for (Eigen::Index k = 0; k < m; ++k)
      values(i, k) = 0.08 * std::sin(static_cast<double>(k + 1) * sphere.V(i, k % 3));
  const sc::spectral::QuantizedBasis K = sc::spectral::quantizeBasis(values);
  Eigen::MatrixXf Z = Eigen::MatrixXf::Zero(m, 3);
  Z(0, 0) = 1.0f;
  Z(1, 1) = -1.0f;
  Z(2, 2) = 0.7f;
  Z(5, 0) = 0.9f;
  const std::vector<float> rest = sc::spectral::interleavedPositions(sphere.V);
  std::vector<float> expected(rest.size());
  sc::spectral::reconstructInterleaved(K, rest, Z, expected);
  const auto prepare = [&](MeshViewport& view) {
    view.resize(320, 240);
    view.setMesh(sphere.V, sphere.F);
    view.setAdaptiveResolution(true);
    view.setPaintBudget(1e6);  // full pixel resolution: only the triangles change
    view.setReconstructionPath(sc::app::ReconstructionPath::Cpu);
    view.setDisplayLevel(sc::spectral::makeDisplayLevel({sphere.V, sphere.F, {}, K}));
    view.show();
    return QTest::qWaitForWindowExposed(&view);
  };
  MeshViewport reference;
  ASSERT_TRUE(prepare(reference));
  reference.showFrame({1, Z});
  QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
  const QImage expectedImage = reference.grabFramebuffer();

  MeshViewport viewport;
  ASSERT_TRUE(prepare(viewport));
  viewport.setInteractiveProxy(sc::model::proxyTriangles(sphere.V, sphere.F, 2000));
  static_cast<void>(viewport.grabFramebuffer());  // a paint
  for (int i = 1; i <= 3; ++i) {                  // frames of a moving shape, right after each other
    viewport.showFrame({static_cast<std::uint32_t>(i), Z * static_cast<float>(i) / 3.0f});
    static_cast<void>(viewport.grabFramebuffer());  // a paint
    EXPECT_EQ(viewport.frameTimes().triangles, viewport.proxyTriangleCount()) << "frame " << i;
  }
  QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
  const QImage idle = viewport.grabFramebuffer();
  EXPECT_EQ(viewport.frameTimes().triangles, sphere.F.rows());
  ASSERT_EQ(idle.size(), expectedImage.size());
  int differ = 0;
  for (int y = 0; y < idle.height(); ++y)
    for (int x = 0; x < idle.width(); ++x) differ += idle.pixel(x, y) != expectedImage.pixel(x, y) ? 1 : 0;
  EXPECT_LT(differ, idle.width() * idle.height() / 200) << "the idle frame shows the mesh at the latest Z";

  const std::vector<float> host = viewport.hostPositions();
  ASSERT_EQ(host.size(), expected.size());
  for (std::size_t i = 0; i < host.size(); ++i) ASSERT_NEAR(host[i], expected[i], 1e-5f) << "coordinate " << i;
}

class InteractiveProxyBuilderTest : public InteractiveProxyTest {
 protected:
  void SetUp() override {
    InteractiveProxyTest::SetUp();
    viewport.setAdaptiveResolution(true);
  }
  const sc::testing::GeneratedMesh dense = sc::testing::torus(300, 125);  // 75,000 triangles
  MeshViewport viewport;
};

// The builder works for dense meshes only, off the GUI thread, and a proxy built for a mesh that was replaced
// in the meantime is thrown away.
TEST_F(InteractiveProxyBuilderTest, AppliesTheProxyOfTheCurrentDenseMeshOnly) {
  ASSERT_GT(dense.F.rows(), InteractiveProxyBuilder::kMinTriangles);
  InteractiveProxyBuilder builder(&viewport);
  QSignalSpy applied(&builder, &InteractiveProxyBuilder::proxyApplied);

  viewport.setMesh(dense.V, dense.F);
  builder.build(dense.V, dense.F);
  EXPECT_TRUE(builder.busy());
  EXPECT_EQ(viewport.proxyTriangleCount(), 0) << "built on a worker thread, not in build()";
  ASSERT_TRUE(applied.wait(30000));
  EXPECT_NEAR(viewport.proxyTriangleCount(), InteractiveProxyBuilder::kProxyTriangles,
              0.1 * InteractiveProxyBuilder::kProxyTriangles);
  EXPECT_EQ(applied.front().front().toInt(), viewport.proxyTriangleCount());
  EXPECT_FALSE(builder.busy());

  // The same faces again (a host showing its mesh again): the proxy comes back at once.
  viewport.setMesh(dense.V, dense.F);
  ASSERT_EQ(viewport.proxyTriangleCount(), 0);
  builder.build(dense.V, dense.F);
  EXPECT_FALSE(builder.busy());
  EXPECT_EQ(applied.size(), 2);
  EXPECT_GT(viewport.proxyTriangleCount(), 0);

  // Replaced while building: the stale proxy is not applied.
  const auto other = sc::testing::torus(310, 125);
  viewport.setMesh(other.V, other.F);
  builder.build(other.V, other.F);
  const auto small = sc::testing::icosphere(3);
  viewport.setMesh(small.V, small.F);
  builder.build(small.V, small.F);  // small: no proxy wanted, and the waiting build (if any) is dropped
  QTRY_VERIFY_WITH_TIMEOUT(!builder.busy(), 30000);
  QTest::qWait(50);
  EXPECT_EQ(applied.size(), 2);
  EXPECT_EQ(viewport.proxyTriangleCount(), 0);
}

// A client's shared display level: the worker reads the level in place (nothing is copied on the GUI thread), the
// same level again gets its proxy at once, and the builder remembers the level without keeping it alive.
TEST_F(InteractiveProxyBuilderTest, BuildsFromASharedLevelInPlaceWithoutHoldingIt) {
  InteractiveProxyBuilder builder(&viewport);
  QSignalSpy applied(&builder, &InteractiveProxyBuilder::proxyApplied);
  sc::spectral::SharedDisplayLevel level = sc::spectral::makeDisplayLevel({dense.V, dense.F, {}, {}});
  viewport.setDisplayLevel(level);
  builder.build(level);
  EXPECT_TRUE(builder.busy());
  EXPECT_EQ(viewport.proxyTriangleCount(), 0) << "built on a worker thread, not in build()";
  ASSERT_TRUE(applied.wait(30000));
  EXPECT_NEAR(viewport.proxyTriangleCount(), InteractiveProxyBuilder::kProxyTriangles,
              0.1 * InteractiveProxyBuilder::kProxyTriangles);
  const int built = viewport.proxyTriangleCount();

  viewport.setDisplayLevel(level);  // shown again: the proxy was dropped, and comes back at once
  ASSERT_EQ(viewport.proxyTriangleCount(), 0);
  builder.build(level);
  EXPECT_FALSE(builder.busy());
  EXPECT_EQ(applied.size(), 2);
  EXPECT_EQ(viewport.proxyTriangleCount(), built);

  const std::weak_ptr<const sc::spectral::DisplayLevel> watch = level;
  viewport.clearMesh();
  level.reset();
  // The build's worker thread lets go of its job when it ends, a moment after it handed the proxy over.
  QTRY_VERIFY_WITH_TIMEOUT(watch.expired(), 5000);
}

// A mesh replaced while its proxy is being built: the waiting build of the new mesh runs next and is applied.
TEST_F(InteractiveProxyBuilderTest, AWaitingBuildRunsAfterTheStaleOne) {
  InteractiveProxyBuilder builder(&viewport);
  QSignalSpy applied(&builder, &InteractiveProxyBuilder::proxyApplied);
  viewport.setMesh(dense.V, dense.F);
  builder.build(dense.V, dense.F);
  const auto other = sc::testing::torus(200, 190);  // 76,000 triangles, fewer vertices
  viewport.setMesh(other.V, other.F);
  builder.build(other.V, other.F);  // waits for the first, which is stale now
  ASSERT_TRUE(applied.wait(60000));
  QTRY_VERIFY_WITH_TIMEOUT(!builder.busy(), 30000);
  EXPECT_EQ(applied.size(), 1);
  EXPECT_GT(viewport.proxyTriangleCount(), 0);
}

TEST_F(InteractiveProxyBuilderTest, NothingIsBuiltWithoutAdaptiveResolutionAndDestroyingMidBuildIsSafe) {
  viewport.setMesh(dense.V, dense.F);
  {
    InteractiveProxyBuilder builder(&viewport);
    viewport.setAdaptiveResolution(false);
    builder.build(dense.V, dense.F);
    EXPECT_FALSE(builder.busy()) << "the proxy would never be drawn";
    viewport.setAdaptiveResolution(true);
    builder.build(dense.V, dense.F);
    EXPECT_TRUE(builder.busy());
  }  // waits for the worker; its result is dropped with the builder
  QTest::qWait(50);
  EXPECT_EQ(viewport.proxyTriangleCount(), 0);
}

}  // namespace
