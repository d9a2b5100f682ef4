// shapecast-bench-factor: the numeric LDLᵀ factorisation of S − σM (σ below the spectrum, as the large-mesh basis
// uses) on a real mesh: CHOLMOD's cholmod_factorize against factorUpLooking() on 1 and 2 threads
// (InertiaLdlt::factorizeOnThreads), each into a fresh factor of one shared analysis per round so that every variant
// pays the same first writes of L's pages; the variants take turns round by round so that the machine's load hits
// them alike. Prints the median and range of each, the largest relative difference of D from CHOLMOD's, and the
// machine. Usage: shapecast-bench-factor MESH [rounds = 5]

#include "experiments/report/machine_info.h"
#include "model/mesh_loader.h"
#include "spectral/laplace_operators.h"
#include "spectral/shift_invert_operator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <variant>
#include <vector>

namespace {

using sc::spectral::SparseMatrix;
using sc::spectral::detail::InertiaLdlt;

/// D, the first entry of each column of a simplicial LDLᵀ factor.
std::vector<double> pivots(const InertiaLdlt& ldlt) {
  const cholmod_factor& factor = ldlt.factor();
  const auto* starts = static_cast<const int*>(factor.p);
  const auto* values = static_cast<const double*>(factor.x);
  std::vector<double> d(factor.n);
  for (std::size_t j = 0; j < factor.n; ++j) d[j] = values[starts[j]];
  return d;
}

struct Variant {
  const char* name;
  std::function<void(InertiaLdlt&, const SparseMatrix&)> factorize;
  std::vector<double> seconds;
  double largestDifference = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: shapecast-bench-factor MESH [rounds = 5]\n");
    return 2;
  }
  const int rounds = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  auto loaded = sc::model::loadMesh(argv[1]);
  const auto* mesh = std::get_if<sc::model::LoadedMesh>(&loaded);
  if (mesh == nullptr) {
    std::fprintf(stderr, "cannot load %s\n", argv[1]);
    return 1;
  }
  const sc::spectral::LaplaceOperators ops = sc::spectral::laplaceOperators(mesh->V, mesh->F);
  SparseMatrix shifted = ops.stiffness;
  shifted.diagonal() += 4.0 * std::numbers::pi / ops.totalArea * ops.mass;  // σ = −4π/area
  std::string load;
  std::getline(std::ifstream("/proc/loadavg"), load);
  std::printf("machine   %s\nload      %s (/proc/loadavg, at the start)\n",
              qPrintable(sc::report::machineDescription()), load.c_str());
  std::printf("matrix    S - sigma M of %s: %ld rows, %ld entries; %d rounds\n", argv[1],
              static_cast<long>(shifted.rows()), static_cast<long>(shifted.nonZeros()), rounds);
  std::vector<Variant> variants;
  variants.push_back({"cholmod_factorize", [](InertiaLdlt& l, const SparseMatrix& a) { l.factorize(a); }, {}});
  variants.push_back(
      {"up-looking, 1 thread", [](InertiaLdlt& l, const SparseMatrix& a) { l.factorizeOnThreads(a, 1); }, {}});
  variants.push_back(
      {"up-looking, 2 threads", [](InertiaLdlt& l, const SparseMatrix& a) { l.factorizeOnThreads(a, 2); }, {}});
  for (int round = 0; round < rounds; ++round) {
    std::vector<double> reference;
    for (Variant& variant : variants) {
      InertiaLdlt ldlt;
      ldlt.analyzePattern(shifted);
      const auto start = std::chrono::steady_clock::now();
      variant.factorize(ldlt, shifted);
      variant.seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      if (ldlt.info() != Eigen::Success) {
        std::fprintf(stderr, "%s: the factorisation failed\n", variant.name);
        return 1;
      }
      const std::vector<double> d = pivots(ldlt);
      if (reference.empty()) reference = d;
      for (std::size_t j = 0; j < d.size(); ++j)
        variant.largestDifference =
            std::max(variant.largestDifference, std::abs(d[j] - reference[j]) / std::abs(reference[j]));
    }
  }
  std::printf("%-24s %10s %10s %10s %14s\n", "factorisation", "median s", "min s", "max s", "D vs CHOLMOD");
  for (Variant& variant : variants) {
    std::sort(variant.seconds.begin(), variant.seconds.end());
    std::printf("%-24s %10.3f %10.3f %10.3f %14.1e\n", variant.name, variant.seconds[variant.seconds.size() / 2],
                variant.seconds.front(), variant.seconds.back(), variant.largestDifference);
  }
  std::getline(std::ifstream("/proc/loadavg"), load);
  std::printf("load      %s (/proc/loadavg, at the end)\n", load.c_str());
  return 0;
}
