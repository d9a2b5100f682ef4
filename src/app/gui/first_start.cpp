#include "app/gui/first_start.h"

#include "app/gui/main_window.h"
#include "app/gui/mesh_viewport.h"
#include "app/gui/session_controller.h"
#include "app/gui/vertex_id_lists.h"
#include "app/gui/vertex_picking.h"

#include <QAction>
#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QHostAddress>
#include <QStatusBar>
#include <QTcpServer>
#include <QTextStream>

#include <cmath>
#include <numbers>

namespace sc::app {

QStringList defaultMeshFolders() {
  QStringList candidates;
  const QString fromEnvironment = qEnvironmentVariable("SHAPECAST_MESH_DIR");
  if (!fromEnvironment.isEmpty()) candidates << fromEnvironment;
  candidates << QCoreApplication::applicationDirPath() + QStringLiteral("/../../assets/meshes");
  candidates << QDir::currentPath() + QStringLiteral("/assets/meshes");
#ifdef SHAPECAST_DEFAULT_ASSETS_DIR
  candidates << QStringLiteral(SHAPECAST_DEFAULT_ASSETS_DIR);
#endif
  QStringList folders;
  for (const QString& candidate : candidates) {
    const QFileInfo info(candidate);
    if (!info.isDir()) continue;
    const QString canonical = info.canonicalFilePath();
    if (!folders.contains(canonical)) folders << canonical;
  }
  return folders;
}

QString findDefaultMesh(const QStringList& folders) {
  for (const QString& folder : folders) {
    const QFileInfo preferred(QDir(folder).filePath(QString::fromLatin1(kDefaultMeshName)));
    if (preferred.isFile() && preferred.isReadable()) return preferred.absoluteFilePath();
  }
  const QStringList patterns{QStringLiteral("*.off"), QStringLiteral("*.obj"), QStringLiteral("*.ply"),
                             QStringLiteral("*.stl"), QStringLiteral("*.OFF"), QStringLiteral("*.OBJ"),
                             QStringLiteral("*.PLY"), QStringLiteral("*.STL")};
  for (const QString& folder : folders) {
    const QFileInfoList files = QDir(folder).entryInfoList(patterns, QDir::Files | QDir::Readable, QDir::Name);
    if (!files.isEmpty()) return files.first().absoluteFilePath();
  }
  return {};
}

void generateTorus(Eigen::MatrixXd& V, Eigen::MatrixXi& F, int rings, int sides) {
  rings = std::max(rings, 3);
  sides = std::max(sides, 3);
  constexpr double kRing = 1.0;
  constexpr double kTube = 0.35;
  V.resize(static_cast<Eigen::Index>(rings) * sides, 3);
  F.resize(static_cast<Eigen::Index>(rings) * sides * 2, 3);
  const auto id = [sides, rings](int i, int j) { return (i % rings) * sides + (j % sides); };
  for (int i = 0; i < rings; ++i) {
    const double u = 2.0 * std::numbers::pi * i / rings;
    for (int j = 0; j < sides; ++j) {
      const double v = 2.0 * std::numbers::pi * j / sides;
      const double r = kRing + kTube * std::cos(v);
      V.row(id(i, j)) << r * std::cos(u), r * std::sin(u), kTube * std::sin(v);
    }
  }
  Eigen::Index f = 0;
  for (int i = 0; i < rings; ++i) {
    for (int j = 0; j < sides; ++j) {
      F.row(f++) << id(i, j), id(i + 1, j), id(i + 1, j + 1);
      F.row(f++) << id(i, j), id(i + 1, j + 1), id(i, j + 1);
    }
  }
}

bool writeGeneratedMesh(const QString& path, QString* error) {
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
  generateTorus(V, F);
  QFile file(path);
  if (!file.open(QIODevice::WriteOnly | QIODevice::Text | QIODevice::Truncate)) {
    if (error != nullptr) *error = QStringLiteral("%1: %2").arg(path, file.errorString());
    return false;
  }
  QTextStream out(&file);
  out.setRealNumberPrecision(12);
  out << "OFF\n" << V.rows() << ' ' << F.rows() << " 0\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i) out << V(i, 0) << ' ' << V(i, 1) << ' ' << V(i, 2) << '\n';
  for (Eigen::Index i = 0; i < F.rows(); ++i) out << "3 " << F(i, 0) << ' ' << F(i, 1) << ' ' << F(i, 2) << '\n';
  out.flush();
  if (out.status() != QTextStream::Ok || !file.flush()) {
    if (error != nullptr) *error = QStringLiteral("%1: %2").arg(path, file.errorString());
    return false;
  }
  return true;
}

QString defaultMeshOrGenerated(const QStringList& folders, QString* error) {
  const QString found = findDefaultMesh(folders);
  if (!found.isEmpty()) return found;
  const QString generated = QDir::temp().filePath(QStringLiteral("shapecast-default-torus.off"));
  return writeGeneratedMesh(generated, error) ? generated : QString();
}

QString firstStartName(const QString& given, const RecentSessions& recent) {
  if (const QString name = given.trimmed(); !name.isEmpty()) return name;
  if (!recent.names.isEmpty() && !recent.names.front().trimmed().isEmpty()) return recent.names.front().trimmed();
  return QStringLiteral("host");
}

quint16 availablePort(quint16 preferred) {
  QTcpServer probe;
  if (!probe.listen(QHostAddress::Any, preferred)) return 0;
  probe.close();
  return preferred;
}

std::vector<int> defaultHandle(const Eigen::MatrixXd& V, double radiusPct) {
  if (V.rows() == 0 || V.cols() != 3) return {};
  Eigen::Index top = 0;
  V.col(1).maxCoeff(&top);
  const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  const double radius = std::max(0.0, radiusPct) / 100.0 * diagonal;
  std::vector<int> handle;
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    if ((V.row(i) - V.row(top)).norm() <= radius) handle.push_back(static_cast<int>(i));
  }
  if (handle.empty()) handle.push_back(static_cast<int>(top));
  return handle;
}

void prepareDefaultDrag(MainWindow& window) {
  SessionController* session = window.session();
  if (session == nullptr) return;
  MainWindow* target = &window;
  QObject::connect(
      session, &SessionController::hostingStarted, target,
      [target, session](quint16 port) {
        if (target->session() != session || session->state() != SessionController::State::Live) return;
        const Eigen::MatrixXd& V = session->displayRestPositions();
        std::vector<int> handle = defaultHandle(V);
        std::vector<int> anchors = defaultAnchors(V, handle, 40.0);
        target->viewport()->setSelection(handle, anchors);
        session->setSelection(typedIds<spectral::DisplayVertexId>(handle),
                              typedIds<spectral::DisplayVertexId>(anchors));
        session->requestLock();
        if (auto* drag = target->findChild<QAction*>(QStringLiteral("actionToolDrag"))) {
          drag->trigger();
        } else {
          target->viewport()->setTool(ViewportTool::Drag);
        }
        target->statusBar()->showMessage(
            QCoreApplication::translate(
                "FirstStart",
                "Drag the orange-red handle. Others join with Session → Join, this computer's address "
                "and port %1.")
                .arg(port));
      },
      Qt::SingleShotConnection);
}

void hostReadyToDrag(MainWindow& window, const HostSettings& settings) {
  window.hostSession(settings);
  prepareDefaultDrag(window);
}

}  // namespace sc::app
