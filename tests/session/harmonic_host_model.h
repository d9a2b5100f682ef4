#pragma once
// The model a test host shares: a generated mesh with its cotangent operators and an m-function manifold harmonic
// basis (shared by the loopback, fault and security suites).

#include "session/engine/host_model.h"
#include "test_meshes.h"

#include <memory>

namespace sc::session::testing {

/// A HostModel of `mesh` with an m-function harmonic basis; a failed basis solve is a test failure (EXPECT) and
/// leaves the basis empty. Cost: one Laplacian and one eigensolve of `mesh`.
std::shared_ptr<const HostModel> harmonicHostModel(const sc::testing::GeneratedMesh& mesh, int m);

/// A HostModel of `mesh` whose m-column "basis" is uniform noise in [−1, 1] (seeded) with eigenvalues 0..1: a level
/// payload that does not compress (the host then sends about 2·#V·m bytes of K), for tests that need a transfer of
/// a known, large size. Not a harmonic basis: no deformation test should use it. Cost: one Laplacian of `mesh`.
std::shared_ptr<const HostModel> incompressibleHostModel(const sc::testing::GeneratedMesh& mesh, int m, unsigned seed);

}  // namespace sc::session::testing
