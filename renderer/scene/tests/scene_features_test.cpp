// Scene features beyond materials: sky cube maps, dynamic mesh refits, drawOnTop overlays,
// instance masks, mip selection from the ray footprint, emissive textures, radiance clamp.
#include <gtest/gtest.h>

#include <numbers>

#include "renderer/scene/lights/sky.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::greyStats;
using test::lookAt;
using test::settingsFor;

glm::vec3 meanRadiance(const FrameView& f) {
  glm::dvec3 sum(0.0);
  for (const glm::vec3& v : f.radiance) sum += glm::dvec3(v);
  return glm::vec3(sum / static_cast<double>(f.radiance.size()));
}

TEST(Sky, CubeLookupFacesAndOrientation) {
  EXPECT_EQ(cubeLookup({1, 0, 0}).face, 0u);
  EXPECT_EQ(cubeLookup({-1, 0.2f, 0}).face, 1u);
  EXPECT_EQ(cubeLookup({0, 1, 0.5f}).face, 2u);
  EXPECT_EQ(cubeLookup({0, -1, 0}).face, 3u);
  EXPECT_EQ(cubeLookup({0.1f, 0, 1}).face, 4u);
  EXPECT_EQ(cubeLookup({0, 0, -1}).face, 5u);
  // +X face: image top is +Z, image right is -Y.
  const CubeLookup up = cubeLookup(glm::normalize(glm::vec3(1, 0, 0.9f)));
  EXPECT_NEAR(up.v, 0.05f, 1e-5f);
  const CubeLookup right = cubeLookup(glm::normalize(glm::vec3(1, -0.9f, 0)));
  EXPECT_NEAR(right.u, 0.95f, 1e-5f);
  EXPECT_NEAR(cubeLookup({1, 0, 0}).u, 0.5f, 1e-6f);
  // +Z face: image top is +X, image right is +Y.
  EXPECT_NEAR(cubeLookup(glm::normalize(glm::vec3(0.9f, 0, 1))).v, 0.05f, 1e-5f);
  EXPECT_NEAR(cubeLookup(glm::normalize(glm::vec3(0, 0.9f, 1))).u, 0.95f, 1e-5f);
}

TEST(Sky, CubeMapFacesAreSeenInTheirDirections) {
  Renderer r({2});
  SkyDesc sky;
  sky.color = glm::vec3(1.0f);   // multiplies the cube map
  sky.intensity = 2.0f;
  for (uint32_t f = 0; f < 6; ++f) {
    const auto v = static_cast<uint8_t>(40 * (f + 1));
    const std::vector<uint8_t> px = test::solidPixels(4, 4, v, v, v, 255);
    sky.faces[f] = r.addTexture({4, 4, px, false, TextureWrap::Clamp});
  }
  r.setSky(sky);
  r.commit();
  const glm::vec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (uint32_t f = 0; f < 6; ++f) {
    const FrameView v = r.render(lookAt({0, 0, 0}, dirs[f], 20.0f), settingsFor(Integrator::Path, 4, 1));
    EXPECT_NEAR(meanRadiance(v).g, 2.0f * 40.0f * (f + 1) / 255.0f, 1e-5f) << f;
    EXPECT_TRUE(std::isinf(v.depth[0]));
  }
}

/// A sky picture of one constant radiance.
class ConstantSkyPicture final : public SkyPicture {
 public:
  explicit ConstantSkyPicture(glm::vec3 radiance) : radiance_(radiance) {}
  glm::vec3 radiance(const glm::vec3&) const override { return radiance_; }

 private:
  glm::vec3 radiance_;
};

