#include "spectral/basis_cache.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace sc::spectral {
namespace {

/// A fresh empty folder per test, removed afterwards.
class BasisCache : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    m_dir = std::filesystem::temp_directory_path() /
            ("shapecast-cache-test-" + std::string(info->name()) + "-" + std::to_string(std::random_device{}()));
    std::filesystem::create_directories(m_dir);
    m_basis.eigenvalues = Eigen::VectorXd::LinSpaced(5, 0.0, 4.0);
    m_basis.vectors = Eigen::MatrixXd::Random(50, 5);
    m_basis.shift = -0.25;
    m_key = {0x1234abcdULL, 50, 5, -0.25};
  }
  void TearDown() override { std::filesystem::remove_all(m_dir); }

  std::filesystem::path file() const { return m_dir / basisCacheFileName(m_key); }

  std::filesystem::path m_dir;
  HarmonicBasis m_basis;
  BasisCacheKey m_key;
};

TEST_F(BasisCache, MissThenWriteThenHitRoundTripsExactly) {
  HarmonicBasis read;
  EXPECT_EQ(readBasisCache(file(), m_key, read), CacheReadStatus::Missing);
  ASSERT_TRUE(writeBasisCache(file(), m_key, m_basis));
  ASSERT_EQ(readBasisCache(file(), m_key, read), CacheReadStatus::Hit);
  EXPECT_EQ(read.vectors, m_basis.vectors);
  EXPECT_EQ(read.eigenvalues, m_basis.eigenvalues);
  EXPECT_EQ(read.shift, m_basis.shift);
  EXPECT_FALSE(std::filesystem::exists(file().string() + ".tmp")) << "the temporary file must be renamed away";
}

// Issue 19: the file records the solver that computed the basis, and the solver is part of the key and of the file
// name, so that a basis asked for from one solver is never another's; Lanczos files keep the name and the header field
// (0) they had before the solver was recorded.
TEST_F(BasisCache, TheSolverIsRecordedAndPartOfTheKeyAndTheName) {
  BasisCacheKey hierarchical = m_key;
  hierarchical.solver = BasisSolver::Hierarchical;
  const std::filesystem::path lanczosFile = file();
  const std::filesystem::path hierarchicalFile = m_dir / basisCacheFileName(hierarchical);
  EXPECT_EQ(lanczosFile.filename().string(), "000000001234abcd-n50-m5.mhb");
  EXPECT_EQ(hierarchicalFile.filename().string(), "000000001234abcd-n50-m5-hierarchical.mhb");
  ASSERT_TRUE(writeBasisCache(hierarchicalFile, hierarchical, m_basis));
  ASSERT_TRUE(writeBasisCache(lanczosFile, m_key, m_basis));
  const auto solverField = [](const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    in.seekg(20);
    std::uint32_t value = 99;
    in.read(reinterpret_cast<char*>(&value), sizeof value);
    return value;
  };
  EXPECT_EQ(solverField(lanczosFile), 0u);
  EXPECT_EQ(solverField(hierarchicalFile), 1u);
  HarmonicBasis read;
  EXPECT_EQ(readBasisCache(hierarchicalFile, m_key, read), CacheReadStatus::Mismatch) << "asked for Lanczos";
  EXPECT_EQ(readBasisCache(lanczosFile, hierarchical, read), CacheReadStatus::Mismatch) << "asked for hierarchical";
  EXPECT_EQ(readBasisCache(hierarchicalFile, hierarchical, read), CacheReadStatus::Hit);
  EXPECT_EQ(read.vectors, m_basis.vectors);
}

// Issue 14, item 11: the temporary file has a unique name, created exclusively. A file or link already at the old
// fixed name "<cache>.tmp" (another writer's, or a link planted to redirect the write) is neither followed nor
// touched, and the write still succeeds; no temporary is left behind.
TEST_F(BasisCache, TheTemporaryFileIsUniqueAndNeverFollowsALink) {
  const std::filesystem::path victim = m_dir / "victim.txt";
  {
    std::ofstream out(victim);
    out << "precious";
  }
  const std::filesystem::path planted = file().string() + ".tmp";
  std::filesystem::create_symlink(victim, planted);
  ASSERT_TRUE(writeBasisCache(file(), m_key, m_basis));
  std::ifstream in(victim);
  const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(content == "precious") << "the write followed the planted link (" << content.size() << " bytes now)";
  EXPECT_TRUE(std::filesystem::is_symlink(planted)) << "the planted link was renamed or removed";
  EXPECT_FALSE(std::filesystem::is_symlink(file()));
  HarmonicBasis read;
  EXPECT_EQ(readBasisCache(file(), m_key, read), CacheReadStatus::Hit);
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(m_dir)) ++entries;
  EXPECT_EQ(entries, 3u) << "the victim, the planted link and the cache only: no temporary left";
}

