#pragma once
// Sliding replay window over 64-bit extended datagram sequence numbers (RFC 6347 §4.1.2.6; the extension of the
// 16-bit wire number as SRTP's index, RFC 3711 §3.3.1, Appendix A).

#include <cstdint>

namespace sc::session {

/// Verdict of ReplayWindow::check().
enum class ReplayVerdict {
  Fresh,     ///< not seen and inside the window (or newer than anything seen): accept.
  Replayed,  ///< already accepted once (duplicate or replay).
  Stale,     ///< older than the window: kWindowSize or more behind the newest accepted number.
};

/// Contract: remembers the newest accepted extended (64-bit) sequence number s and a 64-bit bitmap of which of
/// s−63..s were accepted. Numbers never wrap (2⁶⁴ datagrams), so a number n is simply compared with s:
///   - n > s: fresh, becomes the new newest;
///   - s − 64 < n ≤ s: fresh unless its bit is set (Replayed);
///   - n ≤ s − 64: Stale.
/// The wire carries only the low 16 bits; extend() maps them to the 64-bit number closest to s (ahead by at most
/// 32768, behind by at most 32767). The sender authenticates the full 64-bit number (the MAC covers it), so a
/// datagram recorded in an earlier 16-bit cycle and replayed later extends to a number it was not sent under and
/// fails authentication instead of moving the window 65536·k ahead (Issue 14 item 5: before, one such replay froze
/// a client for 65 s). check() never changes state; call accept() only after the datagram was authenticated and
/// parsed, so forged datagrams cannot move the window. The first accepted number initialises it. Cost: O(1),
/// 24 bytes. Limit: a receiver that misses 32768 or more consecutive datagrams extends wrongly from then on (as
/// SRTP); at the default 2 datagrams per frame that is over 2 minutes of total loss at 125 frames/s.
class ReplayWindow {
 public:
  static constexpr int kWindowSize = 64;

  /// The extended number closest to newest() whose low 16 bits are `wire` (the number itself before any accept).
  std::uint64_t extend(std::uint16_t wire) const;
  ReplayVerdict check(std::uint64_t sequence) const;
  void accept(std::uint64_t sequence);

  bool empty() const { return !m_initialised; }
  std::uint64_t newest() const { return m_newest; }

 private:
  std::uint64_t m_bits = 0;  ///< bit i set: newest − i was accepted.
  std::uint64_t m_newest = 0;
  bool m_initialised = false;
};

}  // namespace sc::session
