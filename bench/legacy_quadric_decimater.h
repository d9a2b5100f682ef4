#pragma once
// The project's own quadric decimater before meshoptimizer replaced it (issue 19), kept only as the "before" of
// shapecast-bench-decimation: the halfedge mesh type and the quadric edge-collapse decimater behind
// legacy_decimation.cpp.

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/BaseDecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <OpenMesh/Tools/Utils/HeapT.hh>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace sc::bench::legacy::detail {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

/// SplitMix64 (Steele, Lea & Flood 2014): fully specified, so a level is the same on every run and platform, and
/// no process-wide rand() state is read or changed.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : m_state(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (m_state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, n), n < 2^32 (Lemire's multiply-shift on the high 32 bits; bias below n / 2^32).
  std::size_t below(std::size_t n) {
    return static_cast<std::size_t>(((next() >> 32) * static_cast<std::uint64_t>(n)) >> 32);
  }

 private:
  std::uint64_t m_state;
};

/// OpenMesh's two decimation loops (McDecimaterT, DecimaterT) on OpenMesh's modules and collapses, priority first:
/// the cheap quadric priority of every candidate halfedge is computed, and the expensive topological test
/// (is_collapse_legal(), mostly TriConnectivity::is_collapse_ok()'s one-ring intersection) runs on the candidates
/// in increasing priority only until one passes. That is still the cheapest legal candidate, first in iteration
/// order on ties, as OpenMesh picks it (with the same random stream the output is bit-identical to
/// MixedDecimaterT's), but with about 1.03 legality tests per choice instead of one per candidate: 2–3× faster.
class Decimater : public OpenMesh::Decimater::BaseDecimaterT<Mesh> {
 public:
  explicit Decimater(Mesh& mesh) : BaseDecimaterT<Mesh>(mesh), m_mesh(mesh) {}

  /// Multiple-choice decimation: each collapse is the cheapest legal one among `samples` halfedges of random live
  /// edges (McDecimaterT draws from all halfedges, deleted ones included, so late in a run it compares only one or
  /// two candidates; drawing live edges keeps the choice real: 0.78% instead of 1.09% of the diagonal on the dragon).
  /// Stops early, like McDecimaterT, after kMaxIdleRounds rounds in a row without a legal candidate.
  /// @return the number of collapses done.
  std::size_t decimateMultipleChoice(std::size_t collapses, std::size_t samples, SplitMix64& random) {
    if (collapses == 0) return 0;
    std::vector<int> edges;
    std::size_t deletedEdges = 0;  // since `edges` was last rebuilt
    std::size_t misses = 0;        // deleted edges drawn in this round
    const auto rebuild = [&] {
      edges.clear();
      for (const auto e : m_mesh.edges())
        if (!m_mesh.status(e).deleted()) edges.push_back(e.idx());
      deletedEdges = 0;
      misses = 0;
    };
    rebuild();
    std::size_t done = 0, idle = 0;
    while (done < collapses && idle <= kMaxIdleRounds && !edges.empty()) {
      m_candidates.clear();
      misses = 0;
      for (std::size_t drawn = 0; drawn < samples && !edges.empty();) {
        const std::size_t k = random.below(2 * edges.size());
        const Mesh::EdgeHandle e(edges[k / 2]);
        if (m_mesh.status(e).deleted()) {  // at most about half of `edges` are: about two draws per sample
          if (++misses > kMaxMisses) rebuild();
          continue;
        }
        ++drawn;
        const Mesh::HalfedgeHandle h = m_mesh.halfedge_handle(e, static_cast<unsigned>(k % 2));
        const float priority = collapse_priority(CollapseInfo(m_mesh, h));
        if (priority >= 0) m_candidates.push_back({priority, h});
      }
      sortByPriority(m_candidates);
      bool collapsed = false;
      for (const Candidate& c : m_candidates) {
        CollapseInfo ci(m_mesh, c.halfedge);
        if (!is_collapse_legal(ci)) continue;
        // A collapse deletes its edge and one more edge per adjacent triangle.
        deletedEdges += 1 + (ci.fl.is_valid() ? 1 : 0) + (ci.fr.is_valid() ? 1 : 0);
        collapse(ci);
        collapsed = true;
        break;
      }
      idle = collapsed ? 0 : idle + 1;
      done += collapsed ? 1 : 0;
      if (2 * deletedEdges > edges.size()) rebuild();
    }
    return done;
  }

  /// Greedy decimation through a priority queue of vertices, each keyed by its cheapest legal outgoing halfedge
  /// (as DecimaterT::decimate(), with OpenMesh's heap).
  /// @return the number of collapses done (fewer than asked when no legal collapse is left).
  std::size_t decimateGreedy(std::size_t collapses) {
    if (collapses == 0) return 0;
    m_target.assign(m_mesh.n_vertices(), Mesh::HalfedgeHandle());
    m_priority.assign(m_mesh.n_vertices(), -1.0f);
    m_position.assign(m_mesh.n_vertices(), -1);
    Heap heap(HeapInterface{&m_priority, &m_position});
    heap.reserve(m_mesh.n_vertices());
    for (const auto v : m_mesh.vertices())
      if (!m_mesh.status(v).deleted()) updateVertex(heap, v);
    std::vector<Mesh::VertexHandle> ring;
    std::size_t done = 0;
    while (!heap.empty() && done < collapses) {
      const Mesh::VertexHandle v = heap.front();
      heap.pop_front();
      CollapseInfo ci(m_mesh, m_target[static_cast<std::size_t>(v.idx())]);
      if (!is_collapse_legal(ci)) continue;
      ring.assign(m_mesh.vv_begin(ci.v0), m_mesh.vv_end(ci.v0));
      collapse(ci);
      ++done;
      for (const auto w : ring) updateVertex(heap, w);
    }
    return done;
  }

