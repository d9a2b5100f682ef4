#pragma once
// BackgroundWork: one job on a worker thread whose progress and result come back to a context object's thread as
// queued calls, so the GUI thread never waits for it (what the host's preparation and the mesh loading share).
// cancel() raises a flag the job reads at its own checkpoints; join() and the destructor wait for the thread.
// Qt drops the queued calls if `context` is destroyed first, so a job may outlive the object that asked for it
// only as long as the BackgroundWork itself lives.

#include <QMetaObject>
#include <QObject>
#include <QString>

#include <atomic>
#include <functional>
#include <thread>
#include <utility>

namespace sc::app {

class BackgroundWork final {
 public:
  /// Progress: percent 0..100 and what is being done.
  using Report = std::function<void(int percent, const QString& what)>;

  BackgroundWork() = default;
  /// cancel() and join().
  ~BackgroundWork();
  BackgroundWork(const BackgroundWork&) = delete;
  BackgroundWork& operator=(const BackgroundWork&) = delete;

  /// Starts `work(cancelled, report)` on a new thread (once). Each report() becomes a queued `progress` call, and
  /// the result a queued `done` call (exactly once), on `context`'s thread. Result must be copyable (a
  /// shared_ptr for anything large).
  template <typename Result>
  void start(QObject* context, std::function<Result(const std::atomic<bool>& cancelled, const Report& report)> work,
             Report progress, std::function<void(Result)> done) {
    m_cancelled.store(false);
    m_worker =
        std::thread([this, context, work = std::move(work), progress = std::move(progress), done = std::move(done)] {
          const Report report = [context, &progress](int percent, const QString& what) {
            QMetaObject::invokeMethod(
                context, [progress, percent, what] { progress(percent, what); }, Qt::QueuedConnection);
          };
          Result result = work(m_cancelled, report);
          QMetaObject::invokeMethod(
              context, [done, result] { done(result); }, Qt::QueuedConnection);
        });
  }
  /// Asks the job to stop at its next checkpoint.
  void cancel() { m_cancelled.store(true); }
  [[nodiscard]] bool cancelRequested() const { return m_cancelled.load(); }
  /// Waits for the worker thread (no-op when none is running, it was joined, or called from the worker itself).
  void join();

 private:
  std::thread m_worker;
  std::atomic<bool> m_cancelled{false};
};

}  // namespace sc::app
