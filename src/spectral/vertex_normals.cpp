#include "spectral/vertex_normals.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sc::spectral {

void vertexNormals(std::span<const float> xyz, std::span<const std::uint32_t> indices, std::span<float> normals) {
  assert(xyz.size() == normals.size() && xyz.size() % 3 == 0 && indices.size() % 3 == 0 && "3 floats per vertex");
  std::fill(normals.begin(), normals.end(), 0.0f);
  // === step 1: accumulate area-weighted face normals on the corners.
  for (std::size_t f = 0; f + 2 < indices.size(); f += 3) {
    const std::size_t i0 = 3 * std::size_t{indices[f]};
    const std::size_t i1 = 3 * std::size_t{indices[f + 1]};
    const std::size_t i2 = 3 * std::size_t{indices[f + 2]};
    assert(i0 < xyz.size() && i1 < xyz.size() && i2 < xyz.size() && "face index out of range");
    const float e1[3] = {xyz[i1] - xyz[i0], xyz[i1 + 1] - xyz[i0 + 1], xyz[i1 + 2] - xyz[i0 + 2]};
    const float e2[3] = {xyz[i2] - xyz[i0], xyz[i2 + 1] - xyz[i0 + 1], xyz[i2 + 2] - xyz[i0 + 2]};
    const float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    for (const std::size_t corner : {i0, i1, i2}) {
      normals[corner] += n[0];
      normals[corner + 1] += n[1];
      normals[corner + 2] += n[2];
    }
  }
  // === step 2: normalise, leaving degenerate neighbourhoods at zero.
  for (std::size_t v = 0; v < normals.size(); v += 3) {
    const float length =
        std::sqrt(normals[v] * normals[v] + normals[v + 1] * normals[v + 1] + normals[v + 2] * normals[v + 2]);
    if (length > 0.0f) {
      normals[v] /= length;
      normals[v + 1] /= length;
      normals[v + 2] /= length;
    }
  }
}

}  // namespace sc::spectral
