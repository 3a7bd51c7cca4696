// lightsFromLightmaps: lightmap texels placed on the world, their unexplained peaks, and a point
// light fitted along each peak's normal from the q3map2 falloff of the texels around it.
#include "port/light_recovery/lightmap_candidates.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "port/light_recovery/calibration_model.h"
#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/world/world_lights.h"

namespace pa::recovery {

using namespace q3;
namespace {

constexpr float kMinLightDistance = 16.0f;   // q3map2 clamps point-light distances here
constexpr float kPlaneTolerance = 4.0f;      // texels this far off the peak's plane are not on it
constexpr float kSameNormalCos = 0.95f;      // texels whose normal is within ~18 degrees share the plane
constexpr int kProminenceWindow = 4;         // pixels around a peak its prominence is measured over
constexpr size_t kMinFitTexels = 5;          // fewer texels around a peak cannot show a falloff
constexpr int kHeightAttempts = 8;           // best-fitting heights tried until one is valid
constexpr uint8_t kSaturatedByte = 254;      // a clamped channel says nothing about the light's magnitude

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

float cross2(const glm::vec2& a, const glm::vec2& b) { return a.x * b.y - a.y * b.x; }

/// True when the world mesh is one the lightmaps light (as the calibration samples them) and does not emit.
bool lightmapped(const WorldScene& scene, const WorldMesh& mesh) {
  if (lightmapPageOf(mesh.lightmap, scene.lightmaps.size()) < 0 || mesh.material >= scene.materials.size())
    return false;
  const WorldMaterial& m = scene.materials[mesh.material];
  if (!m.visible || m.sky || m.vertexLit || m.alphaMode != WorldAlphaMode::Opaque) return false;
  // An emitting surface's own texels are lit by itself (saturated around lamps): the renderer
  // shows its emission there, and no light belongs in front of it.
  if (m.surfaceLight > 0.0f || m.emissiveTexture >= 0) return false;
  const WorldImage& image = scene.lightmaps[size_t(mesh.lightmap)];
  if (image.width == 0 || image.height == 0 || image.rgba8.size() != size_t(image.width) * image.height * 4) return false;
  const size_t n = mesh.positions.size();
  return mesh.normals.size() == n && mesh.lightmapUvs.size() == n;
}

/// A lightmap peak: its texel and pixel, and how much of it the known light leaves.
struct Peak {
  int32_t texel;
  uint32_t page;
  int x, y;
  float unexplained = 0.0f;
};

/// A light along a peak's normal: where, how bright (light value per unit colour sum), how well it fits.
struct HeightFit {
  float height;
  float value;
  double error;
};

/// Cell key of a uniform hash grid.
int64_t cellKey(const glm::vec3& p, float cell) {
  const auto axis = [cell](float v) { return int64_t(std::clamp(std::floor(v / cell), -1.0e6f, 1.0e6f)) & 0x1fffff; };
  return (axis(p.x) << 42) | (axis(p.y) << 21) | axis(p.z);
}

/// Points kept in a hash grid of cell `radius`, for "is one within radius" queries.
class NearbyPoints {
 public:
  explicit NearbyPoints(float radius) : radius_(std::max(radius, 1e-3f)) {}
  void add(const glm::vec3& p) { cells_[cellKey(p, radius_)].push_back(p); }
  bool anyWithin(const glm::vec3& p) const {
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(cellKey(p + glm::vec3(float(dx), float(dy), float(dz)) * radius_, radius_));
          if (it == cells_.end()) continue;
          for (const glm::vec3& q : it->second)
            if (glm::length(q - p) < radius_) return true;
        }
    return false;
  }

