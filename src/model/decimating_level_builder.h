#pragma once
// The host's display-level builder by decimation (session/engine/level_builder.h): the ladder is levelTargets(n)
// (kDefaultLevelFractions: 50%, 20%, 5% of n) and each level is decimateMesh() of the full mesh to its target,
// with the barycentric map and K = P·H of spectral::resolutionLevel(). Handed to SessionHostOptions::levelBuilder
// by the app, so that session does not include model/.
// Cost of build(): one decimation of the full mesh plus the barycentric map, O(#F log #F + n'·m). Not thread-safe
// with other OpenMesh users (the host runs one build at a time on its level thread).

#include "session/engine/level_builder.h"

namespace sc::model {

/// The decimating LevelBuilder (a decimation that leaves fewer than 3 vertices yields an empty level: a failure).
session::LevelBuilder decimatingLevelBuilder();

}  // namespace sc::model
