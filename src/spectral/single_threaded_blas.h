#pragma once
// SingleThreadedBlas: OpenBLAS on one thread for a scope, where the caller runs its own threads. Internal to
// src/spectral (spectrum_slices.cpp, large_mesh_eigenpairs.cpp, lanczos_solver.cpp).

// OpenBLAS's thread-count controls, when the BLAS linked is OpenBLAS (weak: absent with another BLAS).
extern "C" {
__attribute__((weak)) int openblas_get_num_threads();
__attribute__((weak)) void openblas_set_num_threads(int threads);
}

#include <mutex>

namespace sc::spectral::detail {

/// One BLAS thread for the object's lifetime: the eigensolvers split their work over their own std::threads (slices,
/// solve threads, bands of rows), and OpenBLAS's threads on top of them oversubscribe the cores. Measured on 2 cores:
/// two slices each running a 2-thread OpenBLAS GEMV took 5.0–5.3 s on the 100k dragon against 3.9 s; the one block
/// Lanczos run on the 437k scan took 250 s with OpenBLAS's threads against 25 s with one, while two busy processes
/// shared the cores (its BLAS calls came from two band threads at once, and OpenBLAS's waits for its own threads
/// turn into scheduler time slices there). The setting is process-wide, so it is restored when the last holder
/// leaves; another thread's BLAS call meanwhile runs on one thread too. Without OpenBLAS it does nothing.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas() {
    if (openblas_get_num_threads == nullptr || openblas_set_num_threads == nullptr) return;
    const std::lock_guard lock(shared().mutex);
    if (shared().holders++ == 0) {
      shared().previous = openblas_get_num_threads();
      openblas_set_num_threads(1);
    }
  }
  ~SingleThreadedBlas() {
    if (openblas_get_num_threads == nullptr || openblas_set_num_threads == nullptr) return;
    const std::lock_guard lock(shared().mutex);
    if (--shared().holders == 0 && shared().previous > 0) openblas_set_num_threads(shared().previous);
  }
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

 private:
  /// One count per process: the first holder saves the setting, the last restores it, so that holders on several
  /// threads (nested or overlapping) never leave OpenBLAS on one thread, nor restore it while another still runs.
  struct Shared {
    std::mutex mutex;
    int holders = 0;
    int previous = 0;
  };
  static Shared& shared() {
    static Shared state;
    return state;
  }
};

}  // namespace sc::spectral::detail
