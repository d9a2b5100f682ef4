#include "spectral/basis_pipeline.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

namespace sc::spectral {
namespace {

TEST(BasisPipeline, SecondRunHitsTheCacheAndCorruptionRecomputes) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("shapecast-pipeline-test-" + std::to_string(std::random_device{}()));
  const auto mesh = testing::torus(30, 12);
  BasisOptions options;
  options.m = 20;

  const BasisComputation first = basisForMesh(mesh.V, mesh.F, options, dir);
  ASSERT_TRUE(first.result.ok()) << first.result.message;
  EXPECT_FALSE(first.cached);
  EXPECT_EQ(first.cacheStatus, CacheReadStatus::Missing);
  ASSERT_TRUE(std::filesystem::exists(first.cacheFile));

  const BasisComputation second = basisForMesh(mesh.V, mesh.F, options, dir);
  ASSERT_TRUE(second.result.ok());
  EXPECT_TRUE(second.cached);
  EXPECT_EQ(second.eigensolveSeconds, 0.0);
  EXPECT_EQ(second.result.basis.vectors, first.result.basis.vectors);

  std::ofstream(first.cacheFile, std::ios::binary | std::ios::trunc) << "garbage";
  const BasisComputation third = basisForMesh(mesh.V, mesh.F, options, dir);
  ASSERT_TRUE(third.result.ok());
  EXPECT_FALSE(third.cached);
  EXPECT_EQ(third.cacheStatus, CacheReadStatus::Corrupt);
  EXPECT_EQ(third.result.basis.vectors, first.result.basis.vectors);
  EXPECT_TRUE(basisForMesh(mesh.V, mesh.F, options, dir).cached) << "the corrupt file must have been rewritten";

  options.m = 21;
  EXPECT_FALSE(basisForMesh(mesh.V, mesh.F, options, dir).cached) << "another m is another basis";
  EXPECT_FALSE(basisForMesh(mesh.V, mesh.F, options, std::nullopt).cached);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sc::spectral
