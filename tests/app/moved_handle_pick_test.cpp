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

#include <QColor>
#include <QImage>
#include <QLineF>
#include <QTest>

#include <cmath>
#include <span>
#include <string>
#include <vector>

namespace {

using sc::app::MeshViewport;
using sc::app::ReconstructionPath;

constexpr float kSpeckEntry = 17000.0f;  // a 3-vertex component's constant mode on the 100k dragon

/// A basis of 4 columns over `V`: column 0 a bump of height `height` around `centre` (the handle's region),
/// columns 1–2 smooth, column 3 zero but for one huge entry on the vertex farthest from the bump (a speck's mode).
sc::spectral::QuantizedBasis basisWithASpeck(const Eigen::MatrixXd& V, const Eigen::RowVector3d& centre, double radius,
                                             double height) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(V.rows(), 4);
  Eigen::Index farthest = 0;
  double farthestDistance = -1.0;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const double d2 = (V.row(i) - centre).squaredNorm();
    K(i, 0) = height * std::exp(-d2 / (radius * radius));
    K(i, 1) = 0.05 * V(i, 0);
    K(i, 2) = 0.05 * V(i, 1) * V(i, 2);
    if (d2 > farthestDistance) {
      farthestDistance = d2;
      farthest = i;
    }
  }
  K(farthest, 3) = kSpeckEntry;
  return sc::spectral::quantizeBasis(K);
}

TEST(ShownLevelBounds, AHugeRowOfAModeTheFrameLeavesAloneDoesNotWidenTheBox) {
  const auto sphere = sc::testing::icosphere(3);
  const sc::spectral::QuantizedBasis K = basisWithASpeck(sphere.V, Eigen::RowVector3d(1.0, 0.0, 0.0), 0.4, 1.0);
  const sc::spectral::SharedDisplayLevel level = sc::spectral::makeDisplayLevel({sphere.V, sphere.F, {}, K});
  const std::vector<float>& rest = level->geometry.rest;  // relative to the box centre, as the viewport shows it
  sc::app::ShownLevel shown;
  shown.hold(level);
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

  /// A dense torus (75,000 triangles: it gets an interactive proxy) with a speck row in K, shown on GetParam()'s
  /// path with a handle around the bump selected; false when that path is not available here.
  bool prepare() {
    EXPECT_GT(m_torus.F.rows(), sc::app::InteractiveProxyBuilder::kMinTriangles);
    m_K = basisWithASpeck(m_torus.V, kCentre, 0.35, 1.0);
    for (Eigen::Index i = 0; i < m_torus.V.rows(); ++i)
      if ((m_torus.V.row(i) - kCentre).norm() < 0.12) m_handle.push_back(static_cast<int>(i));
    EXPECT_FALSE(m_handle.empty());
    const int path = GetParam();
    m_view.resize(480, 360);
    m_view.setMesh(m_torus.V, m_torus.F);
    m_view.setAdaptiveResolution(path == ProxyCpu);
    m_view.setPaintBudget(1e6);  // full pixel resolution: only the triangles change
    m_view.setDisplayLevel(sc::spectral::makeDisplayLevel({m_torus.V, m_torus.F, {}, m_K}));
    m_view.show();
    EXPECT_TRUE(QTest::qWaitForWindowExposed(&m_view));
    m_view.setReconstructionPath(path == Gpu ? ReconstructionPath::Gpu : ReconstructionPath::Cpu);
    if (path == Gpu && !m_view.gpuReconstructionAvailable()) return false;
    if (path == ProxyCpu) {
      m_view.setInteractiveProxy(sc::model::proxyTriangles(m_torus.V, m_torus.F, 20000));
      EXPECT_GT(m_view.proxyTriangleCount(), 0);
    }
    m_view.setSelection(m_handle, {});
    return true;
  }

  /// Frames of a drag (coefficients arriving, as from another user's drag), right after each other; the last
  /// frame's picture.
  QImage showDragFrames() {
    QImage last;
    for (int i = 1; i <= 5; ++i) {
      m_Z(0, 2) = 0.12f * static_cast<float>(i);
      m_Z(0, 1) = -0.08f * static_cast<float>(i);
      m_Z(1, 0) = 0.1f * static_cast<float>(i);
      m_view.showFrame({static_cast<std::uint32_t>(i), m_Z});
      last = m_view.grabFramebuffer();
    }
    if (GetParam() == ProxyCpu) {
      EXPECT_EQ(m_view.frameTimes().triangles, m_view.proxyTriangleCount()) << "the moving frames drew the proxy";
    }
    return last;
  }

  /// Where the handle's centroid at positions `xyz` (3·#V, the mesh's coordinates) is on screen.
  QPointF screenOfHandle(std::span<const float> xyz) const {
    Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
    for (const int v : m_handle) centroid += Eigen::RowVector3d(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
    const Eigen::RowVector3d origin = 0.5 * (m_torus.V.colwise().minCoeff() + m_torus.V.colwise().maxCoeff());
    const Eigen::RowVector3d relative = centroid / static_cast<double>(m_handle.size()) - origin;
    const std::vector<float> one{static_cast<float>(relative.x()), static_cast<float>(relative.y()),
                                 static_cast<float>(relative.z())};
    const sc::app::ScreenPoint p = sc::app::projectToScreen(one, m_view.camera().view(), m_view.camera().projection(),
                                                            m_view.size(), nullptr, 0.0f)[0];
    return {p.x, p.y};
  }

  /// X̂ + K·Z of the current frame, as the viewport should show it.
  [[nodiscard]] std::vector<float> expectedPositions() const {
    const std::vector<float> rest = sc::spectral::interleavedPositions(m_torus.V);
    std::vector<float> xyz(rest.size());
    sc::spectral::reconstructInterleaved(m_K, rest, m_Z, xyz);
    return xyz;
  }

  const Eigen::RowVector3d kCentre{1.3, 0.0, 0.0};
  sc::testing::GeneratedMesh m_torus = sc::testing::torus(300, 125);
  sc::spectral::QuantizedBasis m_K;
  Eigen::MatrixXf m_Z = Eigen::MatrixXf::Zero(4, 3);
  std::vector<int> m_handle;
  MeshViewport m_view;
};

// Frames move the handle's bump out as coefficients arrive (a drag); then a press on the moved handle with the
// Drag tool starts a drag.
TEST_P(MovedHandlePickTest, APressOnTheMovedHandleStartsADrag) {
  if (!prepare()) GTEST_SKIP() << "no GPU reconstruction here";
  m_view.setTool(sc::app::ViewportTool::Drag);
  int starts = 0;
  QObject::connect(&m_view, &MeshViewport::dragStarted, [&starts] { ++starts; });
  showDragFrames();
  QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);  // the idle frame of the full mesh

  const std::vector<float> shown = m_view.hostPositions();
  ASSERT_LT(sc::testing::maxDifference(shown, expectedPositions()), 1e-4f);
  const QPointF moved = screenOfHandle(shown);
  ASSERT_GT(QLineF(moved, screenOfHandle(sc::spectral::interleavedPositions(m_torus.V))).length(), 20.0)
      << "the handle moved on screen";
  const QPoint at = moved.toPoint();
  ASSERT_TRUE(m_view.rect().contains(at)) << at.x() << "," << at.y();
  const float yaw = m_view.camera().yaw();
  QTest::mousePress(&m_view, Qt::LeftButton, Qt::NoModifier, at);
  EXPECT_EQ(starts, 1) << "the press on the moved handle starts a drag";
  QTest::mouseRelease(&m_view, Qt::LeftButton, Qt::NoModifier, at);
  EXPECT_EQ(m_view.camera().yaw(), yaw) << "and does not orbit";
}

