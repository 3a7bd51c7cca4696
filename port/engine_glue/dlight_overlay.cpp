#include "port/engine_glue/dlight_overlay.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "port/engine_glue/entity_lighting.h"
#include "port/engine_glue/scene.h"
#include "renderer/core/srgb.h"

namespace glue {
namespace {

constexpr int kBlobSize = 16;               // DLIGHT_SIZE
constexpr int32_t kSurfNoDlight = 0x20000;  // SURF_NODLIGHT
constexpr float kOverlayLift = 0.25f;       // units off the surface, towards its front
constexpr int kMaxSubdivision = 3;          // 4^3 pieces per triangle at most

/// The stock falloff image: 4000 / d^2 (d in texels from the centre), cut below 75, max 255.
const std::array<float, kBlobSize * kBlobSize>& blobImage() {
  static const std::array<float, kBlobSize * kBlobSize> image = [] {
    std::array<float, kBlobSize * kBlobSize> texels{};
    for (int y = 0; y < kBlobSize; ++y)
      for (int x = 0; x < kBlobSize; ++x) {
        const float dx = kBlobSize / 2 - 0.5f - x, dy = kBlobSize / 2 - 0.5f - y;
        float b = 4000.0f / (dx * dx + dy * dy);
        b = b > 255.0f ? 255.0f : (b < 75.0f ? 0.0f : std::floor(b));
        texels[size_t(y) * kBlobSize + x] = b / 255.0f;
      }
    return texels;
  }();
  return image;
}

/// The sRGB decoding of a display value, continued above 1 (several lights multiply past white).
float displayToLinear(float c) {
  return pa::srgbToLinear(std::max(c, 0.0f));
}

bool reaches(const DynamicLight& light, const glm::vec3& mins, const glm::vec3& maxs) {
  const glm::vec3 nearest = glm::clamp(light.origin, mins, maxs);
  const glm::vec3 gap = glm::abs(nearest - light.origin);
  return gap.x <= light.radius && gap.y <= light.radius && gap.z <= light.radius;
}

}  // namespace

float stockDlightBlob(glm::vec2 st) {
  const auto& image = blobImage();
  float x = st.x * kBlobSize - 0.5f, y = st.y * kBlobSize - 0.5f;
  if (!std::isfinite(x) || !std::isfinite(y)) return 0.0f;
  x = std::clamp(x, 0.0f, float(kBlobSize - 1));
  y = std::clamp(y, 0.0f, float(kBlobSize - 1));
  const int x0 = int(x), y0 = int(y);
  const int x1 = std::min(x0 + 1, kBlobSize - 1), y1 = std::min(y0 + 1, kBlobSize - 1);
  const float ax = x - float(x0), ay = y - float(y0);
  auto at = [&](int px, int py) { return image[size_t(py) * kBlobSize + px]; };
  return (at(x0, y0) * (1 - ax) + at(x1, y0) * ax) * (1 - ay) + (at(x0, y1) * (1 - ax) + at(x1, y1) * ax) * ay;
}

glm::vec3 stockDlightAt(const DynamicLight& light, const glm::vec3& position, const glm::vec3& normal) {
  if (!(light.radius > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 toLight = light.origin - position;
  if (glm::dot(toLight, normal) < 0.0f) return glm::vec3(0.0f);   // lights only the front
  const float height = std::fabs(toLight.z);
  if (height > light.radius) return glm::vec3(0.0f);
  const float modulate = height < light.radius * 0.5f ? 1.0f : 2.0f * (light.radius - height) / light.radius;
  const glm::vec2 st = glm::vec2(0.5f) + glm::vec2(toLight.x, toLight.y) / light.radius;
  const glm::vec3 color = glm::floor(glm::clamp(light.color, 0.0f, 1.0f) * 255.0f * modulate) / 255.0f;
  return color * stockDlightBlob(st);
}

void DlightOverlay::clear() {
  positions.clear();
  normals.clear();
  uvs.clear();
  colors.clear();
  indices.clear();
  triangleMaterials.clear();
}

void DlightOverlayBuilder::prepare(const q3::WorldScene& scene) {
  triangles_.clear();
  if (scene.models.empty()) return;
  for (const q3::WorldMesh& mesh : scene.models[0].meshes) {
    if (mesh.material >= scene.materials.size()) continue;
    const q3::WorldMaterial& m = scene.materials[mesh.material];
    if (!m.visible || m.sky || m.fog || m.mirror || m.alphaMode != q3::WorldAlphaMode::Opaque ||
        (m.surfaceFlags & kSurfNoDlight) != 0)
      continue;
    const size_t n = mesh.positions.size();
    if (mesh.normals.size() != n || mesh.uvs.size() != n || mesh.lightmapUvs.size() != n || mesh.colors.size() != n)
      continue;
    for (size_t k = 0; k + 2 < mesh.indices.size(); k += 3) {
      Triangle t;
      t.material = mesh.material;
      bool valid = true;
      for (int c = 0; c < 3; ++c) {
        const uint32_t i = mesh.indices[k + size_t(c)];
        if (i >= n) { valid = false; break; }
        t.v[c] = {mesh.positions[i], mesh.normals[i], mesh.uvs[i]};
      }
      if (!valid) continue;
      t.mins = glm::min(glm::min(t.v[0].position, t.v[1].position), t.v[2].position);
      t.maxs = glm::max(glm::max(t.v[0].position, t.v[1].position), t.v[2].position);
      triangles_.push_back(t);
    }
  }
}

std::vector<uint32_t> DlightOverlayBuilder::materials() const {
  std::vector<uint32_t> out;
  for (const Triangle& t : triangles_) out.push_back(t.material);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void DlightOverlayBuilder::build(std::span<const DynamicLight> lights, DlightOverlay& out) {
  if (lights.empty()) return;
  std::vector<DynamicLight>& reaching = reaching_;
  for (const Triangle& t : triangles_) {
    reaching.clear();
    for (const DynamicLight& light : lights)
      if (light.radius > 0.0f && reaches(light, t.mins, t.maxs)) reaching.push_back(light);
    if (!reaching.empty()) emit(t, reaching, 0, out);
  }
}

void DlightOverlayBuilder::emit(const Triangle& t, std::span<const DynamicLight> lights, int depth,
                                DlightOverlay& out) const {
  float smallestRadius = lights.front().radius;
  for (const DynamicLight& light : lights) smallestRadius = std::min(smallestRadius, light.radius);
  const float longestEdge = std::max({glm::length(t.v[1].position - t.v[0].position),
                                      glm::length(t.v[2].position - t.v[1].position),
                                      glm::length(t.v[0].position - t.v[2].position)});
  if (depth < kMaxSubdivision && longestEdge > 0.3f * smallestRadius) {
    auto mid = [](const Vertex& a, const Vertex& b) {
      Vertex m;
      m.position = 0.5f * (a.position + b.position);
      m.normal = glm::normalize(a.normal + b.normal + glm::vec3(1e-9f));
      m.uv = 0.5f * (a.uv + b.uv);
      return m;
    };
    const Vertex ab = mid(t.v[0], t.v[1]), bc = mid(t.v[1], t.v[2]), ca = mid(t.v[2], t.v[0]);
    const Vertex pieces[4][3] = {{t.v[0], ab, ca}, {ab, t.v[1], bc}, {ca, bc, t.v[2]}, {ab, bc, ca}};
    for (const auto& piece : pieces) {
      Triangle sub;
      sub.material = t.material;
      std::copy(std::begin(piece), std::end(piece), sub.v);
      sub.mins = glm::min(glm::min(sub.v[0].position, sub.v[1].position), sub.v[2].position);
      sub.maxs = glm::max(glm::max(sub.v[0].position, sub.v[1].position), sub.v[2].position);
      const bool reached = std::any_of(lights.begin(), lights.end(),
                                       [&](const DynamicLight& light) { return reaches(light, sub.mins, sub.maxs); });
      if (reached) emit(sub, lights, depth + 1, out);
    }
    return;
  }
  glm::vec4 colors[3];
  bool lit = false;
  for (int c = 0; c < 3; ++c) {
    // One pass per light makes dst * (1 + l1) * (1 + l2) ... in display values: the overlay
    // layer (pa::LayerBlend::MultiplyAdd) multiplies dst by 1 + (product - 1), its vertex colour
    // being product - 1 as linear light (the layer is encoded for display before it multiplies).
    glm::vec3 product(1.0f);
    for (const DynamicLight& light : lights)
      product *= glm::vec3(1.0f) + stockDlightAt(light, t.v[c].position, t.v[c].normal);
    const glm::vec3 gain = product - glm::vec3(1.0f);
    colors[c] = glm::vec4(displayToLinear(gain.r), displayToLinear(gain.g), displayToLinear(gain.b), 1.0f);
    lit = lit || glm::vec3(colors[c]) != glm::vec3(0.0f);
  }
  if (!lit) return;
  const auto base = static_cast<uint32_t>(out.positions.size());
  for (int c = 0; c < 3; ++c) {
    out.positions.push_back(t.v[c].position + t.v[c].normal * kOverlayLift);
    out.normals.push_back(t.v[c].normal);
    out.uvs.push_back(t.v[c].uv);
    out.colors.push_back(colors[c]);
  }
  out.indices.insert(out.indices.end(), {base, base + 1, base + 2});
  out.triangleMaterials.push_back(t.material);
}

}  // namespace glue