TEST(Sky, APictureOnlyChangeKeepsTheSamplingAndShowsTheNewPicture) {
  std::vector<std::shared_ptr<const Texture>> textures;
  SkyDesc desc;
  desc.color = glm::vec3(1.0f);
  for (uint32_t f = 0; f < 6; ++f) {
    const auto v = static_cast<uint8_t>(30 * (f + 1));
    const std::vector<uint8_t> px = test::solidPixels(4, 4, v, v, v, 255);
    textures.push_back(std::make_shared<const Texture>(Texture::fromDesc({4, 4, px, false, TextureWrap::Clamp}, "face")));
    desc.faces[f] = f;
  }
  desc.picture = std::make_shared<ConstantSkyPicture>(glm::vec3(0.25f));
  Sky sky(desc, textures);
  EXPECT_FALSE(Sky{}.sameButPicture(desc, textures)) << "a default sky was made from nothing";
  SkyDesc moved = desc;
  moved.picture = std::make_shared<ConstantSkyPicture>(glm::vec3(0.5f));
  ASSERT_TRUE(sky.sameButPicture(moved, textures));
  const Sky rebuilt(moved, textures);
  sky.setPicture(moved.picture);
  const glm::vec3 up(0.0f, 0.0f, 1.0f), side = glm::normalize(glm::vec3(1.0f, 0.3f, 0.2f));
  for (const glm::vec3& d : {up, side}) {
    EXPECT_EQ(sky.radiance(d), rebuilt.radiance(d));
    EXPECT_EQ(sky.pdf(d), rebuilt.pdf(d));   // the faces' sampling distribution is the same
  }
  EXPECT_EQ(sky.average(), rebuilt.average());
  // Anything but the picture is another sky.
  for (auto change : std::initializer_list<void (*)(SkyDesc&)>{
           [](SkyDesc& d) { d.color = glm::vec3(0.5f); }, [](SkyDesc& d) { d.intensity = 2.0f; },
           [](SkyDesc& d) { d.lightingScale = 0.5f; }, [](SkyDesc& d) { d.faces[3] = kNoId; },
           [](SkyDesc& d) { d.ambientRadiance = glm::vec3(0.1f); }, [](SkyDesc& d) { d.minimumRadiance = glm::vec3(0.1f); }}) {
    SkyDesc other = desc;
    change(other);
    EXPECT_FALSE(sky.sameButPicture(other, textures));
  }
  // A face texture replaced under the same id is another face.
  std::vector<std::shared_ptr<const Texture>> replaced = textures;
  const std::vector<uint8_t> px = test::solidPixels(4, 4, 250, 10, 10, 255);
  replaced[2] = std::make_shared<const Texture>(Texture::fromDesc({4, 4, px, false, TextureWrap::Clamp}, "face"));
  EXPECT_FALSE(sky.sameButPicture(desc, replaced));
}

TEST(Sky, CommitShowsAMovedPictureOfTheSameSky) {
  Renderer r({2});
  SkyDesc sky;
  sky.color = glm::vec3(1.0f);
  for (uint32_t f = 0; f < 6; ++f) {
    const std::vector<uint8_t> px = test::solidPixels(4, 4, 100, 100, 100, 255);
    sky.faces[f] = r.addTexture({4, 4, px, false, TextureWrap::Clamp});
  }
  for (const float shown : {0.25f, 0.75f, 0.5f}) {   // a moving sky: only its picture changes
    sky.picture = std::make_shared<ConstantSkyPicture>(glm::vec3(shown));
    r.setSky(sky);
    r.commit();
    const FrameView v = r.render(lookAt({0, 0, 0}, {1, 0, 0}, 20.0f), settingsFor(Integrator::Path, 4, 1));
    EXPECT_NEAR(meanRadiance(v).g, shown, 1e-6f);
  }
}

TEST(Scene, DynamicMeshUpdatesAreVisibleAfterCommit) {
  Renderer r({2});
  test::MeshArrays q = test::quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  MeshDesc d = q.desc();
  d.dynamic = true;
  const MeshId mesh = r.addMesh(d);
  r.addInstance({mesh});
  r.commit();
  const Camera cam = lookAt({0, 0, 5}, {0, 0, 0}, 10.0f);
  const RenderSettings s = settingsFor(Integrator::Lightmap, 4, 1);
  EXPECT_NEAR(r.render(cam, s).depth[5], 5.0f, 0.05f);
  for (auto& p : q.positions) p.z = 2.0f;   // same topology: refit
  d = q.desc();
  d.dynamic = true;
  r.updateMesh(mesh, d);
  EXPECT_NEAR(r.render(cam, s).depth[5], 5.0f, 0.05f);   // not committed yet
  r.commit();
  EXPECT_NEAR(r.render(cam, s).depth[5], 3.0f, 0.05f);
  for (auto& p : q.positions) p.x += 10.0f;   // moved out of view
  d = q.desc();
  d.dynamic = true;
  r.updateMesh(mesh, d);
  r.commit();
  EXPECT_TRUE(std::isinf(r.render(cam, s).depth[5]));
}