 private:
  float radius_;
  std::unordered_map<int64_t, std::vector<glm::vec3>> cells_;
};

/// Local maxima of the lightmap pages that stand out from their surroundings.
std::vector<Peak> lightmapPeaks(const LightmapTexels& placed, const LightmapLightOptions& o) {
  std::vector<Peak> peaks;
  for (uint32_t p = 0; p < placed.pages.size(); ++p) {
    const LightmapTexels::Page& page = placed.pages[p];
    const int w = int(page.width), h = int(page.height);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t index = size_t(y) * size_t(w) + size_t(x);
        const int32_t t = page.texel[index];
        if (t < 0) continue;
        const float v = placed.texels[size_t(t)].value;
        if (!(v >= o.minPeakValue)) continue;
        bool peak = true;
        float lowest = v;
        for (int dy = -kProminenceWindow; dy <= kProminenceWindow && peak; ++dy)
          for (int dx = -kProminenceWindow; dx <= kProminenceWindow; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= w || ny >= h || (dx == 0 && dy == 0)) continue;
            const size_t neighbourIndex = size_t(ny) * size_t(w) + size_t(nx);
            const int32_t n = page.texel[neighbourIndex];
            if (n < 0) continue;
            const float nv = placed.texels[size_t(n)].value;
            // Ties go to the first pixel, so a saturated plateau gives one peak.
            if (std::abs(dx) <= 1 && std::abs(dy) <= 1 && (nv > v || (nv == v && neighbourIndex < index))) {
              peak = false;
              break;
            }
            lowest = std::min(lowest, nv);
          }
        if (peak && v - lowest >= o.minProminence * v) peaks.push_back({t, p, x, y});
      }
  }
  return peaks;
}

/// The best-fitting heights (fewest weighted squared errors first) of a point light along the
/// peak's normal, from the texels around the peak on its plane: texel ~ c + V * 7500 cos / max(d, 16)^2.
std::vector<HeightFit> fitHeights(const LightmapTexels& placed, const Peak& peak, const LightmapLightOptions& o) {
  const LightmapTexels::Page& page = placed.pages[peak.page];
  const LightmapTexel& centre = placed.texels[size_t(peak.texel)];
  std::vector<const LightmapTexel*> around;
  const int w = int(page.width), h = int(page.height);
  for (int y = std::max(0, peak.y - o.fitWindow); y <= std::min(h - 1, peak.y + o.fitWindow); ++y)
    for (int x = std::max(0, peak.x - o.fitWindow); x <= std::min(w - 1, peak.x + o.fitWindow); ++x) {
      const int32_t t = page.texel[size_t(y) * size_t(w) + size_t(x)];
      if (t < 0) continue;
      const LightmapTexel& texel = placed.texels[size_t(t)];
      const glm::vec3 offset = texel.position - centre.position;
      if (glm::dot(texel.normal, centre.normal) < kSameNormalCos || std::abs(glm::dot(offset, centre.normal)) > kPlaneTolerance ||
          glm::length(offset) > o.fitRadius)
        continue;
      around.push_back(&texel);
    }
  std::vector<HeightFit> fits;
  if (around.size() < kMinFitTexels) return fits;
  for (float height = std::max(o.minHeight, 1.0f); height <= o.maxHeight; height *= 1.08f) {
    const glm::vec3 light = centre.position + centre.normal * height;
    double sw = 0, swm = 0, swmm = 0, swv = 0, swmv = 0, swvv = 0;
    for (const LightmapTexel* t : around) {
      const glm::vec3 toLight = light - t->position;
      const float d = glm::length(toLight);
      const float cosine = d > 1e-3f ? std::max(0.0f, glm::dot(t->normal, toLight) / d) : 1.0f;
      const float clamped = std::max(d, kMinLightDistance);
      const double m = double(kQ3mapPointScale * cosine / (clamped * clamped));
      const double v = t->value, weight = 1.0 / (v + 32.0);   // relative errors, as the calibration
      sw += weight, swm += weight * m, swmm += weight * m * m, swv += weight * v, swmv += weight * m * v, swvv += weight * v * v;
    }
    // Weighted least squares of v = c + V m with c, V >= 0.
    const double det = sw * swmm - swm * swm;
    double c = 0.0, value = 0.0;
    if (det > 1e-12 * sw * swmm) {
      c = (swmm * swv - swm * swmv) / det;
      value = (sw * swmv - swm * swv) / det;
    }
    if (!(c >= 0.0)) c = 0.0, value = swmm > 0.0 ? swmv / swmm : 0.0;
    if (!(value > 0.0) || !std::isfinite(value)) continue;
    const double error = swvv + c * c * sw + value * value * swmm - 2.0 * c * swv - 2.0 * value * swmv + 2.0 * c * value * swm;
    fits.push_back({height, float(value), error});
  }
  std::stable_sort(fits.begin(), fits.end(), [](const HeightFit& a, const HeightFit& b) { return a.error < b.error; });
  return fits;
}

}  // namespace

