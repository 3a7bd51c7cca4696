// Known-answer tests of the integrators on analytic scenes. Noise bounds: the image mean is
// compared with the exact value within 4 standard errors, the standard error coming from the
// film's per-pixel Welford variances (plus a small absolute slack for float rounding).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include <glm/common.hpp>

#include "renderer/scene/textures/texture.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::addLightmappedFloor;
using test::greyStats;
using test::lookAt;
using test::settingsFor;

constexpr float kPi = std::numbers::pi_v<float>;

void expectMean(const FrameView& f, double expected, double relativeSlack = 1e-4) {
  const test::FrameStats s = greyStats(f);
  const double bound = 4.0 * s.standardError + relativeSlack * expected;
  EXPECT_NEAR(s.mean, expected, bound) << "standard error " << s.standardError;
}

/// Convex flat-faceted sphere (albedo a) filling the view under a uniform sky L: every facet
/// sees the whole sky hemisphere unoccluded, so its radiance is exactly a * L.
void renderDiffuseSphere(Integrator integrator, float albedo, uint32_t maxBounces) {
  Renderer r({2});
  const MaterialId mat = r.addMaterial(test::diffuse(albedo));
  test::MeshArrays s = test::sphere({0, 0, 0}, 1.0f);
  s.setMaterial(mat);
  r.addInstance({r.addMesh(s.desc())});
  SkyDesc sky;
  sky.color = glm::vec3(0.8f);
  r.setSky(sky);
  r.commit();
  const Camera cam = lookAt({3.0f, 0.2f, 0.3f}, {0, 0, 0}, 15.0f);   // view entirely inside the silhouette
  const FrameView f = r.render(cam, settingsFor(integrator, 16, 8, maxBounces));
  const test::FrameStats st = greyStats(f);
  // NEE (cosine sky sampling) and BSDF sampling share the estimate 50/50: zero variance.
  EXPECT_NEAR(st.minValue, albedo * 0.8, 1e-4);
  EXPECT_NEAR(st.maxValue, albedo * 0.8, 1e-4);
  for (float d : f.depth) EXPECT_TRUE(std::isfinite(d));
}

TEST(KnownAnswer, DiffuseSphereUnderUniformSkyDirect) { renderDiffuseSphere(Integrator::Direct, 0.5f, 1); }
TEST(KnownAnswer, DiffuseSphereUnderUniformSkyPath) { renderDiffuseSphere(Integrator::Path, 0.5f, 8); }
TEST(KnownAnswer, WhiteFurnaceConvexSphereIsInvisible) { renderDiffuseSphere(Integrator::Path, 1.0f, 8); }

/// SkyDesc::lightingScale k: the sphere is lit by k * L, the sky seen past it stays L.
void renderSkyLightingScale(Integrator integrator, float lightingScale) {
  Renderer r({2});
  test::MeshArrays s = test::sphere({0, 0, 0}, 1.0f);
  s.setMaterial(r.addMaterial(test::diffuse(0.5f)));
  r.addInstance({r.addMesh(s.desc())});
  SkyDesc sky;
  sky.color = glm::vec3(0.8f);
  sky.lightingScale = lightingScale;
  r.setSky(sky);
  r.commit();
  const test::FrameStats lit =
      greyStats(r.render(lookAt({3.0f, 0.2f, 0.3f}, {0, 0, 0}, 15.0f), settingsFor(integrator, 16, 8, 8)));
  EXPECT_NEAR(lit.minValue, 0.5 * 0.8 * lightingScale, 1e-4);
  EXPECT_NEAR(lit.maxValue, 0.5 * 0.8 * lightingScale, 1e-4);
  const test::FrameStats seen =
      greyStats(r.render(lookAt({3.0f, 0.2f, 0.3f}, {6.0f, 0.2f, 0.3f}, 15.0f), settingsFor(integrator, 16, 8, 8)));
  EXPECT_NEAR(seen.minValue, 0.8, 1e-5);
  EXPECT_NEAR(seen.maxValue, 0.8, 1e-5);
}

