#pragma once
// Per-sample light transport for the three presets: traceSample picks the Lightmap compositor
// (lightmap_compositor.h: primary rays, baked light, display-value layers) or the Direct/Path
// integrator (path_integrator.h: next-event estimation with ray-traced shadows and MIS, at the
// first vertex or at every vertex up to maxBounces).
#include <cstdint>

#include "renderer/scene/film/film.h"
#include "renderer/scene/integrator/camera_rays.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/scene_types.h"
#include "renderer/scene/world/render_scene.h"

namespace pa {

/// The light sample reservoir resampling kept for a pixel's first hit (renderer/scene/restir):
/// the integrator shades that hit with it instead of drawing its own light sample.
struct ResampledLight {
  LightPoint light;       ///< The sample, on its light.
  float weight = 0.0f;    ///< Its unbiased contribution weight (0: none, or occluded).
};

/// Traces one camera sample through film position (px, py) with settings.integrator and returns
/// radiance and AOVs.
/// A pure function of its arguments (the sampler carries pixel, seed and sample index).
/// `traced`, when given, is this sample's camera ray already traced (cameraRayBits, packets of
/// RenderScene::intersectCameraPacket): the sample starts from its hit instead of tracing it.
/// `resampled`, when given, is the direct light of the first hit when that is diffuse or glossy:
/// BSDF-sampled rays from there then count only lights the light sampler cannot pick.
/// `memo`, when given, is the calling thread's RenderScene::TriangleMemo (same result, less work
/// where consecutive samples end on one triangle; the Lightmap compositor uses it).
PixelSample traceSample(const RenderScene& scene, const CameraRays& camera, const RenderSettings& settings,
                        float px, float py, const sampling::PixelSampler& sampler,
                        const TracedCameraRay* traced = nullptr, const ResampledLight* resampled = nullptr,
                        TriangleMemo* memo = nullptr);

/// Dimension groups of the sampler used per path vertex (group = kGroupsPerVertex * depth + k).
inline constexpr uint32_t kGroupsPerVertex = 4;
/// The group within a vertex whose bits seed the vertex's ray (stochastic transparency).
inline constexpr uint32_t kGroupRayBits = 3;

/// TraceRequest::randomBits of the camera ray of the sample that `sampler` draws.
inline uint32_t cameraRayBits(const sampling::PixelSampler& sampler) { return sampler.bits(kGroupRayBits); }

}  // namespace pa
