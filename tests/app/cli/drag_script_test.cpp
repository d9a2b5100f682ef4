// Drag scripts: parsing of every form, every error (naming the key), selection on a rest mesh, interpolation.

#include "app/cli/drag_script.h"

#include "spectral/hausdorff.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <numbers>

namespace sc::app {
namespace {

DragScript parse(const char* json) {
  std::variant<DragScript, QString> parsed = parseDragScript(QByteArray(json));
  if (const auto* message = std::get_if<QString>(&parsed)) {
    ADD_FAILURE() << message->toStdString();
    return {};
  }
  return std::get<DragScript>(std::move(parsed));
}

/// Parses `json`, expects an error and returns its message.
std::string parseError(const char* json) {
  const std::variant<DragScript, QString> parsed = parseDragScript(QByteArray(json));
  if (!std::holds_alternative<QString>(parsed)) {
    ADD_FAILURE() << "parsed, but an error was expected: " << json;
    return {};
  }
  return std::get<QString>(parsed).toStdString();
}

constexpr const char* kExample = R"({
  "description": "lift the tip",
  "handles": [{"vertices": [3, 1, 2]}, {"sphere": {"vertex": 0, "radius_pct": 5}}],
  "anchors": {"farther_than_pct": 40, "from_vertex": 0},
  "fps": 10,
  "frames": [{"t": 0, "translate_pct": [0, 0, 0], "rotate_deg": [0, 0, 0]},
             {"t": 1.5, "translate_pct": [0, 10, 0]},
             {"t": 2, "translate_pct": [0, 10, 0], "rotate_deg": [90, 0, 0]}]
})";

TEST(DragScript, ParsesBothHandleFormsAndTheFartherThanAnchors) {
  const DragScript s = parse(kExample);
  ASSERT_EQ(s.handles.size(), 2u);
  EXPECT_EQ(s.handles[0].vertices, (std::vector<int>{3, 1, 2}));
  EXPECT_FALSE(s.handles[0].sphere);
  ASSERT_TRUE(s.handles[1].sphere);
  EXPECT_EQ(s.handles[1].sphere->vertex, 0);
  EXPECT_EQ(s.handles[1].sphere->radiusPct, 5.0);
  ASSERT_TRUE(s.anchors.fartherThan);
  EXPECT_EQ(s.anchors.fartherThan->distancePct, 40.0);
  EXPECT_EQ(s.anchors.fartherThan->fromVertex, 0);
  EXPECT_EQ(s.fps, 10.0);
  ASSERT_EQ(s.frames.size(), 3u);
  EXPECT_EQ(s.frames[1].pose.translatePct, Eigen::Vector3d(0, 10, 0));
  EXPECT_EQ(s.frames[1].pose.rotateDeg, Eigen::Vector3d::Zero()) << "a missing key means zero";
}

TEST(DragScript, ParsesExplicitAnchorsAndDefaults) {
  const DragScript s = parse(R"({"handles":[{"vertices":[0]}],"anchors":{"vertices":[5,4]},"frames":[{"t":0}]})");
  EXPECT_EQ(s.anchors.vertices, (std::vector<int>{5, 4}));
  EXPECT_FALSE(s.anchors.fartherThan);
  EXPECT_EQ(s.fps, 30.0) << "default frame rate";
  const DragScript noAnchors = parse(R"({"handles":[{"vertices":[0]}],"frames":[{"t":0}]})");
  EXPECT_TRUE(noAnchors.anchors.vertices.empty());
  EXPECT_FALSE(noAnchors.anchors.fartherThan);
}

