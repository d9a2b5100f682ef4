#pragma once
// Private helper of src/spectral: ask the kernel to back a large buffer with transparent huge pages.

#include <cstddef>
#include <vector>

namespace sc::spectral::detail {

/// Advises Linux to back the 2 MiB-aligned part of [data, data + bytes) with transparent huge pages
/// (madvise(MADV_HUGEPAGE)), for a buffer written for the first time after this call. Where THP is set to
/// "madvise" (Debian's default), each first write then faults 2 MiB instead of 4 KiB, and the sweeps over it miss
/// the TLB less. `shapecast-cli basis` on the 437k scan took 376,000 page faults (about 10% of its CPU time on the
/// measuring VM), 75,000 with the Krylov basis, the residual check's buffers and CHOLMOD's allocations advised.
/// A hint only: does nothing on other systems, where THP is off, or for buffers under 2 MiB; never fails.
/// Cost: one system call.
void adviseHugePages(void* data, std::size_t bytes);

/// `count` copies of `value` in a vector whose buffer was advised onto huge pages before its first write (a
/// std::vector's constructor writes every element at once: 4 KiB faults, about 14 µs each on the measuring VM).
template <class T>
std::vector<T> hugePageVector(std::size_t count, const T& value) {
  std::vector<T> v;
  v.reserve(count);
  adviseHugePages(v.data(), count * sizeof(T));
  v.assign(count, value);
  return v;
}

}  // namespace sc::spectral::detail
