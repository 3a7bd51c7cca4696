// Material behaviour on tiny scenes: alpha mask (and invert), additive, blend, nodraw,
// shadow casting, sky windows, one-sided culling, mirrors, instance tint and overrides.
// Most use the Lightmap preset (no lightmap = fullbright base colour) for exact answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

#include "renderer/scene/textures/texture.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::greyStats;
using test::lookAt;
using test::settingsFor;

/// A camera at z = 3 looking down at layered quads: a background at z = 0 and a foreground
/// quad at z = 1, both larger than the view. Sky is blue-ish (0.1, 0.2, 0.3).
struct Layers {
  Renderer renderer{RendererConfig{2}};
  test::MeshArrays back = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  test::MeshArrays front = test::quad({-5, -5, 1}, {10, 0, 0}, {0, 10, 0});
  MeshId frontMesh = kNoId;
  Layers(const MaterialDesc& backMaterial, const MaterialDesc& frontMaterial) {
    back.setMaterial(renderer.addMaterial(backMaterial));
    front.setMaterial(renderer.addMaterial(frontMaterial));
    renderer.addInstance({renderer.addMesh(back.desc())});
    frontMesh = renderer.addMesh(front.desc());
    renderer.addInstance({frontMesh});
    SkyDesc sky;
    sky.color = {0.1f, 0.2f, 0.3f};
    renderer.setSky(sky);
    renderer.commit();
  }
  glm::vec3 centre(Integrator integrator = Integrator::Lightmap, uint32_t spp = 1) {
    const FrameView f = renderer.render(lookAt({0, 0, 3}, {0, 0, 0}, 20.0f), settingsFor(integrator, 4, spp, 2));
    glm::dvec3 sum(0.0);
    for (const glm::vec3& v : f.radiance) sum += glm::dvec3(v);
    return glm::vec3(sum / static_cast<double>(f.radiance.size()));
  }
};

MaterialDesc coloured(float r, float g, float b) {
  MaterialDesc m;
  m.baseColor = {r, g, b, 1.0f};
  return m;
}

MaterialDesc withTexture(Renderer& r, MaterialDesc m, uint8_t alpha) {
  const std::vector<uint8_t> px = test::solidPixels(2, 2, 255, 255, 255, alpha);
  m.baseTexture = r.addTexture({2, 2, px});
  return m;
}

TEST(Materials, AlphaMaskCutsAndInverts) {
  for (const auto& [alpha, invert, seesFront] :
       {std::tuple{uint8_t{0}, false, false}, {uint8_t{255}, false, true}, {uint8_t{0}, true, true},
        {uint8_t{255}, true, false}, {uint8_t{127}, false, false}, {uint8_t{128}, false, true}}) {
    MaterialDesc front = coloured(0.9f, 0.1f, 0.1f);
    front.alphaMode = AlphaMode::Mask;
    front.alphaInvert = invert;
    // Texture ids are allocated on the layered renderer below, so build the texture there.
    Layers layers(coloured(0.1f, 0.9f, 0.1f), MaterialDesc{});
    MaterialDesc textured = withTexture(layers.renderer, front, alpha);
    layers.renderer.setMaterial(1, textured);
    layers.renderer.commit();
    const glm::vec3 c = layers.centre();
    if (seesFront) {
      EXPECT_NEAR(c.r, 0.9f, 1e-5f) << int{alpha} << " invert " << invert;
    } else {
      EXPECT_NEAR(c.g, 0.9f, 1e-5f) << int{alpha} << " invert " << invert;
    }
  }
}