LightmapTexels placeLightmapTexels(const WorldScene& scene, size_t maxPixelTests, size_t maxPagePixels) {
  LightmapTexels out;
  if (scene.models.empty()) return out;
  std::vector<int32_t> pageOf(scene.lightmaps.size(), -1);
  size_t pagePixels = 0, tests = 0;
  for (const WorldMesh& mesh : scene.models[0].meshes) {
    if (!lightmapped(scene, mesh)) continue;
    const size_t lightmap = size_t(mesh.lightmap);
    const WorldImage& image = scene.lightmaps[lightmap];
    if (pageOf[lightmap] < 0) {
      const size_t pixels = size_t(image.width) * image.height;
      if (pagePixels + pixels > maxPagePixels) continue;
      pagePixels += pixels;
      pageOf[lightmap] = int32_t(out.pages.size());
      out.pages.push_back({uint32_t(lightmap), image.width, image.height, std::vector<int32_t>(pixels, -1)});
    }
    LightmapTexels::Page& page = out.pages[size_t(pageOf[lightmap])];
    const glm::vec2 scale(float(image.width), float(image.height));
    const size_t n = mesh.positions.size();
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
      const uint32_t ia = mesh.indices[i], ib = mesh.indices[i + 1], ic = mesh.indices[i + 2];
      if (ia >= n || ib >= n || ic >= n) continue;
      const glm::vec2 a = mesh.lightmapUvs[ia] * scale, b = mesh.lightmapUvs[ib] * scale, c = mesh.lightmapUvs[ic] * scale;
      const float area = cross2(b - a, c - a);
      if (!(std::abs(area) > 1e-6f) || !std::isfinite(area) || !finite3(mesh.positions[ia]) || !finite3(mesh.positions[ib]) ||
          !finite3(mesh.positions[ic]))
        continue;
      const auto pixelRange = [](float lo, float hi, uint32_t size) {
        const float first = std::clamp(std::floor(lo - 0.5f), 0.0f, float(size - 1));
        const float last = std::clamp(std::ceil(hi - 0.5f), 0.0f, float(size - 1));
        return std::pair<int, int>(int(first), int(last));
      };
      const auto [x0, x1] = pixelRange(std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}), image.width);
      const auto [y0, y1] = pixelRange(std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}), image.height);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          if (++tests > maxPixelTests) return out;
          const glm::vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
          const float s = cross2(centre - a, c - a) / area, t = cross2(b - a, centre - a) / area;
          if (s < -1e-5f || t < -1e-5f || s + t > 1.0f + 1e-5f) continue;
          const size_t index = size_t(y) * image.width + size_t(x);
          if (page.texel[index] >= 0) continue;
          glm::vec3 normal = (1.0f - s - t) * mesh.normals[ia] + s * mesh.normals[ib] + t * mesh.normals[ic];
          const float length = glm::length(normal);
          if (!(length > 1e-4f) || !std::isfinite(length)) continue;
          const uint8_t* rgb = &image.rgba8[index * 4];
          page.texel[index] = int32_t(out.texels.size());
          out.texels.push_back({(1.0f - s - t) * mesh.positions[ia] + s * mesh.positions[ib] + t * mesh.positions[ic],
                                normal / length, float(rgb[0]) + float(rgb[1]) + float(rgb[2])});
        }
    }
  }
  return out;
}

