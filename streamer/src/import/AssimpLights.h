#pragma once
// The punctual lights of a scene read through assimp (Collada, FBX, 3DS, ...), mapped onto the
// records glTF's KHR_lights_punctual fills (core/Light.h). Private to streamer/src/import.
#include <assimp/scene.h>

#include <vector>

#include "vastray/core/Light.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/Import.h"

namespace vastray::import {

// A node's transform to world space: its own, then each parent's up to the root.
aiMatrix4x4 nodeToWorld(const aiNode& node);

// The scene's directional, point and spot lights in world space, in the file's order (read
// before post-processing, while the node tree that places them is whole). Mapping
// (docs/RENDERING.md, "Punctual lights"):
// - placed by the world transform of the node of the light's name: position from mPosition,
//   direction from mDirection (Collada's lights shine down their node's -Z);
// - mColorDiffuse is colour * intensity: the intensity is its largest component, the colour
//   the rest divided by it (so its largest component is 1), for every light alike;
// - mAngleInnerCone / mAngleOuterCone are taken as full cone angles (assimp's 2 pi default for
//   point lights; Blender's, 3ds Max's and Maya's exporters write full angles into Collada,
//   3DS and FBX) and halved into glTF's half angles; a cone wider than a hemisphere is
//   narrowed to one, an inner angle equal to the outer one set just below it;
// - attenuation: lights fall off with the inverse square of the distance, as glTF's do. A pure
//   quadratic term q is honoured exactly (intensity / q); constant and linear terms are not:
//   the intensity is divided by constant + linear + quadratic (the file's falloff at distance 1).
//   An intensity the division lifts above kMaxLightIntensity is clamped to it.
// Ambient and area lights, lights no node places and degenerate placements are left out; each
// of those and every approximation is one warning in `report`. A value out of vastray's limits
// (validateLight; the file's own colour * intensity included), non-finite or negative
// attenuation, or more than kMaxLights lights is an error naming the light and the limit.
Result<std::vector<PunctualLight>> assimpLights(const aiScene& scene, ImportReport& report);

}  // namespace vastray::import
