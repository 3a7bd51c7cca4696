#pragma once
// The Lightmap preset: what a raster engine with baked light shows. Camera rays (and the rays
// leaving portals) end on the first surface: base colour x baked light (lightmap texture or
// vertex colour), its shine stage, glow stages, see-through layers and fog, all composed in
// display values as an 8-bit framebuffer blends them (display_composite.h). An sRGB base texture
// without other factors and an sRGB lightmap are read as stored (Texture::sampleStored: their
// bytes filtered, as a texture unit filters them), so their product is taken without encoding.
#include "renderer/scene/film/film.h"
#include "renderer/scene/integrator/camera_rays.h"
#include "renderer/scene/sampling/sobol_sampler.h"
#include "renderer/scene/scene_types.h"
#include "renderer/scene/world/render_scene.h"

namespace pa {

/// One Lightmap-preset camera sample through film position (px, py) (see traceSample).
/// Deterministic: no light is sampled; the sampler seeds only stochastic transparency.
/// `memo` (may be null): the thread's TriangleMemo for RenderScene::surfaceAt.
PixelSample composeLightmapSample(const RenderScene& scene, const CameraRays& camera, const RenderSettings& settings,
                                  float px, float py, const sampling::PixelSampler& sampler,
                                  const TracedCameraRay* traced, TriangleMemo* memo = nullptr);

}  // namespace pa
