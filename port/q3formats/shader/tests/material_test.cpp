#include "port/q3formats/shader/material.h"

#include <gtest/gtest.h>

#include <cmath>

#include "port/q3formats/shader/shader_parser.h"

namespace {

using namespace q3;

MaterialInfo material(const char* text) {
  auto script = parseShaderScript(text, "m.shader");
  EXPECT_EQ(script.shaders.size(), 1u);
  EXPECT_TRUE(script.warnings.empty());
  return deriveMaterial(script.shaders.at(0));
}

TEST(Material, LightmappedWallIsOpaqueWithItsTexture) {
  auto m = material("w { { map $lightmap rgbGen identity } { map textures/w.tga blendFunc filter } }");
  EXPECT_EQ(m.baseTexture, "textures/w.tga");
  EXPECT_EQ(m.alphaMode, AlphaMode::Opaque);
  EXPECT_EQ(m.lighting, LightingMode::Lightmap);
  EXPECT_FALSE(m.emissive);
  EXPECT_FALSE(m.invisible);
}

TEST(Material, DetailStageBeforeTheTextureIsNoBase) {
  // oacmpdm3's walls (z_oacmp-volume1-v3.pk3): the lightmap, a detail filter on its own uvs, then
  // the texture as a filter: stock shows lightmap x 2 detail x texture.
  auto m = material(R"(textures/oacmp_egyptsoc_wall/stone04a {
    { map $lightmap
      rgbGen identity
      tcGen lightmap }
    { map gfx/fx/detail/d_stone.tga
      blendfunc gl_dst_color gl_src_color
      tcMod scale 8 8
      detail }
    { map textures/oacmp_egyptsoc_wall/stone04a.tga
      blendfunc filter } })");
  EXPECT_EQ(m.baseTexture, "textures/oacmp_egyptsoc_wall/stone04a.tga");
  EXPECT_EQ(m.lighting, LightingMode::Lightmap);
  EXPECT_EQ(m.alphaMode, AlphaMode::Opaque);
  ASSERT_EQ(m.baseModulations.size(), 1u);
  EXPECT_EQ(m.baseModulations[0].texture, "gfx/fx/detail/d_stone.tga");
  EXPECT_FLOAT_EQ(m.baseModulations[0].scale, 2.0f);
  EXPECT_TRUE(m.baseModulations[0].meanOnly);
  // A shader whose only plain image stage is a detail one keeps it as the base.
  auto onlyDetail = material("d { { map $lightmap } { map d.tga blendfunc gl_dst_color gl_src_color detail } }");
  EXPECT_EQ(onlyDetail.baseTexture, "d.tga");
}

TEST(Material, Q3map2ExternalLightmapStageIsTheLightmap) {
  // q3map2 replaces $lightmap by the image it wrote beside the map (non-128 lightmap sizes).
  auto m = material(R"(maps/ext/textures/w_1a2b3c4d { { map textures/w.tga rgbGen identity }
    { map maps/ext/lm_0002.tga blendFunc GL_DST_COLOR GL_ZERO tcgen lightmap } })");
  EXPECT_EQ(m.baseTexture, "textures/w.tga");
  EXPECT_EQ(m.lighting, LightingMode::Lightmap);
  EXPECT_EQ(m.lightmapImage, "maps/ext/lm_0002.tga");
  EXPECT_TRUE(m.baseModulations.empty());   // not multiplied into the base on its uvs
  // Older q3map2 wrote the image without tcGen lightmap; the name alone says what it is.
  auto old = material("w { { map $whiteimage } { map maps/ext/lm_0000 blendFunc filter } { map t.tga blendFunc filter } }");
  EXPECT_EQ(old.lightmapImage, "maps/ext/lm_0000");
  EXPECT_EQ(old.lighting, LightingMode::Lightmap);
  // q3map2's light style stage (an external page added with a flicker) is light, not the base
  // and not a glow; the surface keeps its own lightmap.
  auto styled = material(R"(void3/5D65 { { map $lightmap rgbGen identity }
    { map maps/void3/lm_0000.tga blendFunc GL_SRC_ALPHA GL_ONE rgbGen wave noise 0.5 1 0 5.37 tcGen lightmap }
    { map textures/oquartz/hazard_crate.tga blendFunc GL_DST_COLOR GL_ZERO rgbGen identity } })");
  EXPECT_EQ(styled.baseTexture, "textures/oquartz/hazard_crate.tga");
  EXPECT_EQ(styled.lightmapImage, "");
  EXPECT_TRUE(styled.glowTextures.empty());
  EXPECT_EQ(styled.lighting, LightingMode::Lightmap);
  // A plain $lightmap stage names no image; an image merely in maps/ is an image.
  EXPECT_EQ(material("w { { map $lightmap } }").lightmapImage, "");
  auto image = material("w { { map maps/ext/lm_logo.tga } }");
  EXPECT_EQ(image.lightmapImage, "");
  EXPECT_EQ(image.baseTexture, "maps/ext/lm_logo.tga");
}

