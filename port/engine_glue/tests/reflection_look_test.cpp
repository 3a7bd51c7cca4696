// Models and effects: tcGen environment stages become reflection-sphere materials.
#include <gtest/gtest.h>

#include "port/engine_glue/reflection_look.h"
#include "port/q3formats/shader/shader_parser.h"

namespace glue {
namespace {

ShaderLook lookOf(const char* text) {
  const q3::ShaderScript script = q3::parseShaderScript(text, "env.shader");
  EXPECT_EQ(script.shaders.size(), 1u);
  return lookOfShader(script.shaders.at(0));
}

TEST(ReflectionLook, ChromeStageReadsTheReflectionSphere) {
  // models/powerups/holdable/medkit_base
  const ShaderLook look = lookOf(R"(models/powerups/holdable/medkit_base { { map textures/base_wall/chrome_env.jpg
    tcGen environment rgbGen lightingDiffuse tcMod scale .5 .5 } })");
  EXPECT_TRUE(look.reflectionUv);
  ASSERT_EQ(look.images.size(), 1u);
  EXPECT_EQ(look.images[0], "textures/base_wall/chrome_env.jpg");
  EXPECT_EQ(look.rgbGen, q3::RgbGen::LightingDiffuse);
  pa::MaterialDesc desc;
  applyReflectionLook(look, desc);
  EXPECT_EQ(desc.baseTexCoords, pa::TexCoordSource::ReflectionSphere);
  EXPECT_FLOAT_EQ(desc.uvTransform[0][0], 0.5f);   // s' = 0.5 s
  EXPECT_FLOAT_EQ(desc.uvTransform[1][1], 0.5f);   // t' = 0.5 t
  EXPECT_FLOAT_EQ(desc.uvTransform[0][1], 0.0f);
  EXPECT_FLOAT_EQ(desc.uvTransform[2][0], 0.0f);
  EXPECT_FLOAT_EQ(desc.specular, kReflectionSpecular);
}

TEST(ReflectionLook, TransformTcModMapsToTheUvMatrix) {
  // tcMod transform m00 m01 m10 m11 t0 t1: s' = s m00 + t m10 + t0, t' = s m01 + t m11 + t1.
  const ShaderLook look = lookOf("e { { map env.tga tcGen environment tcMod transform 1 2 3 4 5 6 } }");
  pa::MaterialDesc desc;
  applyReflectionLook(look, desc);
  const glm::vec2 uv = desc.uvTransform * glm::vec3(0.25f, 0.5f, 1.0f);
  EXPECT_FLOAT_EQ(uv.x, 0.25f * 1 + 0.5f * 3 + 5);
  EXPECT_FLOAT_EQ(uv.y, 0.25f * 2 + 0.5f * 4 + 6);
}

TEST(ReflectionLook, AdditiveChromeKeepsItsLayersAndNoGloss) {
  // Powerup glows: additive chrome over additive chrome, both layers reflect.
  const ShaderLook look = lookOf(R"(p { { map a.tga blendFunc GL_SRC_ALPHA GL_ONE tcGen environment }
    { map b.tga blendFunc GL_SRC_ALPHA GL_ONE tcGen environment } })");
  EXPECT_TRUE(look.reflectionUv);
  ASSERT_EQ(look.layers.size(), 1u);
  EXPECT_TRUE(look.layers[0].reflectionUv);
  pa::MaterialDesc desc;
  desc.alphaMode = pa::AlphaMode::Additive;
  applyReflectionLook(look, desc);
  EXPECT_EQ(desc.baseTexCoords, pa::TexCoordSource::ReflectionSphere);
  EXPECT_FLOAT_EQ(desc.specular, 0.0f);   // additive light reflects nothing
}

TEST(ReflectionLook, PlainStagesAreLeftAlone) {
  const ShaderLook look = lookOf("w { { map skin.tga rgbGen lightingDiffuse tcMod scale 2 2 } }");
  EXPECT_FALSE(look.reflectionUv);
  pa::MaterialDesc desc;
  applyReflectionLook(look, desc);
  EXPECT_EQ(desc.baseTexCoords, pa::TexCoordSource::Mesh);
  EXPECT_FLOAT_EQ(desc.uvTransform[0][0], 1.0f);
  EXPECT_FLOAT_EQ(desc.specular, 0.0f);
}