TEST(KnownAnswer, SkyLightingScaleBrightensTheLightNotTheLookDirect) { renderSkyLightingScale(Integrator::Direct, 2.5f); }
TEST(KnownAnswer, SkyLightingScaleBrightensTheLightNotTheLookPath) { renderSkyLightingScale(Integrator::Path, 2.5f); }
TEST(KnownAnswer, SkyLightingScaleZeroLightsNothing) { renderSkyLightingScale(Integrator::Path, 0.0f); }

TEST(KnownAnswer, WhiteFurnaceOpenBoxNeedsManyBounces) {
  // An open box (five quads, albedo 1, two-sided) under a uniform sky L: energy conservation
  // makes every pixel exactly L once all bounces are followed (the box is non-convex).
  Renderer r({2});
  const MaterialId white = r.addMaterial(test::diffuse(1.0f));
  const std::array<test::MeshArrays, 5> walls{
      test::quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}),  test::quad({-1, -1, 0}, {2, 0, 0}, {0, 0, 2}),
      test::quad({-1, 1, 0}, {2, 0, 0}, {0, 0, 2}),   test::quad({-1, -1, 0}, {0, 2, 0}, {0, 0, 2}),
      test::quad({1, -1, 0}, {0, 2, 0}, {0, 0, 2})};
  std::vector<test::MeshArrays> keep(walls.begin(), walls.end());
  for (auto& w : keep) {
    w.setMaterial(white);
    r.addInstance({r.addMesh(w.desc())});
  }
  SkyDesc sky;
  sky.color = glm::vec3(1.0f);
  r.setSky(sky);
  r.commit();
  const Camera cam = lookAt({0.2f, 0.1f, 4.0f}, {0, 0, 0.5f}, 40.0f);
  const FrameView f = r.render(cam, settingsFor(Integrator::Path, 16, 64, 64));
  expectMean(f, 1.0, 2e-3);
}

/// Inside a closed sphere of albedo a emitting E everywhere, L = E + a L, so L = E / (1 - a).
/// Exercises emissive-triangle power sampling, MIS between NEE and BSDF hits, roulette (from the
/// `rouletteStart`-th scattering). Truncation at 40 bounces: 2 * 0.5^41, negligible.
void expectClosedEmissiveSphereFurnace(uint32_t rouletteStart) {
  Renderer r({2});
  MaterialDesc m = test::diffuse(0.5f);
  m.emission = glm::vec3(1.0f);
  const MaterialId mat = r.addMaterial(m);
  test::MeshArrays s = test::sphere({0, 0, 0}, 2.0f, 12, 24);
  s.setMaterial(mat);
  r.addInstance({r.addMesh(s.desc())});
  r.commit();
  const Camera cam = lookAt({0.3f, -0.2f, 0.1f}, {1, 1, 0.5f}, 90.0f);
  RenderSettings settings = settingsFor(Integrator::Path, 16, 32, 40);
  settings.rouletteStart = rouletteStart;
  const FrameView f = r.render(cam, settings);   // a view of r's film: read while r lives
  expectMean(f, 2.0, 1e-3);
  // From the first bounce every bounce ray survives with probability 0.5 (the albedo) and
  // carries twice the light: samples differ.
  if (rouletteStart == 1) {
    EXPECT_GT(greyStats(f).standardError, 0.0);
  }
}

TEST(KnownAnswer, ClosedEmissiveSphereFurnace) { expectClosedEmissiveSphereFurnace(3); }

TEST(KnownAnswer, ClosedEmissiveSphereFurnaceWithRouletteFromTheFirstBounce) { expectClosedEmissiveSphereFurnace(1); }

