#pragma once
// Short human-readable descriptions of a loaded mesh, for the status bar.

#include "model/mesh_cleaning.h"

#include <QString>

namespace sc::app {

/// "N vertices, M triangles" with plain (unlocalised) numbers, e.g. "642 vertices, 1280 triangles".
/// Singular forms are used for 1 ("1 vertex, 1 triangle").
QString meshSizeText(int vertexCount, int triangleCount);

/// One line about the cleaning report: what was changed (only non-zero counts), then what was found, e.g.
/// "Cleaned: merged 3 duplicate vertices, dropped 2 zero-area faces. 1 component, 0 holes, 0 non-manifold edges."
/// or "Mesh is clean. 1 component, 0 holes, 0 non-manifold edges." when nothing was changed.
QString cleaningSummary(const model::MeshCleanReport& report);

}  // namespace sc::app