TEST(DragScript, EveryErrorNamesTheKey) {
  const std::vector<std::pair<const char*, const char*>> cases = {
      {R"({"handles":)", "not valid JSON"},
      {R"([1, 2])", "(root): must be a JSON object"},
      {R"({"frames":[{"t":0}]})", "handles: missing"},
      {R"({"handles":[],"frames":[{"t":0}]})", "handles: must be a non-empty array"},
      {R"({"handles":[{"vertices":[0]}]})", "frames: missing"},
      {R"({"handles":[{"vertices":[0]}],"frames":[]})", "frames: must be a non-empty array"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{"t":0}],"fsp":30})", "fsp: unknown key"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{"t":0}],"fps":0})", "fps: must be positive"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{"t":0},{"t":100}],"fps":1e6})", "fps: too many frames"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{"t":0}],"description":3})", "description: must be a string"},
      {R"({"handles":[7],"frames":[{"t":0}]})", "handles[0]: must be an object"},
      {R"({"handles":[{}],"frames":[{"t":0}]})", "handles[0]: needs exactly one of"},
      {R"({"handles":[{"vertices":[0],"sphere":{}}],"frames":[{"t":0}]})", "handles[0]: needs exactly one of"},
      {R"({"handles":[{"vertices":[]}],"frames":[{"t":0}]})", "handles[0].vertices: must be a non-empty array"},
      {R"({"handles":[{"vertices":[0,-1]}],"frames":[{"t":0}]})", "handles[0].vertices[1]: must be a vertex index"},
      {R"({"handles":[{"vertices":[1.5]}],"frames":[{"t":0}]})", "handles[0].vertices[0]: must be a vertex index"},
      {R"({"handles":[{"vertices":["a"]}],"frames":[{"t":0}]})", "handles[0].vertices[0]: must be a number"},
      {R"({"handles":[{"verts":[0]}],"frames":[{"t":0}]})", "handles[0].verts: unknown key"},
      {R"({"handles":[{"vertices":[0]},{"sphere":{"vertex":0}}],"frames":[{"t":0}]})",
       "handles[1].sphere.radius_pct: missing"},
      {R"({"handles":[{"sphere":{"radius_pct":5}}],"frames":[{"t":0}]})", "handles[0].sphere.vertex: missing"},
      {R"({"handles":[{"sphere":{"vertex":0,"radius_pct":-1}}],"frames":[{"t":0}]})",
       "handles[0].sphere.radius_pct: must be positive"},
      {R"({"handles":[{"sphere":{"vertex":0,"radius_pct":5,"r":1}}],"frames":[{"t":0}]})",
       "handles[0].sphere.r: unknown key"},
      {R"({"handles":[{"vertices":[0]}],"anchors":[],"frames":[{"t":0}]})", "anchors: must be an object"},
      {R"({"handles":[{"vertices":[0]}],"anchors":{"vertices":[1],"from_vertex":0},"frames":[{"t":0}]})",
       "anchors: needs either"},
      {R"({"handles":[{"vertices":[0]}],"anchors":{"from_vertex":0},"frames":[{"t":0}]})",
       "anchors.farther_than_pct: missing"},
      {R"({"handles":[{"vertices":[0]}],"anchors":{"farther_than_pct":40},"frames":[{"t":0}]})",
       "anchors.from_vertex: missing"},
      {R"({"handles":[{"vertices":[0]}],"anchors":{"farther_than_pct":-4,"from_vertex":0},"frames":[{"t":0}]})",
       "anchors.farther_than_pct: must not be negative"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{}]})", "frames[0].t: missing"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{"t":"0"}]})", "frames[0].t: must be a number"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{"t":1},{"t":1}]})",
       "frames[1].t: must be greater than the previous"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{"t":0,"translate":[0,1,0]}]})", "frames[0].translate: unknown key"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{"t":0,"translate_pct":[0,1]}]})",
       "frames[0].translate_pct: must be an array of 3 numbers"},
      {R"({"handles":[{"vertices":[0]}],"frames":[{"t":0,"rotate_deg":[0,null,0]}]})",
       "frames[0].rotate_deg[1]: must be a number"},
  };
  for (const auto& [json, expected] : cases) {
    const std::string message = parseError(json);
    EXPECT_NE(message.find(expected), std::string::npos) << json << "\n  gave: " << message;
  }
}

