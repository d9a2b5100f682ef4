#include "model/mesh_decimation.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/MixedDecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdlib>
#include <numeric>

namespace sc::model {
namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
using Decimater = OpenMesh::Decimater::MixedDecimaterT<Mesh>;

/// Large meshes use Wu & Kobbelt's multiple-choice decimation (OpenMesh's MixedDecimaterT) for the first
/// kRandomShare of the collapses, each the best of kSamples random candidates, then the exact priority queue for the
/// rest. Measured on the 100k dragon to 5%: 1.5–1.7 s instead of 3.4 s, within the same 2% distance tolerance. On
/// coarse meshes every collapse matters and the random choice loses too much shape, so below
/// kMultipleChoiceMinVertices the queue does all collapses (share 0).
constexpr std::size_t kMultipleChoiceMinVertices = 50000;
constexpr float kRandomShare = 0.9f;
constexpr std::size_t kSamples = 8;
constexpr unsigned kRandomSeed = 1;  // OpenMesh draws its candidates with rand(): seeded for repeatable levels

/// ModQuadricT plus Garland–Heckbert boundary constraints: each boundary edge adds, to both its vertices, the
/// quadric of the plane through the edge perpendicular to its face, weighted by kBoundaryWeight·length². Without
/// it a flat open mesh (zero face quadrics) erodes from its boundary, and the scans' holes grow.
class ModBoundaryQuadric : public OpenMesh::Decimater::ModQuadricT<Mesh> {
 public:
  using Handle = OpenMesh::Decimater::ModHandleT<ModBoundaryQuadric>;
  using Quadric = OpenMesh::Geometry::Quadricd;
  static constexpr double kBoundaryWeight = 100.0;

  explicit ModBoundaryQuadric(Mesh& mesh) : ModQuadricT<Mesh>(mesh) { mesh.add_property(m_boundary); }
  ~ModBoundaryQuadric() override { mesh().remove_property(m_boundary); }
  ModBoundaryQuadric(const ModBoundaryQuadric&) = delete;
  ModBoundaryQuadric& operator=(const ModBoundaryQuadric&) = delete;

  const std::string& name() const override {
    static const std::string kName = "BoundaryQuadric";
    return kName;
  }
  void initialize() override {
    ModQuadricT<Mesh>::initialize();
    for (const auto v : mesh().vertices()) mesh().property(m_boundary, v).clear();
    for (const auto h : mesh().halfedges()) {
      if (!h.is_boundary()) continue;  // h borders no face; its opposite borders the face
      const Mesh::Point a = mesh().point(h.from()), b = mesh().point(h.to());
      const Mesh::Point edge = b - a;
      OpenMesh::Vec3d n = OpenMesh::cross(edge, mesh().calc_face_normal(h.opp().face()));
      if (n.norm() <= 0) continue;
      n.normalize();
      Quadric q(n[0], n[1], n[2], -OpenMesh::dot(n, a));
      q *= kBoundaryWeight * edge.sqrnorm();
      mesh().property(m_boundary, h.from()) += q;
      mesh().property(m_boundary, h.to()) += q;
    }
  }
  float collapse_priority(const CollapseInfo& ci) override {
    const float face = ModQuadricT<Mesh>::collapse_priority(ci);
    if (face == float(ILLEGAL_COLLAPSE)) return face;
    Quadric q = mesh().property(m_boundary, ci.v0);
    q += mesh().property(m_boundary, ci.v1);
    return face + static_cast<float>(q(ci.p1));
  }
  void postprocess_collapse(const CollapseInfo& ci) override {
    ModQuadricT<Mesh>::postprocess_collapse(ci);
    mesh().property(m_boundary, ci.v1) += mesh().property(m_boundary, ci.v0);
  }

 private:
  OpenMesh::VPropHandleT<Quadric> m_boundary;
};

/// Silences OpenMesh's error stream for the lifetime of the guard (add_face() reports every refused face).
class QuietOmerr {
 public:
  QuietOmerr() : m_wasEnabled(omerr().is_enabled()) { omerr().disable(); }
  ~QuietOmerr() {
    if (m_wasEnabled) omerr().enable();
  }
  QuietOmerr(const QuietOmerr&) = delete;
  QuietOmerr& operator=(const QuietOmerr&) = delete;

