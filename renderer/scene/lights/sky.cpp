#include "renderer/scene/lights/sky.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "renderer/scene/sampling/warp.h"

namespace pa {

const CubeFaceBasis& cubeFaceBasis(uint32_t face) {
  static const std::array<CubeFaceBasis, 6> kFaces{{
      {{1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
      {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
      {{0, -1, 0}, {0, 0, 1}, {-1, 0, 0}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},
      {{0, 0, -1}, {1, 0, 0}, {0, -1, 0}},
  }};
  return kFaces[std::min<uint32_t>(face, 5)];
}

namespace {


/// Solid angle per unit face area at face coordinates (x, y) in [-1, 1]^2 (face at distance 1).
float solidAngleDensity(float x, float y) {
  const float r2 = 1.0f + x * x + y * y;
  return 1.0f / (r2 * std::sqrt(r2));
}

/// Sampling grid cells per face side.
constexpr uint32_t kGrid = Sky::kImportanceGrid;

}  // namespace

CubeLookup cubeLookup(const glm::vec3& d) {
  const glm::vec3 a = glm::abs(d);
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
  const CubeFaceBasis& f = cubeFaceBasis(face);
  const float inv = major > 0.0f ? 1.0f / major : 0.0f;
  return {face, 0.5f * (glm::dot(d, f.right) * inv + 1.0f), 0.5f * (1.0f - glm::dot(d, f.top) * inv)};
}

Sky::Sky(const SkyDesc& desc, const std::vector<std::shared_ptr<const Texture>>& textures)
    : scale_(desc.color * desc.intensity),
      lightingScale_(desc.lightingScale),
      picture_(desc.picture),
      ambient_{desc.ambientRadiance, desc.minimumRadiance},
      source_(desc),
      made_(true) {
  source_.picture = nullptr;
  glm::vec3 faceMean(0.0f);
  for (size_t i = 0; i < 6; ++i) {
    if (desc.faces[i] == kNoId) continue;
    faces_[i] = textures.at(desc.faces[i]);
    hasFaces_ = true;
  }
  if (hasFaces_) {
    for (const auto& f : faces_) faceMean += f ? glm::vec3(f->average()) : glm::vec3(0.0f);
    average_ = lightingScale_ * scale_ * faceMean / 6.0f;
    buildImportance();
  } else {
    average_ = lightingScale_ * scale_;
  }
}

bool Sky::sameButPicture(const SkyDesc& desc, const std::vector<std::shared_ptr<const Texture>>& textures) const {
  if (!made_ || desc.color != source_.color || desc.faces != source_.faces || desc.intensity != source_.intensity ||
      desc.lightingScale != source_.lightingScale || desc.ambientRadiance != source_.ambientRadiance ||
      desc.minimumRadiance != source_.minimumRadiance)
    return false;
  for (size_t i = 0; i < 6; ++i) {   // a texture updated under the same id is another texture
    const TextureId id = desc.faces[i];
    const Texture* now = id == kNoId ? nullptr : id < textures.size() ? textures[id].get() : nullptr;
    if (now != faces_[i].get()) return false;
  }
  return true;
}

void Sky::buildImportance() {
  // Weight of a cell = luminance of the (pre-filtered) face at its centre x its solid angle,
  // with a floor of 1% of the face mean so that every lit direction keeps a non-zero pdf.
  std::vector<double> weights(6 * kGrid * kGrid, 0.0);
  for (uint32_t f = 0; f < 6; ++f) {
    const auto& tex = faces_[f];
    if (!tex) continue;
    const float lod = std::log2(static_cast<float>(std::max(tex->width(), tex->height())) / kGrid);
    const double floor = 0.01 * std::max(1e-6f, sampling::luminance(scale_ * glm::vec3(tex->average())));
    for (uint32_t j = 0; j < kGrid; ++j) {
      for (uint32_t i = 0; i < kGrid; ++i) {
        const glm::vec2 uv((i + 0.5f) / kGrid, (j + 0.5f) / kGrid);
        const float lum = sampling::luminance(scale_ * glm::vec3(tex->sample(uv, lod)));
        const float area = solidAngleDensity(2.0f * uv.x - 1.0f, 1.0f - 2.0f * uv.y) * 4.0f / (kGrid * kGrid);
        weights[(f * kGrid + j) * kGrid + i] = (std::max(double{lum}, floor)) * area;
      }
    }
  }
  table_ = sampling::AliasTable(weights);
}

bool Sky::sample(const glm::vec3& u, glm::vec3& dir, float& pdf) const {
  if (table_.empty()) return false;
  const uint32_t cell = table_.sample(u.x);
  const uint32_t face = cell / (kGrid * kGrid);
  const uint32_t j = (cell / kGrid) % kGrid;
  const uint32_t i = cell % kGrid;
  const float fu = (static_cast<float>(i) + u.y) / kGrid;
  const float fv = (static_cast<float>(j) + u.z) / kGrid;
  const float x = 2.0f * fu - 1.0f;
  const float y = 1.0f - 2.0f * fv;
  const CubeFaceBasis& b = cubeFaceBasis(face);
  dir = glm::normalize(b.axis + x * b.right + y * b.top);
  // Uniform within the cell in face coordinates (area 4 / kGrid^2), converted to solid angle.
  pdf = table_.pdf(cell) * (kGrid * kGrid / 4.0f) / solidAngleDensity(x, y);
  return pdf > 0.0f && std::isfinite(pdf);
}

float Sky::pdf(const glm::vec3& dir) const {
  if (table_.empty()) return 0.0f;
  const CubeLookup c = cubeLookup(dir);
  const uint32_t i = std::min(static_cast<uint32_t>(c.u * kGrid), kGrid - 1);
  const uint32_t j = std::min(static_cast<uint32_t>(c.v * kGrid), kGrid - 1);
  const float p = table_.pdf((c.face * kGrid + j) * kGrid + i);
  return p * (kGrid * kGrid / 4.0f) / solidAngleDensity(2.0f * c.u - 1.0f, 1.0f - 2.0f * c.v);
}

glm::vec3 Sky::radiance(const glm::vec3& dir) const {
  if (picture_) return scale_ * picture_->radiance(dir);
  if (!hasFaces_) return scale_;
  const CubeLookup c = cubeLookup(dir);
  const auto& tex = faces_[c.face];
  if (!tex) return glm::vec3(0.0f);
  return scale_ * glm::vec3(tex->sampleFull({c.u, c.v}));
}

}  // namespace pa