TEST(Materials, AdditiveAddsAndNeverOccludesOrShadows) {
  MaterialDesc add = coloured(0.2f, 0.3f, 0.0f);
  add.alphaMode = AlphaMode::Additive;
  Layers layers(coloured(0.5f, 0.5f, 0.5f), add);
  // The Lightmap preset adds display values, as framebuffer blending does: 0.5 + 0.2 linear is
  // encoded 0.735 + 0.484, white; 0.5 + 0 stays 0.5.
  const glm::vec3 c = layers.centre();
  const auto displaySum = [](float a, float b) {
    return srgbToLinear(std::min(1.0f, linearToSrgb(a) + linearToSrgb(b)));
  };
  EXPECT_NEAR(c.r, displaySum(0.5f, 0.2f), 1e-5f);
  EXPECT_NEAR(c.r, 1.0f, 1e-5f);
  EXPECT_NEAR(c.g, displaySum(0.5f, 0.3f), 1e-5f);
  EXPECT_NEAR(c.b, 0.5f, 1e-5f);
  // Lit from straight above by a sun: the additive layer casts no shadow on the floor.
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.direction = {0, 0, -1};
  sun.intensity = std::numbers::pi_v<float>;   // floor radiance = albedo
  layers.renderer.addLight(sun);
  SkyDesc black;
  layers.renderer.setSky(black);
  layers.renderer.commit();
  const glm::vec3 lit = layers.centre(Integrator::Direct);
  EXPECT_NEAR(lit.b, 0.5f, 1e-4f);
  EXPECT_NEAR(lit.r, 0.5f + 0.2f, 1e-4f);
}

TEST(Materials, SeenLightAddsInDisplayValuesWithTheStockLook) {
  // An additive layer (linear 0.2, 0.3, 0) over a surface glowing 0.5: with the stock look
  // (LightingLook::DisplaySpace) the traced presets add what the camera sees in display values,
  // as the stock framebuffer adds an effect or a glow stage (0.735 + 0.484 saturates red); with
  // the physical look they add linear radiance.
  MaterialDesc add = coloured(0.2f, 0.3f, 0.0f);
  add.alphaMode = AlphaMode::Additive;
  MaterialDesc glowing = coloured(0.0f, 0.0f, 0.0f);
  glowing.emission = {0.5f, 0.5f, 0.5f};
  Layers layers(glowing, add);
  const auto displaySum = [](float a, float b) {
    return srgbToLinear(std::min(1.0f, linearToSrgb(a) + linearToSrgb(b)));
  };
  for (const Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    for (const LightingLook look : {LightingLook::DisplaySpace, LightingLook::Physical}) {
      RenderSettings s = settingsFor(integrator, 4, 1, 2);
      s.lightingLook = look;
      const FrameView f = layers.renderer.render(lookAt({0, 0, 3}, {0, 0, 0}, 20.0f), s);
      const bool display = look == LightingLook::DisplaySpace;
      for (size_t i = 0; i < f.radiance.size(); ++i) {
        EXPECT_NEAR(f.radiance[i].r, display ? displaySum(0.5f, 0.2f) : 0.7f, 1e-5f) << int(integrator);
        EXPECT_NEAR(f.radiance[i].g, display ? displaySum(0.5f, 0.3f) : 0.8f, 1e-5f) << int(integrator);
        EXPECT_NEAR(f.radiance[i].b, 0.5f, 1e-5f) << int(integrator);
      }
    }
  }
  // Two layers over a dimmer glow: three stages, each added in display values (a sum of the two
  // layers taken through the curve as one would show 0.85, not 0.98).
  MaterialDesc dim = coloured(0.0f, 0.0f, 0.0f);
  dim.emission = {0.05f, 0.05f, 0.05f};
  MaterialDesc first = coloured(0.0f, 0.3f, 0.0f), second = coloured(0.0f, 0.02f, 0.0f);
  first.alphaMode = second.alphaMode = AlphaMode::Additive;
  Layers stacked(dim, first);
  test::MeshArrays nearer = test::quad({-5, -5, 2}, {10, 0, 0}, {0, 10, 0});
  nearer.setMaterial(stacked.renderer.addMaterial(second));
  stacked.renderer.addInstance({stacked.renderer.addMesh(nearer.desc())});
  stacked.renderer.commit();
  const float three = linearToSrgb(0.05f) + linearToSrgb(0.3f) + linearToSrgb(0.02f);
  ASSERT_LT(three, 1.0f);
  for (const Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    RenderSettings s = settingsFor(integrator, 4, 1, 2);
    s.lightingLook = LightingLook::DisplaySpace;
    const FrameView f = stacked.renderer.render(lookAt({0, 0, 3}, {0, 0, 0}, 20.0f), s);
    for (const glm::vec3& v : f.radiance) EXPECT_NEAR(v.g, srgbToLinear(three), 1e-5f) << int(integrator);
  }
}

