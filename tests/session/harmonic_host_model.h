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

}  // namespace sc::session::testing
