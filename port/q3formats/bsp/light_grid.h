#pragma once
// Trilinear lookup in the baked light grid (what the engine's LightForPoint returns).
#include <cstdint>

#include <glm/vec3.hpp>

#include "port/q3formats/bsp/bsp_file.h"

namespace q3 {

/// Light at a point, in the grid's 0..255 units (as stored, or as shifted by shiftLightGridColors).
struct LightGridSample {
  glm::vec3 ambient{0};
  glm::vec3 directed{0};
  glm::vec3 direction{0, 0, 1};  ///< unit vector from the point towards the dominant light
  bool valid = false;            ///< false without a grid or when no neighbour contributed
};

/// Direction encoded by a grid point's longitude/latitude bytes (steps of 360/256 degrees).
glm::vec3 lightGridDirection(uint8_t longitude, uint8_t latitude);

/// Trilinear sample following the engine's R_SetupEntityLightingGrid: the cell index is clamped
/// to the grid but the fractions are not (points outside keep their fractional offset);
/// neighbours past the last grid point and points whose ambient colour is black (inside walls)
/// are left out, and the weights are renormalised when less than 0.99 of them remain.
LightGridSample sampleLightGrid(const BspLightGrid& grid, const glm::vec3& point);

/// The engine's load-time brightening of baked light (R_ColorShiftLightingBytes): each RGB
/// triple is multiplied by 2^shift and, when a channel would pass 255, scaled down as a whole
/// so the hue is kept. Applied to the ambient and directed colour of every grid point.
/// `shift` outside [0, 8] leaves the grid unchanged.
BspLightGrid shiftLightGridColors(const BspLightGrid& grid, int shift);

}  // namespace q3