TEST(Materials, LayerBlendsComposeInDisplayValuesInTheLightmapPreset) {
  // Behind: linear 0.2 (display e); the layer's colour: linear 0.5 (display s), alpha 0.25.
  const float e = linearToSrgb(0.2f), s = linearToSrgb(0.5f);
  const std::pair<LayerBlend, float> cases[] = {
      {LayerBlend::Over, e * 0.75f + s},       {LayerBlend::Multiply, e * s},
      {LayerBlend::MultiplyInverse, e * (1 - s)}, {LayerBlend::MultiplyAdd, e * (1 + s)}};
  for (const auto& [blend, display] : cases) {
    MaterialDesc layer = coloured(0.5f, 0.5f, 0.5f);
    layer.baseColor.a = 0.25f;
    layer.alphaMode = AlphaMode::Additive;
    layer.stock.layerBlend = blend;
    Layers layers(coloured(0.2f, 0.2f, 0.2f), layer);
    EXPECT_NEAR(linearToSrgb(layers.centre().g), std::min(display, 1.0f), 1e-4f) << int(blend);
  }
}

TEST(Materials, AlphaTestedLayersAddOnlyWhereTheTestPasses) {
  // A red additive layer over grey, its texture's alpha 127 or 128 against GE128 (and LT128):
  // where the test fails the layer is discarded, as alphaFunc discards the fragment, in every preset.
  for (const auto& [alpha, invert, shows] : std::initializer_list<std::tuple<uint8_t, bool, bool>>{
           {uint8_t{128}, false, true}, {uint8_t{127}, false, false}, {uint8_t{127}, true, true}, {uint8_t{128}, true, false}}) {
    MaterialDesc layer = coloured(0.3f, 0.0f, 0.0f);
    layer.alphaMode = AlphaMode::Additive;
    layer.layerAlphaTest = true;
    layer.alphaInvert = invert;
    Layers layers(coloured(0.2f, 0.2f, 0.2f), MaterialDesc{});
    layers.renderer.setMaterial(1, withTexture(layers.renderer, layer, alpha));
    layers.renderer.commit();
    Layers bare(coloured(0.2f, 0.2f, 0.2f), MaterialDesc{.castsShadows = false, .visible = false});
    for (const Integrator integrator : {Integrator::Lightmap, Integrator::Path}) {
      const glm::vec3 c = layers.centre(integrator), behind = bare.centre(integrator);
      EXPECT_NEAR(c.g, behind.g, 1e-5f) << int{alpha} << " invert " << invert << " integrator " << int(integrator);
      if (shows) {
        EXPECT_GT(c.r, behind.r + 0.1f) << int{alpha} << " invert " << invert << " integrator " << int(integrator);
      } else {
        EXPECT_NEAR(c.r, behind.r, 1e-5f) << int{alpha} << " invert " << invert << " integrator " << int(integrator);
      }
    }
  }
}

TEST(Materials, MultiplyAddLayersBrightenWhatIsBehindInThePathPreset) {
  // dst x (1 + src) on display values (a team decal, gl_dst_color gl_one): the traced presets
  // multiply the linear light from behind by (1 + src)^2.2; over black it adds nothing.
  const float s = linearToSrgb(0.25f);
  const float gain = std::pow(1.0f + s, 2.2f);
  MaterialDesc decal = coloured(0.25f, 0.25f, 0.25f);
  decal.alphaMode = AlphaMode::Additive;
  decal.stock.layerBlend = LayerBlend::MultiplyAdd;
  MaterialDesc glowing = coloured(0.0f, 0.0f, 0.0f);   // the surface behind shows 0.1 of its own
  glowing.emission = {0.1f, 0.1f, 0.1f};
  Layers lit(glowing, decal);
  EXPECT_NEAR(lit.centre(Integrator::Path).g, 0.1f * gain, 1e-4f);
  Layers dark(coloured(0.0f, 0.0f, 0.0f), decal);
  EXPECT_NEAR(dark.centre(Integrator::Path).g, 0.0f, 1e-6f);
  // Without the layer the surface shows its 0.1.
  Layers bare(glowing, MaterialDesc{.castsShadows = false, .visible = false});
  EXPECT_NEAR(bare.centre(Integrator::Path).g, 0.1f, 1e-4f);
}

