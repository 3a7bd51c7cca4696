#pragma once
// The lightmap calibration of light-grid estimated lights (port/q3formats/world/
// world_light_calibrate.h) with shadow rays traced through a pa::Blas over the world model's
// opaque, shadow-casting triangles, and the lightmap candidates of world_lightmap_lights.h.
#include <vector>

#include "port/q3formats/world/world_light_calibrate.h"
#include "port/q3formats/world/world_scene.h"

namespace pa::bridge {

/// True when the scene has estimated lights or grid candidates worth calibrating.
bool hasEstimatedLights(const q3::WorldScene& scene);

/// The scene's lights with the estimated ones refitted against its lightmaps (see
/// q3::calibrateEstimatedLights) and, on maps whose lights were stripped, the lightmap
/// candidates (q3::lightsFromLightmaps) the lightmaps confirm added; scene.lights unchanged when
/// there is nothing to fit.
std::vector<q3::WorldLight> calibratedLights(const q3::WorldScene& scene,
                                             const q3::LightCalibrationOptions& options = {},
                                             q3::LightCalibrationStats* stats = nullptr);

}  // namespace pa::bridge
