#pragma once
// `shapecast-cli deform MESH --script DRAG.json [--mode linear|rigid] [--out FILE] [--level N] [--m 100]
//  [--cache-dir DIR | --no-cache] [--json]`

#include <QStringList>

namespace sc::app {

/// Runs the deform subcommand: loads MESH and its basis (as `basis` does), replays the drag script's frames
/// through spectral::SpectralDeformer, prints the per-frame solve timing and the final constraint residual, and
/// writes the final deformed mesh X = X̂ + HZ to --out (default: MESH's stem + "-deformed.off" in the current
/// folder; the format follows the extension: .off .obj .ply .stl). With --level N > 0 it writes instead the
/// low-resolution mesh X' = X̂' + K·Z of that display level (level_output.h) and reports the level's size, build
/// time, client reconstruction time and Hausdorff distance to P·X. Errors go to stderr.
/// @param arguments  the arguments after "deform".
/// @return exit code: 0 ok, 1 the mesh could not be loaded, 2 bad usage or bad drag script, 3 the basis could not
///         be computed, 4 the output could not be written.
int runDeformCommand(const QStringList& arguments);

}  // namespace sc::app