TEST(Materials, FactorBlendsComposeInDisplayValues) {
  // Behind: display e; the layer: display s, alpha 0.25. dst' = s x F_src + e x F_dst.
  const float e = linearToSrgb(0.2f), s = linearToSrgb(0.5f), a = 0.25f;
  struct Case {
    BlendFactor src, dst;
    float display;
  };
  const Case cases[] = {
      {BlendFactor::One, BlendFactor::SrcAlpha, s + e * a},             // gl_one gl_src_alpha (explosions)
      {BlendFactor::SrcAlpha, BlendFactor::One, s * a + e},             // gl_src_alpha gl_one
      {BlendFactor::One, BlendFactor::OneMinusSrcColor, s + e * (1 - s)},   // gl_one gl_one_minus_src_color
      {BlendFactor::Zero, BlendFactor::OneMinusSrcAlpha, e * (1 - a)},
      {BlendFactor::SrcColor, BlendFactor::Zero, s * s},
  };
  for (const Case& c : cases) {
    MaterialDesc layer = coloured(0.5f, 0.5f, 0.5f);
    layer.baseColor.a = a;
    layer.alphaMode = AlphaMode::Additive;
    layer.stock.layerBlend = LayerBlend::Factors;
    layer.stock.layerSrcFactor = c.src;
    layer.stock.layerDstFactor = c.dst;
    Layers layers(coloured(0.2f, 0.2f, 0.2f), layer);
    EXPECT_NEAR(linearToSrgb(layers.centre().g), std::min(c.display, 1.0f), 1e-4f)
        << int(c.src) << " " << int(c.dst);
  }
}

TEST(Materials, CoincidentLayersComposeInPrimitiveOrder) {
  // Two copies of one quad in one mesh (a shader's stages): the first pair of triangles filters
  // to black (dst x 0), the other adds 0.5: later primitives are later stages.
  MaterialDesc black = coloured(0.0f, 0.0f, 0.0f);
  black.alphaMode = AlphaMode::Additive;
  black.stock.layerBlend = LayerBlend::Factors;
  black.stock.layerSrcFactor = BlendFactor::Zero;
  black.stock.layerDstFactor = BlendFactor::Zero;
  MaterialDesc add = coloured(0.5f, 0.5f, 0.5f);
  add.alphaMode = AlphaMode::Additive;
  for (const bool blackFirst : {true, false}) {
    Renderer r({2});
    test::MeshArrays back = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
    back.setMaterial(r.addMaterial(coloured(0.2f, 0.2f, 0.2f)));
    test::MeshArrays stages = test::quad({-5, -5, 1}, {10, 0, 0}, {0, 10, 0});
    stages.indices.insert(stages.indices.end(), {0, 1, 2, 0, 2, 3});
    const MaterialId first = r.addMaterial(blackFirst ? black : add), second = r.addMaterial(blackFirst ? add : black);
    stages.materials = {first, first, second, second};
    r.addInstance({r.addMesh(back.desc())});
    r.addInstance({r.addMesh(stages.desc())});
    r.setSky(SkyDesc{});
    r.commit();
    const FrameView f = r.render(lookAt({0, 0, 3}, {0, 0, 0}, 20.0f), settingsFor(Integrator::Lightmap, 4, 1, 2));
    EXPECT_NEAR(f.radiance[5].g, blackFirst ? 0.5f : 0.0f, 1e-5f) << blackFirst;
  }
}

