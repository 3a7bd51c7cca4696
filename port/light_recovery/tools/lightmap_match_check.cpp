// lightmap-match-check: how well the Direct integrator matches the baked lighting on maps
// whose lights were recovered (port/light_recovery). Prints the lightmap calibration's figures
// (samples, fitted lights, time) and, per spawn point, the mean linear luminance of a Lightmap
// render (4 spp) and of Direct renders (16 spp) with the grid's values and the calibrated ones
// (320x180, the same figures pa-render's EXR gives).
//
//   lightmap-match-check [--game DIR] [--spawns N] [--spp N (Direct, default 16)] MAP...
//   lightmap-match-check --recover MAP...   (maps that kept their lights: doubled values refitted)
// Diagnosis switches (environment): PA_LIST_LIGHTS=1 lists the calibrated lights,
// PA_NO_CANDIDATES=1 refits the estimated lights only, PA_NO_LIGHTMAP_LIGHTS=1 proposes no
// lightmap candidates (lightmap_candidates.h), PA_LIGHTMAP_CANDIDATES=N at most N of them, PA_ABSOLUTE=1 fits absolute errors,
// PA_CAL_SKY=V calibrates with sky light value V (summed over RGB, open surface) instead of the
// sky shader's; what is rendered: PA_NO_SKY=1 without the sky, PA_NO_SUN=1 without q3map_sun
// lights, PA_NO_EMITTERS=1 without surface lights and glow stages, PA_PATH=1 the calibrated
// lights with Path (4 bounces) instead of Direct, PA_NO_GRID=1 skips the Direct render with the
// grid's values; PA_PNG=PREFIX writes the renders as PREFIX_sN_{lightmap,grid,direct,path}.png
// (clamp look, sRGB).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <stb_image_write.h>

#include "port/q3formats/world/world_game.h"
#include "port/light_recovery/recover_lights.h"
#include "port/scene_bridge/scene_bridge.h"
#include "renderer/core/srgb.h"

namespace {

/// Mean luminance: plain, and with each pixel capped at its albedo (the most a lightmap can
/// show: Quake's overbright shift saturates at "full bright").
struct Luminance {
  double plain = 0.0;
  double capped = 0.0;
  double black = 0.0;   ///< Share of pixels whose display luma is below 10/255.
};

/// The calibration's knobs as the diagnosis switches set them.
pa::recovery::LightCalibrationOptions calibrationFromEnvironment() {
  pa::recovery::LightCalibrationOptions calibration;
  calibration.admitCandidates = std::getenv("PA_NO_CANDIDATES") == nullptr;
  calibration.lightsFromLightmaps = std::getenv("PA_NO_LIGHTMAP_LIGHTS") == nullptr;
  if (const char* most = std::getenv("PA_LIGHTMAP_CANDIDATES")) calibration.maxLightmapCandidates = size_t(std::atoi(most));
  calibration.relativeErrors = std::getenv("PA_ABSOLUTE") == nullptr;
  if (const char* sky = std::getenv("PA_CAL_SKY")) calibration.skyLightValue = float(std::atof(sky));
  return calibration;
}

/// A render of `scene` lit by scene.lights (`calibrate` names what they are in PNG file names).
Luminance meanLuminance(const q3::WorldScene& scene, size_t spawn, pa::Integrator integrator, bool calibrate,
                        uint32_t directSpp) {
  pa::Renderer renderer;
  const pa::bridge::WorldHandles handles = pa::bridge::uploadWorld(scene, renderer);
  if (std::getenv("PA_NO_SKY") == nullptr) renderer.setSky(handles.sky);
  renderer.setFogVolumes(handles.fog.volumes);
  renderer.commit();
  const pa::Camera camera = pa::bridge::cameraFromSpawn(scene.cameras[spawn], 16.0f / 9.0f);
  pa::RenderSettings settings;
  settings.width = 320;
  settings.height = 180;
  settings.integrator = integrator;
  settings.samplesPerPixel = integrator == pa::Integrator::Lightmap ? 4 : directSpp;
  settings.maxBounces = 4;
  const pa::FrameView frame = renderer.render(camera, settings);
  std::vector<uint8_t> rgb(frame.radiance.size() * 3);   // display values (clamp look, sRGB)
  size_t black = 0;
  for (size_t i = 0; i < frame.radiance.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float v = std::clamp(frame.radiance[i][c], 0.0f, 1.0f);
      const float srgb = pa::linearToSrgb(v);
      rgb[i * 3 + size_t(c)] = uint8_t(255.0f * srgb + 0.5f);
    }
    const float luma = 0.2126f * rgb[i * 3] + 0.7152f * rgb[i * 3 + 1] + 0.0722f * rgb[i * 3 + 2];
    black += luma < 10.0f ? 1 : 0;   // pa-all-maps' "black" pixel (sky not excluded here)
  }
  if (const char* prefix = std::getenv("PA_PNG")) {
    const char* kind = integrator == pa::Integrator::Lightmap ? "lightmap"
                       : integrator == pa::Integrator::Path   ? "path"
                       : calibrate                            ? "direct"
                                                              : "grid";
    const std::string name = std::string(prefix) + "_s" + std::to_string(spawn) + "_" + kind + ".png";
    if (!stbi_write_png(name.c_str(), int(settings.width), int(settings.height), 3, rgb.data(), int(settings.width) * 3))
      std::fprintf(stderr, "lightmap-match-check: cannot write %s\n", name.c_str());
  }
  Luminance sum;
  for (size_t i = 0; i < frame.radiance.size(); ++i) {
    const glm::vec3 r = frame.radiance[i];
    const glm::vec3 capped = i < frame.albedo.size() ? glm::min(r, frame.albedo[i]) : r;
    sum.plain += 0.2126 * r.r + 0.7152 * r.g + 0.0722 * r.b;
    sum.capped += 0.2126 * capped.r + 0.7152 * capped.g + 0.0722 * capped.b;
  }
  const double n = double(std::max<size_t>(frame.radiance.size(), 1));
  return {sum.plain / n, sum.capped / n, double(black) / n};
}

