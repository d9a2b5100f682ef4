#include "session/net/distortion_worker.h"

#include "spectral/hausdorff.h"

#include <QtCore/QMetaObject>

#include <memory>
#include <utility>

namespace sc::session {

DistortionWorker::DistortionWorker(QObject* parent, Measure measure) : QObject(parent), m_measure(std::move(measure)) {}

DistortionWorker::~DistortionWorker() {
  m_stop = true;
  if (m_thread.joinable()) m_thread.join();
}

bool DistortionWorker::busy() const { return m_measuring || std::chrono::steady_clock::now() < m_restUntil; }

bool DistortionWorker::start(spectral::SharedDisplayLevel level, std::vector<DistortionPair> pairs) {
  if (busy() || !level || pairs.empty()) return false;
  if (m_thread.joinable()) m_thread.join();  // the previous batch posted its figures: it has ended
  m_measuring = true;
  m_thread = std::thread([this, level = std::move(level), pairs = std::move(pairs)] {
    const auto begin = std::chrono::steady_clock::now();
    const double diagonal = spectral::boundingBoxDiagonal(level->level.restV);
    auto percents = std::make_shared<std::vector<double>>();
    percents->reserve(pairs.size());
    for (const DistortionPair& pair : pairs) {
      if (m_stop) break;
      percents->push_back(m_measure(level->level, pair.shown, pair.exact, diagonal));
    }
    const auto took = std::chrono::steady_clock::now() - begin;
    // Only a queued call touches `this` afterwards; the destructor joins this thread, so the object is alive here
    // and a call posted to a destroyed object is dropped by Qt.
    QMetaObject::invokeMethod(
        this, [this, percents, took] { finish(*percents, took); }, Qt::QueuedConnection);
  });
  return true;
}

void DistortionWorker::finish(const std::vector<double>& percents, std::chrono::steady_clock::duration took) {
  if (m_thread.joinable()) m_thread.join();  // it posted this call: it is ending
  m_measuring = false;
  m_restUntil = std::chrono::steady_clock::now() +
                std::chrono::duration_cast<std::chrono::steady_clock::duration>(took * kRestFactor);
  emit measured(percents);
}

}  // namespace sc::session
