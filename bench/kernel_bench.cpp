// shapecast-bench-kernel: per-frame time of the client reconstruction X' = X̂' + K·Z (reconstructInterleaved)
// on random data of a display level's size; median over many frames, for 1 and 2 threads, with K in float32 (the
// reference) and quantised to int16 with a scale per column (what a level holds since level format 2), each with the
// portable one-row loop and the fastest loop this CPU has (AVX2 + FMA, four rows per pass), in one run.
// Usage: shapecast-bench-kernel [vertices = 100000] [m = 100] [frames = 200]

#include "experiments/report/machine_info.h"
#include "spectral/reconstruction_kernel.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// CPU time of the calling thread in ms (excludes the time the scheduler gives other processes: on a shared
/// machine the wall time also counts theirs).
double threadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

struct FrameMs {
  double wall = 0.0;
  double cpu = 0.0;  ///< the calling thread's CPU time (meaningful for 1 thread)
};

constexpr sc::spectral::KernelLoop kLoops[] = {sc::spectral::KernelLoop::Portable, sc::spectral::KernelLoop::Fastest};

/// Median milliseconds per frame of each loop (kLoops order), the loops taking turns frame by frame on the same Z so
/// that the machine's load hits both alike; Z changes every frame as a host's stream would. Basis: RowMatrixXf or
/// QuantizedBasis.
template <class Basis>
std::vector<FrameMs> medianFrameMs(const Basis& K, const std::vector<float>& rest, int frames, int threads) {
  std::vector<float> out(rest.size());
  std::vector<std::vector<double>> ms(std::size(kLoops)), cpu(std::size(kLoops));
  float checksum = 0;
  for (int frame = -5; frame < frames; ++frame) {  // 5 warm-up frames
    const Eigen::MatrixXf Z = Eigen::MatrixXf::Random(K.cols(), 3);
    for (std::size_t l = 0; l < std::size(kLoops); ++l) {
      const double cpuStart = threadCpuMs();
      const auto start = std::chrono::steady_clock::now();
      sc::spectral::reconstructInterleaved(K, rest, Z, out, threads, kLoops[l]);
      const auto stop = std::chrono::steady_clock::now();
      if (frame >= 0) cpu[l].push_back(threadCpuMs() - cpuStart);
      checksum += out[static_cast<std::size_t>(frame + 5) % out.size()];
      if (frame >= 0) ms[l].push_back(std::chrono::duration<double, std::milli>(stop - start).count());
    }
  }
  if (checksum == 12345.0f) std::puts("");  // keeps the output observable
  std::vector<FrameMs> result;
  for (std::size_t l = 0; l < std::size(kLoops); ++l) result.push_back({median(ms[l]), median(cpu[l])});
  return result;
}

/// The first line of /proc/loadavg (1, 5 and 15-minute load averages, …), or "?" where there is none.
std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string line;
  return std::getline(in, line) ? line : std::string("?");
}

}  // namespace

int main(int argc, char** argv) {
  const long n = argc > 1 ? std::atol(argv[1]) : 100000;
  const long m = argc > 2 ? std::atol(argv[2]) : 100;
  const int frames = argc > 3 ? std::atoi(argv[3]) : 200;
  if (n <= 0 || m <= 0 || frames <= 0) {
    std::fprintf(stderr, "usage: shapecast-bench-kernel [vertices] [m] [frames]\n");
    return 2;
  }
  const Eigen::MatrixXd random = Eigen::MatrixXd::Random(n, m);
  const sc::spectral::RowMatrixXf K = random.cast<float>();
  const sc::spectral::QuantizedBasis K16 = sc::spectral::quantizeBasis(random);
  const std::vector<float> rest = sc::spectral::interleavedPositions(Eigen::MatrixXd::Random(n, 3));
  std::printf("machine   %s\n", qPrintable(sc::report::machineDescription()));
  std::printf("load      %s (/proc/loadavg, at the start)\n", loadAverage().c_str());
  std::printf("kernel    X' = X^' + K Z, n' = %ld, m = %ld, K row-major, %d frames, loops taking turns per frame\n", n,
              m, frames);
  const auto report = [&](const char* what, double bytesPerEntry, auto&& basis) {
    for (int threads : {1, 2}) {
      const std::vector<FrameMs> ms = medianFrameMs(basis, rest, frames, threads);
      for (std::size_t l = 0; l < std::size(kLoops); ++l)
        std::printf(
            "%-7s K %6.1f MB threads %d %-26s median %.3f ms/frame (%.1f GB/s of K), CPU of the calling thread "
            "%.3f ms\n",
            what, bytesPerEntry * static_cast<double>(n * m) / 1e6, threads,
            sc::spectral::kernelLoopDescription(kLoops[l]), ms[l].wall,
            bytesPerEntry * static_cast<double>(n * m) / (ms[l].wall * 1e6), ms[l].cpu);
    }
  };
  report("float32", 4.0, K);
  report("int16", 2.0, K16);
  std::printf("load      %s (/proc/loadavg, at the end)\n", loadAverage().c_str());
  return 0;
}
