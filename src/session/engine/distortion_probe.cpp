#include "session/engine/distortion_probe.h"

#include "spectral/hausdorff.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <iterator>
#include <utility>

namespace sc::session {
namespace {

/// a is newer than b in 32-bit serial-number arithmetic (RFC 1982).
bool newerFrame(std::uint32_t a, std::uint32_t b) { return static_cast<std::int32_t>(a - b) > 0; }

/// X̂' + K·Z in double precision, one row of the quantised K at a time (no n' by m double temporary): the scales
/// are folded into Z once, X̂'_i + Q_i·(scale ⊙ Z).
Eigen::MatrixXd reconstruct(const spectral::ResolutionLevel& level, const Eigen::MatrixXd& Z) {
  const Eigen::MatrixXd scaledZ = level.K.scale.cast<double>().transpose().asDiagonal() * Z;
  Eigen::MatrixXd X = level.restV;
  for (Eigen::Index i = 0; i < X.rows(); ++i) X.row(i) += level.K.Q.row(i).cast<double>() * scaledZ;
  return X;
}

}  // namespace

DistortionProbe::DistortionProbe(std::size_t history) : m_capacity(std::max<std::size_t>(history, 1)) {}

void DistortionProbe::displayed(std::uint32_t frame, const Eigen::MatrixXd& Z) {
  if (m_history.empty() || newerFrame(frame, m_history.back().frame)) {
    m_history.push_back(Entry{frame, Z});
  } else if (m_history.back().frame == frame) {
    m_history.back().Z = Z;
  } else {
    // Out of order (not produced by FrameAssembler, which only moves forward): keep the history sorted.
    auto it = m_history.end();
    while (it != m_history.begin() && newerFrame(std::prev(it)->frame, frame)) --it;
    if (it != m_history.begin() && std::prev(it)->frame == frame) {
      std::prev(it)->Z = Z;
    } else if (it != m_history.begin() || !m_evicted || newerFrame(frame, m_newestEvicted)) {
      m_history.insert(it, Entry{frame, Z});
    }
  }
  while (m_history.size() > m_capacity) {
    m_evicted = true;
    m_newestEvicted = m_history.front().frame;
    m_history.pop_front();
  }
}

void DistortionProbe::withdraw(std::uint32_t frame) {
  while (!m_history.empty() && newerFrame(m_history.back().frame, frame)) m_history.pop_back();
}

void DistortionProbe::reference(std::uint32_t frame, const Eigen::MatrixXd& Zexact) {
  m_references.push_back(Entry{frame, Zexact});
  while (m_references.size() > m_capacity) {  // nobody takes them: keep memory bounded
    m_references.pop_front();
    ++m_expired;
  }
}

bool DistortionProbe::pairFor(std::uint32_t frame, const Eigen::MatrixXd& exact, DistortionPair& out) const {
  out.frame = frame;
  out.exact = exact;
  for (auto it = m_history.rbegin(); it != m_history.rend(); ++it) {
    if (!newerFrame(it->frame, frame)) {
      out.shownFrame = it->frame;
      out.displayedAny = true;
      out.shown = it->Z;
      return true;
    }
  }
  if (m_evicted) return false;  // what was shown for `frame` has been evicted
  out.shownFrame = 0;
  out.displayedAny = false;
  out.shown = Eigen::MatrixXd::Zero(exact.rows(), exact.cols());
  return true;
}

std::vector<DistortionPair> DistortionProbe::takeReady(std::uint32_t currentFrame) {
  std::vector<DistortionPair> ready;
  std::deque<Entry> waiting;
  for (Entry& reference : m_references) {
    if (!newerFrame(currentFrame, reference.frame)) {
      waiting.push_back(std::move(reference));
      continue;
    }
    DistortionPair pair;
    if (pairFor(reference.frame, reference.Z, pair)) {
      ready.push_back(std::move(pair));
    } else {
      ++m_expired;
    }
  }
  m_references = std::move(waiting);
  return ready;
}

std::vector<DistortionPair> DistortionProbe::takeAll() {
  std::vector<DistortionPair> all;
  for (const Entry& reference : m_references) {
    DistortionPair pair;
    if (pairFor(reference.frame, reference.Z, pair)) {
      all.push_back(std::move(pair));
    } else {
      ++m_expired;
    }
  }
  m_references.clear();
  return all;
}

void DistortionProbe::reset() {
  m_history.clear();
  m_references.clear();
  m_evicted = false;
  m_newestEvicted = 0;
}

double distortionPercent(const spectral::ResolutionLevel& level, const Eigen::MatrixXd& shownZ,
                         const Eigen::MatrixXd& exactZ, double diagonal) {
  assert(level.restV.cols() == 3 && level.K.rows() == level.restV.rows() && "level: restV n' by 3, K n' by m");
  assert(shownZ.rows() == level.K.cols() && shownZ.cols() == 3 && "shownZ must be m by 3");
  assert(exactZ.rows() == level.K.cols() && exactZ.cols() == 3 && "exactZ must be m by 3");
  const Eigen::MatrixXd shown = reconstruct(level, shownZ);
  const Eigen::MatrixXd exact = reconstruct(level, exactZ);
  return spectral::percentOfDiagonal(spectral::hausdorffDistance(shown, exact).value, diagonal);
}

void DistortionSummary::add(double pct) {
  if (std::isnan(pct)) return;
  ++count;
  lastPct = pct;
  maxPct = std::max(maxPct, pct);
  meanPct += (pct - meanPct) / static_cast<double>(count);
}

}  // namespace sc::session