TEST(Material, AlphaTestedFoliageIsMaskAndTwoSided) {
  auto m = material(R"(f { cull none
    { map leaves.tga alphaFunc GE128 depthWrite rgbGen vertex }
    { map $lightmap blendFunc filter depthFunc equal } })");
  EXPECT_EQ(m.alphaMode, AlphaMode::Mask);
  EXPECT_FLOAT_EQ(m.alphaCutoff, 0.5f);
  EXPECT_FALSE(m.alphaInvert);
  EXPECT_TRUE(m.twoSided);
  EXPECT_TRUE(m.vertexColor);
  auto inv = material("f { { map a.tga alphaFunc LT128 } }");
  EXPECT_TRUE(inv.alphaInvert);
  auto gt0 = material("f { { map a.tga alphaFunc GT0 } }");
  // GT0 keeps alpha above zero: a texel of alpha 0 fails, one of 1/255 passes (alpha >= cutoff).
  EXPECT_GT(gt0.alphaCutoff, 0.0f);
  EXPECT_LE(gt0.alphaCutoff, 1.0f / 255.0f);
}

TEST(Material, AdditiveStagesKeepTheirSourceFactorAndAlphaTest) {
  const MaterialInfo add = material("a { { map a.tga blendFunc add } }");
  EXPECT_EQ(add.additiveSource, BlendFactor::One);
  EXPECT_FALSE(add.additiveAlphaTest);
  EXPECT_EQ(material("a { { map a.tga blendFunc GL_SRC_ALPHA GL_ONE } }").additiveSource, BlendFactor::SrcAlpha);
  // The team decal of oasago2 (pak6-patch088's am_proto2.shader).
  const MaterialInfo decal = material(
      "textures/proto2/reda_dcl { polygonoffset cull none { map textures/proto2/reda_dcl.tga alphafunc GE128 "
      "blendFunc GL_DST_COLOR GL_ONE } }");
  EXPECT_EQ(decal.alphaMode, AlphaMode::Additive);
  EXPECT_EQ(decal.additiveSource, BlendFactor::DstColor);
  EXPECT_TRUE(decal.additiveAlphaTest);
  EXPECT_FLOAT_EQ(decal.alphaCutoff, 0.5f);
  EXPECT_FALSE(decal.alphaInvert);
  const MaterialInfo gt0 = material("a { { map a.tga alphaFunc GT0 blendFunc add } }");
  EXPECT_TRUE(gt0.additiveAlphaTest);
  EXPECT_GT(gt0.alphaCutoff, 0.0f);
  // An opaque first stage keeps its source factor out of it.
  EXPECT_FALSE(material("a { { map a.tga alphaFunc GE128 } }").additiveAlphaTest);
}

