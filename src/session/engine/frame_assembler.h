#pragma once
// Receiver side of the coefficient stream: decodes datagrams, applies them latest-wins per row, conceals rows a
// frame did not deliver, and counts what it dropped and why. Pure: bytes in, current Z out; no sockets, no clock.

#include "session/wire/coefficient_codec.h"

#include <Eigen/Core>
#include <QtCore/QByteArray>
#include <QtCore/QByteArrayView>

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace sc::session {

/// What a row that the current frame did not deliver shows.
enum class Concealment {
  HoldLast,  ///< the last received value (default; shared/design/spectral.md §6 recommends it).
  ZeroFill,  ///< 0, i.e. that band falls back to the rest shape (the paper's way, kept for comparison).
  /// "hold-last + extrapolation": the assembler holds as HoldLast; the client displays FramePredictor's dead
  /// reckoning of missing rows and of overdue whole frames (frame_predictor.h).
  Extrapolate,
};

/// "hold-last", "zero-fill" or "extrapolate" (the command line's and the loss experiment's names).
const char* toString(Concealment concealment);
/// The concealment named `name` (as toString() writes it); nullopt for any other text. Cost: O(1).
std::optional<Concealment> concealmentFromString(std::string_view name);

/// Why the assembler dropped a datagram beyond the decoder's own reasons.
enum class AssemblyDrop {
  Late,         ///< authenticated, fresh sequence number, but for a frame older than the current one.
  WrongLength,  ///< m differs from the assembler's m.
  Count,
};

/// Rows of the current frame that arrived vs were concealed.
struct FrameCounts {
  std::uint32_t frame = 0;
  int rowsReceived = 0;
  int rowsConcealed = 0;
};

/// Contract: the current frame is the newest frame number seen in an accepted datagram (serial-number
/// arithmetic on 32 bits). A datagram of a newer frame starts that frame: with ZeroFill every row is reset to 0
/// first, with HoldLast rows keep their values. Rows a datagram carries overwrite the row (latest wins; the
/// protected rows come in every datagram). Datagrams of older frames are dropped as Late, never mixed in.
/// Before any datagram Z is zero (the rest shape). Memory O(m); cost per datagram: one AES-GCM open + O(rows).
class FrameAssembler {
 public:
  /// @param[in] key, peerId  this client's datagram key and peer id (see CoefficientDecoder).
  /// @param[in] m  rows of Z (number of basis functions), ≥ 1.
  FrameAssembler(QByteArray key, std::uint16_t peerId, int m, Concealment concealment = Concealment::HoldLast);

  /// Decodes and applies one datagram; DecodeError::None when applied. Every drop is counted once: decoder
  /// reasons in decodeDrops(); Late (returned as Stale) and WrongLength (returned as Malformed) in assemblyDrops().
  DecodeError receive(QByteArrayView bytes);

  /// Starts from exact coefficients (a join Keyframe, received over TCP): Z := `Z`, current frame := `frame`,
  /// every row valid. Datagrams of frames ≤ `frame` are then Late (docs/protocol.md: "Datagram frames with a
  /// frame number ≤ the keyframe's are stale"). Ignored (returns false) once a datagram was applied, when `Z` is
  /// not m by 3, or when `frame` is older than an earlier seed. Cost: O(m).
  bool seed(std::uint32_t frame, const Eigen::MatrixXd& Z);

  /// m by 3, the concealed current coefficients.
  const Eigen::MatrixXd& z() const { return m_z; }
  FrameCounts counts() const;
  bool hasFrame() const { return m_hasFrame; }
  /// The current frame number (meaningful when hasFrame()).
  std::uint32_t frame() const { return m_frame; }
  int rows() const { return static_cast<int>(m_z.rows()); }
  /// Frame in which row `k` (0..rows()−1) was last written (by a datagram or a seed); meaningful when rowValid(k).
  std::uint32_t rowFrame(int k) const { return m_rowFrame[static_cast<std::size_t>(k)]; }
  /// Row `k` was written at least once.
  bool rowValid(int k) const { return m_rowValid[static_cast<std::size_t>(k)]; }

  /// Header of the last datagram that passed the decoder (authenticated, fresh sequence number), whether it was
  /// then applied or dropped as Late / WrongLength; for receive statistics (sequence, timestamp). Default header
  /// before the first one.
  const DatagramHeader& lastHeader() const { return m_lastHeader; }
  /// Datagrams that passed the decoder: accepted() plus the assembly drops.
  std::uint64_t authenticated() const { return m_authenticated; }

  std::uint64_t decodeDrops(DecodeError reason) const { return m_decodeDrops[static_cast<std::size_t>(reason)]; }
  std::uint64_t assemblyDrops(AssemblyDrop reason) const { return m_assemblyDrops[static_cast<std::size_t>(reason)]; }
  std::uint64_t accepted() const { return m_accepted; }
  std::uint64_t totalDrops() const;

 private:
  void startFrame(std::uint32_t frame);
  void apply(const DecodedDatagram& datagram);

  CoefficientDecoder m_decoder;
  Concealment m_concealment;
  Eigen::MatrixXd m_z;
  std::vector<std::uint32_t> m_rowFrame;  ///< frame each row was last written in.
  std::vector<bool> m_rowValid;           ///< row written at least once.
  std::uint32_t m_frame = 0;
  bool m_hasFrame = false;
  std::uint64_t m_accepted = 0;
  std::uint64_t m_authenticated = 0;
  bool m_seeded = false;  ///< the current frame came from seed(): its datagrams are Late too
  DatagramHeader m_lastHeader;
  std::array<std::uint64_t, static_cast<std::size_t>(DecodeError::Count)> m_decodeDrops{};
  std::array<std::uint64_t, static_cast<std::size_t>(AssemblyDrop::Count)> m_assemblyDrops{};
  DecodedDatagram m_scratch;
};

}  // namespace sc::session
