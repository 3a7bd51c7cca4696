#pragma once
// The Direct and Path presets: next-event estimation with ray-traced shadows and MIS against
// BSDF-sampled emitters and sky, at the first scattering vertex (Direct) or at every vertex up
// to maxBounces with Russian roulette (Path); light is composed linearly.
#include "renderer/scene/film/film.h"
#include "renderer/scene/integrator/camera_rays.h"
#include "renderer/scene/integrator/integrator.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/scene_types.h"
#include "renderer/scene/world/render_scene.h"

namespace pa {

/// One Direct- or Path-preset camera sample through film position (px, py) (see traceSample);
/// `memo`, when given, keeps the first hit's triangle part for the next sample (RenderScene::surfaceAt).
PixelSample tracePathSample(const RenderScene& scene, const CameraRays& camera, const RenderSettings& settings,
                            float px, float py, const sampling::PixelSampler& sampler, const TracedCameraRay* traced,
                            const ResampledLight* resampled, TriangleMemo* memo = nullptr);

}  // namespace pa
