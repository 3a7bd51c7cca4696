#include "renderer/scene/integrator/display_composite.h"

#include <algorithm>

#include <glm/common.hpp>

#include "renderer/scene/textures/texture.h"

namespace pa {
namespace {

glm::vec3 encode(const glm::vec3& linear) {
  const glm::vec3 c = glm::clamp(linear, 0.0f, 1.0f);
  return {linearToSrgb(c.x), linearToSrgb(c.y), linearToSrgb(c.z)};
}

glm::vec3 decode(const glm::vec3& display) { return {srgbToLinear(display.x), srgbToLinear(display.y), srgbToLinear(display.z)}; }

}  // namespace

glm::vec3 displayProduct(const glm::vec3& a, const glm::vec3& b) { return decode(encode(a) * encode(b)); }

glm::vec3 composeShine(const glm::vec3& base, const glm::vec4& shine, LayerBlend blend, float baseRedrawn) {
  const glm::vec3 dst = encode(base);
  const glm::vec3 src = encode(glm::vec3(shine));
  glm::vec3 out = dst;
  switch (blend) {
    case LayerBlend::Add: out = dst + src; break;
    case LayerBlend::Over: {
      const float a = std::clamp(shine.a, 0.0f, 1.0f);
      out = dst * (1.0f - a) + src * a;
      break;
    }
    case LayerBlend::Multiply: out = dst * src; break;
    case LayerBlend::MultiplyInverse: out = dst * (1.0f - src); break;
    case LayerBlend::MultiplyAdd: out = dst * (1.0f + src); break;
    case LayerBlend::Modulate2x: out = 2.0f * dst * src; break;
  }
  out = glm::clamp(out, 0.0f, 1.0f);
  return decode(glm::mix(out, dst, std::clamp(baseRedrawn, 0.0f, 1.0f)));
}

void DisplayComposite::appendBefore(const AdditiveHits& hits, float t) {
  std::array<uint32_t, AdditiveHits::kCapacity> order{};
  uint32_t n = 0;
  for (uint32_t i = 0; i < std::min(hits.count, AdditiveHits::kCapacity); ++i)
    if (hits.entries[i].t < t) order[n++] = i;
  std::sort(order.begin(), order.begin() + n,
            [&](uint32_t a, uint32_t b) { return hits.entries[a].t < hits.entries[b].t; });
  for (uint32_t k = 0; k < n; ++k) {
    const AdditiveHits::Entry& e = hits.entries[order[k]];
    append({e.color, e.transmit});
  }
}

void DisplayComposite::append(const Layer& layer) {
  if (count_ < kCapacity) layers_[count_++] = layer;
}

glm::vec3 DisplayComposite::over(const glm::vec3& behind) const {
  if (count_ == 0) return behind;
  glm::vec3 display = encode(behind);
  for (uint32_t i = count_; i-- > 0;) {
    const Layer& layer = layers_[i];
    display = glm::clamp(display * glm::max(layer.transmit, glm::vec3(0.0f)) + encode(layer.color), 0.0f, 1.0f);
  }
  return decode(display);
}

}  // namespace pa
