// Issue 15: on the 100k dragon a press on the moved handle with the Drag tool orbited instead of dragging. The
// dragon has six specks of 3–7 vertices; their constant modes give K rows of ≈ 17,000 against ≈ 4 on the body, and
// the camera bounds of a frame whose positions lag (proxy-only CPU frames, GPU frames: ShownLevel::bounds()) were
// the rest box widened by max_i ‖K_i‖·‖Z_c‖, thousands of times the shape: the near plane (a thousandth of that)
// cut the front of the mesh away, in the picture and in the picking pass. Here: the bound itself, and a press on a
// moved handle of a dense mesh with such a row, on the interactive proxy's path, the full CPU path and the GPU path.

#include "app/gui/interactive_proxy.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/vertex_picking.h"
#include "app/gui/viewport/shown_level.h"
#include "model/mesh_proxy.h"
#include "spectral/reconstruction_kernel.h"

#include "app_test_support.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <QTest>

#include <cmath>
#include <string>
#include <vector>

namespace {

using sc::app::MeshViewport;
using sc::app::ReconstructionPath;

constexpr float kSpeckEntry = 17000.0f;  // a 3-vertex component's constant mode on the 100k dragon

/// A basis of 4 columns over `V`: column 0 a bump of height `height` around `centre` (the handle's region),
/// columns 1–2 smooth, column 3 zero but for one huge entry on the vertex farthest from the bump (a speck's mode).
sc::spectral::RowMatrixXf basisWithASpeck(const Eigen::MatrixXd& V, const Eigen::RowVector3d& centre, double radius,
                                          double height) {
  sc::spectral::RowMatrixXf K = sc::spectral::RowMatrixXf::Zero(V.rows(), 4);
  Eigen::Index farthest = 0;
  double farthestDistance = -1.0;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double d2 = (V.row(i) - centre).squaredNorm();
    K(i, 0) = static_cast<float>(height * std::exp(-d2 / (radius * radius)));
    K(i, 1) = static_cast<float>(0.05 * V(i, 0));
    K(i, 2) = static_cast<float>(0.05 * V(i, 1) * V(i, 2));
    if (d2 > farthestDistance) {
      farthestDistance = d2;
      farthest = i;
    }
  }
  K(farthest, 3) = kSpeckEntry;
  return K;
}