TEST(Scene, DrawOnTopInstancesWinOverCloserWorldGeometry) {
  Renderer r({2});
  MaterialDesc red, green;
  red.baseColor = {1, 0, 0, 1};
  green.baseColor = {0, 1, 0, 1};
  test::MeshArrays wall = test::quad({-5, -5, 3}, {10, 0, 0}, {0, 10, 0});
  wall.setMaterial(r.addMaterial(red));
  test::MeshArrays weapon = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  weapon.setMaterial(r.addMaterial(green));
  r.addInstance({r.addMesh(wall.desc())});
  InstanceDesc overlay{r.addMesh(weapon.desc())};
  overlay.drawOnTop = true;
  r.addInstance(overlay);
  r.commit();
  const glm::vec3 c = meanRadiance(r.render(lookAt({0, 0, 5}, {0, 0, 0}, 20.0f), settingsFor(Integrator::Lightmap, 4, 1)));
  EXPECT_NEAR(c.g, 1.0f, 1e-5f);
  EXPECT_NEAR(c.r, 0.0f, 1e-5f);
}

TEST(Scene, InstanceMasksSelectRayKinds) {
  // A blocker without the camera bit is invisible but still shadows the floor under a sun.
  Renderer r({2});
  test::MeshArrays floor = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  test::MeshArrays blocker = test::quad({-5, -5, 1}, {10, 0, 0}, {0, 10, 0});
  floor.setMaterial(r.addMaterial(test::diffuse(0.5f)));
  r.addInstance({r.addMesh(floor.desc())});
  InstanceDesc b{r.addMesh(blocker.desc())};
  b.mask = kMaskShadow | kMaskBounce;
  const InstanceId blockerId = r.addInstance(b);
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.intensity = std::numbers::pi_v<float>;
  r.addLight(sun);
  r.commit();
  const Camera cam = lookAt({0, 0, 3}, {0, 0, 0}, 20.0f);
  const RenderSettings s = settingsFor(Integrator::Direct, 4, 1, 1);
  FrameView f = r.render(cam, s);
  EXPECT_NEAR(f.depth[5], 3.0f, 0.05f);   // sees the floor through the blocker
  EXPECT_EQ(greyStats(f).maxValue, 0.0);  // in its shadow
  b.mask = kMaskBounce;                   // no shadow bit: the floor is lit
  r.setInstance(blockerId, b);
  r.commit();
  EXPECT_NEAR(greyStats(r.render(cam, s)).mean, 0.5, 1e-4);
}

/// A floor quad (winding normal +z) with `normal` at every vertex, a sun straight above, seen
/// from a camera low on the -x side; the mean of a Direct render.
double floorSeenFromTheSide(const glm::vec3& normal) {
  Renderer r({2});
  struct Floor : test::MeshArrays {
    std::vector<glm::vec3> normals;
  } floor;
  static_cast<test::MeshArrays&>(floor) = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  floor.normals.assign(4, normal);
  floor.setMaterial(r.addMaterial(test::diffuse(0.5f)));
  r.addInstance({r.addMesh(meshDescOf(floor, floor.materials))});
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.direction = {0, 0, -1};
  sun.intensity = std::numbers::pi_v<float>;
  r.addLight(sun);
  r.commit();
  return greyStats(r.render(lookAt({-3, 0, 1}, {0, 0, 0}, 20.0f), settingsFor(Integrator::Direct, 4, 1, 1))).mean;
}

TEST(Scene, AShadingNormalTheViewerSeesFromBelowIsBentTowardItNotBlack) {
  // Vertex normals that disagree with the faces (some game models have them) can put the
  // viewer below the shading normal's horizon while the face looks at the viewer: that point
  // would reflect nothing. The normal is bent toward the viewer there.
  const double faceNormal = floorSeenFromTheSide({0, 0, 1});
  EXPECT_NEAR(faceNormal, 0.5, 1e-4);
  const double awayFromTheViewer = floorSeenFromTheSide(glm::normalize(glm::vec3(1.0f, 0.0f, 0.1f)));
  EXPECT_GT(awayFromTheViewer, 0.1 * faceNormal);
  // Where the viewer sees the shading normal from above, it is left alone: a normal leaning
  // toward the viewer gives the sun's cosine along it.
  const glm::vec3 toward = glm::normalize(glm::vec3(-1.0f, 0.0f, 1.0f));
  EXPECT_NEAR(floorSeenFromTheSide(toward), 0.5 * toward.z, 1e-4);
}

