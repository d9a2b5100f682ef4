#include "session/engine/frame_assembler.h"

#include <algorithm>
#include <cassert>
#include <numeric>
#include <utility>

namespace sc::session {
namespace {

/// a is newer than b in 32-bit serial-number arithmetic (RFC 1982).
bool newerFrame(std::uint32_t a, std::uint32_t b) { return static_cast<std::int32_t>(a - b) > 0; }

}  // namespace

const char* toString(Concealment concealment) {
  switch (concealment) {
    case Concealment::HoldLast:
      return "hold-last";
    case Concealment::ZeroFill:
      return "zero-fill";
    case Concealment::Extrapolate:
      return "extrapolate";
  }
  return "?";
}

std::optional<Concealment> concealmentFromString(std::string_view name) {
  for (const Concealment c : {Concealment::HoldLast, Concealment::ZeroFill, Concealment::Extrapolate}) {
    if (name == toString(c)) return c;
  }
  return std::nullopt;
}

FrameAssembler::FrameAssembler(QByteArray key, std::uint16_t peerId, int m, Concealment concealment)
    : m_decoder(std::move(key), peerId),
      m_concealment(concealment),
      m_z(Eigen::MatrixXd::Zero(m, 3)),
      m_rowFrame(static_cast<std::size_t>(m), 0),
      m_rowValid(static_cast<std::size_t>(m), false) {
  assert(m >= 1 && m <= kMaxRows && "m must be in 1..kMaxRows");
}

DecodeError FrameAssembler::receive(QByteArrayView bytes) {
  const DecodeError error = m_decoder.decode(bytes, m_scratch);
  if (error != DecodeError::None) {
    ++m_decodeDrops[static_cast<std::size_t>(error)];
    return error;
  }
  ++m_authenticated;
  m_lastHeader = m_scratch.header;
  if (m_scratch.header.rowCount != m_z.rows()) {
    ++m_assemblyDrops[static_cast<std::size_t>(AssemblyDrop::WrongLength)];
    return DecodeError::Malformed;
  }
  const std::uint32_t frame = m_scratch.header.frame;
  if (m_hasFrame && (newerFrame(m_frame, frame) || (m_seeded && frame == m_frame))) {
    ++m_assemblyDrops[static_cast<std::size_t>(AssemblyDrop::Late)];
    return DecodeError::Stale;
  }
  if (!m_hasFrame || newerFrame(frame, m_frame)) startFrame(frame);
  apply(m_scratch);
  ++m_accepted;
  return DecodeError::None;
}

bool FrameAssembler::seed(std::uint32_t frame, const Eigen::MatrixXd& Z) {
  if (m_accepted > 0 || Z.rows() != m_z.rows() || Z.cols() != 3) return false;
  if (m_seeded && newerFrame(m_frame, frame)) return false;
  m_z = Z;
  m_frame = frame;
  m_hasFrame = true;
  m_seeded = true;
  std::fill(m_rowFrame.begin(), m_rowFrame.end(), frame);
  std::fill(m_rowValid.begin(), m_rowValid.end(), true);
  return true;
}

void FrameAssembler::startFrame(std::uint32_t frame) {
  m_frame = frame;
  m_seeded = false;  // the seeded frame is behind us: ordinary Late rule from now on
  m_hasFrame = true;
  if (m_concealment == Concealment::ZeroFill) m_z.setZero();
}

void FrameAssembler::apply(const DecodedDatagram& datagram) {
  for (std::size_t i = 0; i < datagram.rows.size(); ++i) {
    const auto k = static_cast<std::size_t>(datagram.rows[i]);
    m_z.row(static_cast<Eigen::Index>(k)) = datagram.values.row(static_cast<Eigen::Index>(i));
    m_rowFrame[k] = datagram.header.frame;
    m_rowValid[k] = true;
  }
}

FrameCounts FrameAssembler::counts() const {
  FrameCounts counts;
  counts.frame = m_frame;
  for (std::size_t k = 0; k < m_rowFrame.size(); ++k) {
    if (m_hasFrame && m_rowValid[k] && m_rowFrame[k] == m_frame) ++counts.rowsReceived;
  }
  counts.rowsConcealed = static_cast<int>(m_rowFrame.size()) - counts.rowsReceived;
  return counts;
}

std::uint64_t FrameAssembler::totalDrops() const {
  const std::uint64_t decode = std::accumulate(m_decodeDrops.begin(), m_decodeDrops.end(), std::uint64_t{0});
  return decode + std::accumulate(m_assemblyDrops.begin(), m_assemblyDrops.end(), std::uint64_t{0});
}

}  // namespace sc::session