 private:
  bool m_wasEnabled;
};

/// Builds the halfedge mesh; returns the number of faces OpenMesh refused.
int buildMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, Mesh& mesh) {
  mesh.reserve(static_cast<std::size_t>(V.rows()), 3 * static_cast<std::size_t>(F.rows()) / 2,
               static_cast<std::size_t>(F.rows()));
  for (Eigen::Index i = 0; i < V.rows(); ++i) mesh.add_vertex(Mesh::Point(V(i, 0), V(i, 1), V(i, 2)));
  const QuietOmerr quiet;
  int dropped = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const auto corner = [&](int k) { return mesh.vertex_handle(static_cast<unsigned>(F(f, k))); };
    if (!mesh.add_face(corner(0), corner(1), corner(2)).is_valid()) ++dropped;
  }
  return dropped;
}

/// Live vertices that belong to a face (isolated ones never collapse).
std::size_t referencedVertices(const Mesh& mesh) {
  return static_cast<std::size_t>(
      std::count_if(mesh.vertices().begin(), mesh.vertices().end(), [&](auto v) { return !mesh.is_isolated(v); }));
}

/// Copies the live faces and their vertices out, renumbering vertices in handle order.
DecimatedMesh extract(const Mesh& mesh) {
  std::vector<int> index(mesh.n_vertices(), -1);
  int next = 0;
  for (const auto v : mesh.vertices())
    if (!mesh.is_isolated(v)) index[static_cast<std::size_t>(v.idx())] = next++;
  DecimatedMesh out;
  out.V.resize(next, 3);
  for (const auto v : mesh.vertices())
    if (const int i = index[static_cast<std::size_t>(v.idx())]; i >= 0) {
      const Mesh::Point& p = mesh.point(v);
      out.V.row(i) << p[0], p[1], p[2];
    }
  out.F.resize(static_cast<Eigen::Index>(mesh.n_faces()), 3);
  Eigen::Index f = 0;
  for (const auto face : mesh.faces()) {
    int k = 0;
    for (const auto v : face.vertices()) out.F(f, k++) = index[static_cast<std::size_t>(v.idx())];
    ++f;
  }
  out.F.conservativeResize(f, 3);
  return out;
}

}  // namespace

std::vector<int> levelTargets(int vertexCount, const std::vector<double>& fractions) {
  std::vector<int> targets;
  targets.reserve(fractions.size());
  for (double fraction : fractions)
    targets.push_back(std::max(3, static_cast<int>(std::lround(fraction * vertexCount))));
  return targets;
}

std::vector<DecimatedMesh> resolutionLadder(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                            const std::vector<int>& targets) {
  // === halfedge mesh, refusing non-manifold faces
  Mesh mesh;
  const int dropped = buildMesh(V, F, mesh);
  // === quadric decimater, initialised once; each target continues from the previous collapses
  Decimater decimater(mesh);
  ModBoundaryQuadric::Handle quadric;
  decimater.add(quadric);
  decimater.module(quadric).unset_max_err();
  const bool ready = decimater.initialize();
  assert(ready && "a decimater with one priority module always initialises");
  const float randomShare = mesh.n_vertices() >= kMultipleChoiceMinVertices ? kRandomShare : 0.0f;
  decimater.set_samples(kSamples);
  std::srand(kRandomSeed);
  std::vector<std::size_t> order(targets.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return targets[a] > targets[b]; });
  // === collapse down through the targets, largest first, extracting each level
  std::vector<DecimatedMesh> levels(targets.size());
  std::size_t alive = referencedVertices(mesh);
  for (std::size_t i : order) {
    assert(targets[i] >= 3 && "a level needs at least 3 vertices");
    const auto target = static_cast<std::size_t>(targets[i]);
    if (ready && alive > target) alive -= decimater.decimate(alive - target, randomShare);
    levels[i] = extract(mesh);
    levels[i].droppedFaces = dropped;
    levels[i].targetVertices = targets[i];
  }
  return levels;
}

DecimatedMesh decimateMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetVertices) {
  return std::move(resolutionLadder(V, F, {targetVertices}).front());
}

}  // namespace sc::model
