#include "app/gui/mesh_loading.h"

#include "model/mesh_loader.h"

#include <QFile>
#include <QFileInfo>

#include <filesystem>
#include <variant>

namespace sc::app {

namespace {

/// What the worker hands back: the mesh or the error text.
struct MeshRead {
  std::shared_ptr<const model::LoadedMesh> mesh;
  QString error;
};

}  // namespace

MeshLoading::MeshLoading(QObject* parent) : QObject(parent) { setObjectName(QStringLiteral("meshLoading")); }

MeshLoading::~MeshLoading() = default;

void MeshLoading::start(const QString& path) {
  if (m_running || !m_path.isEmpty()) return;
  m_path = path;
  m_running = true;
  emit progress(0, tr("Reading %1").arg(QFileInfo(path).fileName()));
  m_work.start<std::shared_ptr<const MeshRead>>(
      this,
      [path](const std::atomic<bool>&, const BackgroundWork::Report&) {
        auto outcome = std::make_shared<MeshRead>();
        model::MeshLoadResult result = model::loadMesh(std::filesystem::path(QFile::encodeName(path).toStdString()));
        if (const auto* error = std::get_if<model::MeshError>(&result)) {
          outcome->error = QString::fromStdString(error->message);
        } else {
          outcome->mesh = std::make_shared<const model::LoadedMesh>(std::get<model::LoadedMesh>(std::move(result)));
        }
        return std::shared_ptr<const MeshRead>(std::move(outcome));
      },
      [this](int percent, const QString& what) {
        if (m_running) emit progress(percent, what);
      },
      [this](const std::shared_ptr<const MeshRead>& outcome) {
        m_work.join();
        deleteLater();
        if (!m_running) return;  // cancelled: dropped
        m_running = false;
        if (outcome->mesh) {
          emit loaded(m_path, outcome->mesh);
        } else {
          emit failed(m_path, outcome->error);
        }
      });
}

void MeshLoading::cancel() {
  if (!m_running) return;
  m_running = false;
  m_work.cancel();
  emit cancelled(m_path);
}

}  // namespace sc::app
