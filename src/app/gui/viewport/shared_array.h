#pragma once
// SharedArray: one host array of ViewportBuffers that is either the buffers' own std::vector or a view into an
// immutable array someone else owns (a shared display level's rest positions, normals or faces: issue 19 item 3),
// kept alive by a shared_ptr. Installing a level then costs no copy on the GUI thread; the first write detaches.

#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace sc::app {

template <typename T>
class SharedArray {
 public:
  /// The values: the shared array while one is shared, else the own vector.
  [[nodiscard]] std::span<const T> view() const { return m_owner ? m_shared : std::span<const T>(m_own); }
  [[nodiscard]] bool shared() const { return m_owner != nullptr; }
  /// Shows `values` (no copy), kept alive by `owner` (non-null) until the next share() or own(); frees the own
  /// vector. Cost: O(1) plus that free.
  void share(std::shared_ptr<const void> owner, std::span<const T> values) {
    m_owner = std::move(owner);
    m_shared = values;
    std::vector<T>().swap(m_own);
  }
  /// The own vector, for a write that sets every entry (resize, then fill): a shared array is let go, not copied,
  /// and the own vector is empty then. Cost: O(1).
  std::vector<T>& own() {
    if (m_owner) {
      m_owner.reset();
      m_shared = {};
      m_own.clear();
    }
    return m_own;
  }

 private:
  std::shared_ptr<const void> m_owner;  // non-null: m_shared is shown
  std::span<const T> m_shared;
  std::vector<T> m_own;
};

}  // namespace sc::app
