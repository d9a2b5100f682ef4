#include "app/gui/host_preparation.h"

#include "model/cache_location.h"
#include "model/mesh_loader.h"
#include "model/session_file.h"
#include "session/engine/host_model.h"
#include "session/wire/wire_format.h"
#include "spectral/basis_pipeline.h"
#include "spectral/resolution_level.h"

#include <QFile>
#include <QObject>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <optional>
#include <utility>
#include <variant>

namespace sc::app {

namespace {

using Report = std::function<void(int percent, const QString& what)>;

/// The mesh, or nullopt with prepared.error set.
std::optional<model::LoadedMesh> loadHostMesh(const QString& path, PreparedHost& prepared) {
  model::MeshLoadResult loaded = model::loadMesh(std::filesystem::path(QFile::encodeName(path).toStdString()));
  if (const auto* error = std::get_if<model::MeshError>(&loaded)) {
    prepared.error = QString::fromStdString(error->message);
    return std::nullopt;
  }
  auto mesh = std::get<model::LoadedMesh>(std::move(loaded));
  const auto n = static_cast<int>(mesh.V.rows());
  if (n < 4) {
    prepared.error = HostPreparation::tr("The mesh has too few vertices (%1) to host.").arg(n);
    return std::nullopt;
  }
  return mesh;
}

/// The saved session at `path`, or nullopt with prepared.error set.
std::shared_ptr<const model::SessionFile> loadSavedSession(const QString& path, PreparedHost& prepared) {
  model::SessionFileResult read = model::readSessionFile(path);
  if (const auto* error = std::get_if<model::SessionFileError>(&read)) {
    prepared.error = error->message;
    return nullptr;
  }
  auto saved = std::make_shared<model::SessionFile>(std::get<model::SessionFile>(std::move(read)));
  if (saved->m > session::kMaxRows) {
    prepared.error = HostPreparation::tr("The session has m = %1; at most %2 frequencies can be sent.")
                         .arg(saved->m)
                         .arg(session::kMaxRows);
    return nullptr;
  }
  return saved;
}

/// The basis of `mesh`, or nullopt with prepared.error or prepared.cancelled set.
std::optional<spectral::BasisComputation> computeBasis(const model::LoadedMesh& mesh, const HostSettings& settings,
                                                       const std::atomic<bool>& cancelled, const Report& report,
                                                       PreparedHost& prepared) {
  const auto n = static_cast<int>(mesh.V.rows());
  spectral::BasisOptions options;
  options.m = std::clamp(settings.m, 1, std::min(n - 1, session::kMaxRows));
  int lastPercent = 10;
  options.progress = [&cancelled, &report, &lastPercent](double fraction) {
    const int percent = 10 + static_cast<int>(85.0 * std::clamp(fraction, 0.0, 1.0));
    if (percent != lastPercent) {
      lastPercent = percent;
      report(percent, HostPreparation::tr("Computing the harmonic basis"));
    }
    return !cancelled.load();
  };
  std::optional<std::filesystem::path> cacheDir;
  if (settings.useBasisCache) cacheDir = model::basisCacheDirectory();
  spectral::BasisComputation basis = spectral::basisForMesh(mesh.V, mesh.F, options, cacheDir);
  if (basis.result.status == spectral::BasisStatus::Cancelled || cancelled.load()) {
    prepared.cancelled = true;
    return std::nullopt;
  }
  if (!basis.result.ok()) {
    prepared.error = HostPreparation::tr("The harmonic basis could not be computed (%1): %2")
                         .arg(QString::fromLatin1(spectral::toString(basis.result.status)),
                              QString::fromStdString(basis.result.message));
    return std::nullopt;
  }
  return basis;
}

/// The whole preparation, on the worker thread. Never throws.
std::shared_ptr<PreparedHost> prepare(const HostSettings& settings, const std::atomic<bool>& cancelled,
                                      const Report& report) {
  auto prepared = std::make_shared<PreparedHost>();
  try {
    HostSettings used = settings;
    std::optional<model::LoadedMesh> mesh;
    if (model::isSessionFile(settings.meshPath)) {
      prepared->saved = loadSavedSession(settings.meshPath, *prepared);
      if (!prepared->saved) return prepared;
      mesh.emplace();
      mesh->V = prepared->saved->V;
      mesh->F = prepared->saved->F;
      used.m = prepared->saved->m;
    } else {
      mesh = loadHostMesh(settings.meshPath, *prepared);
    }
    if (!mesh) return prepared;
    if (cancelled.load()) {
      prepared->cancelled = true;
      return prepared;
    }
    report(10, HostPreparation::tr("Computing the harmonic basis"));
    std::optional<spectral::BasisComputation> basis = computeBasis(*mesh, used, cancelled, report, *prepared);
    if (!basis) return prepared;
    report(95, HostPreparation::tr("Preparing the display"));
    auto model = std::make_shared<session::HostModel>();
    model->V = std::move(mesh->V);
    model->F = std::move(mesh->F);
    model->basis = std::move(basis->result.basis);
    model->operators = std::move(basis->operators);
    prepared->level =
        spectral::makeDisplayLevel(spectral::fullResolutionLevel(model->V, model->F, model->basis.vectors));
    prepared->model = std::move(model);
  } catch (const std::exception& e) {
    prepared->error = HostPreparation::tr("Preparing the session failed: %1").arg(QString::fromLocal8Bit(e.what()));
  }
  return prepared;
}

}  // namespace

PreparedHost::PreparedHost() = default;
PreparedHost::~PreparedHost() = default;

void HostPreparation::start(const HostSettings& settings, QObject* context, ProgressFn progress, DoneFn done) {
  m_work.start<std::shared_ptr<PreparedHost>>(
      context,
      [settings](const std::atomic<bool>& cancelled, const BackgroundWork::Report& report) {
        return prepare(settings, cancelled, report);
      },
      std::move(progress), std::move(done));
}

}  // namespace sc::app
