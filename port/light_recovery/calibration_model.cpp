// The calibrations' shared light model: texel sampling, q3map2's light at a texel, bounded NNLS.
#include "port/light_recovery/calibration_model.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include "port/q3formats/world/world_lights.h"

namespace pa::recovery::model {

using namespace q3;
namespace {

/// A lightmapped world triangle eligible for sampling.
struct SampleTriangle {
  const WorldMesh* mesh;
  size_t firstIndex;
  const WorldImage* lightmap;
};

/// splitmix64's output function: a bijective mix of 64 bits.
uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

}  // namespace

float uniform01(std::mt19937& rng) { return float(rng() >> 8) * (1.0f / 16777216.0f); }

// The start state is a hash of (seed, index), so neighbouring samples' streams are unrelated.
SampleRandom::SampleRandom(uint32_t seed, uint64_t index) : state_(mix64(mix64(uint64_t{seed} + 1) ^ index)) {}

float SampleRandom::next01() { return float(mix64(state_ += 0x9e3779b97f4a7c15ull) >> 40) * (1.0f / 16777216.0f); }

void parallelOverSamples(size_t count, const std::function<void(size_t, size_t)>& body, size_t grain) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, std::max<size_t>(1, grain)),
                    [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
}

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Area-weighted texel samples over the world model's lightmapped, visible, opaque surfaces.
std::vector<Sample> sampleLightmaps(const WorldScene& scene, const LightCalibrationOptions& o) {
  std::vector<SampleTriangle> triangles;
  std::vector<double> cumulativeArea;
  double total = 0.0;
  if (scene.models.empty()) return {};
  for (const WorldMesh& mesh : scene.models[0].meshes) {
    if (lightmapPageOf(mesh.lightmap, scene.lightmaps.size()) < 0 || mesh.material >= scene.materials.size())
      continue;
    const WorldMaterial& m = scene.materials[mesh.material];
    if (!m.visible || m.sky || m.vertexLit || m.alphaMode != WorldAlphaMode::Opaque) continue;
    const WorldImage& image = scene.lightmaps[mesh.lightmap];
    if (image.width == 0 || image.height == 0 || image.rgba8.size() != size_t(image.width) * image.height * 4) continue;
    const size_t n = mesh.positions.size();
    if (mesh.normals.size() != n || mesh.lightmapUvs.size() != n) continue;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
      if (a >= n || b >= n || c >= n) continue;
      const double area = 0.5 * double(glm::length(glm::cross(mesh.positions[b] - mesh.positions[a],
                                                               mesh.positions[c] - mesh.positions[a])));
      if (!(area > 0.0) || !std::isfinite(area)) continue;
      total += area;
      triangles.push_back({&mesh, t, &image});
      cumulativeArea.push_back(total);
    }
  }
  std::vector<Sample> samples;
  if (triangles.empty()) return samples;
  std::mt19937 rng(o.seed);
  samples.reserve(o.maxSamples);
  for (size_t s = 0; s < o.maxSamples; ++s) {
    const double pick = double(uniform01(rng)) * total;
    const size_t t = std::min(size_t(std::lower_bound(cumulativeArea.begin(), cumulativeArea.end(), pick) -
                                     cumulativeArea.begin()),
                              triangles.size() - 1);
    const SampleTriangle& tri = triangles[t];
    const WorldMesh& mesh = *tri.mesh;
    float u = uniform01(rng), v = uniform01(rng);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    const uint32_t ia = mesh.indices[tri.firstIndex], ib = mesh.indices[tri.firstIndex + 1],
                   ic = mesh.indices[tri.firstIndex + 2];
    const float w = 1.0f - u - v;
    const glm::vec3 p = w * mesh.positions[ia] + u * mesh.positions[ib] + v * mesh.positions[ic];
    glm::vec3 normal = w * mesh.normals[ia] + u * mesh.normals[ib] + v * mesh.normals[ic];
    const glm::vec2 uv = w * mesh.lightmapUvs[ia] + u * mesh.lightmapUvs[ib] + v * mesh.lightmapUvs[ic];
    const float length = glm::length(normal);
    if (!(length > 1e-4f) || !finite3(p) || !std::isfinite(uv.x) || !std::isfinite(uv.y)) continue;
    normal /= length;
    const WorldImage& image = *tri.lightmap;
    const int64_t x = std::clamp<int64_t>(int64_t(std::floor(uv.x * float(image.width))), 0, image.width - 1);
    const int64_t y = std::clamp<int64_t>(int64_t(std::floor(uv.y * float(image.height))), 0, image.height - 1);
    const uint8_t* texel = &image.rgba8[(size_t(y) * image.width + size_t(x)) * 4];
    // Saturated texels are kept at their clamped value: a lower bound, but leaving them out
    // would let lights grow unchecked where q3map2 saturated (measured 5x too bright on oa_dm6).
    samples.push_back({p, normal, float(texel[0]) + float(texel[1]) + float(texel[2])});
  }
  return samples;
}

