// light-estimate-check: validates the light-grid light estimator on maps that kept their
// `light` entities. Hides the entity lights, estimates lights from the grid, and compares:
// positions and light values against the real lights, and (with --render) the mean luminance
// of Direct renders (real lights, estimated lights) against the Lightmap render.
//
//   light-estimate-check [--game DIR] [--render] [MAP...]     (default: every map of the game)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "port/q3formats/world/world_game.h"
#include "port/light_recovery/grid_estimate.h"
#include "port/scene_bridge/scene_bridge.h"

namespace {

double meanLuminance(const q3::WorldScene& scene, pa::Integrator integrator) {
  pa::Renderer renderer;
  pa::bridge::showSkyAndFog(pa::bridge::uploadWorld(scene, renderer), renderer);
  renderer.commit();
  const pa::Camera camera = pa::bridge::cameraFromSpawn(scene.cameras.front(), 16.0f / 9.0f);
  pa::RenderSettings settings;
  settings.width = 128;
  settings.height = 72;
  settings.integrator = integrator;
  settings.samplesPerPixel = integrator == pa::Integrator::Lightmap ? 4 : 16;
  settings.maxBounces = 1;
  const pa::FrameView frame = renderer.render(camera, settings);
  double sum = 0.0;
  for (const glm::vec3& r : frame.radiance) sum += 0.2126 * r.r + 0.7152 * r.g + 0.0722 * r.b;
  return sum / double(frame.radiance.size());
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

void check(const q3::GameWorlds& game, const std::string& map, bool render) {
  q3::WorldScene scene = game.load(map);
  std::vector<q3::WorldLight> real, others;
  for (const q3::WorldLight& l : scene.lights) (l.type == q3::WorldLightType::Sun ? others : real).push_back(l);
  q3::WorldScene hidden = scene;
  hidden.lights = others;
  const auto t0 = std::chrono::steady_clock::now();
  pa::recovery::LightEstimateStats stats;
  std::vector<q3::WorldLight> estimated = pa::recovery::estimateLightsFromGrid(hidden.lightGrid, pa::recovery::knownLightingOf(hidden), {}, &stats);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  // A real light is found when an estimate lies within 64 units; value ratio estimate / real
  // (real lights closer than 64 units to each other are summed: the grid cannot tell them apart).
  constexpr float kMatch = 64.0f;
  std::vector<double> errors, ratios;
  size_t found = 0;
  double realPower = 0.0, foundPower = 0.0;
  for (const q3::WorldLight& r : real) {
    realPower += r.quakeIntensity;
    const q3::WorldLight* best = nullptr;
    for (const q3::WorldLight& e : estimated)
      if (!best || glm::length(e.position - r.position) < glm::length(best->position - r.position)) best = &e;
    if (!best || glm::length(best->position - r.position) > kMatch) continue;
    ++found;
    foundPower += r.quakeIntensity;
    double cluster = 0.0;
    for (const q3::WorldLight& o : real)
      if (glm::length(o.position - r.position) < kMatch) cluster += o.quakeIntensity;
    errors.push_back(glm::length(best->position - r.position));
    ratios.push_back(best->quakeIntensity / cluster);
  }
  size_t precise = 0;
  for (const q3::WorldLight& e : estimated)
    for (const q3::WorldLight& r : real)
      if (glm::length(e.position - r.position) <= kMatch) {
        ++precise;
        break;
      }
  std::printf("%-28s grid %7zu lines %6zu peaks %6zu real %4zu est %4zu | found %4zu (%5.1f%% of light value) "
              "precision %5.1f%% | pos err median %5.1f | value ratio median %5.2f | %6.1f ms",
              map.c_str(), stats.gridPoints, stats.votingLines, stats.peaks, real.size(), estimated.size(), found,
              realPower > 0 ? 100.0 * foundPower / realPower : 0.0,
              estimated.empty() ? 0.0 : 100.0 * double(precise) / double(estimated.size()), median(errors),
              median(ratios), ms);
  if (render && !scene.cameras.empty()) {
    const double baked = meanLuminance(scene, pa::Integrator::Lightmap);
    const double directReal = meanLuminance(scene, pa::Integrator::Direct);
    hidden.lights.insert(hidden.lights.end(), estimated.begin(), estimated.end());
    const double directEstimated = meanLuminance(hidden, pa::Integrator::Direct);
    std::printf(" | mean lum: lightmap %.4f direct(real) %.4f direct(estimated) %.4f", baked, directReal,
                directEstimated);
  }
  std::printf("\n");
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  std::string gameDir = "/usr/share/games/openarena/baseoa";
  bool render = false;
  std::vector<std::string> maps;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--game") == 0 && i + 1 < argc) gameDir = argv[++i];
    else if (std::strcmp(argv[i], "--render") == 0) render = true;
    else if (std::strcmp(argv[i], "--help") == 0) {
      std::printf("usage: %s [--game DIR] [--render] [MAP...]\n", argv[0]);
      return 0;
    } else maps.push_back(argv[i]);
  }
  try {
    q3::GameWorlds game(gameDir);
    if (maps.empty()) maps = game.maps();
    for (const std::string& map : maps) {
      try {
        check(game, map, render);
      } catch (const std::exception& e) {
        std::printf("%-28s ERROR %s\n", map.c_str(), e.what());
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "light-estimate-check: %s\n", e.what());
    return 1;
  }
  return 0;
}
