#include "legacy_decimation.h"

#include "legacy_quadric_decimater.h"

#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <utility>
#include <vector>

namespace sc::bench::legacy {

using model::DecimatedMesh;

namespace {

using detail::Decimater;
using detail::Mesh;
using detail::ModBoundaryQuadric;
using detail::SplitMix64;

/// Large meshes use Wu & Kobbelt's multiple-choice decimation for the first kRandomShare of the collapses, each the
/// cheapest of kSamples random live edges, then the exact priority queue for the rest. Measured on the 100k
/// dragon to 5% (2 cores, loaded): 0.9 s instead of 1.7 s for the queue alone, at a maximum distance to the input
/// of 0.78% of the diagonal instead of 0.62%. On coarse meshes every collapse matters and the random choice loses too
/// much shape, so below kMultipleChoiceMinVertices the queue does all collapses (share 0).
constexpr std::size_t kMultipleChoiceMinVertices = 50000;
constexpr double kRandomShare = 0.9;
constexpr std::size_t kSamples = 8;
constexpr std::uint64_t kRandomSeed = 1;

/// Silences OpenMesh's error stream for the lifetime of the guard (add_face() reports every refused face). The
/// stream is process-wide and decimations run on several threads at once (a host's levels, a viewport's proxy):
/// the first guard in disables it, the last one out restores what it found.
class QuietOmerr {
 public:
  QuietOmerr() {
    const std::lock_guard lock(s_mutex);
    if (s_depth++ == 0) {
      s_wasEnabled = omerr().is_enabled();
      omerr().disable();
    }
  }
  ~QuietOmerr() {
    const std::lock_guard lock(s_mutex);
    if (--s_depth == 0 && s_wasEnabled) omerr().enable();
  }
  QuietOmerr(const QuietOmerr&) = delete;
  QuietOmerr& operator=(const QuietOmerr&) = delete;

 private:
  static inline std::mutex s_mutex;
  static inline int s_depth = 0;
  static inline bool s_wasEnabled = false;
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

/// Collapses from `alive` referenced vertices down to `target`: multiple-choice first on large meshes, then the
/// priority queue (see kRandomShare). Returns the referenced vertices left (more than `target` when no legal
/// collapse is left).
std::size_t decimateTo(Decimater& decimater, const Mesh& mesh, std::size_t alive, std::size_t target,
                       SplitMix64& random) {
  const double randomShare = mesh.n_vertices() >= kMultipleChoiceMinVertices ? kRandomShare : 0.0;
  const std::size_t collapses = alive - target;
  const auto randomCollapses = static_cast<std::size_t>(randomShare * static_cast<double>(collapses));
  alive -= decimater.decimateMultipleChoice(randomCollapses, kSamples, random);
  alive -= decimater.decimateGreedy(collapses - randomCollapses);
  return alive;
}

/// The input faces through the collapses so far (`stand`: Decimater::representatives()): the live faces of the
/// halfedge mesh, plus the faces it refused, so that those leave no holes; faces that collapsed to an edge or a
/// point, and repeats, are left out. Orientation and order as in F.
Eigen::MatrixXi collapsedFaces(const Eigen::MatrixXi& F, const std::vector<int>& stand) {
  // Non-degenerate mapped faces with their vertex set as a sort key; the first face of each set is kept.
  struct Mapped {
    std::array<int, 3> key;
    Eigen::Index face;
  };
  std::vector<Mapped> mapped;
  mapped.reserve(static_cast<std::size_t>(F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    std::array<int, 3> key = {stand[static_cast<std::size_t>(F(f, 0))], stand[static_cast<std::size_t>(F(f, 1))],
                              stand[static_cast<std::size_t>(F(f, 2))]};
    std::sort(key.begin(), key.end());
    if (key[0] != key[1] && key[1] != key[2]) mapped.push_back({key, f});
  }
  std::stable_sort(mapped.begin(), mapped.end(), [](const Mapped& a, const Mapped& b) { return a.key < b.key; });
  std::vector<Eigen::Index> kept;
  for (std::size_t i = 0; i < mapped.size(); ++i)
    if (i == 0 || mapped[i].key != mapped[i - 1].key) kept.push_back(mapped[i].face);
  std::sort(kept.begin(), kept.end());  // input order
  Eigen::MatrixXi out(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t i = 0; i < kept.size(); ++i)
    for (int k = 0; k < 3; ++k) out(static_cast<Eigen::Index>(i), k) = stand[static_cast<std::size_t>(F(kept[i], k))];
  return out;
}

/// The decimated mesh: collapsedFaces() and the input vertices they use, renumbered in input order.
DecimatedMesh extract(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const std::vector<int>& stand) {
  DecimatedMesh out;
  out.F = collapsedFaces(F, stand);
  std::vector<int> index(static_cast<std::size_t>(V.rows()), -1);
  for (Eigen::Index i = 0; i < out.F.size(); ++i) index[static_cast<std::size_t>(out.F(i))] = 0;
  int next = 0;
  for (int& i : index)
    if (i == 0) i = next++;
  out.V.resize(next, 3);
  out.sourceVertices.resize(next);
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (const int i = index[static_cast<std::size_t>(v)]; i >= 0) {
      out.V.row(i) = V.row(v);
      out.sourceVertices(i) = static_cast<int>(v);
    }
  for (Eigen::Index i = 0; i < out.F.size(); ++i) out.F(i) = index[static_cast<std::size_t>(out.F(i))];
  return out;
}

}  // namespace

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
  SplitMix64 random(kRandomSeed);
  std::vector<std::size_t> order(targets.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return targets[a] > targets[b]; });
  // === collapse down through the targets, largest first, extracting each level
  std::vector<DecimatedMesh> levels(targets.size());
  std::size_t alive = referencedVertices(mesh);
  for (std::size_t i : order) {
    assert(targets[i] >= 3 && "a level needs at least 3 vertices");
    const auto target = static_cast<std::size_t>(targets[i]);
    if (ready && alive > target) alive = decimateTo(decimater, mesh, alive, target, random);
    levels[i] = extract(V, F, decimater.representatives());
    levels[i].refusedFaces = dropped;
    levels[i].targetVertices = targets[i];
  }
  return levels;
}

DecimatedMesh decimateMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetVertices) {
  return std::move(resolutionLadder(V, F, {targetVertices}).front());
}

}  // namespace sc::bench::legacy