/// On a map that kept its lights: marks its plain point lights estimated with twice their
/// value and prints how close the calibration brings them back (median and quartiles of
/// fitted / authored).
void recover(const q3::GameWorlds& game, const std::string& map) {
  q3::WorldScene scene = game.load(map);
  std::vector<float> authored;
  for (q3::WorldLight& l : scene.lights)
    if (l.type == q3::WorldLightType::Point && !l.linearFalloff) {
      authored.push_back(l.quakeIntensity);
      l.estimated = true;
      l.quakeIntensity *= 2.0f;
    }
  pa::recovery::LightCalibrationStats stats;
  const std::vector<q3::WorldLight> lights = pa::recovery::calibrateWithShadowRays(scene, scene.lights, {}, {}, &stats);
  std::vector<float> ratios;
  size_t next = 0;
  for (const q3::WorldLight& l : scene.lights) {
    if (!l.estimated) continue;
    const float a = authored[next++];
    bool found = false;
    for (const q3::WorldLight& f : lights)
      if (f.estimated && f.position == l.position) ratios.push_back(f.quakeIntensity / a), found = true;
    if (!found) ratios.push_back(0.0f);
  }
  std::sort(ratios.begin(), ratios.end());
  if (ratios.empty()) return;
  std::printf("%s: %zu lights x2 -> fitted/authored quartiles %.2f %.2f %.2f | texel %.1f direct before %.1f after %.1f constant %.1f\n",
              map.c_str(), ratios.size(), ratios[ratios.size() / 4], ratios[ratios.size() / 2], ratios[ratios.size() * 3 / 4],
              stats.meanTexel, stats.meanBefore, stats.meanAfter, stats.unexplained);
}

