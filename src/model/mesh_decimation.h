#pragma once
// Lower-resolution versions of a triangle mesh by quadric edge-collapse simplification (meshoptimizer's
// meshopt_simplify, Garland & Heckbert 1997 quadrics), for the display levels of src/spectral/resolution_level.h and
// the viewport's interactive proxy (model/mesh_proxy.h).

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
  /// Input faces a halfedge mesh would refuse on their edges (non-manifold: a third face on an edge, a flipped
  /// neighbour, a repeated corner): they do not steer the collapses, but are carried through them into F (see
  /// decimateMesh()).
  int refusedFaces = 0;
  int targetVertices = 0;  ///< the vertex count that was asked for.
};

/// Decimates (V, F) to about `targetVertices` vertices.
///
/// === What is simplified. Faces that a halfedge mesh would refuse on their edges (model/face_edges.h: as in the
/// Stanford dragon scans) and, while they are few, the faces of components of at most 32 vertices (scan debris,
/// which the simplifier would collapse away first) are set aside; the rest goes to meshopt_simplify
/// (meshoptimizer 0.18, float positions, no error limit): quadric edge collapses in passes, each merging a vertex
/// into a neighbour that stays where it is; open borders only collapse along themselves, vertices with several
/// open edges (non-manifold) stay. meshoptimizer aims at a triangle count: the vertex count is reached by a run on
/// the whole input and a few short runs on its result (model/meshopt_simplification.h), within max(1, 0.5%) of
/// the target unless topology stops the collapses (the count then stays above).
/// === What comes out. The simplified faces, the debris as it was, and the refused faces with each corner moved
/// to the nearest surviving vertex (in edges; the simplifier does not report its collapse chains), so they leave
/// no holes; faces that collapsed to an edge or a point, and repeats, are left out. Vertices used only by set-aside
/// faces count towards the target (the simplified part aims at the rest). Every vertex is an input vertex, at its
/// input position (double precision): P maps level vertices exactly.
/// @param[in] V  #V by 3 positions.
/// @param[in] F  #F by 3 indices into V.
/// @param[in] targetVertices  ≥ 3, desired vertex count; ≥ the referenced count returns the (re-indexed) input.
/// @return the decimated mesh, with no unreferenced vertices. Faces: the simplified ones (input order), then the
/// set-aside ones.
/// Deterministic: the same input gives the same output on every run.
/// Cost: O(#F log #F): about 0.15 s for the 100k-vertex dragon to 5% on 2 loaded cores (docs/benchmarks.md).
DecimatedMesh decimateMesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetVertices);

/// The default ladder of display levels: fractions of the input vertex count.
inline const std::vector<double> kDefaultLevelFractions = {0.5, 0.2, 0.05};

/// Vertex targets round(fraction · vertexCount), each at least 3. Cost: O(#fractions).
std::vector<int> levelTargets(int vertexCount, const std::vector<double>& fractions = kDefaultLevelFractions);

/// Several levels in one run: the input is split once (see decimateMesh()) and simplified through the targets in
/// decreasing order, each level from the previous one's simplified faces (every level is a further decimation of
/// the previous one; each run recomputes its quadrics from that level).
/// @param[in] targets  vertex counts, any order (e.g. levelTargets(#V) or explicit counts).
/// @return one mesh per target, in the order of `targets`.
/// Cost: one decimateMesh() to the largest target plus, per further level, runs on the previous level.
std::vector<DecimatedMesh> resolutionLadder(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                                            const std::vector<int>& targets);

/// decimateMesh() aimed at a triangle count instead of a vertex count: one meshopt_simplify run (no steering),
/// for the interactive proxy. targetVertices in the result is the vertex count the triangles stand for.
/// @param[in] targetTriangles  ≥ 1; the result has about this many triangles (at most, plus carried refused faces
///            and debris beyond the estimate; more when topology stops the collapses).
/// Cost: one meshopt_simplify run on the input: about 0.7 s for the 437k dragon to 20,000 triangles (2 loaded cores).
DecimatedMesh decimateToTriangles(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetTriangles);

}  // namespace sc::model