TEST(Material, BlendModesOfTheFirstStage) {
  EXPECT_EQ(material("a { { map a.tga blendFunc blend } }").alphaMode, AlphaMode::Blend);
  EXPECT_EQ(material("a { { map a.tga blendFunc GL_ONE GL_ONE_MINUS_SRC_ALPHA } }").alphaMode, AlphaMode::Blend);
  EXPECT_EQ(material("a { { map a.tga blendFunc GL_SRC_ALPHA GL_ONE } }").alphaMode, AlphaMode::Additive);
  EXPECT_EQ(material("a { { map a.tga blendFunc filter } }").alphaMode, AlphaMode::Multiply);
  EXPECT_EQ(material("a { { map a.tga blendFunc filter } }").filterBlend, FilterBlend::Multiply);
  EXPECT_EQ(material("a { { map a.tga blendFunc GL_DST_COLOR GL_SRC_COLOR } }").filterBlend, FilterBlend::Modulate2x);
  EXPECT_EQ(material("a { { map a.tga blendFunc GL_ZERO GL_ONE_MINUS_SRC_COLOR } }").filterBlend,
            FilterBlend::MultiplyInverse);
  EXPECT_EQ(material("a { { map a.tga blendFunc GL_ONE GL_ZERO } }").alphaMode, AlphaMode::Opaque);
  auto flame = material("a { { map flame.tga blendFunc add rgbGen identity } }");
  EXPECT_EQ(flame.alphaMode, AlphaMode::Additive);
  EXPECT_TRUE(flame.emissive);
  EXPECT_EQ(flame.lighting, LightingMode::Unlit);
}

TEST(Material, SurfaceLightAndGlowStages) {
  auto m = material(R"(l { q3map_surfacelight 1000 q3map_lightimage glow.tga
    { map $lightmap } { map base.tga blendFunc filter } { map glow.tga blendFunc add } })");
  EXPECT_TRUE(m.emissive);
  EXPECT_FLOAT_EQ(m.surfaceLight, 1000);
  EXPECT_EQ(m.lightImage, "glow.tga");
  ASSERT_EQ(m.glowTextures.size(), 1u);
  EXPECT_EQ(m.glowTextures[0], "glow.tga");
  EXPECT_FALSE(m.glowClampUv);
  EXPECT_EQ(m.baseTexture, "base.tga");
  // oa_ctf's teleporter rings: a clampMap glow that stretches and turns (clamped as stock draws it).
  auto rings = material(R"(t { q3map_surfacelight 455
    { clampmap ring.tga blendfunc add tcmod rotate 40 }
    { clampmap rings.jpg blendfunc add tcmod stretch sin 0.6 -0.3 0 0.5 } })");
  ASSERT_EQ(rings.glowTextures.size(), 1u);
  EXPECT_TRUE(rings.glowClampUv);
  EXPECT_EQ(rings.glowTcMods.size(), 1u);
  auto noImage = material("l { q3map_surfacelight 10 { map base.tga } }");
  EXPECT_EQ(noImage.lightImage, "base.tga");
}

TEST(Material, LaterStagesMultiplyingTheBaseOnItsUvs) {
  // oa_ctf2 textures/clown/steel_r_shine: the texture, a chrome add, the same texture as a
  // filter, then the lightmap: stock shows texture^2 * lightmap (+ chrome).
  auto shine = material(R"(s { { map steel.jpg rgbGen identity }
    { clampmap chrome.jpg blendfunc add tcGen environment }
    { map steel.jpg blendfunc filter }
    { map $lightmap blendfunc gl_dst_color gl_one_minus_src_alpha tcGen lightmap } })");
  ASSERT_EQ(shine.baseModulations.size(), 1u);
  EXPECT_EQ(shine.baseModulations[0].texture, "steel.jpg");
  EXPECT_FLOAT_EQ(shine.baseModulations[0].scale, 1.0f);
  EXPECT_EQ(shine.baseTexture, "steel.jpg");
  // GL_DST_COLOR GL_SRC_COLOR doubles; GL_ZERO GL_SRC_COLOR is a filter too.
  auto doubled = material("d { { map a.tga } { map b.tga blendFunc GL_DST_COLOR GL_SRC_COLOR } "
                          "{ map c.tga blendFunc GL_ZERO GL_SRC_COLOR } }");
  ASSERT_EQ(doubled.baseModulations.size(), 2u);
  EXPECT_FLOAT_EQ(doubled.baseModulations[0].scale, 2.0f);
  EXPECT_EQ(doubled.baseModulations[1].texture, "c.tga");
  EXPECT_FLOAT_EQ(doubled.baseModulations[1].scale, 1.0f);
  // A detail texture on other uvs (tcMod scale) multiplies by its mean; the lightmap is none.
  auto detail = material("d { { map a.tga } { map $lightmap blendFunc filter } "
                         "{ map detail.tga blendFunc GL_DST_COLOR GL_SRC_COLOR tcMod scale 8 8 } }");
  ASSERT_EQ(detail.baseModulations.size(), 1u);
  EXPECT_EQ(detail.baseModulations[0].texture, "detail.tga");
  EXPECT_FLOAT_EQ(detail.baseModulations[0].scale, 2.0f);
  EXPECT_TRUE(detail.baseModulations[0].meanOnly);
  EXPECT_FALSE(shine.baseModulations[0].meanOnly);
  // OpenArena's terrain: rock, vegetation blended by vertex alpha, scrolling cloud shadows as a
  // filter on their own uvs, the lightmap.
  auto terrain = material(R"(t { { map rock.jpg rgbGen identity }
    { map veg.tga blendFunc GL_SRC_ALPHA GL_ONE_MINUS_SRC_ALPHA alphaFunc GE128 alphaGen vertex }
    { map clouds.tga blendfunc filter tcmod scale .2 .2 tcMod scroll -0.15 0.15 }
    { map $lightmap rgbGen identity blendFunc GL_DST_COLOR GL_ZERO } })");
  ASSERT_EQ(terrain.baseModulations.size(), 1u);
  EXPECT_EQ(terrain.baseModulations[0].texture, "clouds.tga");
  EXPECT_TRUE(terrain.baseModulations[0].meanOnly);
  // An environment-mapped filter is not on mesh uvs at all: left out.
  EXPECT_TRUE(material("e { { map a.tga } { map env.tga blendFunc filter tcGen environment } }").baseModulations.empty());
  // The ordinary lightmapped wall has none.
  EXPECT_TRUE(material("w { { map $lightmap } { map w.tga blendFunc filter } }").baseModulations.empty());
}

