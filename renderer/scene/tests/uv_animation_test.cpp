// Texture animation through MaterialDesc::uvTransform and uvWobble: a material replaced with the
// transform of a later time (setMaterial, as an application animating its textures does) moves
// the picture as the transform says; the wobble is evaluated per vertex in object space.
#include <gtest/gtest.h>

#include <cmath>

#include "scene_builders.h"

namespace pa {
namespace {

/// A 20 x 20 quad facing +X (uv u along +Y, 0 at y = -10) with a 20 x 1 repeating map, texels 0-9
/// red and 10-19 green, seen head-on from 2 units: the 8 x 8 picture spans u 0.4 .. 0.6, red in
/// the left column (u ~ 0.41), green in the right one (u ~ 0.59).
struct ScrollingQuad {
  Renderer renderer{RendererConfig{2}};
  MaterialDesc material;
  MaterialId id = kNoId;

  ScrollingQuad() {
    std::vector<uint8_t> pixels;
    for (int x = 0; x < 20; ++x) {
      const bool red = x < 10;
      pixels.insert(pixels.end(), {uint8_t(red ? 255 : 0), uint8_t(red ? 0 : 255), 0, 255});
    }
    TextureDesc texture{20, 1, pixels};
    texture.mipmaps = false;
    material.baseTexture = renderer.addTexture(texture);
    id = renderer.addMaterial(material);
    test::MeshArrays quad = test::quad({0, -10, -10}, {0, 20, 0}, {0, 0, 20});
    quad.setMaterial(id);
    renderer.addInstance(InstanceDesc{renderer.addMesh(quad.desc())});
    LightDesc sun;
    sun.type = LightType::Directional;
    sun.direction = {-1, 0, 0};
    renderer.addLight(sun);
  }
  /// Renders with `m` as the quad's material; returns (left column, right column) colours.
  std::pair<glm::vec3, glm::vec3> render(const MaterialDesc& m) {
    renderer.setMaterial(id, m);
    renderer.commit();
    const FrameView frame = renderer.render(test::lookAt({2, 0, 0}, {0, 0, 0}, 90.0f),
                                            test::settingsFor(Integrator::Lightmap, 8, 1, 1));
    glm::vec3 left(0.0f), right(0.0f);
    for (uint32_t y = 0; y < 8; ++y) {
      left += frame.radiance[y * 8] / 8.0f;
      right += frame.radiance[y * 8 + 7] / 8.0f;
    }
    return {left, right};
  }
};

void expectColour(glm::vec3 actual, glm::vec3 expected) {
  EXPECT_NEAR(actual.r, expected.r, 1e-3f);
  EXPECT_NEAR(actual.g, expected.g, 1e-3f);
  EXPECT_NEAR(actual.b, expected.b, 1e-3f);
}

const glm::vec3 kRed(1, 0, 0), kGreen(0, 1, 0);

TEST(UvAnimation, ScrolledMaterialMovesThePicture) {
  ScrollingQuad scene;
  auto [left, right] = scene.render(scene.material);
  expectColour(left, kRed);
  expectColour(right, kGreen);
  // Scrolling 0.25 texture widths per second, 2 s later: u + 0.5 -> left reads u 0.91 (green),
  // right 1.09 = 0.09 after the wrap (red).
  MaterialDesc later = scene.material;
  later.uvTransform[2] = glm::vec2(std::fmod(0.25f * 2.0f, 1.0f), 0.0f);
  std::tie(left, right) = scene.render(later);
  expectColour(left, kGreen);
  expectColour(right, kRed);
  // A quarter of that (0.125 at 0.5 s): u 0.54 .. 0.71 is green in both columns.
  later.uvTransform[2] = glm::vec2(0.125f, 0.0f);
  std::tie(left, right) = scene.render(later);
  expectColour(left, kGreen);
  expectColour(right, kGreen);
}

TEST(UvAnimation, WobbleMovesEachVertexByItsOwnOffset) {
  ScrollingQuad scene;
  // No spatial variation and phase 0.25: every vertex moves by amplitude x sin(pi / 2) = 0.5.
  MaterialDesc wobbling = scene.material;
  wobbling.uvWobble.amplitude = 0.5f;
  wobbling.uvWobble.phase = 0.25f;
  auto [left, right] = scene.render(wobbling);
  expectColour(left, kGreen);
  expectColour(right, kRed);
  // The linear map turns the u offset into a v offset (the map has one row): nothing moves in u.
  wobbling.uvWobble.linear = glm::mat2(glm::vec2(0, 1), glm::vec2(1, 0));
  wobbling.uvWobble.axisV = glm::vec3(0, 0, 0.25f);   // v offset varies; swapped into u it would show
  wobbling.uvWobble.phase = 0.0f;
  wobbling.uvWobble.axisU = glm::vec3(0.0f);          // u offset sin(0) = 0 everywhere
  std::tie(left, right) = scene.render(wobbling);
  expectColour(left, kRed);
  expectColour(right, kGreen);
}

TEST(UvAnimation, WobbleIsInterpolatedBetweenVertices) {
  // u offset 0.25 sin(2 pi (y / 20 + 0.25)): -0.25 at both vertex rows (y = -10 and +10), +0.25
  // near the picture's centre (y ~ 0). Interpolated from the vertices, u 0.41 .. 0.59 becomes
  // 0.16 .. 0.34: red in both columns (evaluated per pixel it would be green in both).
  ScrollingQuad scene;
  MaterialDesc wobbling = scene.material;
  wobbling.uvWobble.amplitude = 0.25f;
  wobbling.uvWobble.phase = 0.25f;
  wobbling.uvWobble.axisU = glm::vec3(0, 1.0f / 20.0f, 0);
  auto [left, right] = scene.render(wobbling);
  expectColour(left, kRed);
  expectColour(right, kRed);
}

/// Mean radiance of a floor lit only by a lamp above it whose emissive texture (4 x 1, clamped:
/// black, black, white, white) is read through `uvTransform` (or, with `ownUv`, through
/// `emissiveUvTransform` whatever the base's transform).
double floorLitByTexturedLamp(const glm::mat3x2& uvTransform, bool ownUv = false,
                              const glm::mat3x2& emissiveUvTransform = glm::mat3x2(1.0f)) {
  Renderer r{RendererConfig{2}};
  test::MeshArrays floor = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  floor.setMaterial(r.addMaterial(test::diffuse(0.5f)));
  r.addInstance(InstanceDesc{r.addMesh(floor.desc())});
  const std::vector<uint8_t> pixels = {0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255};
  TextureDesc texture{4, 1, pixels};
  texture.wrap = TextureWrap::Clamp;
  texture.mipmaps = false;
  MaterialDesc lamp;
  lamp.baseColor = {0, 0, 0, 1};
  lamp.emissiveTexture = r.addTexture(texture);
  lamp.emission = glm::vec3(4.0f);
  lamp.uvTransform = uvTransform;
  lamp.emissiveOwnUv = ownUv;
  lamp.emissiveUvTransform = emissiveUvTransform;
  test::MeshArrays quad = test::quad({-1, -1, 2}, {2, 0, 0}, {0, 2, 0});
  quad.setMaterial(r.addMaterial(lamp));
  r.addInstance(InstanceDesc{r.addMesh(quad.desc())});
  r.commit();
  const FrameView frame = r.render(test::lookAt({3, 0, 1}, {0, 0, 0}, 60.0f), test::settingsFor(Integrator::Direct, 8, 16, 1));
  double sum = 0.0;
  for (const glm::vec3& c : frame.radiance) sum += (c.r + c.g + c.b) / 3.0;
  return sum / double(frame.radiance.size());
}

// Emission is read at the transformed uvs by the light sampler too: an animated lamp lights the
// scene as it looks. Scaled to the texture's dark half it gives (almost) no light, moved by 0.5
// onto the bright half it gives more than the whole texture does.
TEST(UvAnimation, EmissiveLightFollowsTheUvTransform) {
  const double whole = floorLitByTexturedLamp(glm::mat3x2(1.0f));
  const glm::mat3x2 darkHalf(glm::vec2(0.4f, 0.0f), glm::vec2(0.0f, 1.0f), glm::vec2(0.0f));
  const glm::mat3x2 brightHalf(glm::vec2(0.4f, 0.0f), glm::vec2(0.0f, 1.0f), glm::vec2(0.6f, 0.0f));
  const double dark = floorLitByTexturedLamp(darkHalf);
  const double bright = floorLitByTexturedLamp(brightHalf);
  EXPECT_GT(whole, 0.01);
  EXPECT_LT(dark, 0.05 * whole);
  EXPECT_GT(bright, 1.5 * whole);
}

// A glow layer moving on its own: the emission follows emissiveUvTransform, not the base's map.
TEST(UvAnimation, EmissiveOwnUvTransformLeadsTheLight) {
  const glm::mat3x2 darkHalf(glm::vec2(0.4f, 0.0f), glm::vec2(0.0f, 1.0f), glm::vec2(0.0f));
  const glm::mat3x2 brightHalf(glm::vec2(0.4f, 0.0f), glm::vec2(0.0f, 1.0f), glm::vec2(0.6f, 0.0f));
  const double whole = floorLitByTexturedLamp(glm::mat3x2(1.0f));
  EXPECT_GT(floorLitByTexturedLamp(darkHalf, true, brightHalf), 1.5 * whole);
  EXPECT_LT(floorLitByTexturedLamp(brightHalf, true, darkHalf), 0.05 * whole);
}

TEST(UvAnimation, RejectsANonFiniteWobble) {
  Renderer renderer{RendererConfig{1}};
  MaterialDesc material;
  material.uvWobble.amplitude = NAN;
  EXPECT_THROW(renderer.addMaterial(material), SceneError);
}

}  // namespace
}  // namespace pa
