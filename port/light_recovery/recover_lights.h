#pragma once
// Light recovery: the point lights a map's compiler baked into its lightmaps and light grid but
// stripped from its entities, found again so that the traced presets light the map as the
// lightmaps show it. One entry point, recoverLights, runs on a built scene (q3::buildWorldScene)
// and returns the full light list: the grid estimate (grid_estimate.h), the lightmap
// candidates (lightmap_candidates.h) and the lightmap calibration (calibration.h), with shadow
// rays traced through a pa::Blas over the world model's opaque, shadow-casting triangles.
// Every program that shows or exports a map (the engine module, pa-render, assets_converter)
// calls it, so all of them light a map with the same lights. Design: README.md.
#include <cstddef>
#include <vector>

#include "port/light_recovery/calibration.h"
#include "port/light_recovery/emitter_calibration.h"
#include "port/light_recovery/grid_estimate.h"
#include "port/q3formats/world/world_scene.h"

namespace pa::recovery {

/// Knobs of recoverLights.
struct RecoveryOptions {
  /// Estimate lights from the light grid on maps whose `light` entities were stripped
  /// (lightsStripped); false: the scene's authored lights only.
  bool estimate = true;
  /// Refit the estimates against the lightmaps and admit the candidates they confirm; false:
  /// the grid's estimates as they are.
  bool calibrate = true;
  LightEstimateOptions estimation;       ///< Knobs of the grid estimate.
  LightCalibrationOptions calibration;   ///< Knobs of the calibration and lightmap candidates.
};

/// What recoverLights did (for logs and tools).
struct RecoveryStats {
  size_t authored = 0;          ///< The scene's own lights (entities, suns), kept as they are.
  size_t estimated = 0;         ///< Lights the grid estimate kept.
  size_t gridCandidates = 0;    ///< Grid candidates its checks rejected (handed to the calibration).
  LightEstimateStats estimate;          ///< What the grid estimate did.
  LightCalibrationStats calibration;    ///< What the candidates and the calibration did.
  EmitterFitStats emitters;             ///< What the emitter fit did.
  double milliseconds = 0.0;    ///< Wall time of the whole recovery.
};

/// A map's lights: its authored ones, then the recovered ones (WorldLight::estimated).
struct RecoveredLights {
  std::vector<q3::WorldLight> lights;   ///< The list to light (or export) the map with.
  /// Per scene material: the share (0..1) of its q3map_surfacelight the lightmaps confirm
  /// (emitter_calibration.h); empty when nothing was fitted (every material keeps its value).
  std::vector<float> surfaceLightScales;
  /// Light value per channel (0..64) the lightmaps show everywhere beyond every recovered light:
  /// the calibration's fitted constant (an ambient the map was compiled with, light no lamp
  /// explains); lit as an unshadowed ambient. 0 where nothing was calibrated.
  float ambientValue = 0.0f;
  RecoveryStats stats;                  ///< What the recovery did.
};

/// The scene's lights with the stripped ones recovered: the authored lights as they are, then
/// the grid's estimates refitted against the lightmaps and the candidates the lightmaps confirm.
/// Lights of `scene` already marked estimated are ignored (a second run gives the same list).
/// Deterministic; never throws on hostile data. Callers put the result in scene.lights.
RecoveredLights recoverLights(const q3::WorldScene& scene, const RecoveryOptions& options = {});

/// Puts a recovery's result into the scene it was run on: its lights, every material's
/// q3map_surfacelight times its fitted scale, and the ambient (at least ambientValue per
/// channel). What every program calls after recoverLights.
void applyRecoveredLights(q3::WorldScene& scene, const RecoveredLights& recovered);

/// True when `lights` hold estimated lights or there are grid candidates worth calibrating.
bool hasEstimatedLights(const std::vector<q3::WorldLight>& lights, const std::vector<q3::WorldLight>& gridCandidates);

/// The calibration step of recoverLights alone: `lights` (authored and estimated) with the
/// estimated ones refitted against the scene's lightmaps, and the grid candidates and (on maps
/// whose lights were stripped) the lightmap candidates the lightmaps confirm added, shadows
/// traced through a BVH over the scene's world model; `lights` unchanged when there is nothing
/// to fit. On those maps the emitting materials' light is first fitted to the lightmaps
/// (fitEmitterScales; per material in `surfaceLightScales` when given, else all 1) and the
/// steps after it see the emitters at their fitted values.
std::vector<q3::WorldLight> calibrateWithShadowRays(const q3::WorldScene& scene, const std::vector<q3::WorldLight>& lights,
                                                    const std::vector<q3::WorldLight>& gridCandidates,
                                                    const LightCalibrationOptions& options = {},
                                                    LightCalibrationStats* stats = nullptr,
                                                    std::vector<float>* surfaceLightScales = nullptr,
                                                    EmitterFitStats* emitterStats = nullptr);

}  // namespace pa::recovery
