#pragma once
// HostPreparation: the host's long start-up work on a worker thread, for HostController::host(): load the
// mesh (or a saved session, model/session_file.h: its mesh and m), compute (or read from the cache) the harmonic
// basis, and build the full-resolution display level (once: the host shows it, shared with its view). It runs
// as a BackgroundWork (background_work.h): progress and result come back to a context object's thread through
// queued calls, so the GUI thread never waits for it; cancel() stops it at the next check (after the mesh load,
// or at the eigensolve's next progress callback), join() and the destructor wait for the thread.

#include "app/gui/background_work.h"
#include "app/gui/session_settings.h"
#include "spectral/display_level.h"

#include <QCoreApplication>
#include <QString>

#include <functional>
#include <memory>

class QObject;

namespace sc::session {
struct HostModel;
}

namespace sc::model {
struct SessionFile;
}

namespace sc::app {

/// What a preparation hands back: the model and its full level, or an error text, or a cancellation.
struct PreparedHost {
  PreparedHost();
  ~PreparedHost();
  PreparedHost(const PreparedHost&) = delete;
  PreparedHost& operator=(const PreparedHost&) = delete;

  std::shared_ptr<session::HostModel> model;        ///< null unless it succeeded
  spectral::SharedDisplayLevel level;               ///< fullResolutionLevel() of the model: K = quantizeBasis(H)
  std::shared_ptr<const model::SessionFile> saved;  ///< the session file hosted (null for a mesh file)
  QString error;                                    ///< readable reason when it failed
  bool cancelled = false;
};

class HostPreparation final {
  Q_DECLARE_TR_FUNCTIONS(HostPreparation)

 public:
  /// Progress: percent 0..100 and what is being done.
  using ProgressFn = std::function<void(int percent, const QString& what)>;
  using DoneFn = std::function<void(const std::shared_ptr<PreparedHost>& prepared)>;

  HostPreparation() = default;
  /// cancel() and join() (the BackgroundWork's destructor).
  ~HostPreparation() = default;
  HostPreparation(const HostPreparation&) = delete;
  HostPreparation& operator=(const HostPreparation&) = delete;

  /// Starts the worker (once). `progress` (10, then 10..95 during the eigensolve, then 95) and finally `done`
  /// (exactly once) run on `context`'s thread as queued calls, which Qt drops if `context` is destroyed first.
  /// settings: meshPath, m (clamped to 1 ≤ m < #V and the wire's row limit) and useBasisCache are used. A
  /// meshPath that is a session file (model::isSessionFile) is read whole: its mesh (already cleaned: used as it
  /// is, so the basis cache's mesh hash matches the saving host's) and its m replace the mesh load and settings.m;
  /// a broken file is an error naming the problem.
  void start(const HostSettings& settings, QObject* context, ProgressFn progress, DoneFn done);
  /// Asks the worker to stop; `done` then reports cancelled (unless it had already finished).
  void cancel() { m_work.cancel(); }
  /// Waits for the worker thread (no-op when none is running or it was joined).
  void join() { m_work.join(); }

 private:
  BackgroundWork m_work;
};

}  // namespace sc::app
