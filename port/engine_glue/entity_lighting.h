#pragma once
// How the stock opengl1 renderer lights models (MD3 entities) for the lightmap preset: the light
// grid at the entity's lighting origin gives an ambient and a directed light (bytes, gamma space)
// and a direction; every entity gets a fixed minimum ambient, dynamic lights add to the directed
// part, and each vertex gets ambient + directed * max(0, N.L), clamped per channel to 255
// (ioquake3 tr_light.c R_SetupEntityLighting / R_SetupEntityLightingGrid, tr_shade_calc.c
// RB_CalcDiffuseColor; the grid is brightened at load like lightmaps, tr_bsp.c).
#include <span>

#include <glm/vec3.hpp>

#include "port/q3formats/world/world_scene.h"

namespace glue {

struct DynamicLight;

/// The stock renderer's overbright facts for a window without hardware overbright
/// (r_mapOverBrightBits 2, tr.overbrightBits 0): light bytes are multiplied by 4.
inline constexpr int kLightOverbrightShift = 2;

/// Light bytes (0..255 each) times 2^shift; when a channel would pass 255 the three are scaled
/// down together so the hue is kept (R_ColorShiftLightingBytes).
glm::vec3 colorShiftLight(const glm::vec3& bytes, int shift);

/// Light reaching an entity, in the stock renderer's byte scale (255 = full bright).
struct EntityLight {
  glm::vec3 ambient{0.0f};
  glm::vec3 directed{0.0f};
  glm::vec3 direction{0.0f, 0.0f, 1.0f};   ///< Unit vector towards the light, world space.
};

/// The light grid at `point` as the stock renderer reads it: the 8 surrounding grid points,
/// each shifted by kLightOverbrightShift, weighted trilinearly; points with no ambient light
/// (inside walls) and points beyond the grid are skipped and the weights renormalised when
/// they sum below 0.99; ambient is then scaled by r_ambientScale (0.6). False when the grid is
/// empty (the caller then uses noWorldLight()).
/// `shift` replaces kLightOverbrightShift (r_mapOverBrightBits minus display overbright bits).
bool lightGridAt(const q3::WorldLightGrid& grid, const glm::vec3& point, EntityLight& out,
                 int shift = kLightOverbrightShift);

/// The light of entities in views without a world (HUD heads, menus): 150 ambient and directed
/// from the stock sun direction (0.45, 0.3, 0.9).
EntityLight noWorldLight();

/// Adds the minimum light every entity gets (32), the dynamic lights (radius r reaches
/// 16 * r^2 / d^2 at distance d, never closer than 16 units) and clamps ambient to 255.
EntityLight finishEntityLight(EntityLight light, const glm::vec3& lightOrigin,
                              std::span<const DynamicLight> dynamicLights);

/// A vertex's colour (bytes scale, 0..255 per channel) for unit world normal `normal`.
glm::vec3 diffuseVertexLight(const EntityLight& light, const glm::vec3& normal);

}  // namespace glue
