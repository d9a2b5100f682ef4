// SessionClient: the level decode worker (one std::thread at a time, started when the engine says so) and the
// displayed frame (one float conversion of the channel's Z per update, positions() reconstructed when read).

#include "session/net/session_client.h"

#include <QtCore/QMetaObject>

#include <chrono>
#include <memory>
#include <utility>

namespace sc::session {

void SessionClient::execute(client_action::StartDecode& decode) {
  if (m_decoder.joinable()) m_decoder.join();  // the previous worker already handed its result back
  m_decoder = std::thread([this, job = std::move(decode.job)]() mutable {
    auto result = std::make_shared<DecodedLevel>(decodeLevel(std::move(job)));
    // Only a queued call touches `this`; the destructor joins this thread, so the object is alive here.
    QMetaObject::invokeMethod(
        this, [this, result] { finishDecode(*result); }, Qt::QueuedConnection);
  });
}

void SessionClient::finishDecode(DecodedLevel& result) {
  if (m_decoder.joinable()) m_decoder.join();  // it has posted this call: it is ending
  apply(m_engine.onLevelDecoded(std::move(result)));
}

void SessionClient::execute(client_action::PublishFrame) {
  const spectral::SharedDisplayLevel& level = displayLevel();
  if (!level) return;
  const Eigen::MatrixXd& Z = m_channel->coefficients();
  const Eigen::Index m = level->basisSize();
  if (Z.rows() == m && Z.cols() == 3) {
    if (!m_engine.admitFrame(Z)) return;  // absurd coefficients (e.g. an overflowing exponent): the last frame stays
    m_frame.Z = Z.cast<float>();          // the one conversion (in place once sized)
  } else {
    m_frame.Z.setZero(m, 3);
  }
  m_frame.frame = m_channel->currentFrame();
  m_positionsStale = true;  // reconstructed by the next positions()
  emit frameUpdated(m_frame);
  emit positionsUpdated(m_frame.frame);
}

const std::vector<float>& SessionClient::positions() const {
  if (m_positionsStale && displayLevel()) {
    const auto start = std::chrono::steady_clock::now();
    spectral::reconstruct(*displayLevel(), m_frame, m_positions);
    m_reconstructionMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    m_positionsStale = false;
  }
  return m_positions;
}

}  // namespace sc::session
