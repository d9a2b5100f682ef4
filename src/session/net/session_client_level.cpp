// SessionClient: the level transfer (model chunks), its decode worker (checksum, decode, shape check off the
// event-loop thread, one at a time), installing the level, Keyframes and the reconstruction of positions.

#include "session/net/session_client.h"

#include "spectral/display_level.h"
#include "spectral/reconstruction_kernel.h"

#include <QtCore/QMetaObject>
#include <QtCore/QTimer>

#include <chrono>
#include <exception>
#include <span>

namespace sc::session {

/// What the decode worker hands back: the level (and its interleaved rest positions) or a reason.
struct SessionClient::DecodedLevel {
  QByteArray payload;
  std::optional<spectral::ResolutionLevel> level;
  QString error;  ///< set when `level` is not
};

// --- level transfer and decoding

void SessionClient::onModelChunk(const ModelChunk& chunk) {
  const ModelReceiver::Status status = m_receiver.addUnchecked(chunk);  // the SHA-256 is checked off-thread
  switch (status) {
    case ModelReceiver::Status::InProgress:
      emit modelProgress(m_receiver.receivedBytes(), m_receiver.totalBytes());
      return;
    case ModelReceiver::Status::Complete: {
      emit modelProgress(m_receiver.totalBytes(), m_receiver.totalBytes());
      QByteArray expected = m_receiver.current() ? m_receiver.current()->sha256 : QByteArray();
      startDecode(m_receiver.take(), std::move(expected));
      return;
    }
    case ModelReceiver::Status::UnknownTransfer:
      return;  // a chunk of an abandoned transfer
    case ModelReceiver::Status::OutOfOrder:
    case ModelReceiver::Status::BadChecksum:
      m_levelError = QStringLiteral("model transfer failed: %1").arg(QString::fromLatin1(toString(status)));
      emit levelFailed(m_levelError);
      return;
  }
}

void SessionClient::startDecode(QByteArray payload, QByteArray expectedSha256) {
  if (!m_session) return;
  if (m_decoding) {  // one worker at a time: this transfer supersedes the one being decoded
    m_nextDecode.emplace(std::move(payload), std::move(expectedSha256));
    return;
  }
  if (m_decoder.joinable()) m_decoder.join();  // the previous worker already handed its result back
  m_decoding = true;
  m_decoder = std::thread([this, payload = std::move(payload), expected = std::move(expectedSha256),
                           m = m_session->rowCount, n = m_session->vertexCount]() mutable {
    auto result = std::make_shared<DecodedLevel>(decodeLevel(std::move(payload), expected, m, n));
    // Only a queued call touches `this`; the destructor joins this thread, so the object is alive here.
    QMetaObject::invokeMethod(
        this, [this, result] { finishDecode(result); }, Qt::QueuedConnection);
  });
}

SessionClient::DecodedLevel SessionClient::decodeLevel(QByteArray payload, const QByteArray& expectedSha256,
                                                       std::uint16_t rowCount, std::uint32_t vertexCount) {
  DecodedLevel out;
  try {
    if (!checksumMatches(payload, expectedSha256)) {
      out.error = QStringLiteral("model transfer failed: %1")
                      .arg(QString::fromLatin1(toString(ModelReceiver::Status::BadChecksum)));
      return out;
    }
    const auto* data = reinterpret_cast<const std::byte*>(payload.constData());
    spectral::LevelDecodeResult decoded =
        spectral::decodeResolutionLevel(std::span<const std::byte>(data, static_cast<std::size_t>(payload.size())));
    if (!decoded.ok()) {
      out.error = QStringLiteral("bad level payload: %1").arg(QString::fromStdString(decoded.message));
      return out;
    }
    if (decoded.level->K.cols() != rowCount || decoded.level->P.cols() != vertexCount ||
        decoded.level->K.rows() != decoded.level->restV.rows()) {
      out.error = QStringLiteral("level does not match the session (m = %1, n = %2)").arg(rowCount).arg(vertexCount);
      return out;
    }
    out.level = std::move(decoded.level);
    out.payload = std::move(payload);
  } catch (const std::exception& e) {  // e.g. std::bad_alloc: never let it escape the worker
    out.level.reset();
    out.error = QStringLiteral("decoding the level failed: %1").arg(QString::fromLocal8Bit(e.what()));
  }
  return out;
}

void SessionClient::finishDecode(const std::shared_ptr<DecodedLevel>& result) {
  m_decoding = false;
  if (m_decoder.joinable()) m_decoder.join();  // it has posted this call: it is ending
  if (m_nextDecode) {                          // superseded by a transfer completed meanwhile: decode that one instead
    auto [payload, sha] = std::move(*m_nextDecode);
    m_nextDecode.reset();
    if (live()) startDecode(std::move(payload), std::move(sha));
    return;
  }
  if (!live()) return;  // left or failed meanwhile
  if (!result->level) {
    m_levelError = result->error;
    emit levelFailed(m_levelError);
    return;
  }
  installLevel(*result);
}

const std::vector<float>& SessionClient::positions() const {
  if (m_positionsStale && m_level) {
    const auto start = std::chrono::steady_clock::now();
    spectral::reconstruct(*m_level, displayFrame(), m_positions);
    m_reconstructionMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    m_positionsStale = false;
  }
  return m_positions;
}

void SessionClient::installLevel(DecodedLevel& decoded) {
  m_level = spectral::makeDisplayLevel(std::move(*decoded.level));
  m_levelPayload = std::move(decoded.payload);
  m_levelError.clear();
  m_positions.assign(m_level->rest.size(), 0.0f);
  emit displayLevelChanged(m_level);
  updatePositions();
  changeState(State::Ready);
  emit levelReady(levelVertexCount());
}

std::uint32_t SessionClient::levelVertexCount() const { return m_level ? m_level->vertexCount() : 0; }

void SessionClient::onKeyframe(const Keyframe& keyframe) {
  const auto m = static_cast<Eigen::Index>(keyframe.z.size() / 3);
  if (!m_session || m != m_session->rowCount) return;  // not this session's shape: ignore
  Eigen::MatrixXd Z(m, 3);
  for (Eigen::Index r = 0; r < m; ++r) {
    for (Eigen::Index c = 0; c < 3; ++c) Z(r, c) = keyframe.z[static_cast<std::size_t>(3 * r + c)];
  }
  ++m_keyframes;
  m_channel->seed(keyframe.frame, Z);  // ignored once datagram frames flow; emits frameUpdated when applied
  emit keyframeReceived(keyframe.frame, Z);
}

void SessionClient::onFrameUpdated() {
  if (!m_level) return;  // installing a level recomputes anyway
  m_positionsDirty = true;
  if (!m_recomputeTimer->isActive()) m_recomputeTimer->start();  // after the datagrams already pending
}

void SessionClient::updatePositions() {
  m_positionsDirty = false;
  if (!m_level) return;
  const Eigen::MatrixXd& Z = m_channel->coefficients();
  const Eigen::Index m = m_level->basisSize();
  m_positionsZ =
      Z.rows() == m && Z.cols() == 3 ? Eigen::MatrixXf(Z.cast<float>()) : Eigen::MatrixXf(Eigen::MatrixXf::Zero(m, 3));
  m_positionsStale = true;  // reconstructed by the next positions()
  m_positionsFrame = m_channel->currentFrame();
  ++m_positionUpdates;
  emit frameUpdated(displayFrame());
  emit positionsUpdated(m_positionsFrame);
}

}  // namespace sc::session