TEST(KnownAnswer, GlossyClosedSphereKeepsItsMeanWithRouletteFromTheFirstBounce) {
  // The roulette reads the surface's reflectance before a direction is drawn. On a glossy
  // surface that is not the sample's weight (as it is on a diffuse one), and the estimate must
  // stay that of paths followed without roulette.
  const auto render = [](uint32_t rouletteStart) {
    Renderer r({2});
    MaterialDesc m = test::diffuse(0.5f);
    m.emission = glm::vec3(1.0f);
    m.specular = 0.5f;
    m.roughness = 0.4f;
    const MaterialId mat = r.addMaterial(m);
    test::MeshArrays s = test::sphere({0, 0, 0}, 2.0f, 12, 24);
    s.setMaterial(mat);
    r.addInstance({r.addMesh(s.desc())});
    r.commit();
    RenderSettings settings = settingsFor(Integrator::Path, 64, 32, 40);
    settings.rouletteStart = rouletteStart;
    return greyStats(r.render(lookAt({0.3f, -0.2f, 0.1f}, {1, 1, 0.5f}, 90.0f), settings));
  };
  const test::FrameStats without = render(41), first = render(1);
  EXPECT_GT(without.mean, 1.5);   // more than the emission and one bounce of it
  EXPECT_NEAR(first.mean, without.mean, 4.0 * std::hypot(first.standardError, without.standardError) + 1e-3 * without.mean);
  EXPECT_GT(first.standardError, without.standardError);   // roulette ended paths: samples differ more
}

/// Large floor quad at z = 0 (albedo a) and a camera between it and an overhead emitter,
/// looking straight down at the foot point with a 1 degree field of view.
struct FloorScene {
  Renderer renderer{RendererConfig{2}};
  test::MeshArrays floor = test::quad({-50, -50, 0}, {100, 0, 0}, {0, 100, 0});
  explicit FloorScene(float albedo) {
    floor.setMaterial(renderer.addMaterial(test::diffuse(albedo)));
    renderer.addInstance({renderer.addMesh(floor.desc())});
  }
  Camera camera(float height) const { return lookAt({0, 0, height}, {0, 0, 0}, 1.0f); }
};

TEST(KnownAnswer, PointLightInverseSquare) {
  // L = albedo / pi * I / d^2 at the foot of a point light of intensity I (W/sr) at height d.
  FloorScene s(0.6f);
  LightDesc light;
  light.position = {0, 0, 2.0f};
  light.intensity = 10.0f;
  s.renderer.addLight(light);
  s.renderer.commit();
  const double expected = 0.6 / kPi * 10.0 / 4.0;
  for (Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    const FrameView f = s.renderer.render(s.camera(1.0f), settingsFor(integrator, 4, 4, 1));
    const test::FrameStats st = greyStats(f);
    EXPECT_NEAR(st.mean, expected, 1e-3 * expected);
  }
}

TEST(KnownAnswer, SpotAndLinearFalloff) {
  FloorScene s(1.0f);
  LightDesc spot;
  spot.type = LightType::Spot;
  spot.position = {0, 0, 4.0f};
  spot.direction = {0, 0, -1};
  spot.intensity = 16.0f;
  spot.cosInnerAngle = 0.99f;
  spot.cosOuterAngle = 0.9f;
  const LightId id = s.renderer.addLight(spot);
  s.renderer.commit();
  const RenderSettings settings = settingsFor(Integrator::Direct, 4, 1, 1);
  EXPECT_NEAR(greyStats(s.renderer.render(s.camera(1.0f), settings)).mean, 1.0 / kPi * 16.0 / 16.0, 1e-3);
  // Pointing away: the foot is outside the cone.
  spot.direction = {1, 0, 0};
  s.renderer.setLight(id, spot);
  s.renderer.commit();
  EXPECT_EQ(greyStats(s.renderer.render(s.camera(1.0f), settings)).mean, 0.0);
  // Linear falloff: I * (1 - d / range).
  LightDesc linear;
  linear.position = {0, 0, 2.0f};
  linear.intensity = 3.0f;
  linear.falloff = Falloff::Linear;
  linear.range = 8.0f;
  s.renderer.setLight(id, linear);
  s.renderer.commit();
  EXPECT_NEAR(greyStats(s.renderer.render(s.camera(1.0f), settings)).mean, 1.0 / kPi * 3.0 * 0.75, 1e-3);
  // Beyond the range nothing arrives.
  linear.falloff = Falloff::InverseSquare;
  linear.range = 1.5f;
  s.renderer.setLight(id, linear);
  s.renderer.commit();
  EXPECT_EQ(greyStats(s.renderer.render(s.camera(1.0f), settings)).mean, 0.0);
}