TEST_F(BasisCache, FlippedByteIsCorrupt) {
  ASSERT_TRUE(writeBasisCache(file(), m_key, m_basis));
  {
    std::fstream stream(file(), std::ios::in | std::ios::out | std::ios::binary);
    stream.seekp(200);
    stream.put('\x5a');
  }
  HarmonicBasis read;
  EXPECT_EQ(readBasisCache(file(), m_key, read), CacheReadStatus::Corrupt);
  EXPECT_EQ(read.vectors.size(), 0) << "nothing may be returned from a corrupt file";
}

TEST_F(BasisCache, TruncatedAndGarbageFilesAreCorrupt) {
  ASSERT_TRUE(writeBasisCache(file(), m_key, m_basis));
  std::filesystem::resize_file(file(), std::filesystem::file_size(file()) - 100);
  HarmonicBasis read;
  EXPECT_EQ(readBasisCache(file(), m_key, read), CacheReadStatus::Corrupt);
  std::filesystem::resize_file(file(), 7);
  EXPECT_EQ(readBasisCache(file(), m_key, read), CacheReadStatus::Corrupt);
  std::ofstream(file(), std::ios::trunc) << "this is not a basis file but it is long enough to have a header";
  EXPECT_EQ(readBasisCache(file(), m_key, read), CacheReadStatus::Corrupt);
}

TEST_F(BasisCache, OtherMeshSizeOrShiftIsAMismatch) {
  ASSERT_TRUE(writeBasisCache(file(), m_key, m_basis));
  HarmonicBasis read;
  for (BasisCacheKey other :
       {BasisCacheKey{m_key.meshHash + 1, 50, 5, -0.25}, BasisCacheKey{m_key.meshHash, 50, 5, -0.5}}) {
    EXPECT_EQ(readBasisCache(file(), other, read), CacheReadStatus::Mismatch);
  }
}

TEST_F(BasisCache, WriteRefusesABasisThatDoesNotMatchItsKey) {
  BasisCacheKey wrong = m_key;
  wrong.m = 6;
  EXPECT_FALSE(writeBasisCache(file(), wrong, m_basis));
}

TEST(MeshContentHash, ChangesWithAnyCoordinateOrIndex) {
  const auto mesh = testing::icosphere(1);
  const std::uint64_t h = meshContentHash(mesh.V, mesh.F);
  EXPECT_EQ(h, meshContentHash(mesh.V, mesh.F));
  Eigen::MatrixXd V = mesh.V;
  V(7, 1) = std::nextafter(V(7, 1), 2.0);
  EXPECT_NE(h, meshContentHash(V, mesh.F));
  Eigen::MatrixXi F = mesh.F;
  std::swap(F(3, 0), F(3, 1));
  EXPECT_NE(h, meshContentHash(mesh.V, F));
}

TEST(MeshContentHash, IsTheChecksumOfItsBytesLaidEndToEnd) {
  // What cache files written before it was computed in pieces hold: counts, then V and F row by row. An odd face
  // count leaves a tail shorter than a word; half a megabyte of bytes spans several of its buffers.
  const auto mesh = testing::icosphere(5);
  const Eigen::MatrixXi F = mesh.F.topRows(mesh.F.rows() - 1);
  std::vector<std::byte> bytes;
  const auto put = [&bytes](const auto& value) {
    const auto* p = reinterpret_cast<const std::byte*>(&value);
    bytes.insert(bytes.end(), p, p + sizeof(value));
  };
  put(static_cast<std::uint64_t>(mesh.V.rows()));
  put(static_cast<std::uint64_t>(F.rows()));
  for (Eigen::Index i = 0; i < mesh.V.rows(); ++i)
    for (Eigen::Index c = 0; c < 3; ++c) put(mesh.V(i, c));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (Eigen::Index c = 0; c < 3; ++c) put(static_cast<std::int32_t>(F(f, c)));
  ASSERT_NE(bytes.size() % 8, 0u);
  ASSERT_GT(bytes.size(), std::size_t{4} << 16);
  EXPECT_EQ(meshContentHash(mesh.V, F), checksum64(bytes));
}

}  // namespace
}  // namespace sc::spectral
