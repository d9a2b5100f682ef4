#pragma once
// Conversions between the viewport's interface types and its flat vertex arrays (x y z per vertex, 3 indices per
// triangle), and the origin shift that keeps float precision on the shape rather than on its placement.

#include <Eigen/Core>

#include <QVector3D>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace sc::app {

/// The 3·#F indices of F, triangle by triangle (an element buffer). @param[in] F #F by 3, entries ≥ 0. Cost: O(#F).
std::vector<std::uint32_t> flatIndices(const Eigen::MatrixXi& F);

/// out[3i + c] = xyz[3i + c] + shift(c) in float (out is resized to xyz's size; may not alias it). Cost: O(#V).
void shifted(std::span<const float> xyz, const Eigen::RowVector3d& shift, std::vector<float>& out);

/// The axis-aligned box (lo, hi) of 3·n floats; for n = 0 lo = +max and hi = −max. Cost: O(n).
std::pair<QVector3D, QVector3D> boundsOf(std::span<const float> xyz);

}  // namespace sc::app