TEST(Materials, LayersThatShowNothingTakeNoSlot) {
  // Twenty black additive quads (sprite margins) in front of one that adds 0.5, over grey 0.2:
  // more layers than a ray keeps (AdditiveHits::kCapacity), yet the one that shows is composed.
  Renderer r({2});
  test::MeshArrays back = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  back.setMaterial(r.addMaterial(coloured(0.2f, 0.2f, 0.2f)));
  r.addInstance({r.addMesh(back.desc())});
  MaterialDesc black = coloured(0.0f, 0.0f, 0.0f);
  black.alphaMode = AlphaMode::Additive;
  const MaterialId blackId = r.addMaterial(black);
  for (int k = 0; k < 20; ++k) {
    test::MeshArrays quad = test::quad({-5, -5, 1.0f + 0.05f * float(k)}, {10, 0, 0}, {0, 10, 0});
    quad.setMaterial(blackId);
    r.addInstance({r.addMesh(quad.desc())});
  }
  MaterialDesc add = coloured(0.5f, 0.5f, 0.5f);
  add.alphaMode = AlphaMode::Additive;
  test::MeshArrays shown = test::quad({-5, -5, 0.5f}, {10, 0, 0}, {0, 10, 0});
  shown.setMaterial(r.addMaterial(add));
  r.addInstance({r.addMesh(shown.desc())});
  r.setSky(SkyDesc{});
  r.commit();
  const FrameView f = r.render(lookAt({0, 0, 3}, {0, 0, 0}, 20.0f), settingsFor(Integrator::Lightmap, 4, 1, 2));
  const float expected = srgbToLinear(std::min(1.0f, linearToSrgb(0.2f) + linearToSrgb(0.5f)));
  EXPECT_NEAR(f.radiance[5].g, expected, 1e-5f);
}

TEST(Materials, BlendIsStochasticCoverage) {
  MaterialDesc glass = coloured(1.0f, 0.0f, 0.0f);
  glass.alphaMode = AlphaMode::Blend;
  glass.opacity = 0.25f;
  Layers layers(coloured(0.0f, 1.0f, 0.0f), glass);
  const glm::vec3 c = layers.centre(Integrator::Lightmap, 256);
  EXPECT_NEAR(c.r, 0.25f, 0.02f);
  EXPECT_NEAR(c.g, 0.75f, 0.02f);
  EXPECT_NEAR(c.r + c.g, 1.0f, 1e-5f);
}

TEST(Materials, InvisibleAndNonShadowCastingSurfaces) {
  MaterialDesc nodraw = coloured(1.0f, 0.0f, 0.0f);
  nodraw.visible = false;
  Layers layers(coloured(0.5f, 0.5f, 0.5f), nodraw);
  EXPECT_NEAR(layers.centre().r, 0.5f, 1e-5f);   // camera sees through it
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.direction = {0, 0, -1};
  sun.intensity = std::numbers::pi_v<float>;
  layers.renderer.addLight(sun);
  layers.renderer.setSky(SkyDesc{});
  layers.renderer.commit();
  EXPECT_NEAR(layers.centre(Integrator::Direct).r, 0.0f, 1e-6f);   // but still casts a shadow
  nodraw.castsShadows = false;
  layers.renderer.setMaterial(1, nodraw);
  layers.renderer.commit();
  EXPECT_NEAR(layers.centre(Integrator::Direct).r, 0.5f, 1e-4f);
}

TEST(Materials, SkySurfaceShowsSkyAndPassesSunlight) {
  MaterialDesc skyWindow;
  skyWindow.sky = true;
  Layers layers(coloured(0.5f, 0.5f, 0.5f), skyWindow);
  const glm::vec3 c = layers.centre();
  EXPECT_NEAR(c.r, 0.1f, 1e-6f);
  EXPECT_NEAR(c.b, 0.3f, 1e-6f);
}

TEST(Materials, OneSidedSurfacesAreCulledFromBehind) {
  MaterialDesc oneSided = coloured(1.0f, 0.0f, 0.0f);
  oneSided.twoSided = false;
  Layers layers(coloured(0.0f, 0.0f, 1.0f), oneSided);
  EXPECT_NEAR(layers.centre().r, 1.0f, 1e-5f);   // front faces the camera (+z)
  // Flip the winding: now the camera sees its back and looks through it.
  layers.front.indices = {0, 2, 1, 0, 3, 2};
  layers.renderer.updateMesh(layers.frontMesh, layers.front.desc());
  layers.renderer.commit();
  EXPECT_NEAR(layers.centre().b, 1.0f, 1e-5f);
}

