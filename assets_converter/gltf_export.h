#pragma once
// Writes a q3::WorldScene as binary glTF 2.0 (.glb) with embedded PNG textures.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "assets_converter/gltf_axes.h"
#include "port/q3formats/world/world_scene.h"

namespace pa::converter {

/// What to write and how.
struct ExportOptions {
  float metresPerUnit = kDefaultMetresPerUnit;   ///< Length scale (Quake unit -> metre).
  bool lightmaps = true;      ///< Lightmaps as images + TEXCOORD_1 (referenced from primitive extras).
  bool lights = true;         ///< KHR_lights_punctual from scene.lights (entities, q3map_sun, recovered lights).
  bool cameras = true;        ///< Cameras at spawn points.
  bool skySurfaces = false;   ///< Keep the sky box brushes (hidden by default: they box the map in).
  std::string generator = "PathArena assets_converter";
};

/// Counts of what was written.
struct ExportStats {
  uint64_t triangles = 0;
  uint32_t primitives = 0;
  uint32_t materials = 0;
  uint32_t images = 0;
  uint32_t lights = 0;
  uint32_t cameras = 0;
  uint32_t nodes = 0;
  uint64_t bytes = 0;
};

/// Converts the scene to GLB bytes. Never throws for content (missing textures are
/// already fallbacks in the scene); throws std::runtime_error if an image cannot be encoded.
std::vector<std::byte> exportGlb(const q3::WorldScene& scene, const ExportOptions& options = {},
                                 ExportStats* stats = nullptr);

}  // namespace pa::converter