float colorSum(const WorldLight& l) { return std::max(0.0f, l.color.r) + std::max(0.0f, l.color.g) + std::max(0.0f, l.color.b); }

/// Unshadowed light value a unit-valued inverse-square point light at `light` gives the sample
/// (q3map2's pointScale, cosine and 16-unit distance clamp), summed over RGB.
float pointGain(const Sample& s, const WorldLight& light) {
  const glm::vec3 toLight = light.position - s.position;
  const float d = glm::length(toLight);
  if (!(d > 1e-3f)) return 0.0f;
  const float cosine = glm::dot(s.normal, toLight) / d;
  if (!(cosine > 0.0f)) return 0.0f;
  if (light.type == WorldLightType::Spot && glm::dot(-toLight / d, light.direction) < light.cosOuterAngle) return 0.0f;
  const float clamped = std::max(d, kMinLightDistance);
  return kQ3mapPointScale * cosine / (clamped * clamped) * colorSum(light);
}

/// Light value (summed over RGB) an authored light gives the sample, shadows included.
float authoredLight(const Sample& s, const WorldLight& light, const glm::vec3& origin, const SegmentBlocked& blocked,
                    size_t& rays) {
  if (light.type == WorldLightType::Sun) {
    const float len = glm::length(light.direction);
    if (!(len > 1e-6f)) return 0.0f;
    const glm::vec3 toward = -light.direction / len;
    const float cosine = glm::dot(s.normal, toward);
    if (!(cosine > 0.0f)) return 0.0f;
    ++rays;
    return blocked(origin, origin + toward * kSunDistance) ? 0.0f : light.quakeIntensity * cosine * colorSum(light);
  }
  float value;
  if (light.linearFalloff) {
    const glm::vec3 toLight = light.position - s.position;
    const float d = glm::length(toLight);
    const float cosine = d > 1e-3f ? glm::dot(s.normal, toLight) / d : 0.0f;
    value = cosine > 0.0f ? std::max(0.0f, cosine * light.quakeIntensity * kQ3mapPointScale * kQ3mapLinearScale - d) *
                                colorSum(light)
                          : 0.0f;
  } else {
    value = light.quakeIntensity * pointGain(s, light);
  }
  if (!(value > 0.0f)) return 0.0f;
  ++rays;
  return blocked(origin, light.position) ? 0.0f : value;
}

/// Cosine-weighted share of the hemisphere above the sample through which the sky is seen.
float openSky(const Sample& s, const glm::vec3& origin, const SegmentBlocked& blocked, SampleRandom& random, int rays) {
  const glm::vec3 n = s.normal;
  const glm::vec3 helper = std::abs(n.x) > 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 t = glm::normalize(glm::cross(helper, n)), b = glm::cross(n, t);
  int open = 0;
  for (int r = 0; r < rays; ++r) {
    const float u = random.next01(), v = random.next01();
    const float radius = std::sqrt(u), phi = 6.2831853f * v;
    const glm::vec3 dir = t * (radius * std::cos(phi)) + b * (radius * std::sin(phi)) + n * std::sqrt(std::max(0.0f, 1.0f - u));
    open += blocked(origin, origin + dir * kSunDistance) ? 0 : 1;
  }
  return float(open) / float(rays);
}

/// Light value (summed over RGB) an emitting triangle gives the sample: the renderer's
/// irradiance L * A * cos * cos' / d^2 (d^2 kept above the area near the triangle) in
/// light-value units (x 64 / pi), shadowed towards its centre.
float emitterLight(const Sample& s, const PreparedEmitter& e, const glm::vec3& origin, const SegmentBlocked& blocked,
                   const LightCalibrationOptions& o, size_t& rays) {
  const glm::vec3 toEmitter = e.centre - s.position;
  const float d2 = glm::dot(toEmitter, toEmitter);
  if (!(d2 > 1e-6f)) return 0.0f;
  const glm::vec3 dir = toEmitter / std::sqrt(d2);
  const float cosReceiver = glm::dot(s.normal, dir);
  float cosEmitter = -glm::dot(e.unitNormal, dir);
  if (e.twoSided) cosEmitter = std::abs(cosEmitter);
  if (!(cosReceiver > 0.0f) || !(cosEmitter > 0.0f)) return 0.0f;
  const float value = e.power * cosReceiver * cosEmitter / std::max(d2, e.area);
  if (value < o.minTracedValue) return 0.0f;
  ++rays;
  return blocked(origin, e.centre - dir * 0.5f) ? 0.0f : value;
}

