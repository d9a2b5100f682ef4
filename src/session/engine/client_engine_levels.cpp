// ClientEngine: the level transfer (model chunks), the decode scheduling (one at a time, the latest transfer
// supersedes), installing a level, Keyframes and the coalesced frame updates.

#include "session/engine/client_engine.h"

#include <utility>

namespace sc::session {

// --- level transfer and decode scheduling

void ClientEngine::onModelBegin(const ModelBegin& begin, ClientActions& out) {
  // Only a size the level list implies (checkLevelList() bounded it by n', f', m), and one transfer in flight: a
  // new announcement frees the unfinished one (ModelReceiver::begin) and a completed one still waiting to decode.
  if (const QString unlisted = checkAnnouncement(begin, m_levels); !unlisted.isEmpty()) {
    fail(QStringLiteral("protocol error from the host: %1").arg(unlisted), out);
    return;
  }
  m_nextDecode.reset();
  m_nextIsPreview = false;
  m_receiver.begin(begin);
  out.emplace_back(client_action::ModelProgress{0, begin.totalSize});
}

void ClientEngine::onModelChunk(const ModelChunk& chunk, ClientActions& out) {
  const ModelReceiver::Status status = m_receiver.addUnchecked(chunk);  // decodeLevel() checks the SHA-256
  switch (status) {
    case ModelReceiver::Status::InProgress:
      out.emplace_back(client_action::ModelProgress{m_receiver.receivedBytes(), m_receiver.totalBytes()});
      return;
    case ModelReceiver::Status::Complete: {
      out.emplace_back(client_action::ModelProgress{m_receiver.totalBytes(), m_receiver.totalBytes()});
      QByteArray expected = m_receiver.current() ? m_receiver.current()->sha256 : QByteArray();
      const std::uint32_t arrived = m_receiver.current() ? m_receiver.current()->vertexCount : 0;
      QByteArray payload = m_receiver.take();
      const bool preview = m_deferredLevel.has_value();
      startDecode(LevelJob{std::move(payload), std::move(expected), m_session->rowCount, m_session->vertexCount},
                  preview, out);
      if (preview) requestDeferredLevel(arrived, out);  // streams while the preview decodes and shows
      return;
    }
    case ModelReceiver::Status::UnknownTransfer:
      return;  // a chunk of an abandoned transfer
    case ModelReceiver::Status::OutOfOrder:
    case ModelReceiver::Status::BadChecksum:
      m_levelError = QStringLiteral("model transfer failed: %1").arg(QString::fromLatin1(toString(status)));
      out.emplace_back(client_action::LevelFailed{m_levelError});
      if (m_deferredLevel) {
        requestDeferredLevel(0, out);  // no preview: the wanted level at once
      } else {
        m_wantedInFlight = false;
      }
      return;
  }
}

void ClientEngine::requestDeferredLevel(std::uint32_t arrived, ClientActions& out) {
  const std::uint32_t wanted = *m_deferredLevel;
  m_deferredLevel.reset();
  const std::uint32_t n = m_session->vertexCount;
  bool served = false;  // the preview already is the wanted level: nothing more to ask
  if (arrived != 0) {
    const LevelInfo* closest = m_levels.complete() ? closestLevel(m_levels, wanted) : nullptr;
    served = (arrived == n && (wanted == 0 || wanted >= n)) || m_levels.total == 1 ||
             (closest != nullptr && closest->vertexCount == arrived);
  }
  if (served) return;
  m_wantedInFlight = true;
  send(ResolutionRequest{wanted}, out);
}

void ClientEngine::startDecode(LevelJob job, bool preview, ClientActions& out) {
  if (m_decoding) {  // one decode at a time: this transfer supersedes the one being decoded
    m_nextDecode = std::move(job);
    m_nextIsPreview = preview;
    return;
  }
  m_decoding = true;
  m_decodingPreview = preview;
  out.emplace_back(client_action::StartDecode{std::move(job)});
}

ClientActions ClientEngine::onLevelDecoded(DecodedLevel result) {
  ClientActions out;
  m_decoding = false;
  const bool preview = std::exchange(m_decodingPreview, false);
  if (m_nextDecode) {  // superseded by a transfer completed meanwhile: decode that one instead
    LevelJob next = std::move(*m_nextDecode);
    m_nextDecode.reset();
    const bool nextIsPreview = std::exchange(m_nextIsPreview, false);
    // A progressive join's preview is shown all the same: something to look at while the wanted level decodes.
    if (preview && live() && result.level) install(result, true, out);
    if (live()) startDecode(std::move(next), nextIsPreview, out);
    return out;
  }
  if (!live()) return out;  // left or failed meanwhile
  if (!result.level) {
    m_levelError = result.error;
    if (!preview) m_wantedInFlight = false;
    out.emplace_back(client_action::LevelFailed{m_levelError});
    return out;
  }
  install(result, preview, out);
  return out;
}

void ClientEngine::install(DecodedLevel& decoded, bool preview, ClientActions& out) {
  if (!preview) m_wantedInFlight = false;
  m_level = std::move(decoded.level);
  // The payload is not needed once decoded: freed here unless kept for diagnostics (it is the size of the level).
  m_levelPayload = m_config.keepLevelPayload ? std::move(decoded.payload) : QByteArray();
  decoded.payload = QByteArray();
  m_levelError.clear();
  out.emplace_back(client_action::Notify{ClientNotice::LevelInstalled});
  publishFrame(out);
  changeState(ClientState::Ready, out);
  out.emplace_back(client_action::LevelReady{levelVertexCount()});
}

// --- keyframes and frames

void ClientEngine::onKeyframe(const Keyframe& keyframe, ClientActions& out) {
  const auto m = static_cast<Eigen::Index>(keyframe.z.size() / 3);
  if (!m_session || m != m_session->rowCount) return;  // not this session's shape: ignore
  const Eigen::Map<const Eigen::VectorXd> values(keyframe.z.data(), static_cast<Eigen::Index>(keyframe.z.size()));
  if (!displayable(values)) {  // absurd coefficients: never shown, counted like a bad datagram
    ++m_framesRefused;
    return;
  }
  Eigen::MatrixXd Z(m, 3);
  for (Eigen::Index r = 0; r < m; ++r) {
    for (Eigen::Index c = 0; c < 3; ++c) Z(r, c) = keyframe.z[static_cast<std::size_t>(3 * r + c)];
  }
  ++m_keyframes;
  out.emplace_back(client_action::SeedKeyframe{keyframe.frame, std::move(Z)});
}

bool ClientEngine::admitFrame(const Eigen::MatrixXd& Z) {
  if (displayable(Z)) return true;
  ++m_framesRefused;
  return false;
}

void ClientEngine::onFrameChanged(Micros now) {
  if (!m_level || m_frameDirty) return;  // installing a level publishes anyway; already due
  m_frameDirty = true;
  m_dirtySince = now;
}

void ClientEngine::publishFrame(ClientActions& out) {
  m_frameDirty = false;
  ++m_framesPublished;
  out.emplace_back(client_action::PublishFrame{});
}

}  // namespace sc::session
