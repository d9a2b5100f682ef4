// shapecast-make-mesh: makes a large test mesh from a fetched scan, reproducibly.
//   shapecast-make-mesh [--subdivide K] [--vertices N] IN OUT
// Reads IN (loadMesh: cleaned), applies K midpoint subdivisions (midpoint_subdivision.h), then, with --vertices,
// simplifies to N vertices with the product's decimation (model::decimateMesh, meshoptimizer), and writes OUT
// (format from the extension; OFF keeps doubles). Prints each step's time and the counts. Deterministic: the same
// IN gives the same OUT (scripts/make-large-meshes.sh checks the SHA-256).

#include "model/mesh_decimation.h"
#include "model/mesh_loader.h"
#include "model/mesh_writer.h"
#include "tools/large_mesh/midpoint_subdivision.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <variant>

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int usage() {
  std::fprintf(stderr, "usage: shapecast-make-mesh [--subdivide K] [--vertices N] IN OUT\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  int subdivisions = 0;
  long vertices = 0;
  std::string in, out;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--subdivide" && i + 1 < argc) {
      subdivisions = std::atoi(argv[++i]);
    } else if (arg == "--vertices" && i + 1 < argc) {
      vertices = std::atol(argv[++i]);
    } else if (in.empty()) {
      in = arg;
    } else if (out.empty()) {
      out = arg;
    } else {
      return usage();
    }
  }
  if (in.empty() || out.empty() || subdivisions < 0 || subdivisions > 3 || vertices < 0) return usage();

  auto start = std::chrono::steady_clock::now();
  const sc::model::MeshLoadResult loaded = sc::model::loadMesh(in);
  if (const auto* error = std::get_if<sc::model::MeshError>(&loaded)) {
    std::fprintf(stderr, "%s\n", error->message.c_str());
    return 1;
  }
  Eigen::MatrixXd V = std::get<sc::model::LoadedMesh>(loaded).V;
  Eigen::MatrixXi F = std::get<sc::model::LoadedMesh>(loaded).F;
  std::printf("read %s: %lld vertices, %lld triangles, %.2f s\n", in.c_str(), static_cast<long long>(V.rows()),
              static_cast<long long>(F.rows()), secondsSince(start));
  for (int k = 0; k < subdivisions; ++k) {
    start = std::chrono::steady_clock::now();
    sc::tools::SubdividedMesh finer = sc::tools::subdivideMidpoints(V, F);
    V = std::move(finer.V);
    F = std::move(finer.F);
    std::printf("subdivided: %lld vertices, %lld triangles, %.2f s\n", static_cast<long long>(V.rows()),
                static_cast<long long>(F.rows()), secondsSince(start));
  }
  if (vertices > 0 && vertices < V.rows()) {
    start = std::chrono::steady_clock::now();
    sc::model::DecimatedMesh fewer = sc::model::decimateMesh(V, F, static_cast<int>(vertices));
    V = std::move(fewer.V);
    F = std::move(fewer.F);
    std::printf("simplified: %lld vertices, %lld triangles, %.2f s\n", static_cast<long long>(V.rows()),
                static_cast<long long>(F.rows()), secondsSince(start));
  }
  start = std::chrono::steady_clock::now();
  if (const auto failed = sc::model::writeMesh(out, V, F)) {
    std::fprintf(stderr, "%s\n", failed->message.c_str());
    return 1;
  }
  std::printf("wrote %s, %.2f s\n", out.c_str(), secondsSince(start));
  return 0;
}