/// Light value (summed over RGB) the scene's own light gives the sample: authored lights,
/// emitting triangles and the open sky, shadows included. Shadow rays towards lights and
/// emitters are counted in `rays` (the sky's are not).
float knownLight(const WorldScene& scene, const Sample& s, const glm::vec3& origin, const SegmentBlocked& blocked,
                 const EmitterIndex& emitters, const LightCalibrationOptions& o, SampleRandom& random, size_t& rays,
                 std::vector<uint32_t>& near) {
  float value = 0.0f;
  for (const WorldLight& l : scene.lights)
    if (!l.estimated) value += authoredLight(s, l, origin, blocked, rays);
  // In index order, as a sum over every emitter would add them: the ones left out give 0.
  emitters.near(s.position, o.minTracedValue, near);
  for (const uint32_t i : near) value += emitterLight(s, emitters.emitters()[i], origin, blocked, o, rays);
  if (o.skyLightValue > 0.0f && o.skyRays > 0) value += o.skyLightValue * openSky(s, origin, blocked, random, o.skyRays);
  return value;
}

/// Least-squares weight of a texel: 1 (absolute errors) or 1 / (texel + 32) (relative).
double weightOf(float texel, const LightCalibrationOptions& o) {
  return o.relativeErrors ? 1.0 / (double(texel) + 32.0) : 1.0;
}

void appendShadowedGains(const Sample& s, const glm::vec3& origin, const std::vector<const WorldLight*>& lights,
                         uint32_t offset, const SegmentBlocked& blocked, const LightCalibrationOptions& o, size_t& rays,
                         std::vector<Entry>& entries) {
  for (size_t i = 0; i < lights.size(); ++i) {
    const float gain = pointGain(s, *lights[i]);
    if (!(gain > 0.0f) || gain * 4.0f * std::max(lights[i]->quakeIntensity, o.minLightValue) < o.minTracedValue) continue;
    ++rays;
    if (blocked(origin, lights[i]->position)) continue;
    entries.push_back({offset + uint32_t(i), gain});
  }
}

void accumulateRow(const std::vector<Entry>& entries, double w, double target, size_t n, std::vector<double>& gram,
                   std::vector<double>& rhs, std::vector<size_t>& lit) {
  const size_t constant = n - 1;
  for (const Entry& a : entries) {
    ++lit[a.light];
    for (const Entry& b : entries) gram[a.light * n + b.light] += w * a.gain * b.gain;
    gram[a.light * n + constant] += w * a.gain;
    gram[constant * n + a.light] += w * a.gain;
    rhs[a.light] += w * a.gain * target;
  }
  gram[constant * n + constant] += w;
  rhs[constant] += w * target;
}

std::vector<double> solveBounded(const std::vector<double>& gram, const std::vector<double>& rhs, std::vector<double> x,
                                 const std::vector<double>& lower, const std::vector<double>& upper, int sweeps) {
  const size_t n = rhs.size();
  std::vector<double> gradient(n);
  for (size_t i = 0; i < n; ++i) {
    double g = -rhs[i];
    for (size_t k = 0; k < n; ++k) g += gram[i * n + k] * x[k];
    gradient[i] = g;
  }
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    double largest = 0.0, scale = 1e-12;
    for (size_t i = 0; i < n; ++i) {
      const double diagonal = gram[i * n + i];
      if (!(diagonal > 0.0)) continue;
      const double updated = std::clamp(x[i] - gradient[i] / diagonal, lower[i], upper[i]);
      const double delta = updated - x[i];
      if (delta == 0.0) continue;
      x[i] = updated;
      for (size_t k = 0; k < n; ++k) gradient[k] += delta * gram[k * n + i];
      largest = std::max(largest, std::abs(delta));
      scale = std::max(scale, std::abs(updated));
    }
    if (largest < 1e-6 * scale) break;
  }
  return x;
}

}  // namespace pa::recovery::model