TEST(Scene, HiddenInstancesNeitherShowNorLight) {
  // An emissive quad above a floor lights it; with mask 0 (a mover the game did not add this
  // frame) it must neither be seen, nor shadow, nor remain a light, and it comes back when shown.
  Renderer r({2});
  test::MeshArrays floor = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  floor.setMaterial(r.addMaterial(test::diffuse(0.5f)));
  r.addInstance({r.addMesh(floor.desc())});
  MaterialDesc lampMaterial;
  lampMaterial.baseColor = {0, 0, 0, 1};
  lampMaterial.emission = glm::vec3(4.0f);
  lampMaterial.twoSided = true;
  test::MeshArrays lamp = test::quad({-1, -1, 2}, {2, 0, 0}, {0, 2, 0});
  lamp.setMaterial(r.addMaterial(lampMaterial));
  InstanceDesc lampInstance{r.addMesh(lamp.desc())};
  const InstanceId lampId = r.addInstance(lampInstance);
  r.commit();
  const Camera cam = lookAt({3, 0, 1}, {0, 0, 0}, 60.0f);
  const RenderSettings s = settingsFor(Integrator::Direct, 8, 1, 1);
  const double lit = greyStats(r.render(cam, s)).mean;
  EXPECT_GT(lit, 0.01);
  lampInstance.mask = 0;
  r.setInstance(lampId, lampInstance);
  r.commit();
  EXPECT_EQ(greyStats(r.render(cam, s)).maxValue, 0.0);   // no light left, nothing emissive seen
  lampInstance.mask = kMaskAll;
  r.setInstance(lampId, lampInstance);
  r.commit();
  EXPECT_DOUBLE_EQ(greyStats(r.render(cam, s)).mean, lit);
}

TEST(Scene, DistantFineTexturesUseCoarseMips) {
  // A 256x256 one-texel checker seen so that each pixel covers ~32x32 texels: the footprint
  // picks a coarse level, so every single sample is already ~0.5 grey (no aliasing noise).
  Renderer r({2});
  std::vector<uint8_t> px(256 * 256 * 4);
  for (uint32_t y = 0; y < 256; ++y)
    for (uint32_t x = 0; x < 256; ++x) {
      const uint8_t v = ((x + y) & 1) ? 255 : 0;
      uint8_t* p = &px[(y * 256 + x) * 4];
      p[0] = p[1] = p[2] = v;
      p[3] = 255;
    }
  MaterialDesc m;
  m.baseTexture = r.addTexture({256, 256, px, false});
  test::MeshArrays q = test::quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  q.setMaterial(r.addMaterial(m));
  r.addInstance({r.addMesh(q.desc())});
  r.commit();
  const FrameView f = r.render(lookAt({0, 0, 2}, {0, 0, 0}, 40.0f), settingsFor(Integrator::Lightmap, 8, 1));
  const test::FrameStats st = greyStats(f);
  EXPECT_GT(st.minValue, 0.45);
  EXPECT_LT(st.maxValue, 0.55);
}

TEST(Scene, EmissiveTextureModulatesEmission) {
  Renderer r({2});
  const std::vector<uint8_t> px = test::solidPixels(2, 2, 255, 128, 0, 255);
  MaterialDesc lamp;
  lamp.baseColor = {0, 0, 0, 1};
  lamp.emission = glm::vec3(2.0f);
  lamp.emissiveTexture = r.addTexture({2, 2, px, false});
  test::MeshArrays q = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  q.setMaterial(r.addMaterial(lamp));
  r.addInstance({r.addMesh(q.desc())});
  r.commit();
  const glm::vec3 c = meanRadiance(r.render(lookAt({0, 0, 2}, {0, 0, 0}, 20.0f), settingsFor(Integrator::Path, 4, 1)));
  EXPECT_NEAR(c.r, 2.0f, 1e-5f);
  EXPECT_NEAR(c.g, 2.0f * 128.0f / 255.0f, 1e-5f);
  EXPECT_NEAR(c.b, 0.0f, 1e-6f);
}