TEST(ShownLevelBounds, AHugeRowOfAModeTheFrameLeavesAloneDoesNotWidenTheBox) {
  const auto sphere = sc::testing::icosphere(3);
  const sc::spectral::RowMatrixXf K = basisWithASpeck(sphere.V, Eigen::RowVector3d(1.0, 0.0, 0.0), 0.4, 1.0);
  const std::vector<float> rest = sc::spectral::interleavedPositions(sphere.V);
  sc::app::ShownLevel shown;
  shown.hold(sc::spectral::makeDisplayLevel({sphere.V, sphere.F, {}, K}), rest);
  Eigen::MatrixXf Z = Eigen::MatrixXf::Zero(4, 3);
  Z(0, 0) = 0.8f;  // the handle's bump moves out along +x and up
  Z(0, 2) = 0.5f;
  Z(1, 1) = 0.3f;
  Z(2, 0) = -0.2f;
  ASSERT_TRUE(shown.show(Z));
  std::vector<float> exact(rest.size());
  sc::spectral::reconstructInterleaved(K, rest, Z, exact);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  for (std::size_t i = 0; i < exact.size(); i += 3) {
    const Eigen::Vector3f p(exact[i], exact[i + 1], exact[i + 2]);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const auto [boundsLo, boundsHi] = shown.bounds();
  const Eigen::Vector3f blo(boundsLo.x(), boundsLo.y(), boundsLo.z()), bhi(boundsHi.x(), boundsHi.y(), boundsHi.z());
  EXPECT_TRUE((blo.array() <= lo.array() + 1e-5f).all() && (bhi.array() >= hi.array() - 1e-5f).all())
      << "the box holds every position";
  EXPECT_LT((bhi - blo).norm(), 3.0f * (hi - lo).norm()) << "and is not thousands of times the shape";
}

class MovedHandlePickTest : public ::testing::TestWithParam<int> {
 protected:
  enum Path { ProxyCpu = 0, FullCpu = 1, Gpu = 2 };
  void SetUp() override {
    if (!sc::testing::openGlAvailable()) GTEST_SKIP() << "no OpenGL 3.3 context (run under xvfb-run)";
  }
};

// A dense torus (75,000 triangles: it gets an interactive proxy) with a speck row in K; frames move the handle's
// bump out as coefficients arrive (a drag), then a press on the moved handle with the Drag tool starts a drag.
TEST_P(MovedHandlePickTest, APressOnTheMovedHandleStartsADrag) {
  const int path = GetParam();
  const auto torus = sc::testing::torus(300, 125);
  ASSERT_GT(torus.F.rows(), sc::app::InteractiveProxyBuilder::kMinTriangles);
  const Eigen::RowVector3d centre(1.3, 0.0, 0.0);
  const sc::spectral::RowMatrixXf K = basisWithASpeck(torus.V, centre, 0.35, 1.0);
  std::vector<int> handle;
  for (Eigen::Index i = 0; i < torus.V.rows(); ++i)
    if ((torus.V.row(i) - centre).norm() < 0.12) handle.push_back(static_cast<int>(i));
  ASSERT_FALSE(handle.empty());

  MeshViewport view;
  view.resize(480, 360);
  view.setMesh(torus.V, torus.F);
  view.setAdaptiveResolution(path == ProxyCpu);
  view.setDisplayLevel(sc::spectral::makeDisplayLevel({torus.V, torus.F, {}, K}));
  view.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&view));
  view.setReconstructionPath(path == Gpu ? ReconstructionPath::Gpu : ReconstructionPath::Cpu);
  if (path == Gpu && !view.gpuReconstructionAvailable()) GTEST_SKIP() << "no GPU reconstruction here";
  if (path == ProxyCpu) {
    view.setInteractiveProxy(sc::model::proxyTriangles(torus.V, torus.F, 20000));
    ASSERT_GT(view.proxyTriangleCount(), 0);
  }
  view.setSelection(handle, {});
  view.setTool(sc::app::ViewportTool::Drag);
  int starts = 0;
  QObject::connect(&view, &MeshViewport::dragStarted, [&starts] { ++starts; });

  Eigen::MatrixXf Z = Eigen::MatrixXf::Zero(4, 3);
  for (int i = 1; i <= 5; ++i) {  // frames of a drag, right after each other
    Z(0, 2) = 0.12f * static_cast<float>(i);
    Z(0, 1) = -0.08f * static_cast<float>(i);
    Z(1, 0) = 0.1f * static_cast<float>(i);
    view.showFrame({static_cast<std::uint32_t>(i), Z});
    view.grabFramebuffer();
  }
  if (path == ProxyCpu) {
    EXPECT_EQ(view.frameTimes().triangles, view.proxyTriangleCount()) << "the moving frames drew the proxy";
  }
  QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);  // the idle frame of the full mesh

  // The moved handle on screen: the projection of its centroid (inside the bump) at the displayed positions.
  const std::vector<float> shown = view.hostPositions();
  const Eigen::RowVector3d origin = 0.5 * (torus.V.colwise().minCoeff() + torus.V.colwise().maxCoeff());
  Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero(), restCentroid = Eigen::RowVector3d::Zero();
  for (const int v : handle) {
    centroid += Eigen::RowVector3d(shown[3 * v], shown[3 * v + 1], shown[3 * v + 2]);
    restCentroid += torus.V.row(v);
  }
  centroid /= static_cast<double>(handle.size());
  restCentroid /= static_cast<double>(handle.size());
  ASSERT_GT((centroid - restCentroid).norm(), 0.3) << "the handle moved";
  const Eigen::RowVector3d relative = centroid - origin;
  const std::vector<float> xyz{static_cast<float>(relative.x()), static_cast<float>(relative.y()),
                               static_cast<float>(relative.z())};
  const sc::app::ScreenPoint screen =
      sc::app::projectToScreen(xyz, view.camera().view(), view.camera().projection(), view.size(), nullptr, 0.0f)[0];
  const QPoint at(static_cast<int>(screen.x), static_cast<int>(screen.y));
  ASSERT_TRUE(view.rect().contains(at)) << at.x() << "," << at.y();
  const float yaw = view.camera().yaw();
  QTest::mousePress(&view, Qt::LeftButton, Qt::NoModifier, at);
  EXPECT_EQ(starts, 1) << "the press on the moved handle starts a drag";
  QTest::mouseRelease(&view, Qt::LeftButton, Qt::NoModifier, at);
  EXPECT_EQ(view.camera().yaw(), yaw) << "and does not orbit";
}

std::string pathName(const ::testing::TestParamInfo<int>& param) {
  constexpr const char* kNames[] = {"InteractiveProxy", "FullCpu", "Gpu"};
  return kNames[param.param];
}

INSTANTIATE_TEST_SUITE_P(Paths, MovedHandlePickTest, ::testing::Values(0, 1, 2), pathName);

}  // namespace
