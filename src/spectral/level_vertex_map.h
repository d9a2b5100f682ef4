#pragma once
// From full-resolution vertices back to the displayed vertices of a level (dominantFullVertices() in
// resolution_level.h goes the other way). A client keeps its handle and anchors as full-resolution ids, the ids
// Constraints carry, and shows them on whichever level it displays: on the level they were picked on they are the
// same displayed vertices again; on a coarser level some full vertices have no displayed vertex standing for them,
// and the displayed vertex nearest to where they lie stands in, so that a group never vanishes from the screen.

#include "spectral/resolution_level.h"
#include "spectral/vertex_ids.h"

#include <Eigen/Core>

#include <span>

namespace sc::spectral {

/// Full-resolution vertices and where each lies at rest.
struct LocatedFullVertices {
  FullVertexIds ids;       ///< sorted ascending, unique
  Eigen::MatrixXd points;  ///< ids.size() by 3: row k where ids[k] lies at rest; 0 rows: not known
};

/// dominantFullVertices(level.P, displayed), each with where it lies: the rest position X̂' of the first displayed
/// vertex (in the order given) that stands for it, on a face of the full mesh around it.
/// Cost: O(k log k) for k = displayed.size().
LocatedFullVertices locateFullVertices(const ResolutionLevel& level, std::span<const DisplayVertexId> displayed);

/// The displayed vertices of `level` that show `full`: every displayed vertex whose dominant full vertex is one of
/// full.ids, and for each id that none stands for, the displayed vertex nearest to its point (exact Euclidean
/// distance at rest; nothing for it when full.points has no rows). Sorted ascending, unique.
/// Cost: O(n' log k) over the rows of P; when an id has no displayed vertex, O(n' log n') once for a kd-tree over
/// X̂' and O(log n') per such id.
DisplayVertexIds displayedVertices(const ResolutionLevel& level, const LocatedFullVertices& full);

}  // namespace sc::spectral
