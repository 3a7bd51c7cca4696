#pragma once
// How much of its compiled light each emitting material really put into the lightmaps.
//
// A q3map_surfacelight shader tells how bright a surface was when the map was compiled, but
// shaders change after a map is compiled: OpenArena replaced many textures and shaders of maps
// converted from other games, so a lamp may now claim 20000 where the bake shows a dim glow
// (oa_dm4's iron crosses light its rooms deep red at the shader's value; the bake shows them
// barely lit by the crosses). The lightmaps are the ground truth: the fit samples texels, predicts
// each emitting material's light there with q3map2's model (calibration_model.h), and finds for
// every material a scale in [0, 1] by bounded least squares, beside the estimated lights and a
// constant for bounce. A scale never raises a material above its shader's value.
#include <cstddef>
#include <vector>

#include "port/light_recovery/calibration.h"
#include "port/q3formats/world/world_scene.h"

namespace pa::recovery {

/// What fitEmitterScales did (for logs, tools and tests).
struct EmitterFitStats {
  size_t samples = 0;     ///< Texels used.
  size_t groups = 0;      ///< Emitter groups fitted (groups lighting too few texels keep 1).
  size_t lowered = 0;     ///< Groups fitted below 0.9.
};

/// Scale in [0, 1] of each emitter group's light (CalibrationEmitter::group, 0..groupCount-1)
/// that the scene's lightmaps confirm, fitted together with the estimated lights of `lights`,
/// the grid candidates, the lightmap candidates (lightmap_candidates.h) and a constant. Emitters without a group (-1), authored lights and the
/// sky (options.skyLightValue) are known light. Groups lighting fewer than
/// options.minLitSamples texels keep 1. Deterministic; all 1 when there is nothing to fit.
std::vector<float> fitEmitterScales(const q3::WorldScene& scene, const std::vector<q3::WorldLight>& lights,
                                    const std::vector<q3::WorldLight>& gridCandidates,
                                    const std::vector<q3::WorldLight>& lightmapCandidates,
                                    const std::vector<CalibrationEmitter>& emitters, size_t groupCount,
                                    const SegmentBlocked& blocked, const LightCalibrationOptions& options = {},
                                    EmitterFitStats* stats = nullptr);

}  // namespace pa::recovery
