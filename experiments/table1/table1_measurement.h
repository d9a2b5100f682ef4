#pragma once
// The measurements behind `shapecast-cli bench table1`: the paper's Table 1 (pre-computing, server and client time
// per frame, at full and at a low resolution) for one mesh, on this machine.

#include "model/mesh_loader.h"

#include <string>

namespace sc::app {

/// One mesh's row, in seconds (medians), plus the sizes.
struct Table1Row {
  std::string mesh;
  int verticesFull = 0, verticesLow = 0, trianglesFull = 0, trianglesLow = 0;
  double precomputeFullSeconds = 0;  ///< operators + basis (no cache).
  double precomputeLowSeconds = 0;   ///< the above + decimation + barycentric map P + K = P·H.
  double levelBuildSeconds = 0;      ///< decimation + P + K alone.
  double decimationSeconds = 0;      ///< the decimation part of levelBuildSeconds.
  double serverFrameSeconds = 0;  ///< one drag frame: right-hand side + back-substitution (handle ≤ 2000 vertices).
  double constraintChangeSeconds = 0;  ///< forming and factoring the m×m system (handle ≤ 3000 vertices).
  double clientFullSeconds = 0;        ///< X̂ + H·Z in float32 on one thread, full resolution.
  double clientLowSeconds = 0;         ///< X̂' + K·Z in float32 on one thread, low resolution.
  int serverHandleVertices = 0, changeHandleVertices = 0;
};

struct Table1Options {
  int m = 100;                ///< harmonics.
  double lowFraction = 0.05;  ///< low resolution as a fraction of the vertices (the paper's dragon used 5%).
  int frames = 200;           ///< timed frames for the per-frame medians.
};

/// Measures one row on a loaded mesh. Returns false with `error` set when the basis cannot be computed.
/// Cost: one basis computation, one decimation and `frames` solves and reconstructions.
bool measureTable1Row(const std::string& name, const model::LoadedMesh& mesh, const Table1Options& options,
                      Table1Row& row, std::string& error);

}  // namespace sc::app
