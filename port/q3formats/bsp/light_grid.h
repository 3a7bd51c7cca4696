#pragma once
// Trilinear lookup in the baked light grid (what the engine's LightForPoint returns).
#include <glm/vec3.hpp>

#include "port/q3formats/bsp/bsp_file.h"

namespace q3 {

/// Light at a point, in the file's 0..255 units (before any overbright shift).
struct LightGridSample {
  glm::vec3 ambient{0};
  glm::vec3 directed{0};
  glm::vec3 direction{0, 0, 1};  ///< unit vector from the point towards the dominant light
  bool valid = false;            ///< false without a grid or when all 8 neighbours are in solid
};

/// Direction encoded by a grid point's longitude/latitude bytes (steps of 360/256 degrees).
glm::vec3 lightGridDirection(uint8_t longitude, uint8_t latitude);

/// Trilinear sample; points outside the grid are clamped to its edge and grid points that are
/// entirely black (inside walls) are left out and the remaining weights renormalised.
LightGridSample sampleLightGrid(const BspLightGrid& grid, const glm::vec3& point);

}  // namespace q3