TEST(Material, AlphaBlendedStageBeforeTheLightmapCoversTheBase) {
  // OpenArena's blue_launchpad (oasfx.shader): scrolling treads, an added glow, the pad's frame
  // blended over both, the lightmap, then a glow after it: the frame covers the treads.
  auto pad = material(R"(p { { map tread.jpg tcmod scroll 0 1 rgbgen identity }
    { map blaunch.jpg blendfunc add tcmod scroll 0 4 }
    { map launchpad03.tga blendfunc blend rgbgen identity }
    { map $lightmap blendfunc filter rgbgen identity }
    { map blaunch2.jpg blendfunc add } })");
  EXPECT_EQ(pad.baseTexture, "tread.jpg");
  EXPECT_EQ(pad.coverTexture, "launchpad03.tga");
  EXPECT_TRUE(pad.coverTcMods.empty());
  EXPECT_FALSE(pad.coverVertexAlpha);
  EXPECT_EQ(pad.coverAlphaCutoff, 0.0f);
  // islandctf's terrain: a second texture faded in by vertex alpha, on uvs of its own.
  auto terrain = material(R"(t { { map sand.tga }
    { map rock.jpg alphagen vertex blendfunc GL_SRC_ALPHA GL_ONE_MINUS_SRC_ALPHA alphaFunc GE128 tcmod scale 2 2 }
    { map $lightmap blendfunc GL_DST_COLOR GL_SRC_COLOR tcgen lightmap } })");
  EXPECT_EQ(terrain.coverTexture, "rock.jpg");
  ASSERT_EQ(terrain.coverTcMods.size(), 1u);
  EXPECT_EQ(terrain.coverTcMods[0].kind, TcModKind::Scale);
  EXPECT_TRUE(terrain.coverVertexAlpha);
  EXPECT_EQ(terrain.coverAlphaCutoff, 0.5f);
  EXPECT_EQ(terrain.lightmapScale, 2.0f);   // GL_DST_COLOR GL_SRC_COLOR: the lit frame doubled
  EXPECT_EQ(pad.lightmapScale, 1.0f);
  // oasfx's xmetalfloor_wall_5b: the panel, a scrolling glow drawn opaque over it, the panel
  // again blended by its alpha: the glow is what shows through the panel's holes.
  auto panel = material(R"(x { { map panel.tga rgbgen identity }
    { map glow.jpg rgbgen identity tcmod scale .5 .5 }
    { map panel.tga blendfunc blend rgbgen identity }
    { map $lightmap blendfunc filter rgbgen identity } })");
  EXPECT_EQ(panel.baseTexture, "glow.jpg");
  EXPECT_EQ(panel.uvAnimation.size(), 1u);
  EXPECT_EQ(panel.coverTexture, "panel.tga");
  // evil8_base's e8metal_red_shiney: chrome, the painted metal over it with holes, the lightmap:
  // the reflection is the base, the metal its cover.
  auto shiny = material(R"(s { { map tinfx.tga rgbgen identity tcgen environment }
    { map metal.tga blendfunc blend rgbgen identity }
    { map $lightmap blendfunc gl_dst_color gl_one_minus_dst_alpha rgbgen identity tcgen lightmap } })");
  EXPECT_EQ(shiny.baseTexture, "tinfx.tga");
  EXPECT_TRUE(shiny.baseReflects);
  EXPECT_EQ(shiny.coverTexture, "metal.tga");
  // evil8's launch pads: the lightmap as GL_DST_COLOR GL_ONE_MINUS_DST_ALPHA (a filter over the
  // solid frame, whose alpha is 1).
  EXPECT_EQ(material(R"(l { { map fx.tga tcmod scroll 0 3 }
    { map pad.tga blendfunc blend rgbgen identity }
    { map $lightmap blendfunc gl_dst_color gl_one_minus_dst_alpha tcgen lightmap } })").coverTexture, "pad.tga");
  // Of two, the topmost; the base's own image at its own uvs redrawn over effects is no cover.
  EXPECT_EQ(material("t { { map a.tga } { map b.tga blendfunc blend } { map c.tga blendfunc blend } "
                     "{ map $lightmap blendfunc filter } }").coverTexture, "c.tga");
  EXPECT_EQ(material("j { { map pad.tga } { map fx.tga blendfunc add tcmod rotate 360 } "
                     "{ map pad.tga blendfunc blend } { map $lightmap blendfunc filter } }").coverTexture, "");
  // No cover: blended after the lightmap (not lit with the base), no lightmap at all, a
  // reflection, another colour (rgbGen wave), a premultiplied blend, a see-through base.
  for (const char* text : {"a { { map a.tga } { map $lightmap blendfunc filter } { map b.tga blendfunc blend } }",
                           "b { { map a.tga } { map b.tga blendfunc blend } }",
                           "c { { map a.tga } { map e.tga blendfunc blend tcGen environment } "
                           "{ map $lightmap blendfunc filter } }",
                           "d { { map a.tga } { map b.tga blendfunc blend rgbGen wave sin 0 1 0 1 } "
                           "{ map $lightmap blendfunc filter } }",
                           "e { { map a.tga } { map b.tga blendfunc GL_ONE GL_ONE_MINUS_SRC_ALPHA } "
                           "{ map $lightmap blendfunc filter } }",
                           "f { { map a.tga blendfunc blend } { map b.tga blendfunc blend } "
                           "{ map $lightmap blendfunc filter } }"})
    EXPECT_EQ(material(text).coverTexture, "") << text;
}