TEST(Materials, MirrorReflectsWhatIsInFront) {
  // A mirror floor facing +z and an emissive ceiling quad behind the camera: the camera,
  // looking down, sees the ceiling's emission through the mirror (times the mirror colour).
  Renderer r({2});
  MaterialDesc mirror = coloured(0.8f, 0.8f, 0.8f);
  mirror.mirror = true;
  MaterialDesc lamp = coloured(0.0f, 0.0f, 0.0f);   // black emitter: no light bounces off it
  lamp.emission = glm::vec3(2.0f);
  test::MeshArrays floor = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  floor.setMaterial(r.addMaterial(mirror));
  test::MeshArrays ceiling = test::quad({-5, -5, 4}, {0, 10, 0}, {10, 0, 0});
  ceiling.setMaterial(r.addMaterial(lamp));
  r.addInstance({r.addMesh(floor.desc())});
  r.addInstance({r.addMesh(ceiling.desc())});
  r.commit();
  const FrameView f = r.render(lookAt({0, 0, 2}, {0, 0, 0}, 20.0f), settingsFor(Integrator::Path, 4, 4, 2));
  EXPECT_NEAR(greyStats(f).mean, 1.6, 1e-4);
}

TEST(Materials, PortalShowsTheViewFromItsOtherSide) {
  // A mirror quad facing the camera on the plane x = 5, a blue lamp behind the camera (what the
  // mirror reflects) and a green lamp far away at (100, 40, 0) facing -y. With a portal on the
  // quad's plane that turns +x into +y and moves (5, 0, 0) to (100, 0, 0), the camera sees green.
  Renderer r({2});
  MaterialDesc mirror = coloured(0.8f, 0.8f, 0.8f);
  mirror.mirror = true;
  auto lamp = [&](const glm::vec3& colour) {
    MaterialDesc m = coloured(0.0f, 0.0f, 0.0f);
    m.emission = colour;
    return r.addMaterial(m);
  };
  test::MeshArrays window = test::quad({5, -2, -2}, {0, 0, 4}, {0, 4, 0});   // front faces -x
  window.setMaterial(r.addMaterial(mirror));
  test::MeshArrays behind = test::quad({-5, -50, -50}, {0, 100, 0}, {0, 0, 100});   // faces +x
  behind.setMaterial(lamp({0.0f, 0.0f, 1.0f}));
  test::MeshArrays far = test::quad({50, 40, -50}, {0, 0, 100}, {100, 0, 0});   // faces -y
  far.setMaterial(lamp({0.0f, 1.0f, 0.0f}));
  for (auto* mesh : {&window, &behind, &far}) r.addInstance({r.addMesh(mesh->desc())});
  r.commit();
  const Camera camera = lookAt({0, 0, 0}, {1, 0, 0}, 10.0f);
  auto centre = [&](Integrator integrator) {
    const FrameView f = r.render(camera, settingsFor(integrator, 4, 2, 2));
    glm::vec3 sum(0.0f);
    for (const glm::vec3& c : f.radiance) sum += c;
    return sum / float(f.radiance.size());
  };
  // No portal: a mirror, tinted by its colour.
  EXPECT_NEAR(centre(Integrator::Path).b, 0.8f, 1e-4f);

  PortalDesc portal;
  portal.normal = {-1, 0, 0};
  portal.distance = -5;
  const glm::mat3 turn(glm::vec3(0, 1, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 0, 1));   // +x -> +y
  portal.transform = glm::mat4x3(turn[0], turn[1], turn[2], glm::vec3(100, 0, 0) - turn * glm::vec3(5, 0, 0));
  r.setPortals(std::span(&portal, 1));
  r.commit();
  for (Integrator integrator : {Integrator::Path, Integrator::Direct, Integrator::Lightmap}) {
    const glm::vec3 c = centre(integrator);
    EXPECT_NEAR(c.g, 1.0f, 1e-4f) << int(integrator);   // unweighted: the lamp itself
    EXPECT_NEAR(c.b, 0.0f, 1e-4f) << int(integrator);
  }
  // A second portal on the same plane facing the other way (listed first) does not take the
  // rays that enter from the front.
  PortalDesc backwards = portal;
  backwards.normal = {1, 0, 0};
  backwards.distance = 5;
  const PortalDesc both[2] = {backwards, portal};
  r.setPortals(both);
  r.commit();
  EXPECT_NEAR(centre(Integrator::Path).g, 1.0f, 1e-4f);
  r.setPortals(std::span(&portal, 1));
  r.commit();
  // Seen from behind (the plane's back side) the quad is a mirror again: camera at x = 10
  // looking -x sees the mirror's reflection of the empty +x side (the green lamp is out of view).
  const FrameView back = r.render(lookAt({10, 0, 0}, {0, 0, 0}, 10.0f), settingsFor(Integrator::Path, 4, 2, 2));
  for (const glm::vec3& c : back.radiance) EXPECT_NEAR(c.g, 0.0f, 1e-4f);

  // Hostile portals are refused with the reason.
  PortalDesc flat = portal;
  flat.transform = glm::mat4x3(0.0f);
  EXPECT_THROW(r.setPortals(std::span(&flat, 1)), SceneError);
  PortalDesc nan = portal;
  nan.distance = std::nanf("");
  EXPECT_THROW(r.setPortals(std::span(&nan, 1)), SceneError);
}

