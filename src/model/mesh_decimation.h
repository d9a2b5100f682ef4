#pragma once
// Lower-resolution versions of a triangle mesh by quadric edge-collapse decimation (OpenMesh's decimation framework
// with ModQuadricT, Garland & Heckbert 1997), for the display levels of src/spectral/resolution_level.h.

#include <Eigen/Core>

#include <vector>

namespace sc::model {

/// A decimated mesh.
struct DecimatedMesh {
  Eigen::MatrixXd V;  ///< #V' by 3 positions, every vertex referenced by a face.
  Eigen::MatrixXi F;  ///< #F' by 3 indices into V, orientation as in the input.
  /// #V' indices into the input vertices: V.row(i) is the input's vertex sourceVertices(i) (edge collapses keep
  /// the surviving vertex where it is), so F mapped through it is a coarse triangulation of the input's own
  /// vertices (model::proxyTriangles()).
  Eigen::VectorXi sourceVertices;
  /// Input faces OpenMesh's halfedge mesh refused (non-manifold): they do not steer the collapses, but are carried
  /// through them into F (see decimateMesh()).
  int refusedFaces = 0;
  int targetVertices = 0;  ///< the vertex count that was asked for.
};

/// Decimates (V, F) to about `targetVertices` vertices.
///
/// The faces are added one by one to an OpenMesh TriMesh (double precision); faces it refuses — complex
/// (non-manifold) edges or vertices, as in the Stanford dragon scans — are counted and the decimation runs on what
/// remains. The quadric decimater collapses the cheapest edges (quadric error plus Garland–Heckbert boundary planes,
/// so open boundaries keep their outline) until `targetVertices` vertices of the halfedge mesh remain, or no legal
/// collapse is left (the count may then stay above the target). Each collapse merges a vertex into a neighbour that
/// stays where it is; the result's faces are ALL input faces mapped through these merges, so the refused faces are
/// kept (merged like the rest) instead of leaving holes, and faces that collapsed to an edge or a point, and
/// repeats, are left out. The result may therefore have a few more vertices than the target (vertices that only
/// refused faces use). OpenMesh's complaints on std::cerr are silenced while faces are added (a process-wide
/// switch, shared safely by concurrent calls; other OpenMesh users in the meantime are silenced too).
/// @param[in] V  #V by 3 positions.
/// @param[in] F  #F by 3 indices into V.
/// @param[in] targetVertices  ≥ 3, desired vertex count; ≥ the referenced count returns the (re-indexed) input.
/// @return the decimated mesh, with no unreferenced vertices.
/// Deterministic: the same input gives the same output on every run (the random choices of large meshes come from
/// a fixed-seed generator of our own, not rand()).
/// Cost: O(#F log #F) (priority queue of collapses), ≈ 10 µs per collapse on large meshes (memory-bound: OpenMesh's
/// is_collapse_ok and the candidates' quadrics): about 0.8–0.9 s for the 100k-vertex dragon to 5% on 2 loaded cores.
DecimatedMesh decimateMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetVertices);

/// The default ladder of display levels: fractions of the input vertex count.
inline const std::vector<double> kDefaultLevelFractions = {0.5, 0.2, 0.05};

/// Vertex targets round(fraction · vertexCount), each at least 3. Cost: O(#fractions).
std::vector<int> levelTargets(int vertexCount, const std::vector<double>& fractions = kDefaultLevelFractions);

/// Several levels in one decimation run: the mesh is built once and collapsed progressively through the targets
/// in decreasing order, each level being extracted on the way (every level is a further decimation of the
/// previous one).
/// @param[in] targets  vertex counts, any order (e.g. levelTargets(#V) or explicit counts).
/// @return one mesh per target, in the order of `targets`.
/// Cost: one decimateMesh() to the smallest target plus O(#F) per extracted level.
std::vector<DecimatedMesh> resolutionLadder(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                            const std::vector<int>& targets);

}  // namespace sc::model
