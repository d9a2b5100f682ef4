#pragma once
// K's rows predicted along the mesh, for the level codec (level_codec.h, section "K"; issue 17). A level's K is n'
// rows of m int16 (one row per display vertex, row-major); neighbouring vertices have similar rows, so each row is
// replaced by its difference from a prediction made from rows visited before it. The visiting order is breadth-first
// over the edges of the faces (restarting at the lowest unvisited vertex); a row's prediction is the rounded mean of
// the parallelograms Q_a + Q_b − Q_c over its faces (v, a, b) whose corners a, b and a vertex c across (a, b) are
// visited (at most 16 faces looked at per vertex, which bounds the work on hostile faces), else the rounded mean of
// its visited neighbours' rows, else 0. Differences wrap around in int16 and are zig-zag coded; they are stored
// column by column as a plane of low bytes followed by a plane of high bytes (2n'm bytes), which zstd squeezes well.
//
// Both directions are exact inverses for any faces (indices ≥ n' are ignored) and any int16 K. Cost: O(n' + f') for
// the order plus O(m) per visited face and neighbour; memory O(n' + f' + n'm).

#include <cstdint>
#include <span>
#include <vector>

namespace sc::session {

/// The residual planes (2n'm bytes) of `rows` (n'·m int16, row-major) over `faces` (3f' vertex indices).
std::vector<std::uint8_t> kResidualPlanes(std::span<const std::uint32_t> faces, std::span<const std::int16_t> rows,
                                          std::uint32_t n, std::uint32_t m);

/// The inverse of kResidualPlanes(): the n'·m int16 rows from `planes` (exactly 2n'm bytes) over the same faces.
std::vector<std::int16_t> kFromResidualPlanes(std::span<const std::uint32_t> faces,
                                              std::span<const std::uint8_t> planes, std::uint32_t n, std::uint32_t m);

}  // namespace sc::session
