#pragma once
// The stock renderer's dynamic-light pass in its lightmap look (opengl1's ProjectDlightTexture):
// after a surface's stages, each light that reaches it draws it again with a 16x16 falloff blob
// projected along the world's z axis (texture coordinate 0.5 + (light - point).xy / radius,
// full strength within radius / 2 in height, fading to nothing at radius) blended as
// dst * (1 + light) in display values, clamped at white pass by pass. Evaluated per pixel at the
// hit: the blob's coordinates are linear in the position, as the raster interpolates them.
#include <cstddef>
#include <span>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "renderer/scene/scene_types.h"

namespace pa {

/// Most stock dynamic lights a scene takes (the engine sends at most 32 a view).
inline constexpr size_t kMaxStockDynamicLights = 256;

/// The stock falloff blob at texture coordinates (s, t) in [0, 1]^2 (bilinear, clamped), 0..1.
float stockDlightBlob(glm::vec2 st);

/// What one light adds at a world point with unit normal `normal` (display values, per channel
/// in [0, 1]): colour x blob x height modulation; 0 behind the surface or out of reach.
glm::vec3 stockDlightAt(const StockDynamicLight& light, const glm::vec3& position, const glm::vec3& normal);

/// A surface's display value `display` after the dynamic-light passes of `lights` at a point:
/// display x (1 + light), clamped to [0, 1], one light after the other.
glm::vec3 stockDlightsOver(std::span<const StockDynamicLight> lights, const glm::vec3& position,
                           const glm::vec3& normal, glm::vec3 display);

}  // namespace pa
