#include "port/engine_glue/fog_volumes.h"

namespace glue {

void ViewFog::load(const q3::WorldScene& scene, pa::Renderer& renderer) {
  volumes_ = pa::bridge::fogVolumes(scene);
  renderer.setFogVolumes(volumes_.volumes);
  shown_ = true;
}

void ViewFog::show(bool withWorld, pa::Renderer& renderer) {
  const bool wanted = withWorld && !volumes_.volumes.empty();
  if (wanted == shown_) return;
  if (wanted) renderer.setFogVolumes(volumes_.volumes);
  else renderer.setFogVolumes({});
  shown_ = wanted;
}

}  // namespace glue
