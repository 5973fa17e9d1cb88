// mvr/adelson/village_scene.h — adelson1991's village (makeVillage()) as an mvr::Scene that
// every backend renders: `mvr render --scene village`.
#pragma once

#include "mvr/core/scene.h"

namespace mvr::adelson {

/// The village of `buildings` houses (1..8) in mvr's right-handed world (the paper's z
/// negated, windings kept counter-clockwise), one mesh and instance per polygon color, flat
/// normals, defaultLights(), and the paper's viewpoint (the origin, looking down -z).
Scene makeVillageScene(int buildings = 8);

}  // namespace mvr::adelson
