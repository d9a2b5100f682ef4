#pragma once
// Private helper of src/spectral: split an index range over a few std::threads.

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace sc::spectral::detail {

/// Calls body(begin, end) on `threads` contiguous, near-equal chunks of [0, count): chunk 0 on the calling
/// thread, the others on new std::threads joined before returning. threads ≤ 1 (or count small) runs inline.
/// `body` must be safe to call concurrently on disjoint ranges. Cost: count work plus ≈ 20–50 µs per extra thread.
template <class Body>
void parallelRanges(std::ptrdiff_t count, int threads, const Body& body) {
  const std::ptrdiff_t chunks = std::clamp<std::ptrdiff_t>(threads, 1, std::max<std::ptrdiff_t>(count, 1));
  if (chunks == 1) {
    body(std::ptrdiff_t{0}, count);
    return;
  }
  const auto bound = [&](std::ptrdiff_t c) { return count * c / chunks; };
  std::vector<std::thread> workers;
  workers.reserve(static_cast<std::size_t>(chunks - 1));
  for (std::ptrdiff_t c = 1; c < chunks; ++c) workers.emplace_back([&, c] { body(bound(c), bound(c + 1)); });
  body(bound(0), bound(1));
  for (std::thread& w : workers) w.join();
}

}  // namespace sc::spectral::detail