TEST(KnownAnswer, DirectionalLightIsIrradiance) {
  FloorScene s(0.5f);
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(1, 0, -1));   // 45 degrees
  sun.intensity = 2.0f;
  s.renderer.addLight(sun);
  s.renderer.commit();
  const FrameView f = s.renderer.render(s.camera(1.0f), settingsFor(Integrator::Path, 4, 1, 1));
  EXPECT_NEAR(greyStats(f).mean, 0.5 / kPi * 2.0 * std::sqrt(0.5), 1e-4);
}

/// On-axis irradiance under a uniform square emitter of half-side a at height h:
/// E = 4 L X / sqrt(1 + X^2) * atan(X / sqrt(1 + X^2)), X = a / h.
double squareIrradiance(double radiance, double halfSide, double height) {
  const double x = halfSide / height;
  const double s = std::sqrt(1.0 + x * x);
  return 4.0 * radiance * x / s * std::atan(x / s);
}

TEST(KnownAnswer, EmissiveSquareOnAxisIrradiance) {
  // Two triangles of different radiance (3 and 1): by symmetry about the diagonal each gives
  // half of the square's irradiance, so E = (3 + 1) / 2 * E_unit. Checks power-proportional
  // triangle selection, area-to-solid-angle pdfs and MIS with BSDF-sampled hits.
  FloorScene s(1.0f);
  MaterialDesc bright, dim;
  bright.emission = glm::vec3(3.0f);
  dim.emission = glm::vec3(1.0f);
  bright.twoSided = dim.twoSided = false;
  const MaterialId b = s.renderer.addMaterial(bright), d = s.renderer.addMaterial(dim);
  // Facing down: cross(u, v) = -z.
  test::MeshArrays light = test::quad({-1, -1, 2}, {0, 2, 0}, {2, 0, 0});
  light.materials = {b, d};
  s.renderer.addInstance({s.renderer.addMesh(light.desc())});
  s.renderer.commit();
  const double expected = squareIrradiance(2.0, 1.0, 2.0) / kPi;   // albedo 1
  for (Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    const FrameView f = s.renderer.render(s.camera(1.0f), settingsFor(integrator, 8, 128, 1));
    expectMean(f, expected, 1e-3);
  }
}

TEST(KnownAnswer, LightmapPresetIsAlbedoTimesBakedLight) {
  Renderer r({2});
  const std::vector<uint8_t> lm = test::solidPixels(2, 2, 51, 102, 204, 255);
  TextureDesc lmDesc{2, 2, lm, false};
  MaterialDesc m = test::diffuse(0.5f);
  m.stock.lightmapTexture = r.addTexture(lmDesc);
  m.emission = glm::vec3(0.25f);
  addLightmappedFloor(r, m);
  const FrameView f = r.render(lookAt({0, 0, 2}, {0, 0, 0}, 30.0f), settingsFor(Integrator::Lightmap, 4, 1));
  // Emission (a glow stage) adds to the lit texture in display values, as framebuffer blending does.
  const auto displaySum = [](float a, float b) {
    return srgbToLinear(std::min(1.0f, linearToSrgb(a) + linearToSrgb(b)));
  };
  // Texture x lightmap multiply display values too (the stock 8-bit multiply).
  const auto displayProduct = [](float a, float b) { return srgbToLinear(linearToSrgb(a) * linearToSrgb(b)); };
  EXPECT_NEAR(f.radiance[5].r, displaySum(displayProduct(0.5f, 0.2f), 0.25f), 1e-5f);
  EXPECT_NEAR(f.radiance[5].g, displaySum(displayProduct(0.5f, 0.4f), 0.25f), 1e-5f);
  EXPECT_NEAR(f.radiance[5].b, 1.0f, 1e-5f);   // encoded 0.74 * 0.91 + 0.54: white
  EXPECT_NEAR(f.albedo[5].g, 0.5f, 1e-6f);
  EXPECT_NEAR(f.depth[5], 2.0f, 0.05f);   // jittered rays near the centre: 2 / cos
  EXPECT_NEAR(f.normal[5].z, 1.0f, 1e-5f);
}

