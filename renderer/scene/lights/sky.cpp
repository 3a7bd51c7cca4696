#include "renderer/scene/lights/sky.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace pa {

CubeLookup cubeLookup(const glm::vec3& d) {
  const glm::vec3 a = glm::abs(d);
  // Axis, image-top and image-right vectors per face (right = axis x top).
  struct Face { glm::vec3 axis, top, right; };
  static const std::array<Face, 6> kFaces{{
      {{1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
      {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
      {{0, -1, 0}, {0, 0, 1}, {-1, 0, 0}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},
      {{0, 0, -1}, {1, 0, 0}, {0, -1, 0}},
  }};
  uint32_t face;
  float major;
  if (a.x >= a.y && a.x >= a.z) {
    face = d.x >= 0.0f ? 0 : 1;
    major = a.x;
  } else if (a.y >= a.z) {
    face = d.y >= 0.0f ? 2 : 3;
    major = a.y;
  } else {
    face = d.z >= 0.0f ? 4 : 5;
    major = a.z;
  }
  const Face& f = kFaces[face];
  const float inv = major > 0.0f ? 1.0f / major : 0.0f;
  return {face, 0.5f * (glm::dot(d, f.right) * inv + 1.0f), 0.5f * (1.0f - glm::dot(d, f.top) * inv)};
}

Sky::Sky(const SkyDesc& desc, const std::vector<std::shared_ptr<const Texture>>& textures)
    : scale_(desc.color * desc.intensity) {
  glm::vec3 faceMean(0.0f);
  for (size_t i = 0; i < 6; ++i) {
    if (desc.faces[i] == kNoId) continue;
    faces_[i] = textures.at(desc.faces[i]);
    hasFaces_ = true;
  }
  if (hasFaces_) {
    for (const auto& f : faces_) faceMean += f ? glm::vec3(f->average()) : glm::vec3(0.0f);
    average_ = scale_ * faceMean / 6.0f;
  } else {
    average_ = scale_;
  }
}

glm::vec3 Sky::radiance(const glm::vec3& dir) const {
  if (!hasFaces_) return scale_;
  const CubeLookup c = cubeLookup(dir);
  const auto& tex = faces_[c.face];
  if (!tex) return glm::vec3(0.0f);
  return scale_ * glm::vec3(tex->sampleFull({c.u, c.v}));
}

}  // namespace pa
