#pragma once
// Sliding replay window over 16-bit datagram sequence numbers (style.md item 11; RFC 6347 §4.1.2.6, ENet).

#include <cstdint>

namespace sc::session {

/// Verdict of ReplayWindow::check().
enum class ReplayVerdict {
  Fresh,     ///< not seen and inside the window (or newer than anything seen): accept.
  Replayed,  ///< already accepted once (duplicate or replay).
  Stale,     ///< older than the window: kWindowSize or more behind the newest accepted number.
};

/// Contract: remembers the newest accepted sequence number s and a 64-bit bitmap of which of s−63..s were accepted.
/// A number n is compared with s in serial-number arithmetic, d = int16(n − s):
///   - d > 0 (up to 32767 ahead, wrap 65535 → 0 included): fresh, becomes the new newest;
///   - −64 < d ≤ 0: fresh unless its bit is set (Replayed);
///   - d ≤ −64 (or more than 32767 "ahead", which reads as behind): Stale.
/// check() never changes state; call accept() only after the datagram was authenticated and parsed, so forged
/// datagrams cannot move the window. The first accepted number initialises it. Cost: O(1), 16 bytes.
class ReplayWindow {
 public:
  static constexpr int kWindowSize = 64;

  ReplayVerdict check(std::uint16_t sequence) const;
  void accept(std::uint16_t sequence);

  bool empty() const { return !m_initialised; }
  std::uint16_t newest() const { return m_newest; }

 private:
  std::uint64_t m_bits = 0;  ///< bit i set: newest − i was accepted.
  std::uint16_t m_newest = 0;
  bool m_initialised = false;
};

}  // namespace sc::session
