#include "session/engine/frame_predictor.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sc::session {
namespace {

/// a is newer than b in 32-bit serial-number arithmetic (RFC 1982).
bool newerFrame(std::uint32_t a, std::uint32_t b) { return static_cast<std::int32_t>(a - b) > 0; }

}  // namespace

FramePredictor::FramePredictor(int m, PredictorSettings settings)
    : m_settings(settings), m_rows(static_cast<std::size_t>(std::max(m, 1))), m_display(Eigen::MatrixXd::Zero(m, 3)) {
  assert(m >= 1 && "m must be ≥ 1");
  m_settings.maxFrames = std::max(1, m_settings.maxFrames);
  m_settings.gain = std::clamp(m_settings.gain, 0.0, 1.0);
  m_settings.overdueFactor = std::max(1.0, m_settings.overdueFactor);
}

void FramePredictor::observe(const FrameAssembler& assembler, Micros now) {
  if (!assembler.hasFrame() || assembler.rows() != static_cast<int>(m_rows.size())) return;
  const Eigen::MatrixXd& Z = assembler.z();
  for (int r = 0; r < assembler.rows(); ++r) {
    if (assembler.rowValid(r)) observeRow(r, assembler.rowFrame(r), Z.row(r));
  }
  observeCurrent(assembler.frame(), now);
}

void FramePredictor::observeFrame(std::uint32_t frame, const Eigen::MatrixXd& Z, Micros now) {
  if (Z.rows() != static_cast<Eigen::Index>(m_rows.size()) || Z.cols() != 3) return;
  if (m_hasFrame && !newerFrame(frame, m_received) && frame != m_received) return;  // older: latest wins
  for (int r = 0; r < static_cast<int>(Z.rows()); ++r) observeRow(r, frame, Z.row(r));
  observeCurrent(frame, now);
}

void FramePredictor::observeRow(int r, std::uint32_t frame, const Eigen::RowVector3d& value) {
  Row& row = m_rows[static_cast<std::size_t>(r)];
  if (row.seen && newerFrame(frame, row.frame)) {
    row.previousFrame = row.frame;
    row.previousValue = row.value;
    row.hasPrevious = true;
  } else if (row.seen && frame != row.frame) {
    return;  // older than what the row has (not produced by FrameAssembler, which only moves forward)
  }
  row.seen = true;
  row.frame = frame;
  row.value = value;
}

void FramePredictor::observeCurrent(std::uint32_t frame, Micros now) {
  if (!m_hasFrame || newerFrame(frame, m_received)) {
    if (m_hasFrame) {
      const Micros sample = (now - m_receivedAt) / static_cast<std::int64_t>(frame - m_received);
      if (sample >= kMinInterval && sample <= kMaxInterval) {
        m_interval = m_interval == Micros{0} ? sample : m_interval + (sample - m_interval) / 8;
      }
    }
    m_hasFrame = true;
    m_received = frame;
    m_receivedAt = now;
    m_predicted = 0;
    m_withdrawn = false;
  }
  m_still = currentFrameStill();
  showFrame(displayedFrame());
}

bool FramePredictor::currentFrameStill() const {
  bool received = false;
  for (const Row& row : m_rows) {
    if (!row.seen || row.frame != m_received) continue;
    if (row.hasPrevious && row.value != row.previousValue) return false;
    received = true;
  }
  return received;
}

bool FramePredictor::moving() const {
  if (m_still) return false;
  return std::any_of(m_rows.begin(), m_rows.end(), [](const Row& row) {
    return row.hasPrevious && row.frame - row.previousFrame <= static_cast<std::uint32_t>(kMaxVelocityGap) &&
           row.value != row.previousValue;
  });
}

std::optional<Micros> FramePredictor::nextDue() const {
  if (!m_hasFrame || m_withdrawn || m_interval == Micros{0} || !moving()) return std::nullopt;
  const double intervals = m_settings.overdueFactor + m_predicted;
  return m_receivedAt + Micros{std::llround(intervals * static_cast<double>(m_interval.count()))};
}

FramePredictor::Step FramePredictor::advance(Micros now) {
  const std::optional<Micros> due = nextDue();
  if (!due || now < *due) return Step::None;
  // Frames due by now: j with receivedAt + (overdue + j − 1)·T ≤ now.
  const double elapsed = static_cast<double>((now - m_receivedAt).count()) / static_cast<double>(m_interval.count());
  const int dueFrames = static_cast<int>(std::floor(elapsed - m_settings.overdueFactor)) + 1;
  const int j = std::max(m_predicted + 1, dueFrames);
  if (j > m_settings.maxFrames) {
    m_predicted = 0;
    m_withdrawn = true;
    ++m_withdrawals;
    showFrame(m_received);
    return Step::Withdrawn;
  }
  m_framesPredicted += static_cast<std::uint64_t>(j - m_predicted);
  m_predicted = j;
  showFrame(displayedFrame());
  return Step::Predicted;
}

Eigen::RowVector3d FramePredictor::predictRow(int r, std::uint32_t frame) const {
  const Row& row = m_rows[static_cast<std::size_t>(r)];
  if (!row.seen) return Eigen::RowVector3d::Zero();
  const auto steps = static_cast<std::int32_t>(frame - row.frame);
  const std::uint32_t gap = row.frame - row.previousFrame;
  if (steps <= 0 || !row.hasPrevious || gap > static_cast<std::uint32_t>(kMaxVelocityGap)) return row.value;
  const Eigen::RowVector3d velocity = (row.value - row.previousValue) / static_cast<double>(gap);
  return row.value + m_settings.gain * std::min(steps, m_settings.maxFrames) * velocity;
}

void FramePredictor::showFrame(std::uint32_t frame) {
  if (m_still) {  // the stream stopped: every row held at its last value
    for (int r = 0; r < static_cast<int>(m_rows.size()); ++r)
      m_display.row(r) = m_rows[static_cast<std::size_t>(r)].value;
    return;
  }
  for (int r = 0; r < static_cast<int>(m_rows.size()); ++r) m_display.row(r) = predictRow(r, frame);
}

}  // namespace sc::session