// Issue 15, "your own tint goes stale while someone else drags": the handle's tint is drawn where the handle is
// shown, in the moving frames (the proxy's on that path) and in the idle frame.
TEST_P(MovedHandlePickTest, TheSelectionTintFollowsTheFrames) {
  if (!prepare()) GTEST_SKIP() << "no GPU reconstruction here";
  const QPointF atRest = screenOfHandle(sc::spectral::interleavedPositions(m_torus.V));
  const QImage moving = showDragFrames();
  const QPointF moved = screenOfHandle(expectedPositions());
  ASSERT_GT(QLineF(moved, atRest).length(), 20.0) << "the handle moved on screen";
  EXPECT_LT(QLineF(sc::testing::handleTintCentroid(moving), moved).length(), 8.0) << "a moving frame";
  QTest::qWait(sc::app::FramePolicy::kIdleRestoreMs * 2);
  EXPECT_LT(QLineF(sc::testing::handleTintCentroid(m_view.grabFramebuffer()), moved).length(), 8.0) << "the idle frame";
}

std::string pathName(const ::testing::TestParamInfo<int>& param) {
  constexpr const char* kNames[] = {"InteractiveProxy", "FullCpu", "Gpu"};
  return kNames[param.param];
}

INSTANTIATE_TEST_SUITE_P(Paths, MovedHandlePickTest, ::testing::Values(0, 1, 2), pathName);

}  // namespace
