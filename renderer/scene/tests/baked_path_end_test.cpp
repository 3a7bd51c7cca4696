// Known answers of RenderSettings::bakedLightAtPathEnd (integrator/baked_light.h): inside a
// closed box whose walls all carry the same baked light and no light source, every path scatters
// into another wall, so each sample is exact: a path of N scatterings ends on a wall that
// reflects albedo x E, E = baked display value x bakedLightScale, and the camera sees
// albedo^N x albedo x E (no noise, before Russian roulette starts at the third scattering; from the
// first with RenderSettings::rouletteStart 1, where the mean stays that). Without the setting the box is black.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "renderer/core/srgb.h"
#include "renderer/scene/integrator/baked_light.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::lookAt;
using test::settingsFor;

constexpr float kBakedLightScale = 2.0f;

/// A closed 10-unit box around the origin, every wall of `albedo` with baked light: a lightmap of
/// one texel `lightmapBytes` (sRGB flag `srgbLightmap`), or vertex light of linear `vertexLight`
/// when `lightmapBytes` is empty; `stageScale`: a lightmap stage that multiplies by that much
/// (StockLook::lightmapStageScale, part of bakedLightScale).
struct BakedBox {
  Renderer renderer{RendererConfig{2}};
  BakedBox(const glm::vec3& albedo, const std::vector<uint8_t>& lightmapBytes, bool srgbLightmap,
           const glm::vec3& vertexLight = glm::vec3(0.0f), bool mirrorsAboveTheFloor = false,
           float stageScale = 1.0f) {
    MaterialDesc m;
    m.baseColor = glm::vec4(albedo, 1.0f);
    m.stock.bakedLightScale = kBakedLightScale * stageScale;
    m.stock.lightmapStageScale = stageScale;
    if (!lightmapBytes.empty()) {
      m.stock.lightmapTexture = renderer.addTexture(TextureDesc{1, 1, lightmapBytes, srgbLightmap});
    } else {
      m.stock.useVertexLight = true;
    }
    const MaterialId id = renderer.addMaterial(m);
    m.mirror = true;
    const MaterialId mirror = mirrorsAboveTheFloor ? renderer.addMaterial(m) : id;
    const std::vector<glm::vec2> lightmapUvs(4, glm::vec2(0.5f));
    const std::vector<glm::vec4> colors(4, glm::vec4(vertexLight, 1.0f));
    const float h = 5.0f;
    const std::vector<test::MeshArrays> walls = {
        test::quad({-h, -h, -h}, {2 * h, 0, 0}, {0, 2 * h, 0}), test::quad({-h, -h, h}, {2 * h, 0, 0}, {0, 2 * h, 0}),
        test::quad({-h, -h, -h}, {2 * h, 0, 0}, {0, 0, 2 * h}), test::quad({-h, h, -h}, {2 * h, 0, 0}, {0, 0, 2 * h}),
        test::quad({-h, -h, -h}, {0, 2 * h, 0}, {0, 0, 2 * h}), test::quad({h, -h, -h}, {0, 2 * h, 0}, {0, 0, 2 * h})};
    for (size_t i = 0; i < walls.size(); ++i) {
      test::MeshArrays wall = walls[i];
      wall.setMaterial(i == 0 ? id : mirror);   // walls[0] is the floor
      if (lightmapBytes.empty()) wall.colors = colors;   // vertex light (else they would tint the base)
      MeshDesc desc = wall.desc();
      desc.lightmapUvs = lightmapUvs;
      renderer.addInstance({renderer.addMesh(desc)});
    }
    renderer.commit();
  }
  /// Every pixel of an 8x8 view of the floor from the box's centre, 4 samples each.
  FrameView render(Integrator integrator, uint32_t maxBounces, bool bakedEnd, uint32_t rouletteStart = 3,
                   uint32_t spp = 4) {
    RenderSettings s = settingsFor(integrator, 8, spp, maxBounces);
    s.bakedLightAtPathEnd = bakedEnd;
    s.rouletteStart = rouletteStart;
    return renderer.render(lookAt({0, 0, 0}, {0, 0, -5}, 60.0f), s);
  }
};

void expectEveryPixel(const FrameView& f, const glm::vec3& expected) {
  for (const glm::vec3& p : f.radiance) {
    EXPECT_NEAR(p.r, expected.r, 1e-4f * (1.0f + expected.r));
    EXPECT_NEAR(p.g, expected.g, 1e-4f * (1.0f + expected.g));
    EXPECT_NEAR(p.b, expected.b, 1e-4f * (1.0f + expected.b));
  }
}

TEST(BakedPathEnd, TheLastBounceReflectsTheLightmapTimesItsScale) {
  const glm::vec3 albedo(0.5f, 0.8f, 0.25f);
  // An sRGB lightmap is read as stored: E = byte / 255 x scale, not decoded.
  BakedBox box(albedo, test::solidPixels(1, 1, 51, 102, 204, 255), true);
  const glm::vec3 e = glm::vec3(51, 102, 204) / 255.0f * kBakedLightScale;
  for (Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    SCOPED_TRACE(integrator == Integrator::Direct ? "direct" : "path");
    expectEveryPixel(box.render(integrator, 1, true), albedo * albedo * e);
    expectEveryPixel(box.render(integrator, 1, false), glm::vec3(0.0f));
  }
}