TEST(Material, ModulateBaseMultipliesDisplayValuesTexelForTexel) {
  std::vector<uint8_t> base = {200, 100, 255, 77, 128, 255, 0, 255};   // 2 x 1
  const std::vector<uint8_t> self = base;
  ASSERT_TRUE(modulateBase(base, 2, 1, self, 2, 1, 1.0f));
  EXPECT_EQ(base, (std::vector<uint8_t>{157, 39, 255, 77, 64, 255, 0, 255}));   // 200*200/255 = 156.9
  std::vector<uint8_t> grey = {100, 100, 100, 255};
  const std::vector<uint8_t> half = {128, 255, 0, 9};                         // 1 x 1, stretched
  ASSERT_TRUE(modulateBase(grey, 1, 1, half, 1, 1, 2.0f));
  EXPECT_EQ(grey, (std::vector<uint8_t>{100, 200, 0, 255}));                  // x2, clamped, alpha kept
  std::vector<uint8_t> wrongSize = {1, 2, 3};
  EXPECT_FALSE(modulateBase(wrongSize, 1, 1, half, 1, 1, 1.0f));
  EXPECT_EQ(wrongSize, (std::vector<uint8_t>{1, 2, 3}));
}

TEST(Material, LightImageCandidatesInQ3map2Order) {
  using Names = std::vector<std::string>;
  // q3map_lightimage first, then the editor image, the shader's name, the first stage image.
  EXPECT_EQ(material("l { q3map_lightimage glow.tga qer_editorimage ed.tga { map $lightmap } { map base.tga } }")
                .lightImageCandidates,
            (Names{"glow.tga", "ed.tga", "l", "base.tga"}));
  // Without q3map_lightimage and editor image: the first stage image that is not $lightmap.
  EXPECT_EQ(material("l { { map $lightmap } { animMap 2 a1.tga a2.tga } { map b.tga } }").lightImageCandidates,
            (Names{"a1.tga", "l"}));
  // With an editor image the stage image is not the light image path, only the last resort.
  EXPECT_EQ(material("l { qer_editorimage ed.tga { map base.tga } }").lightImageCandidates,
            (Names{"ed.tga", "l", "base.tga"}));
  // A sky shader lights with its far box's top image.
  EXPECT_EQ(material("s { skyparms env/red - - }").lightImageCandidates, (Names{"env/red_up", "s"}));
}

