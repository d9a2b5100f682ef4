#include "spectral/surface_distance.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace sc::spectral {
namespace {

TEST(SurfaceDistance, IdenticalMeshesAreAtZero) {
  const auto mesh = testing::torus(30, 12);
  const SymmetricSurfaceDistance d = symmetricSurfaceDistance(mesh.V, mesh.F, mesh.V, mesh.F, 1.0);
  EXPECT_LT(d.maxRaw, 1e-15);
}

TEST(SurfaceDistance, ParallelGridsAreTheirOffsetApart) {
  const auto a = testing::grid(10, 10);
  auto b = testing::grid(7, 5);
  b.V.col(2).array() += 0.25;
  const double diagonal = 2.0;
  const SymmetricSurfaceDistance d = symmetricSurfaceDistance(a.V, a.F, b.V, b.F, diagonal);
  for (const SurfaceDistance* s : {&d.aToB, &d.bToA}) {
    EXPECT_NEAR(s->raw.max, 0.25, 1e-14);
    EXPECT_NEAR(s->raw.mean, 0.25, 1e-14);
    EXPECT_NEAR(s->raw.rms, 0.25, 1e-14);
    EXPECT_NEAR(s->relative.max, 0.125, 1e-14);
  }
  EXPECT_NEAR(d.maxRelative, 0.125, 1e-14);
}

TEST(SurfaceDistance, OneSidedDiffersFromSymmetricForAPartialSurface) {
  // A half grid lies on the full grid (0 one way) but the full grid's far half is away from it.
  const auto full = testing::grid(10, 10);
  auto half = testing::grid(10, 10);
  half.V.col(0) *= 0.5;
  const SymmetricSurfaceDistance d = symmetricSurfaceDistance(half.V, half.F, full.V, full.F, 1.0);
  EXPECT_LT(d.aToB.raw.max, 1e-15);
  EXPECT_NEAR(d.bToA.raw.max, 0.5, 1e-14);
  EXPECT_NEAR(d.maxRaw, 0.5, 1e-14);
  EXPECT_GT(d.bToA.raw.rms, d.bToA.raw.mean);
}

TEST(SurfaceDistance, ConcentricSpheresAreAboutTheRadiusGapApart) {
  const auto inner = testing::icosphere(4, 1.0), outer = testing::icosphere(3, 1.1);
  const double diagonal = boundingBoxDiagonal(inner.V);
  const SurfaceDistance d = pointToSurfaceDistance(outer.V, inner.V, inner.F, diagonal);
  EXPECT_GE(d.raw.max, 0.1);
  EXPECT_LT(d.raw.max, 0.1 + 0.01);  // plus the chord sagitta of the inner sphere
  EXPECT_DOUBLE_EQ(d.relative.max, d.raw.max / diagonal);
}

}  // namespace
}  // namespace sc::spectral
