#pragma once
// The bake as the end of a path (RenderSettings::bakedLightAtPathEnd): a Direct or Path sample
// whose last vertex, after a diffuse or glossy scattering, lies on a surface with baked light
// (a lightmap or vertex light, StockLook) takes the light the bake shows there as that vertex's
// reflected light, where the path would otherwise end dark (mirrors excepted: they reflect what
// lies beyond them). The bake holds every light the map compiler traced, bounced light
// included, so the path's last bounce gathers the designer's light at the cost of the ray it
// already traced.
//
// Units: the Lightmap preset shows display(base) x baked x bakedLightScale; the DisplaySpace
// look shows display(albedo) x E with E = reflected radiance / albedo. The bake therefore means
// E = baked x bakedLightScale, and the vertex reflects diffuse albedo x E; a doubling lightmap
// stage's part of the scale (StockLook::lightmapStageScale) is in the albedo already.
#include <glm/vec3.hpp>

#include "renderer/scene/world/render_scene.h"

namespace pa {

/// The light E the bake shows on a hit (baked display value x bakedLightScale, per channel);
/// false where the surface has none (no lightmap and no vertex light) or emits light itself
/// (its light is the emission the path already gathered).
bool bakedLightAt(const SurfaceHit& s, glm::vec3& light);

}  // namespace pa