std::vector<WorldLight> lightsFromLightmaps(const WorldScene& scene, const KnownLightAt& known,
                                            const std::vector<glm::vec3>& avoid, const SegmentBlocked& blocked,
                                            const PointInSolid& inSolid, const LightmapLightOptions& o,
                                            LightmapLightStats* statsOut) {
  LightmapLightStats stats;
  const LightmapTexels placed = placeLightmapTexels(scene);
  stats.texels = placed.texels.size();
  std::vector<Peak> peaks = lightmapPeaks(placed, o);
  // Strongest first; a peak must be the brightest within suppressionRadius (across charts and surfaces).
  const auto valueOf = [&](const Peak& p) { return placed.texels[size_t(p.texel)].value; };
  std::stable_sort(peaks.begin(), peaks.end(), [&](const Peak& a, const Peak& b) { return valueOf(a) > valueOf(b); });
  {
    NearbyPoints kept(o.suppressionRadius);
    std::vector<Peak> strongest;
    for (const Peak& p : peaks) {
      const glm::vec3& position = placed.texels[size_t(p.texel)].position;
      if (kept.anyWithin(position)) continue;
      kept.add(position);
      strongest.push_back(p);
      if (strongest.size() >= o.maxKnownEvaluations) break;
    }
    peaks = std::move(strongest);
  }
  stats.peaks = peaks.size();

  NearbyPoints taken(o.mergeDistance);
  for (const glm::vec3& p : avoid)
    if (finite3(p)) taken.add(p);
  std::vector<WorldLight> lights;
  // Brightest peaks first; the known light (the costly part: shadow rays to every emitter) and
  // the height fits are evaluated only until enough candidates are found, for batches of peaks
  // in parallel (each peak's own results); the choices below stay in order.
  constexpr size_t kBatch = 32;
  std::vector<std::vector<HeightFit>> peakFits(peaks.size());
  size_t evaluated = 0;
  for (size_t index = 0; index < peaks.size(); ++index) {
    if (lights.size() >= o.maxCandidates) break;
    if (index == evaluated) {
      evaluated = std::min(peaks.size(), index + kBatch);
      model::parallelOverSamples(
          evaluated - index,
          [&](size_t begin, size_t end) {
            for (size_t j = index + begin; j < index + end; ++j) {
              Peak& p = peaks[j];
              const LightmapTexel& t = placed.texels[size_t(p.texel)];
              const float explained = known ? known(t.position, t.normal) : 0.0f;
              p.unexplained = t.value - (std::isfinite(explained) ? std::max(0.0f, explained) : 0.0f);
              if (p.unexplained >= o.minUnexplainedShare * t.value) peakFits[j] = fitHeights(placed, p, o);
            }
          },
          1);
    }
    Peak& peak = peaks[index];
    if (!(peak.unexplained >= o.minUnexplainedShare * placed.texels[size_t(peak.texel)].value)) continue;
    ++stats.unexplained;
    const LightmapTexel& centre = placed.texels[size_t(peak.texel)];
    const std::vector<HeightFit>& fits = peakFits[index];
    const HeightFit* chosen = nullptr;
    glm::vec3 position{0.0f};
    for (size_t k = 0; k < fits.size() && k < size_t(kHeightAttempts); ++k) {
      position = centre.position + centre.normal * fits[k].height;
      if (inSolid && inSolid(position)) continue;
      if (blocked && blocked(centre.position + centre.normal, position)) continue;
      chosen = &fits[k];
      break;
    }
    if (!chosen) {
      ++stats.rejected;
      continue;
    }
    if (taken.anyWithin(position)) continue;
    taken.add(position);
    // The peak's colour, normalised so that the largest channel is 1 (as `_color`).
    const LightmapTexels::Page& page = placed.pages[peak.page];
    const uint8_t* rgb = &scene.lightmaps[page.lightmap].rgba8[(size_t(peak.y) * page.width + size_t(peak.x)) * 4];
    const float largest = float(std::max({rgb[0], rgb[1], rgb[2], uint8_t(1)}));
    WorldLight light;
    light.type = WorldLightType::Point;
    light.position = position;
    light.color = glm::vec3(std::max<float>(rgb[0], 1.0f), std::max<float>(rgb[1], 1.0f), std::max<float>(rgb[2], 1.0f)) / largest;
    light.color = glm::min(light.color, glm::vec3(1.0f));
    const float colorSum = light.color.r + light.color.g + light.color.b;
    light.quakeIntensity = chosen->value / colorSum;
    light.intensity = pointLightIntensity(light.quakeIntensity);
    // The light must not give its own peak more than the peak's unexplained light (with some
    // slack for blur and rounding), unless the peak saturated and its true value is unknown.
    const bool saturated = std::max({rgb[0], rgb[1], rgb[2]}) >= kSaturatedByte;
    const float clamped = std::max(chosen->height, kMinLightDistance);
    const float peakGain = kQ3mapPointScale / (clamped * clamped) * colorSum;
    if (!saturated) light.maxQuakeIntensity = o.peakSlack * peak.unexplained / peakGain;
    light.estimated = true;
    light.source = "lightmap peak (lightmap " + std::to_string(page.lightmap) + " at " + std::to_string(peak.x) + "," +
                   std::to_string(peak.y) + ", " + std::to_string(int(chosen->height)) + " units off the surface)";
    lights.push_back(std::move(light));
  }
  stats.candidates = lights.size();
  if (statsOut) *statsOut = stats;
  return lights;
}

}  // namespace pa::recovery