// OpenArena's scripts/models.shader (grenade launcher) and scripts/weapons.shader (rocket).
constexpr const char* kGrenadeLauncher = R"(models/weapons2/grenadel/grenadel
{
  { map models/weapons2/grenadel/grenadel.tga rgbGen lightingDiffuse }
  { map models/weapons2/grenadel/chromey.tga rgbGen lightingDiffuse tcGen environment blendfunc add }
  { map models/weapons2/grenadel/grenadel.tga rgbGen lightingDiffuse blendfunc blend }
})";
constexpr const char* kRocket = R"(rocketProjectile
{
  { map models/ammo/rocket/rocket.tga rgbGen lightingDiffuse }
  { map models/weapons2/machinegun/woodspec.tga blendfunc gl_dst_color gl_src_color tcGen environment }
})";

TEST(ShineLook, OpaqueBaseKeepsItsEnvironmentMappedAddStage) {
  const ShaderLook look = lookOf(kGrenadeLauncher);
  ASSERT_EQ(look.images.size(), 1u);
  EXPECT_EQ(look.images[0], "models/weapons2/grenadel/grenadel.tga");
  EXPECT_FALSE(look.reflectionUv);
  EXPECT_TRUE(look.layers.empty());   // nothing drawn as coincident duplicate triangles
  ASSERT_TRUE(look.shine.has_value());
  EXPECT_EQ(look.shine->image, "models/weapons2/grenadel/chromey.tga");
  EXPECT_EQ(look.shine->blend.src, 1u);   // GL_ONE
  EXPECT_EQ(look.shine->blend.dst, 1u);
  EXPECT_EQ(look.shine->rgbGen, q3::RgbGen::LightingDiffuse);
  EXPECT_TRUE(look.shine->baseRedrawn);   // third stage: the paint blended over the chrome

  pa::MaterialDesc desc;
  applyShineLook(look, 7, desc);
  EXPECT_EQ(desc.stock.shineTexture, 7u);
  EXPECT_EQ(desc.stock.shineTexCoords, pa::TexCoordSource::ReflectionSphere);
  EXPECT_EQ(desc.stock.shineBlend, pa::LayerBlend::Add);
  EXPECT_TRUE(desc.stock.shineVertexColor);
  EXPECT_TRUE(desc.stock.shineMaskedByBaseAlpha);
  EXPECT_EQ(desc.baseTexCoords, pa::TexCoordSource::Mesh);   // the paint keeps its mesh uvs
  EXPECT_FLOAT_EQ(desc.specular, kReflectionSpecular);      // Direct/Path: a glossy lobe
  EXPECT_FALSE(desc.specularTinted);                        // an added chrome reflects white
}

TEST(ShineLook, FilterStageBecomesAModulate2xShine) {
  const ShaderLook look = lookOf(kRocket);
  ASSERT_TRUE(look.shine.has_value());
  EXPECT_EQ(look.shine->image, "models/weapons2/machinegun/woodspec.tga");
  EXPECT_FALSE(look.shine->baseRedrawn);
  pa::MaterialDesc desc;
  applyShineLook(look, 3, desc);
  EXPECT_EQ(desc.stock.shineBlend, pa::LayerBlend::Modulate2x);
  EXPECT_FALSE(desc.stock.shineVertexColor);   // rgbGen identity: white
  EXPECT_FALSE(desc.stock.shineMaskedByBaseAlpha);
  EXPECT_EQ(desc.stock.shineColor, glm::vec3(1.0f));
}

