// TexCoordSource::ReflectionSphere: known answers of the coordinate formula and a small render
// that shows the lookup happens per hit in the instance's object space.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "renderer/scene/textures/reflection_uv.h"
#include "scene_builders.h"

namespace pa {
namespace {

constexpr float kTolerance = 1e-5f;
const float kHalfSqrt2 = std::sqrt(0.5f);

void expectUv(glm::vec2 actual, glm::vec2 expected) {
  EXPECT_NEAR(actual.x, expected.x, kTolerance);
  EXPECT_NEAR(actual.y, expected.y, kTolerance);
}

TEST(ReflectionUv, HeadOnReflectionIsTheCentre) {
  expectUv(reflectionSphereUv({1, 0, 0}, {1, 0, 0}), {0.5f, 0.5f});
  expectUv(reflectionSphereUv({3, 0, 0}, {0.25f, 0, 0}), {0.5f, 0.5f});   // lengths do not matter
}

TEST(ReflectionUv, KnownDirections) {
  // Surface facing +X seen from 45 degrees toward +Y: the view mirrors to (h, -h, 0): s = 0.5 - h/2.
  expectUv(reflectionSphereUv({1, 0, 0}, {1, 1, 0}), {0.5f - 0.5f * kHalfSqrt2, 0.5f});
  // ... toward -Y mirrors to +Y: right half of the map.
  expectUv(reflectionSphereUv({1, 0, 0}, {1, -1, 0}), {0.5f + 0.5f * kHalfSqrt2, 0.5f});
  // ... from above (+Z) mirrors below (r.z < 0): lower half (t > 0.5).
  expectUv(reflectionSphereUv({1, 0, 0}, {1, 0, 1}), {0.5f, 0.5f + 0.5f * kHalfSqrt2});
  // Floor (normal +Z) seen straight from above reflects up: top edge of the map.
  expectUv(reflectionSphereUv({0, 0, 1}, {0, 0, 1}), {0.5f, 0.0f});
  // Grazing view along the surface: the reflection is the view itself mirrored, r = -v.
  expectUv(reflectionSphereUv({0, 0, 1}, {0, 1, 0}), {0.0f, 0.5f});
}

TEST(ReflectionUv, NormalSideDoesNotMatter) {
  for (const glm::vec3 v : {glm::vec3(1, 2, 3), glm::vec3(-1, 0.5f, 0.2f), glm::vec3(0.1f, -4, 1)})
    expectUv(reflectionSphereUv({0.3f, -0.2f, 0.9f}, v), reflectionSphereUv({-0.3f, 0.2f, -0.9f}, v));
}

TEST(ReflectionUv, MatchesMirroredIncomingDirection) {
  // r is the incoming direction (-v) reflected about n, i.e. glm::reflect(-v, n).
  for (const glm::vec3 n : {glm::vec3(0.2f, 0.5f, 0.8f), glm::vec3(-1, 0, 0.1f)}) {
    for (const glm::vec3 v : {glm::vec3(0.3f, -0.7f, 0.2f), glm::vec3(1, 1, 1), glm::vec3(0, 0, -1)}) {
      const glm::vec3 r = glm::reflect(-glm::normalize(v), glm::normalize(n));
      expectUv(reflectionSphereUv(n, v), {0.5f + 0.5f * r.y, 0.5f - 0.5f * r.z});
    }
  }
}

TEST(ReflectionUv, DegenerateInputIsTheCentre) {
  expectUv(reflectionSphereUv({0, 0, 0}, {1, 0, 0}), {0.5f, 0.5f});
  expectUv(reflectionSphereUv({1, 0, 0}, {0, 0, 0}), {0.5f, 0.5f});
  expectUv(reflectionSphereUv({NAN, 0, 0}, {1, 0, 0}), {0.5f, 0.5f});
  expectUv(reflectionSphereUv({1, 0, 0}, {INFINITY, 0, 0}), {0.5f, 0.5f});
}

/// A 20 x 20 quad facing +X in object space, textured with a 4 x 1 clamped map (left half red,
/// right half green) through the reflection sphere, placed by `objectToWorld`, seen from `eye`.
struct ReflectiveQuad {
  Renderer renderer{RendererConfig{2}};
  FrameView frame;
  ReflectiveQuad(const glm::mat4x3& objectToWorld, const glm::vec3& eye, const glm::vec3& target,
                 Integrator integrator) {
    const std::vector<uint8_t> pixels = {255, 0, 0, 255, 255, 0, 0, 255, 0, 255, 0, 255, 0, 255, 0, 255};
    TextureDesc texture{4, 1, pixels};
    texture.wrap = TextureWrap::Clamp;
    texture.mipmaps = false;
    MaterialDesc material;
    material.baseTexture = renderer.addTexture(texture);
    material.baseTexCoords = TexCoordSource::ReflectionSphere;
    test::MeshArrays quad = test::quad({0, -10, -10}, {0, 20, 0}, {0, 0, 20});
    quad.setMaterial(renderer.addMaterial(material));
    InstanceDesc instance{renderer.addMesh(quad.desc())};
    instance.objectToWorld = objectToWorld;
    renderer.addInstance(instance);
    LightDesc sun;
    sun.type = LightType::Directional;
    sun.direction = glm::normalize(target - eye);
    renderer.addLight(sun);
    renderer.commit();
    frame = renderer.render(test::lookAt(eye, target, 90.0f), test::settingsFor(integrator, 8, 1, 1));
  }
  /// Mean of a column of `image` (8 x 8).
  static glm::vec3 column(std::span<const glm::vec3> image, uint32_t x) {
    glm::vec3 sum(0.0f);
    for (uint32_t y = 0; y < 8; ++y) sum += image[y * 8 + x];
    return sum / 8.0f;
  }
  /// The image's left column is the map's red half, its right column the green half.
  static void expectRedLeftGreenRight(std::span<const glm::vec3> image, float tolerance) {
    const glm::vec3 left = column(image, 0);
    const glm::vec3 right = column(image, 7);
    EXPECT_NEAR(left.r, 1.0f, tolerance);
    EXPECT_NEAR(left.g, 0.0f, tolerance);
    EXPECT_NEAR(right.r, 0.0f, tolerance);
    EXPECT_NEAR(right.g, 1.0f, tolerance);
  }
};

// Camera 2 units in front (+X) of the quad looking at it: the image's left half is the -Y side
// of the quad, whose reflection goes to -Y (s < 0.5: red); the right half reflects to +Y (green).
TEST(ReflectionUv, LightmapPresetShowsTheReflectionLookup) {
  ReflectiveQuad scene(glm::mat4x3(1.0f), {2, 0, 0}, {0, 0, 0}, Integrator::Lightmap);
  ReflectiveQuad::expectRedLeftGreenRight(scene.frame.radiance, 1e-3f);
}

// The same quad turned 90 degrees about Z (facing +Y) and seen from +Y: in object space nothing
// changed, so neither did the picture (a world-space lookup would show the right texel everywhere).
TEST(ReflectionUv, LookupIsInObjectSpace) {
  const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 0, 1));
  ReflectiveQuad scene(glm::mat4x3(turn), {0, 2, 0}, {0, 0, 0}, Integrator::Lightmap);
  ReflectiveQuad::expectRedLeftGreenRight(scene.frame.radiance, 1e-3f);
}