  /// The vertex each input vertex now stands for: itself, or (after collapses) the vertex it was merged into.
  /// Cost: O(#V) (each chain is followed once, then short-cut).
  std::vector<int> representatives() {
    std::vector<int> out(m_mesh.n_vertices(), -1);
    m_collapsedInto.resize(m_mesh.n_vertices(), -1);
    std::vector<int> path;
    const auto find = [&](int v) {
      path.clear();
      while (out[static_cast<std::size_t>(v)] < 0 && m_collapsedInto[static_cast<std::size_t>(v)] >= 0) {
        path.push_back(v);
        v = m_collapsedInto[static_cast<std::size_t>(v)];
      }
      const int root = out[static_cast<std::size_t>(v)] >= 0 ? out[static_cast<std::size_t>(v)] : v;
      out[static_cast<std::size_t>(v)] = root;
      for (const int w : path) out[static_cast<std::size_t>(w)] = root;
      return root;
    };
    for (std::size_t v = 0; v < out.size(); ++v) find(static_cast<int>(v));
    return out;
  }

 private:
  struct Candidate {
    float priority;
    Mesh::HalfedgeHandle halfedge;
  };
  /// OpenMesh's heap keyed by plain per-vertex arrays.
  struct HeapInterface {
    std::vector<float>* priority;
    std::vector<int>* position;
    bool less(Mesh::VertexHandle a, Mesh::VertexHandle b) const { return at(priority, a) < at(priority, b); }
    bool greater(Mesh::VertexHandle a, Mesh::VertexHandle b) const { return at(priority, a) > at(priority, b); }
    int get_heap_position(Mesh::VertexHandle v) const { return at(position, v); }
    void set_heap_position(Mesh::VertexHandle v, int i) { at(position, v) = i; }
    template <class T>
    static T& at(std::vector<T>* values, Mesh::VertexHandle v) {
      return (*values)[static_cast<std::size_t>(v.idx())];
    }
  };
  using Heap = OpenMesh::Utils::HeapT<Mesh::VertexHandle, HeapInterface>;
  /// McDecimaterT gives up after this many rounds in a row without a collapse.
  static constexpr std::size_t kMaxIdleRounds = 20;
  /// Deleted edges drawn in one round before the live list is rebuilt anyway (a safeguard: with at most about half
  /// of the list deleted, more than 64 misses before 8 hits has probability below 1e-12).
  static constexpr std::size_t kMaxMisses = 64;

  /// Stable insertion sort by increasing priority (a handful of candidates: no allocation, ties keep their order).
  static void sortByPriority(std::vector<Candidate>& candidates) {
    for (std::size_t i = 1; i < candidates.size(); ++i)
      for (std::size_t j = i; j > 0 && candidates[j].priority < candidates[j - 1].priority; --j)
        std::swap(candidates[j], candidates[j - 1]);
  }

  void collapse(CollapseInfo& ci) {
    m_collapsedInto.resize(m_mesh.n_vertices(), -1);
    m_collapsedInto[static_cast<std::size_t>(ci.v0.idx())] = ci.v1.idx();  // v0 merges into v1, which stays put
    preprocess_collapse(ci);
    m_mesh.collapse(ci.v0v1);
    postprocess_collapse(ci);
  }

  /// Re-keys v by its cheapest legal outgoing halfedge, or takes it off the heap when it has none.
  void updateVertex(Heap& heap, Mesh::VertexHandle v) {
    m_candidates.clear();
    for (const auto h : m_mesh.voh_range(v)) {
      const float priority = collapse_priority(CollapseInfo(m_mesh, h));
      if (priority >= 0) m_candidates.push_back({priority, h});
    }
    sortByPriority(m_candidates);
    const auto i = static_cast<std::size_t>(v.idx());
    for (const Candidate& c : m_candidates) {
      if (!is_collapse_legal(CollapseInfo(m_mesh, c.halfedge))) continue;
      m_target[i] = c.halfedge;
      m_priority[i] = c.priority;
      if (heap.is_stored(v))
        heap.update(v);
      else
        heap.insert(v);
      return;
    }
    if (heap.is_stored(v)) heap.remove(v);
    m_target[i] = Mesh::HalfedgeHandle();
    m_priority[i] = -1.0f;
  }

  Mesh& m_mesh;
  std::vector<Mesh::HalfedgeHandle> m_target;  ///< per vertex: its cheapest legal collapse
  std::vector<float> m_priority;               ///< per vertex: that collapse's priority (heap key), −1 if none
  std::vector<int> m_position;                 ///< per vertex: heap position, −1 when not stored
  std::vector<int> m_collapsedInto;            ///< per vertex: the vertex it was collapsed into, −1 if none
  std::vector<Candidate> m_candidates;         ///< scratch
};

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

}  // namespace sc::bench::legacy::detail