/// Lightmap preset over a quad of white base (alpha baseAlpha) under a lightmap of linear 0.4,
/// with a shine texture of display (0.3, 0.75, 0.5): the centre pixel's display value.
glm::vec3 shineOverLitBase(LayerBlend blend, float baseAlpha, bool masked, Integrator integrator = Integrator::Lightmap) {
  Renderer r({2});
  const std::vector<uint8_t> lm = test::solidPixels(1, 1, 102, 102, 102, 255);   // linear 0.4 (data)
  const std::vector<uint8_t> shine = test::solidPixels(1, 1, 77, 191, 128, 255);   // ~ (0.3, 0.75, 0.5)
  MaterialDesc m = test::diffuse(1.0f);
  m.baseColor.a = baseAlpha;
  m.stock.lightmapTexture = r.addTexture(TextureDesc{1, 1, lm, false});
  m.stock.shineTexture = r.addTexture(TextureDesc{1, 1, shine, true});
  m.stock.shineBlend = blend;
  m.stock.shineMaskedByBaseAlpha = masked;
  addLightmappedFloor(r, m);
  const FrameView f = r.render(lookAt({0, 0, 2}, {0, 0, 0}, 30.0f), settingsFor(integrator, 4, 1));
  const glm::vec3 c = f.radiance[5];
  return {linearToSrgb(c.r), linearToSrgb(c.g), linearToSrgb(c.b)};
}

TEST(KnownAnswer, LightmapPresetComposesTheShineInDisplayValues) {
  const glm::vec3 src(77 / 255.0f, 191 / 255.0f, 128 / 255.0f);
  const float base = linearToSrgb(102 / 255.0f);   // white x lightmap, displayed
  // blendfunc add: base + shine (per channel, clamped).
  const glm::vec3 add = shineOverLitBase(LayerBlend::Add, 1.0f, false);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(add[c], std::min(1.0f, base + src[c]), 2e-3f) << c;
  // gl_dst_color gl_src_color: 2 base shine.
  const glm::vec3 filter = shineOverLitBase(LayerBlend::Modulate2x, 1.0f, false);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(filter[c], 2.0f * base * src[c], 2e-3f) << c;
  // The base redrawn over the shine with alpha 0.75 leaves a quarter of the added shine.
  const glm::vec3 masked = shineOverLitBase(LayerBlend::Add, 0.75f, true);
  EXPECT_NEAR(masked.x, base + 0.25f * src.x, 2e-3f);
  // Direct preset: no lights, no sky: the shine is no light source (it is the glossy lobe's job).
  EXPECT_NEAR(shineOverLitBase(LayerBlend::Add, 1.0f, false, Integrator::Direct).x, 0.0f, 1e-6f);
}

/// A lightmapped floor whose base (display (200, 100, 50)) is covered by an image of display
/// (20, 220, 120) and alpha 64 / 255 (MaterialDesc::coverTexture), its corners' colours of alpha
/// vertexAlpha; the centre pixel's radiance and albedo with `integrator`.
std::pair<glm::vec3, glm::vec3> coveredFloor(Integrator integrator, bool byVertexAlpha, float vertexAlpha,
                                             float cutoff) {
  Renderer r({2});
  MaterialDesc m = test::diffuse(1.0f);
  m.baseTexture = r.addTexture(TextureDesc{1, 1, test::solidPixels(1, 1, 200, 100, 50, 255), true});
  m.coverTexture = r.addTexture(TextureDesc{1, 1, test::solidPixels(1, 1, 20, 220, 120, 64), true});
  m.coverVertexAlpha = byVertexAlpha;
  m.coverAlphaCutoff = cutoff;
  m.stock.lightmapTexture = r.addTexture(TextureDesc{1, 1, test::solidPixels(1, 1, 102, 102, 102, 255), false});
  test::MeshArrays q = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  q.setMaterial(r.addMaterial(m));
  const std::vector<glm::vec2> lightmapUvs(4, glm::vec2(0.5f));
  const std::vector<glm::vec4> colors(4, glm::vec4(1.0f, 1.0f, 1.0f, vertexAlpha));
  MeshDesc desc = q.desc();
  desc.lightmapUvs = lightmapUvs;
  desc.colors = colors;
  r.addInstance({r.addMesh(desc)});
  r.commit();
  const FrameView f = r.render(lookAt({0, 0, 2}, {0, 0, 0}, 30.0f), settingsFor(integrator, 4, 1));
  return {f.radiance[5], f.albedo[5]};
}