class DragScriptOnTorus : public ::testing::Test {
 protected:
  void SetUp() override {
    m_rest = sc::testing::torus(40, 16).V;
    m_diagonal = spectral::boundingBoxDiagonal(m_rest);
  }
  spectral::ConstraintSet resolve(const char* json) const {
    std::variant<spectral::ConstraintSet, QString> set = resolveConstraints(parse(json), m_rest);
    if (const auto* message = std::get_if<QString>(&set)) {
      ADD_FAILURE() << message->toStdString();
      return {};
    }
    return std::get<spectral::ConstraintSet>(std::move(set));
  }
  std::string resolveError(const char* json) const {
    const auto set = resolveConstraints(parse(json), m_rest);
    return std::holds_alternative<QString>(set) ? std::get<QString>(set).toStdString() : std::string("resolved");
  }
  Eigen::MatrixXd m_rest;
  double m_diagonal = 0.0;
};

TEST_F(DragScriptOnTorus, SphereAndFartherThanSelectByRestDistance) {
  const spectral::ConstraintSet set = resolve(
      R"({"handles":[{"sphere":{"vertex":0,"radius_pct":10}}],"anchors":{"farther_than_pct":40,"from_vertex":0},
          "frames":[{"t":0}]})");
  ASSERT_EQ(set.handles.size(), 1u);
  const auto distance = [this](int v) { return (m_rest.row(v) - m_rest.row(0)).norm(); };
  std::size_t inside = 0, farther = 0;
  for (Eigen::Index v = 0; v < m_rest.rows(); ++v) {
    inside += distance(static_cast<int>(v)) <= 0.1 * m_diagonal ? 1 : 0;
    farther += distance(static_cast<int>(v)) > 0.4 * m_diagonal ? 1 : 0;
  }
  EXPECT_EQ(set.handles[0].vertices.size(), inside);
  EXPECT_GT(inside, 1u);
  EXPECT_EQ(set.handles[0].vertices.front(), 0) << "the centre vertex is in its own sphere";
  for (int v : set.handles[0].vertices) EXPECT_LE(distance(v), 0.1 * m_diagonal);
  EXPECT_EQ(set.anchors.size(), farther);
  for (int v : set.anchors) EXPECT_GT(distance(v), 0.4 * m_diagonal);
}

TEST_F(DragScriptOnTorus, ExplicitListsAreSortedAndHandlesWinOverAnchors) {
  const spectral::ConstraintSet set =
      resolve(R"({"handles":[{"vertices":[9,3,3]}],"anchors":{"vertices":[3,100,50]},"frames":[{"t":0}]})");
  ASSERT_EQ(set.handles.size(), 1u);
  EXPECT_EQ(set.handles[0].vertices, (std::vector<int>{3, 9}));
  EXPECT_EQ(set.anchors, (std::vector<int>{50, 100})) << "vertex 3 is a handle, not an anchor";
}

TEST_F(DragScriptOnTorus, ResolutionErrorsNameTheKey) {
  EXPECT_NE(resolveError(R"({"handles":[{"vertices":[0, 640]}],"frames":[{"t":0}]})")
                .find("handles[0].vertices: vertex 640 is out of range (the mesh has 640 vertices)"),
            std::string::npos);
  EXPECT_NE(resolveError(R"({"handles":[{"sphere":{"vertex":9999,"radius_pct":1}}],"frames":[{"t":0}]})")
                .find("handles[0].sphere.vertex: vertex 9999"),
            std::string::npos);
  EXPECT_NE(resolveError(R"({"handles":[{"vertices":[1]}],"anchors":{"vertices":[700]},"frames":[{"t":0}]})")
                .find("anchors.vertices: vertex 700"),
            std::string::npos);
  EXPECT_NE(resolveError(R"({"handles":[{"vertices":[1]}],"anchors":{"farther_than_pct":10,"from_vertex":900},
                             "frames":[{"t":0}]})")
                .find("anchors.from_vertex: vertex 900"),
            std::string::npos);
  EXPECT_NE(resolveError(R"({"handles":[{"vertices":[1,2]},{"vertices":[2,3]}],"frames":[{"t":0}]})")
                .find("handles[1]: shares 1 vertices (e.g. 2)"),
            std::string::npos);
  EXPECT_NE(resolveError(R"({"handles":[{"vertices":[1]}],"anchors":{"farther_than_pct":150,"from_vertex":0},
                             "frames":[{"t":0}]})")
                .find("anchors.farther_than_pct: selects no vertex"),
            std::string::npos);
}

