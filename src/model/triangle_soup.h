#pragma once
// Private to shapecast_model: what a mesh file reader delivers before cleaning.

#include <Eigen/Core>

#include <cstddef>

namespace sc::model::detail {

/// A triangulated but uncleaned mesh as read: V #V by 3, F #F by 3 with every index valid in V.
struct TriangleSoup {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  std::size_t polygonCount = 0;  ///< faces in the file, before fan triangulation.
};

}  // namespace sc::model::detail
