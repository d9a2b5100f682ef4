#include "test_meshes.h"

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

namespace sc::testing {
namespace {

GeneratedMesh fromLists(const std::vector<Eigen::Vector3d>& points, const std::vector<std::array<int, 3>>& faces) {
  GeneratedMesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) mesh.V.row(static_cast<Eigen::Index>(i)) = points[i];
  mesh.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int c = 0; c < 3; ++c) mesh.F(static_cast<Eigen::Index>(f), c) = faces[f][static_cast<std::size_t>(c)];
  return mesh;
}

}  // namespace

GeneratedMesh icosphere(int subdivisions, double radius, const Eigen::Vector3d& center) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& q : p) q.normalize();
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (auto it = midpoint.find(key); it != midpoint.end()) return it->second;
      p.push_back((p[static_cast<std::size_t>(a)] + p[static_cast<std::size_t>(b)]).normalized());
      return midpoint[key] = static_cast<int>(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(f.size() * 4);
    for (const auto& [a, b, c] : f) {
      const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
      next.push_back({a, ab, ca});
      next.push_back({b, bc, ab});
      next.push_back({c, ca, bc});
      next.push_back({ab, bc, ca});
    }
    f = std::move(next);
  }
  for (auto& q : p) q = center + radius * q;
  return fromLists(p, f);
}

GeneratedMesh torus(int u, int v, double R, double r) {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::array<int, 3>> f;
  const double twoPi = 2.0 * std::numbers::pi;
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      const double a = twoPi * i / u, b = twoPi * j / v;
      p.emplace_back((R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b));
    }
  auto id = [&](int i, int j) { return (i % u) * v + (j % v); };
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return fromLists(p, f);
}

GeneratedMesh grid(int nx, int ny) {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::array<int, 3>> f;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) p.emplace_back(static_cast<double>(i) / nx, static_cast<double>(j) / ny, 0.0);
  auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return fromLists(p, f);
}

GeneratedMesh tube(int around, int along, double length, double r) {
  std::vector<Eigen::Vector3d> p;
  std::vector<std::array<int, 3>> f;
  const double twoPi = 2.0 * std::numbers::pi;
  for (int i = 0; i <= along; ++i)
    for (int j = 0; j < around; ++j) {
      const double a = twoPi * j / around;
      p.emplace_back(length * i / along, r * std::cos(a), r * std::sin(a));
    }
  auto id = [&](int i, int j) { return i * around + (j % around); };
  for (int i = 0; i < along; ++i)
    for (int j = 0; j < around; ++j) {
      f.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      f.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
  return fromLists(p, f);
}

GeneratedMesh twoSpheres(int subdivisions) {
  return joined(icosphere(subdivisions, 1.0, {0, 0, 0}), icosphere(subdivisions, 1.0, {3, 0, 0}));
}

GeneratedMesh twoSpheresAndATorus() {
  GeneratedMesh ring = torus(48, 16);
  ring.V.col(1).array() += 4.0;
  return joined(twoSpheres(4), ring);
}

GeneratedMesh joined(const GeneratedMesh& a, const GeneratedMesh& b) {
  GeneratedMesh both;
  both.V.resize(a.V.rows() + b.V.rows(), 3);
  both.V << a.V, b.V;
  both.F.resize(a.F.rows() + b.F.rows(), 3);
  both.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  return both;
}

}  // namespace sc::testing