TEST(Material, SkyBoxFacesInCubeOrderAsTheStockRendererShowsThem) {
  auto m = material("s { surfaceparm sky skyparms env/red 256 - { map clouds.tga } }");
  EXPECT_TRUE(m.sky);
  const std::array<std::string, 6> expected{"env/red_rt", "env/red_lf", "env/red_bk",
                                            "env/red_ft", "env/red_up", "env/red_dn"};
  EXPECT_EQ(m.skyBox.farFaces, expected);
  const std::array<bool, 6> turned{false, false, false, false, true, false};
  EXPECT_EQ(m.skyBox.turned180, turned);
  EXPECT_EQ(m.skyBox.nearFaces[0], "");
  EXPECT_FLOAT_EQ(m.skyBox.cloudHeight, 256);
  EXPECT_FALSE(m.invisible);
}

// Known answers from ioquake3 tr_sky.c: side k of the stock box holds the point
// (x, y, z) = st_to_vec[k] applied to (s, t, 1) and shows image sky_texorder[k] of the
// skyParms images (rt bk lf ft up dn) at texture (s', t') = ((s + 1) / 2, 1 - (t + 1) / 2).
// The SkyBox layout: face f seen along axis, u = (1 + right.d / |d_axis|) / 2,
// v = (1 - top.d / |d_axis|) / 2. Every side, sampled on a grid, must agree.
TEST(Material, SkyFaceImagesReproduceTheStockBoxTexelForTexel) {
  const int stToVec[6][3] = {{3, -1, 2}, {-3, 1, 2}, {1, 3, 2}, {-1, -3, 2}, {-2, -1, 3}, {2, -1, -3}};
  const int texOrder[6] = {0, 2, 1, 3, 4, 5};
  const char* loaded[6] = {"_rt", "_bk", "_lf", "_ft", "_up", "_dn"};
  struct Basis { std::array<float, 3> axis, top, right; };
  const Basis layout[6] = {{{1, 0, 0}, {0, 0, 1}, {0, -1, 0}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                           {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},   {{0, -1, 0}, {0, 0, 1}, {-1, 0, 0}},
                           {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {1, 0, 0}, {0, -1, 0}}};
  auto dot = [](const std::array<float, 3>& a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  for (int side = 0; side < 6; ++side) {
    const SkyFaceImage ours = skyFaceImage(side);
    EXPECT_STREQ(ours.suffix, loaded[texOrder[side]]) << "side " << side;
    for (float s : {-0.75f, 0.0f, 0.5f})
      for (float t : {-0.5f, 0.25f, 0.9f}) {
        const float b[3] = {s, t, 1.0f};
        float d[3];
        for (int j = 0; j < 3; ++j) {
          const int k = stToVec[side][j];
          d[j] = k < 0 ? -b[-k - 1] : b[k - 1];
        }
        const Basis& f = layout[side];
        float u = 0.5f * (1.0f + dot(f.right, d)), v = 0.5f * (1.0f - dot(f.top, d));
        if (ours.turned180) u = 1.0f - u, v = 1.0f - v;
        EXPECT_NEAR(u, 0.5f * (s + 1.0f), 1e-6f) << "side " << side;
        EXPECT_NEAR(v, 1.0f - 0.5f * (t + 1.0f), 1e-6f) << "side " << side;
      }
  }
}

TEST(Material, NodrawPortalFogEnvironment) {
  EXPECT_TRUE(material("c { surfaceparm nodraw surfaceparm playerclip }").invisible);
  EXPECT_TRUE(material("c { surfaceparm trans }").invisible);
  auto mirror = material("m { portal { map $whiteimage blendFunc GL_ONE GL_ONE_MINUS_SRC_ALPHA alphaGen portal 256 } }");
  EXPECT_TRUE(mirror.portal);
  EXPECT_FALSE(mirror.invisible);
  auto fog = material("f { surfaceparm fog fogparms ( 1 0 0 ) 200 }");
  EXPECT_TRUE(fog.fogVolume);
  auto chrome = material("c { { map base.tga } { map env.tga tcGen environment blendFunc add } }");
  EXPECT_TRUE(chrome.environmentMapped);
  EXPECT_EQ(chrome.environmentTexture, "env.tga");
  EXPECT_TRUE(chrome.glowTextures.empty());
  EXPECT_EQ(chrome.baseTexture, "base.tga");
  EXPECT_TRUE(material("w { surfaceparm water { map w.tga } }").liquid);
}

TEST(Material, AnimMapFrames) {
  auto m = material("a { { animMap 2 f1.tga f2.tga } }");
  EXPECT_EQ(m.baseTexture, "f1.tga");
  ASSERT_EQ(m.animFrames.size(), 2u);
  EXPECT_FLOAT_EQ(m.animFrequency, 2);
}

TEST(Material, UvAnimationKnownAnswers) {
  TcMod scroll;
  scroll.kind = TcModKind::Scroll;
  scroll.scroll = {0.25f, -0.5f};
  auto uv = uvTransformAt({scroll}, 3.0).apply(0.1f, 0.2f);
  EXPECT_NEAR(uv[0], 0.1f + 0.75f, 1e-5);  // fract(0.75)
  EXPECT_NEAR(uv[1], 0.2f + 0.5f, 1e-5);   // fract(-1.5) = 0.5

  TcMod rotate;
  rotate.kind = TcModKind::Rotate;
  rotate.degreesPerSecond = 90;
  auto centre = uvTransformAt({rotate}, 1.0).apply(0.5f, 0.5f);
  EXPECT_NEAR(centre[0], 0.5f, 1e-5);
  EXPECT_NEAR(centre[1], 0.5f, 1e-5);
  auto corner = uvTransformAt({rotate}, 1.0).apply(1.0f, 0.5f);  // -90 degrees about the centre
  EXPECT_NEAR(corner[0], 0.5f, 1e-5);
  EXPECT_NEAR(corner[1], 0.0f, 1e-5);

  TcMod scale;
  scale.kind = TcModKind::Scale;
  scale.scroll = {2, 3};
  // Order matters: scale then scroll differs from scroll then scale.
  auto a = uvTransformAt({scale, scroll}, 1.0).apply(1, 1);
  EXPECT_NEAR(a[0], 2.25f, 1e-5);
  EXPECT_NEAR(a[1], 3.5f, 1e-5);
  auto b = uvTransformAt({scroll, scale}, 1.0).apply(1, 1);
  EXPECT_NEAR(b[0], 2.5f, 1e-5);
  EXPECT_NEAR(b[1], 4.5f, 1e-5);

  TcMod stretch;
  stretch.kind = TcModKind::Stretch;
  stretch.wave = {WaveFunc::Sin, 2, 0, 0, 1};  // constant 2 -> scale by 1/2 about the centre
  auto s = uvTransformAt({stretch}, 0.3).apply(1, 0);
  EXPECT_NEAR(s[0], 0.75f, 1e-5);
  EXPECT_NEAR(s[1], 0.25f, 1e-5);

  TcMod transform;
  transform.kind = TcModKind::Transform;
  transform.matrix = {1, 2, 3, 4};
  transform.translate = {5, 6};
  auto t = uvTransformAt({transform}, 0).apply(1, 1);
  EXPECT_NEAR(t[0], 1 * 1 + 1 * 3 + 5, 1e-5);
  EXPECT_NEAR(t[1], 1 * 2 + 1 * 4 + 6, 1e-5);
}

}  // namespace