// The traced presets read the albedo through the same lookup.
TEST(ReflectionUv, DirectPresetAlbedoUsesTheLookup) {
  ReflectiveQuad scene(glm::mat4x3(1.0f), {2, 0, 0}, {0, 0, 0}, Integrator::Direct);
  ReflectiveQuad::expectRedLeftGreenRight(scene.frame.albedo, 0.01f);
}

TEST(ReflectionUv, RejectsAnUnknownSource) {
  Renderer renderer{RendererConfig{1}};
  MaterialDesc material;
  material.baseTexCoords = static_cast<TexCoordSource>(7);
  EXPECT_THROW(renderer.addMaterial(material), SceneError);
}

TEST(ReflectionUv, RejectsABadShine) {
  Renderer renderer{RendererConfig{1}};
  MaterialDesc unknownTexture;
  unknownTexture.stock.shineTexture = 3;   // no textures added
  EXPECT_THROW(renderer.addMaterial(unknownTexture), SceneError);
  MaterialDesc unknownSource;
  unknownSource.stock.shineTexCoords = static_cast<TexCoordSource>(7);
  EXPECT_THROW(renderer.addMaterial(unknownSource), SceneError);
  MaterialDesc unknownBlend;
  unknownBlend.stock.shineBlend = static_cast<LayerBlend>(42);
  EXPECT_THROW(renderer.addMaterial(unknownBlend), SceneError);
  MaterialDesc negativeColour;
  negativeColour.stock.shineColor = glm::vec3(-1.0f);
  EXPECT_THROW(renderer.addMaterial(negativeColour), SceneError);
}

}  // namespace
}  // namespace pa