TEST(DragScriptFrames, SamplesAtTheFrameRateAndKeepsTheLastKeyframe) {
  const DragScript s = parse(kExample);  // t = 0 … 2 at 10 fps
  const std::vector<double> times = frameTimes(s);
  ASSERT_EQ(times.size(), 21u);
  EXPECT_DOUBLE_EQ(times[1], 0.1);
  EXPECT_DOUBLE_EQ(times.back(), 2.0);

  const DragScript odd = parse(R"({"handles":[{"vertices":[0]}],"fps":4,"frames":[{"t":1},{"t":1.6}]})");
  EXPECT_EQ(frameTimes(odd), (std::vector<double>{1.0, 1.25, 1.5, 1.6})) << "the last keyframe is always sampled";
  EXPECT_EQ(frameTimes(parse(R"({"handles":[{"vertices":[0]}],"frames":[{"t":3}]})")).size(), 1u);
  EXPECT_EQ(frameTimes(parse(R"({"handles":[{"vertices":[0]}],"frames":[{"t":0},{"t":1}]})")).size(), 31u)
      << "30 fps default: 0, 1/30, …, 1";
}

TEST(DragScriptFrames, InterpolatesTranslationAndAnglesLinearlyAndClamps) {
  const DragScript s = parse(kExample);
  EXPECT_TRUE(poseAt(s, 0.75).translatePct.isApprox(Eigen::Vector3d(0, 5, 0)));
  EXPECT_TRUE(poseAt(s, 1.75).rotateDeg.isApprox(Eigen::Vector3d(45, 0, 0)));
  EXPECT_TRUE(poseAt(s, 1.75).translatePct.isApprox(Eigen::Vector3d(0, 10, 0)));
  EXPECT_EQ(poseAt(s, -1.0).translatePct, Eigen::Vector3d::Zero()) << "clamped before the first keyframe";
  EXPECT_EQ(poseAt(s, 9.0).rotateDeg, Eigen::Vector3d(90, 0, 0)) << "clamped after the last keyframe";
  EXPECT_EQ(poseAt(s, 1.5).translatePct, Eigen::Vector3d(0, 10, 0)) << "exactly on a keyframe";
}

TEST(DragScriptFrames, TransformScalesByTheDiagonalAndComposesXyzEulerAngles) {
  DragPose pose;
  pose.translatePct = {10, -20, 5};
  pose.rotateDeg = {30, 45, 60};
  const spectral::HandleTransform T = transformAt(pose, 4.0);
  EXPECT_TRUE(T.translation.isApprox(Eigen::Vector3d(0.4, -0.8, 0.2)));
  const double deg = std::numbers::pi / 180.0;
  const Eigen::Matrix3d expected =
      (Eigen::AngleAxisd(60 * deg, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(45 * deg, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(30 * deg, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  EXPECT_TRUE(T.rotation.isApprox(expected, 1e-14));
  EXPECT_NEAR((T.rotation * T.rotation.transpose() - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-14);
  // A pure 90° rotation about X maps y onto z.
  DragPose aboutX;
  aboutX.rotateDeg = {90, 0, 0};
  EXPECT_TRUE((transformAt(aboutX, 1.0).rotation * Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ()));
}

}  // namespace
}  // namespace sc::app
