#include "port/engine_glue/fog_volumes.h"

#include <utility>

namespace glue {

void ViewFog::load(pa::bridge::FogVolumes volumes, pa::Renderer& renderer) {
  volumes_ = std::move(volumes);
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
