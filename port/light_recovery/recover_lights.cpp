// recoverLights: the grid estimate, then the lightmap candidates and the calibration with a
// shadow-ray BVH over the world.
#include "port/light_recovery/recover_lights.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iterator>

#include <glm/geometric.hpp>

#include "port/light_recovery/emitter_index.h"
#include "port/light_recovery/lightmap_candidates.h"
#include "port/q3formats/world/world_lights.h"
#include "port/scene_bridge/scene_bridge.h"   // skyLightingRadiance: how the renderer lights with the sky
#include "renderer/bvh/bvh.h"
#include "renderer/core/srgb.h"

namespace pa::recovery {
namespace {

/// Mean radiance (summed over RGB) the renderer emits from a material (see materialDesc).
float emittedRadiance(const q3::WorldScene& scene, const q3::WorldMaterial& m) {
  if (m.surfaceLight > 0.0f) {
    const glm::vec3 radiance = m.emission * q3::surfaceLightRadiance(m.surfaceLight);
    return radiance.r + radiance.g + radiance.b;
  }
  if (m.emissiveTexture < 0 || size_t(m.emissiveTexture) >= scene.textures.size()) return 0.0f;
  const q3::WorldImage& image = scene.textures[size_t(m.emissiveTexture)].image;
  if (image.rgba8.size() != size_t(image.width) * image.height * 4 || image.rgba8.empty()) return 0.0f;
  double sum = 0.0;
  for (size_t i = 0; i + 3 < image.rgba8.size(); i += 4)
    for (int c = 0; c < 3; ++c) sum += pa::srgbToLinear(image.rgba8[i + size_t(c)] / 255.0);
  return float(sum / double(image.rgba8.size() / 4));
}

/// Appends the triangle to `emitters`, split into four at its edge midpoints until no edge is
/// longer than kEmitterPieceEdge: the calibration sees each piece as light from its centre, and
/// a whole lava pool seen from a wall beside it is no point (q3map2 subdivides its area lights
/// too). Bounded: pieces stop splitting once `emitters` holds kMaxEmitterPieces.
constexpr float kEmitterPieceEdge = 64.0f;
constexpr size_t kMaxEmitterPieces = size_t(1) << 16;
void appendEmitter(std::vector<CalibrationEmitter>& emitters, const CalibrationEmitter& e, int depth = 0) {
  const float longest = std::max({glm::length(e.b - e.a), glm::length(e.c - e.b), glm::length(e.a - e.c)});
  if (!(longest > kEmitterPieceEdge) || depth >= 8 || emitters.size() + 4 > kMaxEmitterPieces) {
    emitters.push_back(e);
    return;
  }
  const glm::vec3 ab = (e.a + e.b) * 0.5f, bc = (e.b + e.c) * 0.5f, ca = (e.c + e.a) * 0.5f;
  for (const auto& [p, q, r] : {std::array{e.a, ab, ca}, std::array{ab, e.b, bc}, std::array{ca, bc, e.c}, std::array{ab, bc, ca}}) {
    CalibrationEmitter piece = e;
    piece.a = p, piece.b = q, piece.c = r;
    appendEmitter(emitters, piece, depth + 1);
  }
}

}  // namespace

bool hasEstimatedLights(const std::vector<q3::WorldLight>& lights, const std::vector<q3::WorldLight>& gridCandidates) {
  return !gridCandidates.empty() ||
         std::any_of(lights.begin(), lights.end(), [](const q3::WorldLight& l) { return l.estimated; });
}

RecoveredLights recoverLights(const q3::WorldScene& scene, const RecoveryOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  RecoveredLights out;
  for (const q3::WorldLight& l : scene.lights)
    if (!l.estimated) out.lights.push_back(l);
  out.stats.authored = out.lights.size();
  // Maps that kept their light entities need none (estimating would cost seconds on the
  // largest ones, measured 4 s on oacmpdm4, for 5% precision next to its 86 lights).
  if (options.estimate && lightsStripped(out.lights)) {
    std::vector<q3::WorldLight> gridCandidates;
    std::vector<q3::WorldLight> estimated = estimateLightsFromGrid(scene.lightGrid, knownLightingOf(scene),
                                                                   options.estimation, &out.stats.estimate, &gridCandidates);
    out.stats.estimated = estimated.size();
    out.stats.gridCandidates = gridCandidates.size();
    out.lights.insert(out.lights.end(), estimated.begin(), estimated.end());
    if (options.calibrate) {
      out.lights = calibrateWithShadowRays(scene, out.lights, gridCandidates, options.calibration, &out.stats.calibration,
                                           &out.surfaceLightScales, &out.stats.emitters);
      // The constant is summed over RGB, like every texel value the calibration fits.
      const float perChannel = out.stats.calibration.unexplained / 3.0f;
      out.ambientValue = std::isfinite(perChannel) ? std::clamp(perChannel, 0.0f, q3::kQ3FullBright) : 0.0f;
    }
  }
  out.stats.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return out;
}

void applyRecoveredLights(q3::WorldScene& scene, const RecoveredLights& recovered) {
  scene.lights = recovered.lights;
  if (recovered.ambientValue > 0.0f && std::isfinite(recovered.ambientValue))
    scene.ambientLight = glm::max(scene.ambientLight, glm::vec3(std::min(recovered.ambientValue, q3::kQ3FullBright)));
  for (size_t i = 0; i < scene.materials.size() && i < recovered.surfaceLightScales.size(); ++i) {
    const float scale = recovered.surfaceLightScales[i];
    if (std::isfinite(scale) && scale >= 0.0f && scale < 1.0f) scene.materials[i].surfaceLight *= scale;
  }
}

std::vector<q3::WorldLight> calibrateWithShadowRays(const q3::WorldScene& scene, const std::vector<q3::WorldLight>& lights,
                                                    const std::vector<q3::WorldLight>& gridCandidates,
                                                    const LightCalibrationOptions& options,
                                                    LightCalibrationStats* stats, std::vector<float>* surfaceLightScales,
                                                    EmitterFitStats* emitterStats) {
  if (surfaceLightScales) surfaceLightScales->clear();
  const bool fromLightmaps = options.lightsFromLightmaps && options.admitCandidates && !scene.lightmaps.empty() &&
                            lightsStripped(lights);
  if ((!hasEstimatedLights(lights, gridCandidates) && !fromLightmaps) || scene.models.empty()) return lights;
  // The world's opaque shadow casters (q3map2 traces against the world's brushes and patches).
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  for (const q3::WorldMesh& mesh : scene.models[0].meshes) {
    if (mesh.material >= scene.materials.size()) continue;
    const q3::WorldMaterial& m = scene.materials[mesh.material];
    if (!m.castsShadows || m.sky || m.alphaMode != q3::WorldAlphaMode::Opaque) continue;
    const uint32_t base = uint32_t(positions.size());
    bool finite = true;
    for (const glm::vec3& p : mesh.positions) finite = finite && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
    if (!finite) continue;
    positions.insert(positions.end(), mesh.positions.begin(), mesh.positions.end());
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
      if (a >= mesh.positions.size() || b >= mesh.positions.size() || c >= mesh.positions.size()) continue;
      indices.insert(indices.end(), {base + a, base + b, base + c});
    }
  }
  // What the renderer's emitting surfaces give (surface lights, glow stages). Surface lights
  // are grouped by material for the emitter fit; glow stages are what the surface looks like
  // and stay known light.
  std::vector<CalibrationEmitter> emitters;
  for (const q3::WorldModel& model : scene.models)
    for (const q3::WorldMesh& mesh : model.meshes) {
      if (mesh.material >= scene.materials.size()) continue;
      const q3::WorldMaterial& m = scene.materials[mesh.material];
      const float radiance = emittedRadiance(scene, m);
      if (!(radiance > 0.0f) || m.sky) continue;
      const int32_t group = m.surfaceLight > 0.0f ? int32_t(mesh.material) : -1;
      for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        if (a >= mesh.positions.size() || b >= mesh.positions.size() || c >= mesh.positions.size()) continue;
        appendEmitter(emitters, {mesh.positions[a], mesh.positions[b], mesh.positions[c], radiance, m.twoSided, group});
      }
    }
  Blas blas;
  if (!indices.empty()) blas.build(BlasInput{positions, indices, {}});
  const bool empty = indices.empty();
  const SegmentBlocked blocked = [&](const glm::vec3& from, const glm::vec3& to) {
    if (empty) return false;
    const glm::vec3 delta = to - from;
    const float length = glm::length(delta);
    if (!(length > 1e-3f) || !std::isfinite(length)) return false;
    Ray ray;
    ray.origin = from;
    ray.dir = delta / length;
    ray.tmin = 0.0f;
    ray.tmax = length * (1.0f - 1e-4f) - 0.05f;
    return ray.tmax > 0.0f && blas.occluded(ray);
  };
  LightCalibrationOptions withSky = options;
  if (!(withSky.skyLightValue > 0.0f)) {
    const glm::vec3 sky = bridge::skyLightingRadiance(scene);
    withSky.skyLightValue = q3::kQ3FullBright * (sky.r + sky.g + sky.b);
  }
  // Inside solid: most directions first meet a triangle from behind (brushes are closed and
  // face outwards). Open directions (sky, leaks) count as outside.
  const PointInSolid inSolid = [&](const glm::vec3& point) {
    if (empty) return false;
    static constexpr float kDirections[14][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0},  {0, 0, 1},
                                                 {0, 0, -1}, {1, 1, 1},  {1, 1, -1},  {1, -1, 1},  {1, -1, -1},
                                                 {-1, 1, 1}, {-1, 1, -1}, {-1, -1, 1}, {-1, -1, -1}};
    int behind = 0;
    for (const auto& d : kDirections) {
      Ray ray;
      ray.origin = point;
      ray.dir = glm::normalize(glm::vec3(d[0], d[1], d[2]));
      ray.tmax = 65536.0f;
      Hit hit;
      if (!blas.intersect(ray, hit) || hit.prim >= indices.size() / 3) continue;
      const glm::vec3& a = positions[indices[hit.prim * 3]];
      const glm::vec3 normal =
          glm::cross(positions[indices[hit.prim * 3 + 1]] - a, positions[indices[hit.prim * 3 + 2]] - a);
      behind += glm::dot(normal, ray.dir) > 0.0f ? 1 : 0;
    }
    return behind >= 10;
  };
  std::vector<glm::vec3> avoid;   // lights the calibration fits anyway
  for (const q3::WorldLight& l : lights)
    if (l.type != q3::WorldLightType::Sun) avoid.push_back(l.position);
  for (const q3::WorldLight& l : gridCandidates) avoid.push_back(l.position);
  LightmapLightOptions lightmapOptions;
  lightmapOptions.maxCandidates = options.maxLightmapCandidates;
  // On maps whose lights were stripped, the emitting materials' light as the lightmaps show it,
  // fitted beside the grid's lights and candidates from every unexplained lightmap peak as if no
  // surface light were known (else a too bright emitter would leave no candidate to take its
  // place). The steps below see the emitters at the fitted values.
  const bool anyGroup = std::any_of(emitters.begin(), emitters.end(), [](const CalibrationEmitter& e) { return e.group >= 0; });
  if (fromLightmaps && anyGroup) {
    std::vector<CalibrationEmitter> ungrouped;
    std::copy_if(emitters.begin(), emitters.end(), std::back_inserter(ungrouped),
                 [](const CalibrationEmitter& e) { return e.group < 0; });
    const EmitterIndex ungroupedIndex(ungrouped, withSky.minTracedValue);
    const KnownLightAt withoutSurfaceLights = [&](const glm::vec3& position, const glm::vec3& normal) {
      return knownLightAt(scene, position, normal, blocked, ungroupedIndex, withSky);
    };
    const std::vector<q3::WorldLight> peaks =
        lightsFromLightmaps(scene, withoutSurfaceLights, avoid, blocked, inSolid, lightmapOptions, nullptr);
    const std::vector<float> scales = fitEmitterScales(scene, lights, gridCandidates, peaks, emitters,
                                                       scene.materials.size(), blocked, withSky, emitterStats);
    for (CalibrationEmitter& e : emitters)
      if (e.group >= 0 && size_t(e.group) < scales.size()) e.radiance *= scales[size_t(e.group)];
    if (surfaceLightScales) *surfaceLightScales = scales;
  }
  // Candidates where the lightmaps show light that neither the authored lights, the emitters nor
  // the sky explain (the light grid may be too coarse to show it, or its estimates blended).
  std::vector<q3::WorldLight> lightmapCandidates;
  LightmapLightStats lightmapStats;
  const auto start = std::chrono::steady_clock::now();
  if (fromLightmaps) {
    const EmitterIndex emitterIndex(emitters, withSky.minTracedValue);
    const KnownLightAt known = [&](const glm::vec3& position, const glm::vec3& normal) {
      return knownLightAt(scene, position, normal, blocked, emitterIndex, withSky);
    };
    lightmapCandidates = lightsFromLightmaps(scene, known, avoid, blocked, inSolid, lightmapOptions, &lightmapStats);
  }
  const double lightmapMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::vector<q3::WorldLight> calibrated =
      calibrateEstimatedLights(scene, lights, gridCandidates, blocked, withSky, stats, emitters, inSolid, lightmapCandidates);
  if (stats) {
    stats->lightmapPeaks = lightmapStats.peaks;
    stats->lightmapUnexplained = lightmapStats.unexplained;
    stats->lightmapCandidates = lightmapStats.candidates;
    stats->lightmapMs = lightmapMs;
  }
  return calibrated;
}

}  // namespace pa::recovery
