#pragma once
// MeshLoading: one mesh file read on a worker thread (BackgroundWork, as the host's preparation) for the window's
// File → Open, Open Recent and drops, so that a large file never freezes the window. It reports progress (the
// reader has no progress of its own: "Reading FILE" at 0 %, then done), and exactly one of loaded(), failed() or
// cancelled(). cancel() answers at once (cancelled(); the caller keeps what it showed); the reader cannot be
// interrupted inside a file, so the thread finishes its read in the background and the result is dropped.
// The object deletes itself (deleteLater) once its worker has ended; destroying it earlier waits for the read.

#include "app/gui/background_work.h"

#include <QObject>
#include <QString>

#include <memory>

namespace sc::model {
struct LoadedMesh;
}

namespace sc::app {

class MeshLoading final : public QObject {
  Q_OBJECT
  Q_DISABLE_COPY_MOVE(MeshLoading)

 public:
  explicit MeshLoading(QObject* parent = nullptr);
  ~MeshLoading() override;

  /// Starts reading `path` (model::loadMesh, once).
  void start(const QString& path);
  /// Stops waiting for the file: cancelled() now, nothing else later.
  void cancel();
  [[nodiscard]] const QString& path() const { return m_path; }
  /// Whether it is still reading and not cancelled.
  [[nodiscard]] bool running() const { return m_running; }

 signals:
  void progress(int percent, const QString& what);
  /// The mesh read and cleaned (shared: the window keeps it).
  void loaded(const QString& path, const std::shared_ptr<const sc::model::LoadedMesh>& mesh);
  /// The file could not be read; `message` names it and the problem.
  void failed(const QString& path, const QString& message);
  void cancelled(const QString& path);

 private:
  BackgroundWork m_work;
  QString m_path;
  bool m_running = false;
};

}  // namespace sc::app