TEST(ShineLook, DstAlphaFilterAndConstColourAndTcMods) {
  const ShaderLook look = lookOf(R"(s { { map paint.tga } { map env.tga blendfunc gl_dst_color gl_dst_alpha
    tcGen environment rgbGen const ( 1 0 0 ) tcMod scale 2 2 } })");
  ASSERT_TRUE(look.shine.has_value());
  pa::MaterialDesc desc;
  applyShineLook(look, 1, desc);
  EXPECT_EQ(desc.stock.shineBlend, pa::LayerBlend::MultiplyAdd);
  EXPECT_EQ(desc.stock.shineColor, glm::vec3(1.0f, 0.0f, 0.0f));
  // It multiplies the paint under it: the glossy lobe reflects in the paint's colour (the
  // lightning gun's blue rear turned dark red in the traced presets' stock look when it was white).
  EXPECT_FLOAT_EQ(desc.specular, kReflectionSpecular);
  EXPECT_TRUE(desc.specularTinted);
  EXPECT_FLOAT_EQ(desc.stock.shineUvTransform[0][0], 2.0f);
  EXPECT_FLOAT_EQ(desc.stock.shineUvTransform[1][1], 2.0f);
}

TEST(ShineLook, MeshUvFilterIsTheShineWhenNoStageIsEnvironmentMapped) {
  // OpenArena 0.8.8's grenade launcher: the paint brightened by itself, dst (1 + src).
  const ShaderLook look = lookOf(R"(models/weapons2/grenadel/grenadel
  { { map models/weapons2/grenadel/grenadel.tga rgbGen lightingDiffuse }
    { map models/weapons2/grenadel/grenadel.tga blendfunc gl_dst_color gl_dst_alpha rgbGen lightingDiffuse
      alphaGen lightingSpecular } })");
  ASSERT_TRUE(look.shine.has_value());
  EXPECT_FALSE(look.shine->reflectionUv);
  pa::MaterialDesc desc;
  applyShineLook(look, 4, desc);
  EXPECT_EQ(desc.stock.shineTexCoords, pa::TexCoordSource::Mesh);
  EXPECT_EQ(desc.stock.shineBlend, pa::LayerBlend::MultiplyAdd);
  EXPECT_FLOAT_EQ(desc.specular, 0.0f);   // paint, not chrome: no glossy lobe
  // An environment-mapped stage wins over an earlier mesh-uv filter (the shotgun's detail).
  const ShaderLook both = lookOf(R"(s { { map paint.tga } { map d_met.tga blendfunc gl_dst_color gl_src_color tcMod scale 8 8 }
    { map gunmetal.tga blendfunc gl_dst_color gl_dst_alpha tcGen environment } })");
  ASSERT_TRUE(both.shine.has_value());
  EXPECT_EQ(both.shine->image, "gunmetal.tga");
}

TEST(ShineLook, OnlyOpaqueBasesWithEnvironmentMappedShineBlendsGetOne) {
  // Additive base: later stages stay layers.
  EXPECT_FALSE(lookOf("a { { map a.tga blendfunc add } { map b.tga blendfunc add tcGen environment } }").shine);
  // Added stage without tcGen environment, or an alpha blend: not a shine.
  EXPECT_FALSE(lookOf("b { { map a.tga } { map b.tga blendfunc add } }").shine);
  EXPECT_FALSE(lookOf("c { { map a.tga } { map b.tga blendfunc blend tcGen environment } }").shine);
  // A lightmap stage between base and shine does not hide the shine.
  EXPECT_TRUE(lookOf("d { { map a.tga } { map $lightmap blendfunc filter } { map b.tga blendfunc add tcGen environment } }").shine);
  // No texture given: the material is left alone; a blended base gets no shine.
  pa::MaterialDesc desc;
  applyShineLook(lookOf(kRocket), pa::kNoId, desc);
  EXPECT_EQ(desc.stock.shineTexture, pa::kNoId);
  desc.alphaMode = pa::AlphaMode::Blend;
  applyShineLook(lookOf(kRocket), 2, desc);
  EXPECT_EQ(desc.stock.shineTexture, pa::kNoId);
  EXPECT_FLOAT_EQ(desc.specular, 0.0f);
}

}  // namespace
}  // namespace glue