TEST(Materials, InstanceTintAndMaterialOverride) {
  Layers layers(coloured(1.0f, 1.0f, 1.0f), coloured(1.0f, 1.0f, 1.0f));
  InstanceDesc inst{layers.frontMesh};
  inst.tint = {0.5f, 0.25f, 1.0f, 1.0f};
  layers.renderer.setInstance(1, inst);
  layers.renderer.commit();
  glm::vec3 c = layers.centre();
  EXPECT_NEAR(c.r, 0.5f, 1e-5f);
  EXPECT_NEAR(c.g, 0.25f, 1e-5f);
  // Override with an alpha-masked, fully transparent material: the front layer disappears.
  MaterialDesc cut = withTexture(layers.renderer, coloured(1, 0, 0), 0);
  cut.alphaMode = AlphaMode::Mask;
  inst.materialOverride = layers.renderer.addMaterial(cut);
  inst.tint = glm::vec4(1.0f);
  layers.renderer.setInstance(1, inst);
  layers.renderer.commit();
  c = layers.centre();
  EXPECT_NEAR(c.r, 1.0f, 1e-5f);
  EXPECT_NEAR(c.b, 1.0f, 1e-5f);
}

TEST(Materials, UvTransformScrollsTheTexture) {
  // 4x1 texture: left half black, right half white; the quad maps u in [0, 1] across x.
  // A scroll of 0.5 swaps the halves.
  Renderer r({1});
  const std::vector<uint8_t> px{0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255};
  MaterialDesc m;
  m.baseTexture = r.addTexture({4, 1, px, false, TextureWrap::Repeat, false});
  const MaterialId id = r.addMaterial(m);
  test::MeshArrays q = test::quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  q.setMaterial(id);
  r.addInstance({r.addMesh(q.desc())});
  r.commit();
  // Looking down with image right = +x (left = -x) and image up = +y.
  Camera cam;
  cam.origin = {0, 0, 2};
  cam.forward = {0, 0, -1};
  cam.left = {-1, 0, 0};
  cam.up = {0, 1, 0};
  cam.fovX = cam.fovY = 40.0f;
  const RenderSettings s = settingsFor(Integrator::Lightmap, 8, 1);
  FrameView f = r.render(cam, s);
  EXPECT_EQ(f.radiance[4 * 8 + 0].r, 0.0f);   // left column: u in [0.14, 0.23], black texels
  EXPECT_NEAR(f.radiance[4 * 8 + 7].r, 1.0f, 1e-5f);   // right column: u in [0.77, 0.86], white texels
  m.uvTransform[2] = glm::vec2(0.5f, 0.0f);
  r.setMaterial(id, m);
  r.commit();
  f = r.render(cam, s);
  EXPECT_NEAR(f.radiance[4 * 8 + 0].r, 1.0f, 1e-5f);
  EXPECT_EQ(f.radiance[4 * 8 + 7].r, 0.0f);
}

}  // namespace
}  // namespace pa