TEST(KnownAnswer, CoverMixesOverTheBaseBeforeTheLightmap) {
  const glm::vec3 base(200 / 255.0f, 100 / 255.0f, 50 / 255.0f), cover(20 / 255.0f, 220 / 255.0f, 120 / 255.0f);
  const float a = 64 / 255.0f, light = linearToSrgb(0.4f);
  const auto display = [](const glm::vec3& c) {
    return glm::vec3(linearToSrgb(c.r), linearToSrgb(c.g), linearToSrgb(c.b));
  };
  const auto linear = [](const glm::vec3& c) {
    return glm::vec3(srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b));
  };
  // The Lightmap preset blends display values (the stage over the base), then multiplies by the light.
  const glm::vec3 lit = display(coveredFloor(Integrator::Lightmap, false, 1.0f, 0.0f).first);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(lit[c], glm::mix(base[c], cover[c], a) * light, 2e-3f) << c;
  // With the vertex alpha: a half-faded cover.
  const glm::vec3 faded = display(coveredFloor(Integrator::Lightmap, true, 0.5f, 0.0f).first);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(faded[c], glm::mix(base[c], cover[c], 0.5f * a) * light, 2e-3f) << c;
  // Below the cutoff the cover covers nothing; the vertex alpha alone changes nothing without coverVertexAlpha.
  const glm::vec3 cut = display(coveredFloor(Integrator::Lightmap, false, 0.5f, 0.5f).first);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(cut[c], base[c] * light, 2e-3f) << c;
  // Direct and Path: the albedo mixes linear colours.
  const glm::vec3 albedo = coveredFloor(Integrator::Direct, false, 1.0f, 0.0f).second;
  const glm::vec3 expected = glm::mix(linear(base), linear(cover), a);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(albedo[c], expected[c], 2e-3f) << c;
}

TEST(KnownAnswer, MeshUvShineFollowsTheMeshUvs) {
  // A black base under a red-left / green-right shine on the mesh uvs (clamped): opposite
  // corners of the view show one colour each, added at full strength.
  Renderer r({2});
  const std::vector<uint8_t> shine = {255, 0, 0, 255, 0, 255, 0, 255};
  TextureDesc shineDesc{2, 1, shine, true};
  shineDesc.wrap = TextureWrap::Clamp;
  shineDesc.mipmaps = false;
  MaterialDesc m = test::diffuse(0.0f);
  m.stock.shineTexture = r.addTexture(shineDesc);
  m.stock.shineTexCoords = TexCoordSource::Mesh;
  test::MeshArrays q = test::quad({-0.5f, -0.5f, 0}, {1, 0, 0}, {0, 1, 0});
  q.setMaterial(r.addMaterial(m));
  r.addInstance({r.addMesh(q.desc())});
  r.commit();
  const FrameView f = r.render(lookAt({0, 0, 2}, {0, 0, 0}, 30.0f), settingsFor(Integrator::Lightmap, 4, 1));
  const glm::vec3 first = f.radiance[0], last = f.radiance[15];   // opposite corners: u near 0.1 and 0.9
  const bool firstRed = first.r > 0.99f && first.g < 0.01f && last.g > 0.99f && last.r < 0.01f;
  const bool firstGreen = first.g > 0.99f && first.r < 0.01f && last.r > 0.99f && last.g < 0.01f;
  EXPECT_TRUE(firstRed != firstGreen) << "first " << first.r << " " << first.g << ", last " << last.r << " " << last.g;
}

}  // namespace
}  // namespace pa
