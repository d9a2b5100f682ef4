#pragma once
// Private to shapecast_model: the reader of ASCII OFF files (Object File Format, as Geomview, CGAL and MeshLab
// write it). OpenMesh's OFF reader reads coordinates as float32 and rejects comments; this one keeps doubles and
// skips comments. Binary OFF is still read by OpenMesh (its coordinates are float32 in the file).

#include "model/triangle_soup.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>

namespace sc::model::detail {

/// Whether an OFF file's first line asks for the binary variant ("OFF BINARY"). Cost: O(first line).
bool isBinaryOff(std::string_view bytes);

/// Parses an ASCII OFF file held in `bytes`:
///
///     [ST][C][N]OFF           keyword line (the guard checkOffHeaderLine() has already checked it)
///     nv nf [ne]              counts
///     x y z [extras]          nv vertex lines: the first three numbers, as doubles; the rest of the line
///                             (normal, colour, texture coordinate) is ignored
///     n i1 … in [extras]      nf face lines: n ≥ 3 indices into the vertices, counting from 0; extras ignored
///
/// '#' starts a comment that runs to the end of its line, anywhere; blank lines are skipped. Polygons are
/// fan-triangulated (v0 v1 v2), (v0 v2 v3), … as the other readers do. Anything after the last face is ignored.
/// Rejected, with a message naming the line: counts larger than the file can hold (each element takes at least one
/// byte: nothing is allocated from a hostile header), a vertex without three finite numbers, a face with fewer than
/// three corners, fewer indices than it declares or an index out of range, fewer lines than the header declares.
/// @return the soup, or the problem.
/// Cost: O(file size); memory O(#V + #F) beyond the bytes.
std::variant<TriangleSoup, std::string> readAsciiOff(std::string_view bytes);

}  // namespace sc::model::detail
