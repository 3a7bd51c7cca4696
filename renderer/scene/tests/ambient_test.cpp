// Known answers of the scene's ambient terms (SkyDesc::ambientRadiance / minimumRadiance,
// lights/ambient.h): with no light at all a diffuse surface shows exactly albedo x ambient; the
// floor lifts a point light's exact (delta, noise-free) estimate only where it is below it.
#include <gtest/gtest.h>

#include <limits>
#include <numbers>

#include "renderer/scene/lights/ambient.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::lookAt;
using test::settingsFor;

constexpr float kPi = std::numbers::pi_v<float>;

/// Large floor quad at z = 0 and a camera 1 unit above looking straight down (1 degree view).
struct AmbientFloor {
  Renderer renderer{RendererConfig{2}};
  test::MeshArrays floor = test::quad({-50, -50, 0}, {100, 0, 0}, {0, 100, 0});
  explicit AmbientFloor(const MaterialDesc& material) {
    floor.setMaterial(renderer.addMaterial(material));
    renderer.addInstance({renderer.addMesh(floor.desc())});
  }
  void setAmbient(const glm::vec3& radiance, const glm::vec3& minimum) {
    SkyDesc sky;   // black: the sky lights nothing
    sky.ambientRadiance = radiance;
    sky.minimumRadiance = minimum;
    renderer.setSky(sky);
  }
  /// Every pixel's radiance must equal `expected` per channel within `relative` (float rounding;
  /// a point light's pixels off the foot point differ by ~4e-5 in a 1 degree view).
  void expectEveryPixel(Integrator integrator, uint32_t maxBounces, const glm::vec3& expected,
                        float relative = 1e-5f) {
    renderer.commit();
    const FrameView f = renderer.render(lookAt({0, 0, 1}, {0, 0, 0}, 1.0f), settingsFor(integrator, 4, 4, maxBounces));
    for (const glm::vec3& p : f.radiance) {
      EXPECT_NEAR(p.r, expected.r, relative * (1.0f + expected.r));
      EXPECT_NEAR(p.g, expected.g, relative * (1.0f + expected.g));
      EXPECT_NEAR(p.b, expected.b, relative * (1.0f + expected.b));
    }
  }
};

MaterialDesc colouredDiffuse(const glm::vec3& albedo) {
  MaterialDesc m;
  m.baseColor = glm::vec4(albedo, 1.0f);
  return m;
}

TEST(Ambient, ApplyAddsTheAmbientAndLiftsToTheFloorPerChannel) {
  const AmbientLight ambient{{0.1f, 0.0f, 0.2f}, {0.5f, 0.5f, 0.0f}};
  EXPECT_TRUE(ambient.active());
  EXPECT_FALSE(AmbientLight{}.active());
  const glm::vec3 out = ambient.apply({0.3f, 0.1f, 0.05f}, {0.8f, 0.8f, 0.5f});
  EXPECT_FLOAT_EQ(out.r, 0.4f);    // max(0.3 + 0.08, 0.4)
  EXPECT_FLOAT_EQ(out.g, 0.4f);    // max(0.1 + 0, 0.4): the floor
  EXPECT_FLOAT_EQ(out.b, 0.15f);   // max(0.05 + 0.1, 0): the ambient added
}

TEST(Ambient, WhiteDiffusePlaneWithoutLightsShowsAlbedoTimesAmbient) {
  const glm::vec3 ambient(0.2f, 0.3f, 0.4f);
  for (float albedo : {1.0f, 0.6f}) {
    AmbientFloor s(test::diffuse(albedo));
    s.setAmbient(ambient, glm::vec3(0.0f));
    s.expectEveryPixel(Integrator::Direct, 1, albedo * ambient);
    // Path: the bounce rays of an open plane leave to a black sky, nothing more arrives.
    s.expectEveryPixel(Integrator::Path, 4, albedo * ambient);
  }
}

TEST(Ambient, FloorAloneWithoutLightsIsAlbedoTimesMinimum) {
  AmbientFloor s(colouredDiffuse({0.5f, 0.25f, 1.0f}));
  s.setAmbient(glm::vec3(0.0f), {0.4f, 0.4f, 0.1f});
  s.expectEveryPixel(Integrator::Direct, 1, {0.2f, 0.1f, 0.1f});
}

TEST(Ambient, FloorLiftsOnlyWhatAPointLightLeavesBelowIt) {
  // Point light of intensity 10 at height 2 over albedo 0.6: L = 0.6 / pi * 10 / 4 = 0.477.
  AmbientFloor s(test::diffuse(0.6f));
  LightDesc light;
  light.position = {0, 0, 2.0f};
  light.intensity = 10.0f;
  s.renderer.addLight(light);
  const float lit = 0.6f / kPi * 10.0f / 4.0f;
  s.setAmbient(glm::vec3(0.0f), glm::vec3(0.5f));   // floor 0.3 < lit
  s.expectEveryPixel(Integrator::Direct, 1, glm::vec3(lit), 1e-4f);
  s.setAmbient(glm::vec3(0.0f), glm::vec3(1.0f));   // floor 0.6 > lit
  s.expectEveryPixel(Integrator::Direct, 1, glm::vec3(0.6f));
  s.setAmbient(glm::vec3(0.25f), glm::vec3(1.0f));  // lit + 0.15 = 0.627 > floor 0.6
  s.expectEveryPixel(Integrator::Direct, 1, glm::vec3(lit + 0.15f), 1e-4f);
}

TEST(Ambient, GlossyLobeKeepsOnlyTheDiffuseShare) {
  MaterialDesc shiny = test::diffuse(0.8f);
  shiny.specular = 0.25f;
  AmbientFloor s(shiny);
  s.setAmbient(glm::vec3(0.5f), glm::vec3(0.0f));
  s.expectEveryPixel(Integrator::Direct, 1, glm::vec3(0.75f * 0.8f * 0.5f));
}

TEST(Ambient, LightmapPresetIgnoresIt) {
  AmbientFloor s(test::diffuse(0.6f));   // no lightmap: fullbright, the albedo
  s.setAmbient(glm::vec3(0.3f), glm::vec3(2.0f));
  s.renderer.commit();
  const FrameView f =
      s.renderer.render(lookAt({0, 0, 1}, {0, 0, 0}, 1.0f), settingsFor(Integrator::Lightmap, 4, 1));
  s.setAmbient(glm::vec3(0.0f), glm::vec3(0.0f));
  s.renderer.commit();
  const glm::vec3 withAmbient = f.radiance[0];
  const FrameView g =
      s.renderer.render(lookAt({0, 0, 1}, {0, 0, 0}, 1.0f), settingsFor(Integrator::Lightmap, 4, 1));
  EXPECT_EQ(withAmbient, g.radiance[0]);
}

TEST(Ambient, NegativeOrNonFiniteValuesAreRejected) {
  Renderer r(RendererConfig{1});
  SkyDesc sky;
  sky.ambientRadiance = {0.1f, -0.1f, 0.0f};
  EXPECT_THROW(r.setSky(sky), SceneError);
  sky.ambientRadiance = glm::vec3(0.0f);
  sky.minimumRadiance = {std::numeric_limits<float>::infinity(), 0.0f, 0.0f};
  EXPECT_THROW(r.setSky(sky), SceneError);
}

}  // namespace
}  // namespace pa
