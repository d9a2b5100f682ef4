#pragma once
// First start: what `shapecast` with no arguments (and `shapecast --demo`) does so that a newcomer sees the idea work
// within seconds: pick a default mesh (the 23k-vertex Stanford dragon from assets/meshes/ if it was fetched, else
// the first fetched mesh, else a generated torus written to a temporary file), host it on the default port (any
// free port when 47100 is taken), and once live select a default handle (the vertices around the highest one) and
// default anchors (everything farther than 40% of the bounding-box diagonal), request the lock and switch to the
// Drag tool, so that a left drag on the handle deforms the mesh at once.

#include "app/gui/recent_sessions.h"
#include "app/gui/session_settings.h"

#include <Eigen/Core>
#include <QString>
#include <QStringList>

#include <vector>

namespace sc::app {

class MainWindow;

/// The preferred default mesh's file name in the mesh folders.
inline constexpr const char* kDefaultMeshName = "dragon_vrip_res3.ply";

/// Folders searched for the default mesh, in order: $SHAPECAST_MESH_DIR if set, assets/meshes next to the build
/// (<executable>/../../assets/meshes), ./assets/meshes, and the assets folder configured at build time. Only
/// existing folders are listed, each once.
[[nodiscard]] QStringList defaultMeshFolders();

/// kDefaultMeshName in the first folder that has it, else the first mesh file (OFF, OBJ, PLY, STL; by name) of the
/// first folder that has one, else an empty string.
[[nodiscard]] QString findDefaultMesh(const QStringList& folders);

/// A closed torus standing in the x–y plane (ring radius 1, tube radius 0.35), `rings` × `sides` vertices.
void generateTorus(Eigen::MatrixXd& V, Eigen::MatrixXi& F, int rings = 64, int sides = 24);

/// Writes generateTorus() as an ASCII OFF file. False (with the reason in *error, if given) when it cannot.
bool writeGeneratedMesh(const QString& path, QString* error = nullptr);

/// findDefaultMesh(folders), else a generated torus written to the temporary folder
/// (shapecast-default-torus.off). Empty, with the reason in *error, only when even that file cannot be written.
[[nodiscard]] QString defaultMeshOrGenerated(const QStringList& folders, QString* error = nullptr);

/// The first start's display name: `given` (--name, trimmed) when not empty, else the most recently used name of
/// `recent` (the host and join dialogs remember it), else "host".
[[nodiscard]] QString firstStartName(const QString& given, const RecentSessions& recent);

/// `preferred` if a TCP server can listen on it now, else 0 (any free port; the status bar tells which).
[[nodiscard]] quint16 availablePort(quint16 preferred = 47100);

/// The default handle: every vertex within radiusPct% of the bounding-box diagonal of the vertex with the largest
/// y (at least that vertex). Sorted. Empty for an empty V.
[[nodiscard]] std::vector<int> defaultHandle(const Eigen::MatrixXd& V, double radiusPct = 8.0);

/// Once `window`'s current session is hosting (hostingStarted), selects defaultHandle() and defaultAnchors(40%)
/// in the viewport and the session, requests the lock and activates the Drag tool. Call right after
/// MainWindow::hostSession(). Does nothing if the session fails.
void prepareDefaultDrag(MainWindow& window);

/// window.hostSession(settings) followed by prepareDefaultDrag(window).
void hostReadyToDrag(MainWindow& window, const HostSettings& settings);

}  // namespace sc::app