void check(const q3::GameWorlds& game, const std::string& map, size_t spawns, uint32_t spp) {
  q3::WorldScene scene = game.load(map);
  if (std::getenv("PA_NO_SUN"))
    std::erase_if(scene.lights, [](const q3::WorldLight& l) { return l.type == q3::WorldLightType::Sun; });
  if (std::getenv("PA_NO_EMITTERS"))
    for (q3::WorldMaterial& m : scene.materials) m.surfaceLight = 0.0f, m.emissiveTexture = -1;
  pa::recovery::RecoveryOptions gridOnly;
  gridOnly.calibrate = false;
  const std::vector<q3::WorldLight> grid = pa::recovery::recoverLights(scene, gridOnly).lights;
  pa::recovery::RecoveryOptions options;
  options.calibration = calibrationFromEnvironment();
  const pa::recovery::RecoveredLights recovered = pa::recovery::recoverLights(scene, options);
  const std::vector<q3::WorldLight>& lights = recovered.lights;
  const pa::recovery::RecoveryStats& found = recovered.stats;
  const pa::recovery::LightCalibrationStats& stats = found.calibration;
  std::printf("%s: %zu lights (%zu estimated, %zu candidates) -> %zu | samples %zu, rays %zu, refitted %zu, dropped %zu, "
              "admitted %zu, in solid %zu | mean texel %.1f, direct before %.1f after %.1f, constant %.1f | %.0f ms\n",
              map.c_str(), found.authored + found.estimated, found.estimated, found.gridCandidates, lights.size(), stats.samples,
              stats.shadowRays, stats.refitted, stats.dropped, stats.admitted, stats.inSolid, stats.meanTexel, stats.meanBefore,
              stats.meanAfter, stats.unexplained, found.milliseconds);
  const glm::vec3 sky = pa::bridge::skyLightingRadiance(scene);
  std::printf("  sky lighting radiance %.3f %.3f %.3f | lightmap peaks %zu, unexplained %zu, candidates %zu, admitted %zu "
              "(%.0f ms of the calibration)\n",
              sky.r, sky.g, sky.b, stats.lightmapPeaks, stats.lightmapUnexplained, stats.lightmapCandidates,
              stats.admittedFromLightmaps, stats.lightmapMs);
  std::printf("  emitter fit: %zu materials fitted, %zu lowered below 0.9\n", found.emitters.groups, found.emitters.lowered);
  for (size_t m = 0; m < recovered.surfaceLightScales.size() && m < scene.materials.size(); ++m)
    if (scene.materials[m].surfaceLight > 0.0f && recovered.surfaceLightScales[m] < 1.0f)
      std::printf("    %-60s q3map_surfacelight %g x %.3f\n", scene.materials[m].shaderName.c_str(), scene.materials[m].surfaceLight,
                  recovered.surfaceLightScales[m]);
  if (std::getenv("PA_LIST_LIGHTS"))
    for (const q3::WorldLight& l : lights)
      std::printf("    %-60s (%.9g %.9g %.9g) value %.9g colour %.9g %.9g %.9g intensity %.9g\n", l.source.c_str(), l.position.x, l.position.y, l.position.z, l.quakeIntensity, l.color.r, l.color.g, l.color.b, l.intensity);
  const std::vector<q3::WorldMaterial> asCompiled = scene.materials;
  q3::WorldScene fitted = scene;
  pa::recovery::applyRecoveredLights(fitted, recovered);
  const std::vector<q3::WorldMaterial> asFitted = fitted.materials;   // emitters at their fitted scales
  for (size_t s = 0; s < std::min(spawns, scene.cameras.size()); ++s) {
    scene.lights = lights;
    scene.materials = asFitted;
    const Luminance lightmap = meanLuminance(scene, s, pa::Integrator::Lightmap, true, spp);
    const double baked = lightmap.plain;
    scene.lights = grid;
    scene.materials = asCompiled;
    const Luminance before = std::getenv("PA_NO_GRID") ? Luminance{NAN, NAN, NAN}
                                                       : meanLuminance(scene, s, pa::Integrator::Direct, false, spp);
    scene.lights = lights;
    scene.materials = asFitted;
    const bool path = std::getenv("PA_PATH") != nullptr;
    const Luminance after = meanLuminance(scene, s, path ? pa::Integrator::Path : pa::Integrator::Direct, true, spp);
    std::printf("  spawn %zu (%s): lightmap %.4f (capped %.4f, black %.0f%%) | direct grid %.4f (x%.2f, capped x%.2f) | %s "
                "calibrated %.4f (x%.2f, capped x%.2f, black %.0f%%)\n",
                s, scene.cameras[s].name.c_str(), baked, lightmap.capped, 100.0 * lightmap.black, before.plain,
                before.plain / baked, before.capped / lightmap.capped, path ? "path" : "direct", after.plain,
                after.plain / baked, after.capped / lightmap.capped, 100.0 * after.black);
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string gameDir = "/usr/share/games/openarena/baseoa";
  size_t spawns = 2;
  uint32_t spp = 16;
  bool recoverMode = false;
  std::vector<std::string> maps;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--game") == 0 && i + 1 < argc) gameDir = argv[++i];
    else if (std::strcmp(argv[i], "--spawns") == 0 && i + 1 < argc) spawns = size_t(std::strtoul(argv[++i], nullptr, 10));
    else if (std::strcmp(argv[i], "--spp") == 0 && i + 1 < argc) spp = uint32_t(std::clamp(std::atoi(argv[++i]), 1, 4096));
    else if (std::strcmp(argv[i], "--recover") == 0) recoverMode = true;
    else if (std::strcmp(argv[i], "--help") == 0) {
      std::printf("usage: %s [--game DIR] [--spawns N] [--spp N] [--recover] MAP...\n", argv[0]);
      return 0;
    } else maps.push_back(argv[i]);
  }
  try {
    q3::GameWorlds game(gameDir);
    for (const std::string& map : maps) {
      try {
        if (recoverMode) recover(game, map);
        else check(game, map, spawns, spp);
      } catch (const std::exception& e) {
        std::printf("%s: ERROR %s\n", map.c_str(), e.what());
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lightmap-match-check: %s\n", e.what());
    return 1;
  }
  return 0;
}
