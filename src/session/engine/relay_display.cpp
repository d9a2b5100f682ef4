#include "session/engine/relay_display.h"

#include <algorithm>
#include <iterator>
#include <utility>

namespace sc::session {
namespace {

/// a is newer than b in 32-bit serial-number arithmetic (RFC 1982).
bool newerFrame(std::uint32_t a, std::uint32_t b) { return static_cast<std::int32_t>(a - b) > 0; }

}  // namespace

RelayDisplay::RelayDisplay(Concealment concealment, PredictorSettings predictor, std::size_t history)
    : m_concealment(concealment), m_settings(predictor), m_probe(history) {}

RelayDisplay::~RelayDisplay() = default;

void RelayDisplay::applied(std::uint32_t frame, const Eigen::MatrixXd& Z, Micros now) {
  if (Z.cols() != 3 || Z.rows() < 1) return;
  if (m_hasFrame && (Z.rows() != m_Z.rows() || newerFrame(m_received, frame))) return;
  if (!m_hasFrame && m_concealment == Concealment::Extrapolate) {
    m_predictor = std::make_unique<FramePredictor>(static_cast<int>(Z.rows()), m_settings);
  }
  m_hasFrame = true;
  m_received = frame;
  m_Z = Z;
  if (m_predictor) m_predictor->observeFrame(frame, Z, now);
  record();
}

std::optional<Micros> RelayDisplay::nextDue() const { return m_predictor ? m_predictor->nextDue() : std::nullopt; }

FramePredictor::Step RelayDisplay::advance(Micros now) {
  if (!m_predictor) return FramePredictor::Step::None;
  const FramePredictor::Step step = m_predictor->advance(now);
  if (step == FramePredictor::Step::Withdrawn) {
    m_probe.withdraw(m_received);  // the withdrawn prediction is not what stands for the frames after it
    record();
  } else if (step == FramePredictor::Step::Predicted) {
    record();
  }
  return step;
}

const Eigen::MatrixXd& RelayDisplay::display() const { return m_predictor ? m_predictor->display() : m_Z; }

std::uint32_t RelayDisplay::displayedFrame() const { return m_predictor ? m_predictor->displayedFrame() : m_received; }

void RelayDisplay::record() { m_probe.displayed(displayedFrame(), display()); }

void RelayDisplay::reference(std::uint32_t frame, const Eigen::MatrixXd& Zexact) {
  if (m_hasReference && !newerFrame(frame, m_lastReference)) return;
  m_hasReference = true;
  m_lastReference = frame;
  ++m_counts.references;
  m_probe.reference(frame, Zexact);
}

std::vector<DistortionPair> RelayDisplay::takeReady() {
  if (!m_hasFrame) return {};
  // The received frame's entry is final (whole and exact): references up to it are ready.
  return m_probe.takeReady(m_received + 1u);
}

std::vector<RelayDistortionSample> RelayDisplay::measure(const spectral::ResolutionLevel& level, double diagonal,
                                                         int maxPairs) {
  std::vector<DistortionPair> ready = takeReady();
  const std::size_t keep = static_cast<std::size_t>(std::max(1, maxPairs));
  auto first = ready.begin();
  if (ready.size() > keep) {
    first = ready.end() - static_cast<std::ptrdiff_t>(keep);
    m_counts.skipped += static_cast<std::uint64_t>(ready.size() - keep);
  }
  std::vector<RelayDistortionSample> out;
  for (auto it = first; it != ready.end(); ++it) {
    // Nothing displayed at or before the reference (it predates the join): no meaningful comparison.
    if (!it->displayedAny) continue;
    if (it->shown.rows() != level.K.cols() || it->exact.rows() != level.K.cols()) continue;
    const double pct = distortionPercent(level, it->shown, it->exact, diagonal);
    m_summary.add(pct);
    out.push_back({it->frame, it->shownFrame, pct});
  }
  return out;
}

RelayDisplayCounts RelayDisplay::counts() const {
  RelayDisplayCounts out = m_counts;
  if (m_predictor) {
    out.predicted = m_predictor->framesPredicted();
    out.withdrawn = m_predictor->withdrawals();
  }
  out.expired = m_probe.expired();
  return out;
}

}  // namespace sc::session
