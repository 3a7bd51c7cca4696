#include "renderer/scene/integrator/integrator.h"

#include "renderer/scene/integrator/lightmap_compositor.h"
#include "renderer/scene/integrator/path_integrator.h"

namespace pa {

PixelSample traceSample(const RenderScene& scene, const CameraRays& camera, const RenderSettings& settings,
                        float px, float py, const sampling::PixelSampler& sampler, const TracedCameraRay* traced,
                        const ResampledLight* resampled, TriangleMemo* memo) {
  if (settings.integrator == Integrator::Lightmap)
    return composeLightmapSample(scene, camera, settings, px, py, sampler, traced, memo);
  return tracePathSample(scene, camera, settings, px, py, sampler, traced, resampled, memo);
}

}  // namespace pa