TEST(Scene, RadianceClampBoundsIndirectContributions) {
  // Floor lit by a small, very bright emitter (radiance ~0.14 without clamp): with a clamp of
  // 0.05 each light contribution is capped, so no pixel exceeds NEE + BSDF hit = 2 * 0.05.
  Renderer r({2});
  test::MeshArrays floor = test::quad({-5, -5, 0}, {10, 0, 0}, {0, 10, 0});
  floor.setMaterial(r.addMaterial(test::diffuse(0.8f)));
  r.addInstance({r.addMesh(floor.desc())});
  MaterialDesc lamp;
  lamp.baseColor = {0, 0, 0, 1};
  lamp.emission = glm::vec3(1000.0f);
  test::MeshArrays small = test::quad({-0.05f, -0.05f, 2}, {0, 0.1f, 0}, {0.1f, 0, 0});
  small.setMaterial(r.addMaterial(lamp));
  r.addInstance({r.addMesh(small.desc())});
  r.commit();
  RenderSettings s = settingsFor(Integrator::Path, 8, 4, 2);
  s.radianceClamp = 0.05f;
  const test::FrameStats clamped = greyStats(r.render(lookAt({1, 1, 1}, {1.5f, 1.5f, 0}, 20.0f), s));
  EXPECT_LE(clamped.maxValue, 2 * 0.05 + 1e-6);
  s.radianceClamp = 0.0f;
  const test::FrameStats unclamped = greyStats(r.render(lookAt({1, 1, 1}, {1.5f, 1.5f, 0}, 20.0f), s));
  EXPECT_GT(unclamped.mean, clamped.mean);
}

}  // namespace
}  // namespace pa

namespace pa {
namespace {

/// Floor of albedo 1 under a cube-map sky whose +Z face has radiance `top` and whose other
/// faces have radiance `sides` (linear data, color 1). Returns the statistics of the frame
/// looking down at it (the frame itself dies with the renderer).
test::FrameStats renderUnderCubeSky(float top, float sides, Integrator integrator, uint32_t spp) {
  Renderer r({2});
  SkyDesc sky;
  sky.color = glm::vec3(1.0f);
  for (uint32_t f = 0; f < 6; ++f) {
    const auto v = static_cast<uint8_t>(std::lround(255.0f * (f == 4 ? top : sides)));
    const std::vector<uint8_t> px = test::solidPixels(8, 8, v, v, v, 255);
    sky.faces[f] = r.addTexture({8, 8, px, false, TextureWrap::Clamp});
  }
  r.setSky(sky);
  test::MeshArrays floor = test::quad({-50, -50, 0}, {100, 0, 0}, {0, 100, 0});
  floor.setMaterial(r.addMaterial(test::diffuse(1.0f)));
  r.addInstance({r.addMesh(floor.desc())});
  r.commit();
  return greyStats(r.render(lookAt({0, 0, 1}, {0, 0, 0}, 1.0f), settingsFor(integrator, 8, spp, 1)));
}

TEST(Sky, CubeMapImportanceSamplingKnownAnswer) {
  // Only the top face is lit: E = B * integral over the face z = 1 of cos / r^2 dA
  //   = B * integral over [-1,1]^2 of 1 / (1 + x^2 + y^2)^2, integrated numerically here.
  double projected = 0.0;
  constexpr int kN = 1000;
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i) {
      const double x = -1.0 + (i + 0.5) * 2.0 / kN, y = -1.0 + (j + 0.5) * 2.0 / kN;
      const double r2 = 1.0 + x * x + y * y;
      projected += (4.0 / (kN * kN)) / (r2 * r2);
    }
  const double expected = 1.0 / std::numbers::pi * projected;   // albedo 1, B = 1
  for (Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    const test::FrameStats s = renderUnderCubeSky(1.0f, 0.0f, integrator, 64);
    EXPECT_NEAR(s.mean, expected, 4.0 * s.standardError + 1e-3 * expected) << s.standardError;
  }
  // A uniform cube map is a uniform sky: radiance = albedo * L.
  const test::FrameStats uniform = renderUnderCubeSky(0.6f, 0.6f, Integrator::Path, 64);
  const double l = 153.0 / 255.0;
  EXPECT_NEAR(uniform.mean, l, 4.0 * uniform.standardError + 1e-3 * l);
}

}  // namespace
}  // namespace pa
