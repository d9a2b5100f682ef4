#include "session/frame_assembler.h"

#include <cassert>
#include <numeric>
#include <utility>

namespace sc::session {
namespace {

/// a is newer than b in 32-bit serial-number arithmetic (RFC 1982).
bool newerFrame(std::uint32_t a, std::uint32_t b) { return static_cast<std::int32_t>(a - b) > 0; }

}  // namespace

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
  if (m_scratch.header.rowCount != m_z.rows()) {
    ++m_assemblyDrops[static_cast<std::size_t>(AssemblyDrop::WrongLength)];
    return DecodeError::Malformed;
  }
  if (m_hasFrame && newerFrame(m_frame, m_scratch.header.frame)) {
    ++m_assemblyDrops[static_cast<std::size_t>(AssemblyDrop::Late)];
    return DecodeError::Stale;
  }
  if (!m_hasFrame || newerFrame(m_scratch.header.frame, m_frame)) startFrame(m_scratch.header.frame);
  apply(m_scratch);
  ++m_accepted;
  return DecodeError::None;
}

void FrameAssembler::startFrame(std::uint32_t frame) {
  m_frame = frame;
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