TEST(BakedPathEnd, ADoublingLightmapStageBrightensTheBaseColourNotTheBake) {
  // Stock shows min(1, 2 x base x lightmap) in display values: Direct and Path show the base
  // colour twice as bright in display values (clamped at white) under the light the bake holds.
  const glm::vec3 albedo(0.05f, 0.3f, 0.8f);
  BakedBox box(albedo, test::solidPixels(1, 1, 51, 102, 204, 255), true, glm::vec3(0.0f), false, 2.0f);
  const glm::vec3 e = glm::vec3(51, 102, 204) / 255.0f * kBakedLightScale;
  glm::vec3 brighter;
  for (int k = 0; k < 3; ++k) brighter[k] = srgbToLinear(std::min(1.0f, 2.0f * linearToSrgb(albedo[k])));
  EXPECT_NEAR(brighter.b, 1.0f, 1e-6f);   // 0.8 doubled in display values clamps at white
  EXPECT_GT(brighter.r, 4.0f * albedo.r);  // about 2^2.2 times the linear value below the clamp
  for (Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    SCOPED_TRACE(integrator == Integrator::Direct ? "direct" : "path");
    expectEveryPixel(box.render(integrator, 1, true), brighter * brighter * e);
  }
}

TEST(BakedPathEnd, OnlyThePathsLastVertexTakesTheBake) {
  const glm::vec3 albedo(0.6f);
  BakedBox box(albedo, test::solidPixels(1, 1, 128, 128, 128, 255), true);
  const glm::vec3 e = glm::vec3(128.0f / 255.0f * kBakedLightScale);
  expectEveryPixel(box.render(Integrator::Path, 2, true), albedo * albedo * albedo * e);
  // No scattering, no bake: the camera's own hit shows only what it emits.
  expectEveryPixel(box.render(Integrator::Path, 0, true), glm::vec3(0.0f));
}

TEST(BakedPathEnd, RouletteFromTheFirstBounceKeepsTheMean) {
  // RenderSettings::rouletteStart 1: the bounce ray leaves the grey floor with probability 0.6
  // (its albedo) and brings back 1 / 0.6 of the bake's light, so samples are 0 or
  // albedo^2 E / 0.6: the pixels differ, their mean is albedo^2 E.
  const glm::vec3 albedo(0.6f);
  BakedBox box(albedo, test::solidPixels(1, 1, 128, 128, 128, 255), true);
  const double exact = 0.6 * 0.6 * 128.0 / 255.0 * kBakedLightScale;
  for (Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    SCOPED_TRACE(integrator == Integrator::Direct ? "direct" : "path");
    const test::FrameStats st = test::greyStats(box.render(integrator, 1, true, 1, 64));
    EXPECT_GT(st.standardError, 0.0);
    EXPECT_LT(st.minValue, exact * 0.99);   // some pixel lost more of its bounces than it kept
    EXPECT_GT(st.maxValue, exact * 1.01);
    EXPECT_NEAR(st.mean, exact, 4.0 * st.standardError + 1e-5);
    EXPECT_NEAR(st.mean, exact, 0.05 * exact);
  }
  // From the third scattering on (the default) the single bounce is never cut.
  expectEveryPixel(box.render(Integrator::Direct, 1, true, 3), glm::vec3(float(exact)));
}

TEST(BakedPathEnd, AMirrorAtThePathsEndTakesNoBake) {
  // The floor scatters once, then every path ends on a mirror: it reflects what lies beyond it,
  // which the ended path does not trace, so nothing comes back.
  BakedBox box(glm::vec3(0.6f), test::solidPixels(1, 1, 128, 128, 128, 255), true, glm::vec3(0.0f), true);
  expectEveryPixel(box.render(Integrator::Path, 1, true), glm::vec3(0.0f));
}

TEST(BakedPathEnd, LinearLightmapsAndVertexLightAreEncodedAsTheLightmapPresetShowsThem) {
  const glm::vec3 albedo(0.5f);
  BakedBox linearLightmap(albedo, test::solidPixels(1, 1, 102, 102, 102, 255), false);   // data: linear 0.4
  expectEveryPixel(linearLightmap.render(Integrator::Path, 1, true),
                   albedo * albedo * glm::vec3(linearToSrgb(0.4f) * kBakedLightScale));
  BakedBox vertexLit(albedo, {}, false, glm::vec3(0.2f, 0.4f, 0.1f));
  const glm::vec3 e = glm::vec3(linearToSrgb(0.2f), linearToSrgb(0.4f), linearToSrgb(0.1f)) * kBakedLightScale;
  expectEveryPixel(vertexLit.render(Integrator::Path, 1, true), albedo * albedo * e);
}

TEST(BakedPathEnd, EmittersAndSurfacesWithoutBakeHaveNone) {
  MaterialRecord plain;
  SurfaceHit s;
  s.material = &plain;
  glm::vec3 light(-1.0f);
  EXPECT_FALSE(bakedLightAt(s, light));
  MaterialRecord emitter;
  emitter.desc.stock.useVertexLight = true;
  emitter.emits = true;
  s.material = &emitter;
  EXPECT_FALSE(bakedLightAt(s, light));
  emitter.emits = false;
  s.vertexColor = glm::vec4(1.0f);
  ASSERT_TRUE(bakedLightAt(s, light));
  EXPECT_NEAR(light.g, 1.0f, 1e-6f);
}

TEST(BakedPathEnd, TogglingItStartsTheAccumulationAgain) {
  BakedBox box(glm::vec3(0.5f), test::solidPixels(1, 1, 128, 128, 128, 255), true);
  RenderSettings s = settingsFor(Integrator::Path, 8, 1, 1);
  s.accumulate = true;
  const Camera camera = lookAt({0, 0, 0}, {0, 0, -5}, 60.0f);
  box.renderer.render(camera, s);
  EXPECT_EQ(box.renderer.render(camera, s).accumulatedFrames, 2u);
  s.bakedLightAtPathEnd = true;
  EXPECT_EQ(box.renderer.render(camera, s).accumulatedFrames, 1u);
}

}  // namespace
}  // namespace pa
