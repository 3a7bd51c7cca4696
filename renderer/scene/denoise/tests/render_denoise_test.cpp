// RenderSettings::denoise through pa::Renderer: the filtered 1-spp frame has at least 5x less
// squared error than the raw one against 128 spp (measured: 10x),
// accumulation is untouched by it, and it is thread-count independent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "renderer/scene/renderer.h"
#include "renderer/scene/tests/scene_builders.h"

namespace pa {
namespace {

/// A floor and a back wall lit by a soft point light and a sky; with `smallLamp`, a 0.3 x 0.3
/// emissive square (radiance 4) on the wall, about two pixels wide at 64 x 64.
void buildScene(Renderer& r, bool smallLamp = false) {
  const MaterialId grey = r.addMaterial(test::diffuse(0.6f));
  test::addMesh(r, test::quad({-3, -3, 0}, {6, 0, 0}, {0, 6, 0}), grey);
  test::addMesh(r, test::quad({-3, 3, 0}, {6, 0, 0}, {0, 0, 4}), grey);
  LightDesc point;
  point.position = {1.5f, -1, 2.5f};
  point.intensity = 4.0f;
  point.radius = 0.5f;
  r.addLight(point);
  SkyDesc sky;
  sky.color = glm::vec3(0.2f, 0.3f, 0.5f);
  r.setSky(sky);
  if (smallLamp) {
    MaterialDesc lamp = test::diffuse(0.8f);
    lamp.emission = glm::vec3(4.0f);
    test::addMesh(r, test::quad({-0.15f, 2.99f, 0.85f}, {0.3f, 0, 0}, {0, 0, 0.3f}), r.addMaterial(lamp));   // faces -y
  }
  r.commit();
}

Camera camera() { return test::lookAt({0, -6, 2}, {0, 0, 1}, 50.0f); }

std::vector<glm::vec3> render(uint32_t threads, const RenderSettings& settings, uint32_t frames = 1,
                              bool smallLamp = false) {
  Renderer r({threads});
  buildScene(r, smallLamp);
  FrameView f;
  for (uint32_t i = 0; i < frames; ++i) f = r.render(camera(), settings);
  return {f.radiance.begin(), f.radiance.end()};
}

double meanSquaredError(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const glm::vec3 d = a[i] - b[i];
    sum += static_cast<double>(glm::dot(d, d));
  }
  return sum / static_cast<double>(a.size());
}

TEST(RenderDenoise, FilteredFrameIsCloserToTheConvergedImage) {
  RenderSettings s = test::settingsFor(Integrator::Direct, 64, 1, 1);
  const std::vector<glm::vec3> raw = render(2, s);
  s.denoise = true;
  const std::vector<glm::vec3> filtered = render(2, s);
  RenderSettings reference = test::settingsFor(Integrator::Direct, 64, 128, 1);
  const std::vector<glm::vec3> converged = render(2, reference);
  for (const glm::vec3& c : filtered) ASSERT_TRUE(std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b));
  const double before = meanSquaredError(raw, converged);
  const double after = meanSquaredError(filtered, converged);
  EXPECT_LT(after * 5.0, before) << "raw MSE " << before << ", denoised " << after;

}

TEST(RenderDenoise, SmallEmitterKeepsItsRadianceAtOneSpp) {
  // Issue #2 ("an emissive quad measured 0.2 at 1 spp, 3 at 128 spp", denoised): what the
  // camera sees of an emitter is exact in every sample and must not be blurred into the lit wall
  // around it. Its pixels keep the lamp's radiance (4) and change only by the filtered light the
  // lamp's own surface reflects: between 0 and the brightest reflected light of the raw frame.
  constexpr float kLampRadiance = 4.0f;
  RenderSettings s = test::settingsFor(Integrator::Path, 64, 1, 2);
  const std::vector<glm::vec3> raw = render(2, s, 1, true);
  s.denoise = true;
  const std::vector<glm::vec3> filtered = render(2, s, 1, true);
  float brightestReflected = 0.0f;
  for (const glm::vec3& c : raw) {
    if (c.g < kLampRadiance) brightestReflected = std::max(brightestReflected, c.g);
  }
  int lampPixels = 0;
  for (size_t i = 0; i < raw.size(); ++i) {
    if (raw[i].g < kLampRadiance) continue;   // only pixels whose sample hit the lamp
    ++lampPixels;
    EXPECT_GE(filtered[i].g, kLampRadiance * (1.0f - 1e-5f)) << "lamp pixel " << i;
    EXPECT_LE(filtered[i].g, kLampRadiance + brightestReflected) << "lamp pixel " << i;
  }
  EXPECT_GE(lampPixels, 2);
}

TEST(RenderDenoise, AccumulationIgnoresTheFilter) {
  // Two frames, the first shown filtered, equal two raw frames: the filter never feeds back.
  RenderSettings raw = test::settingsFor(Integrator::Path, 32, 1, 2);
  RenderSettings filtered = raw;
  filtered.denoise = true;
  Renderer r({2});
  buildScene(r);
  r.render(camera(), filtered);
  const FrameView f = r.render(camera(), raw);
  ASSERT_EQ(f.accumulatedFrames, 2u);
  const std::vector<glm::vec3> mixed(f.radiance.begin(), f.radiance.end());
  const std::vector<glm::vec3> plain = render(2, raw, 2);
  EXPECT_EQ(0, std::memcmp(mixed.data(), plain.data(), plain.size() * sizeof(glm::vec3)));
}

TEST(RenderDenoise, OneAndTwoThreadsGiveBitIdenticalImages) {
  RenderSettings s = test::settingsFor(Integrator::Path, 40, 1, 2);
  s.denoise = true;
  const std::vector<glm::vec3> one = render(1, s);
  const std::vector<glm::vec3> two = render(2, s);
  EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(glm::vec3)));
}

}  // namespace
}  // namespace pa
