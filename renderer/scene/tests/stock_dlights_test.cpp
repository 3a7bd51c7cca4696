// Known answers of the stock dynamic-light pass (lights/stock_dlights.h): the falloff blob, the
// height modulation, the passes clamped one after the other, and the Lightmap look's lit floor
// multiplied by one plus the light where its material takes dynamic lights.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <vector>

#include "renderer/core/srgb.h"
#include "renderer/scene/lights/stock_dlights.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::lookAt;
using test::settingsFor;

TEST(StockDlights, BlobIsFullInTheMiddleAndZeroAtTheRim) {
  EXPECT_FLOAT_EQ(stockDlightBlob({0.5f, 0.5f}), 1.0f);
  EXPECT_FLOAT_EQ(stockDlightBlob({0.0f, 0.0f}), 0.0f);
  EXPECT_FLOAT_EQ(stockDlightBlob({1.0f, 0.5f}), 0.0f);
  EXPECT_GT(stockDlightBlob({0.75f, 0.5f}), 0.3f);   // 4 texels out: 4000 / 12.25 -> 255
  EXPECT_EQ(stockDlightBlob({std::numeric_limits<float>::quiet_NaN(), 0.5f}), 0.0f);
}

TEST(StockDlights, LightIsModulatedByHeightAndOnlyLightsTheFront) {
  const StockDynamicLight light{{0, 0, 100}, 300, {1, 1, 0}};
  const glm::vec3 up(0, 0, 1);
  EXPECT_EQ(stockDlightAt(light, {0, 0, 0}, up), glm::vec3(1, 1, 0));
  EXPECT_EQ(stockDlightAt(light, {0, 0, 0}, -up), glm::vec3(0));        // behind the surface
  // 225 below the light: modulate 2 * (300 - 225) / 300 = 0.5 (bytes truncated).
  EXPECT_NEAR(stockDlightAt(light, {0, 0, -125}, up).r, 127.0f / 255.0f, 1e-6f);
  EXPECT_EQ(stockDlightAt(light, {0, 0, -250}, up), glm::vec3(0));      // out of reach in height
  EXPECT_EQ(stockDlightAt({{0, 0, 100}, 0, {1, 1, 1}}, {0, 0, 0}, up), glm::vec3(0));   // no reach
}

TEST(StockDlights, EachPassMultipliesAndClampsInTurn) {
  const StockDynamicLight red{{0, 0, 40}, 400, {1, 0, 0}};
  const glm::vec3 up(0, 0, 1);
  const StockDynamicLight two[2] = {red, red};
  // dst x (1 + 1), twice: 0.2 -> 0.4 -> 0.8; 0.3 -> 0.6 -> 1 (clamped after the second pass).
  EXPECT_NEAR(stockDlightsOver(two, {0, 0, 0}, up, glm::vec3(0.2f, 0.5f, 0.0f)).r, 0.8f, 1e-6f);
  EXPECT_NEAR(stockDlightsOver(two, {0, 0, 0}, up, glm::vec3(0.3f, 0.5f, 0.0f)).r, 1.0f, 1e-6f);
  EXPECT_EQ(stockDlightsOver(two, {0, 0, 0}, up, glm::vec3(0.3f, 0.5f, 0.0f)).g, 0.5f);   // no green light
  EXPECT_EQ(stockDlightsOver({}, {0, 0, 0}, up, glm::vec3(0.3f)), glm::vec3(0.3f));
}

/// The centre pixel's display value of a lit 10x10 floor at z = 0 (white base x a lightmap of
/// stored 0.4) seen from 2 above, under a red light 1 unit above its centre.
glm::vec3 litFloorCentre(bool takesDynamicLights, bool withLight, Integrator integrator = Integrator::Lightmap) {
  Renderer r({2});
  MaterialDesc m = test::diffuse(1.0f);
  m.stock.lightmapTexture = r.addTexture(TextureDesc{1, 1, test::solidPixels(1, 1, 102, 102, 102, 255), true});
  m.stock.takesDynamicLights = takesDynamicLights;
  test::addLightmappedFloor(r, m);
  const StockDynamicLight red{{0, 0, 1}, 200, {1, 0, 0}};
  if (withLight) r.setStockDynamicLights(std::span(&red, 1));
  r.commit();
  const FrameView f = r.render(lookAt({0, 0, 2}, {0, 0, 0}, 30.0f), settingsFor(integrator, 5, 1));
  const glm::vec3 c = f.radiance[12];
  return {linearToSrgb(c.r), linearToSrgb(c.g), linearToSrgb(c.b)};
}

TEST(StockDlights, TheLightmapLookMultipliesTheLitSurfaceByOnePlusTheLight) {
  const float lit = 102.0f / 255.0f;
  const glm::vec3 plain = litFloorCentre(false, true);
  EXPECT_NEAR(plain.r, lit, 2e-3f);   // a material that takes no dynamic light
  EXPECT_NEAR(litFloorCentre(true, false).r, lit, 2e-3f);   // no light
  const glm::vec3 lightened = litFloorCentre(true, true);
  EXPECT_NEAR(lightened.r, 2.0f * lit, 2e-3f);   // within the blob's full middle: dst x (1 + 1)
  EXPECT_NEAR(lightened.g, lit, 2e-3f);
  // Direct takes them as nothing (it lights with point lights).
  EXPECT_EQ(litFloorCentre(true, true, Integrator::Direct), litFloorCentre(true, false, Integrator::Direct));
}

TEST(StockDlights, BadLightsAreRefused) {
  Renderer r({1});
  const StockDynamicLight bad{{0, 0, std::numeric_limits<float>::infinity()}, 100, {1, 1, 1}};
  EXPECT_THROW(r.setStockDynamicLights(std::span(&bad, 1)), SceneError);
  const std::vector<StockDynamicLight> many(kMaxStockDynamicLights + 1);
  EXPECT_THROW(r.setStockDynamicLights(many), SceneError);
}

}  // namespace
}  // namespace pa
