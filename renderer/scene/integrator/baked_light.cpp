#include "renderer/scene/integrator/baked_light.h"

#include <algorithm>

#include <glm/common.hpp>

#include "renderer/scene/integrator/display_composite.h"

namespace pa {

bool bakedLightAt(const SurfaceHit& s, glm::vec3& light) {
  const MaterialRecord& m = *s.material;
  if (m.emits) return false;
  if (m.desc.stock.useVertexLight) {
    light = glm::clamp(glm::vec3(s.vertexColor), 0.0f, 1.0f);   // display values already
  } else if (m.lightmap != nullptr && m.lightmap->srgb()) {
    light = glm::clamp(glm::vec3(m.lightmap->sampleStored(s.lightmapUv, 0.0f)), 0.0f, 1.0f);
  } else if (m.lightmap != nullptr) {
    light = encodeTwo(glm::clamp(glm::vec3(m.lightmap->sample(s.lightmapUv, 0.0f)), 0.0f, 1.0f), glm::vec3(0.0f)).first;
  } else {
    return false;
  }
  // The lightmap stage's own scale is in the base colour already (RenderScene::baseColor).
  const float stage = m.desc.stock.lightmapStageScale > 0.0f ? m.desc.stock.lightmapStageScale : 1.0f;
  light *= std::max(0.0f, m.desc.stock.bakedLightScale) / stage;
  return true;
}

}  // namespace pa
