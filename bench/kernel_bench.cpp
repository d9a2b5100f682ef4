// shapecast-bench-kernel: per-frame time of the client reconstruction X' = X̂' + K·Z (reconstructInterleaved)
// on random data of a display level's size; median over many frames, for 1 and 2 threads.
// Usage: shapecast-bench-kernel [vertices = 100000] [m = 100] [frames = 200]

#include "experiments/report/machine_info.h"
#include "spectral/reconstruction_kernel.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// Median milliseconds per frame; Z changes every frame as a host's stream would.
double medianFrameMs(const sc::spectral::RowMatrixXf& K, const std::vector<float>& rest, int frames, int threads) {
  std::vector<float> out(rest.size());
  std::vector<double> ms;
  float checksum = 0;
  for (int frame = -5; frame < frames; ++frame) {  // 5 warm-up frames
    const Eigen::MatrixXf Z = Eigen::MatrixXf::Random(K.cols(), 3);
    const auto start = std::chrono::steady_clock::now();
    sc::spectral::reconstructInterleaved(K, rest, Z, out, threads);
    const auto stop = std::chrono::steady_clock::now();
    checksum += out[static_cast<std::size_t>(frame + 5) % out.size()];
    if (frame >= 0) ms.push_back(std::chrono::duration<double, std::milli>(stop - start).count());
  }
  if (checksum == 12345.0f) std::puts("");  // keeps the output observable
  return median(ms);
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
  const sc::spectral::RowMatrixXf K = sc::spectral::RowMatrixXf::Random(n, m);
  const std::vector<float> rest = sc::spectral::interleavedPositions(Eigen::MatrixXd::Random(n, 3));
  std::printf("machine   %s\n", qPrintable(sc::report::machineDescription()));
  std::printf("kernel    X' = X^' + K Z, n' = %ld, m = %ld, K = %.1f MB float32 row-major, %d frames\n", n, m,
              4.0 * static_cast<double>(n * m) / 1e6, frames);
  for (int threads : {1, 2}) {
    const double ms = medianFrameMs(K, rest, frames, threads);
    std::printf("threads %d median %.3f ms/frame (%.1f GB/s of K)\n", threads, ms,
                4.0 * static_cast<double>(n * m) / (ms * 1e6));
  }
  return 0;
}
