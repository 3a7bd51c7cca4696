// Known-answer tests of motion vectors and temporal accumulation through pa::Renderer, on small
// scenes built here.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstring>
#include <tuple>
#include <vector>

#include "motion_checks.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::bytesOf;
using test::lookAt;
using test::settingsFor;

/// Floor and back wall with smooth vertex-colour gradients (fullbright under Lightmap: no noise).
void buildGradientScene(Renderer& r) {
  const MaterialId white = r.addMaterial(test::diffuse(1.0f));
  test::MeshArrays floor = test::quad({-6, -6, 0}, {12, 0, 0}, {0, 12, 0});
  floor.colors = {{0.1f, 0.2f, 0.9f, 1}, {0.9f, 0.3f, 0.1f, 1}, {0.2f, 0.9f, 0.3f, 1}, {0.8f, 0.8f, 0.2f, 1}};
  test::addMesh(r, floor, white);
  test::MeshArrays wall = test::quad({-6, 6, 0}, {12, 0, 0}, {0, 0, 6});
  wall.colors = {{0.9f, 0.1f, 0.5f, 1}, {0.1f, 0.9f, 0.9f, 1}, {0.5f, 0.5f, 0.1f, 1}, {0.2f, 0.1f, 0.2f, 1}};
  test::addMesh(r, wall, white);
  r.commit();
}

/// Bilinear fetch of image `a` (w x h) at continuous pixel-centre coordinates (fx, fy).
glm::vec3 bilinear(std::span<const glm::vec3> a, uint32_t w, float fx, float fy) {
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const float tx = fx - static_cast<float>(x0), ty = fy - static_cast<float>(y0);
  const auto at = [&](int x, int y) { return a[size_t(y) * w + size_t(x)]; };
  return (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x0 + 1, y0)) + ty * ((1 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1));
}

TEST(Reprojection, StaticSceneUnderCameraMotionMatchesReRender) {
  Renderer r({2});
  buildGradientScene(r);
  const uint32_t size = 64;
  RenderSettings s = settingsFor(Integrator::Lightmap, size, 16);
  s.accumulate = false;
  const Camera a = lookAt({0.0f, -4.0f, 3.0f}, {0.0f, 2.0f, 1.0f}, 60.0f);
  const Camera b = lookAt({0.6f, -3.6f, 3.2f}, {0.4f, 2.0f, 1.2f}, 60.0f);   // moved and turned
  const FrameView fa = r.render(a, s);
  const std::vector<glm::vec3> imageA(fa.radiance.begin(), fa.radiance.end());
  const std::vector<InstanceId> instanceA(fa.instance.begin(), fa.instance.end());
  const FrameView fb = r.render(b, s);
  double reprojected = 0.0, unmoved = 0.0;
  size_t count = 0, withMotion = 0;
  for (uint32_t y = 0; y < size; ++y) {
    for (uint32_t x = 0; x < size; ++x) {
      const size_t i = size_t{y} * size + x;
      const glm::vec2 m = fb.motion[i];
      if (!std::isfinite(m.x)) continue;
      ++withMotion;
      const float fx = static_cast<float>(x) + m.x, fy = static_cast<float>(y) + m.y;
      if (!(fx >= 0.0f && fy >= 0.0f && fx < size - 1.0f && fy < size - 1.0f)) continue;
      // Only where the four taps lie on the same surface (a bilinear fetch across an edge blends).
      const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
      bool same = true;
      for (int dy = 0; dy <= 1; ++dy)
        for (int dx = 0; dx <= 1; ++dx) same = same && instanceA[size_t(y0 + dy) * size + size_t(x0 + dx)] == fb.instance[i];
      if (!same) continue;
      const glm::vec3 fetched = bilinear(imageA, size, fx, fy);
      reprojected += glm::length(fetched - fb.radiance[i]);
      unmoved += glm::length(imageA[i] - fb.radiance[i]);
      ++count;
    }
  }
  EXPECT_GT(withMotion, size_t{size} * size * 9 / 10);   // no sky in view: nearly every pixel moves
  ASSERT_GT(count, size_t{size} * size / 2);
  reprojected /= static_cast<double>(count);
  unmoved /= static_cast<double>(count);
  EXPECT_LT(reprojected, 0.01) << "unmoved " << unmoved;
  EXPECT_GT(unmoved, 10.0 * reprojected);   // the motion is what made it match
}

TEST(Reprojection, MovingInstanceHasItsOwnMotionAndTheStillWorldNone) {
  Renderer r({2});
  const MaterialId grey = r.addMaterial(test::diffuse(0.5f));
  test::addMesh(r, test::quad({-6, -6, 0}, {12, 0, 0}, {0, 12, 0}), grey);
  test::MeshArrays box = test::quad({-0.5f, -0.5f, 0.01f}, {1, 0, 0}, {0, 1, 0});
  box.setMaterial(grey);
  const MeshId boxMesh = r.addMesh(box.desc());
  InstanceDesc moving{boxMesh};
  const InstanceId id = r.addInstance(moving);
  r.commit();
  const uint32_t size = 64;
  RenderSettings s = settingsFor(Integrator::Lightmap, size, 1);
  s.accumulate = false;
  const Camera top = lookAt({0, 0, 10}, {0, 0, 0}, 40.0f);   // looks down: +X is up on the film
  r.render(top, s);
  moving.objectToWorld[3] = glm::vec3(0.0f, 1.0f, 0.0f);   // one unit along +Y
  r.setInstance(id, moving);
  r.commit();
  const FrameView f = r.render(top, s);
  // At distance 10 with a 40 degree field, one unit spans 32 / (10 tan 20 deg) = 8.79 pixels;
  // the box's pixels point back to where it was.
  test::expectMotionOnlyOn(f, id, test::pixelsPerUnitAt10(size), 30, 1000);
}

TEST(Reprojection, InstanceShownAgainAfterBeingHiddenIsDisoccluded) {
  // The glue reuses instances: a slot hidden last frame (mask 0) and shown now carries no
  // previous transform, so its pixels have no motion and start a new history.
  Renderer r({2});
  const MaterialId grey = r.addMaterial(test::diffuse(0.5f));
  test::addMesh(r, test::quad({-6, -6, 0}, {12, 0, 0}, {0, 12, 0}), grey);
  test::MeshArrays box = test::quad({-1, -1, 0.01f}, {2, 0, 0}, {0, 2, 0});
  box.setMaterial(grey);
  InstanceDesc desc{r.addMesh(box.desc())};
  desc.mask = 0;
  const InstanceId id = r.addInstance(desc);
  r.commit();
  RenderSettings s = settingsFor(Integrator::Direct, 32, 1, 1);
  s.accumulate = false;
  s.temporal = true;
  const Camera top = lookAt({0, 0, 10}, {0, 0, 0}, 40.0f);
  r.render(top, s);
  desc.mask = kMaskAll;
  r.setInstance(id, desc);
  r.commit();
  const FrameView f = r.render(top, s);
  size_t onBox = 0;
  for (size_t i = 0; i < f.motion.size(); ++i) {
    if (f.instance[i] != id) {
      EXPECT_TRUE(std::isfinite(f.motion[i].x)) << i;   // the floor moved by 0: it has motion
      continue;
    }
    ++onBox;
    EXPECT_FALSE(std::isfinite(f.motion[i].x)) << i;
    EXPECT_EQ(f.historyLength[i], 1.0f) << i;
  }
  EXPECT_GT(onBox, 20u);
}

/// Floor lit by two point lights far apart; the left one can be switched off. Black sky.
struct TwoLamps {
  Renderer r{RendererConfig{2}};
  LightId left = kNoId;
  LightDesc leftDesc;
  TwoLamps() {
    left = test::addFloorWithTwoLamps(r, leftDesc);
    r.commit();
  }
  /// Looks down at the floor from the -Y side: film +x is world +x, and world x = 0 is the middle column.
  static Camera camera() { return lookAt({0, -3, 9}, {0, 0, 0}, 100.0f); }
};

TEST(TemporalAccumulation, SwitchedOffLightLeavesNothingLitAfterTwoFrames) {
  TwoLamps scene;
  RenderSettings s = settingsFor(Integrator::Direct, 64, 1, 1);
  s.accumulate = false;
  s.denoise = true;
  s.temporal = true;
  std::vector<float> lit;
  for (uint32_t frame = 0; frame < 24; ++frame) {
    s.seed = frame;
    const FrameView f = scene.r.render(TwoLamps::camera(), s);
    lit.assign(f.radiance.size(), 0.0f);
    for (size_t i = 0; i < f.radiance.size(); ++i) lit[i] = f.radiance[i].g;
  }
  LightDesc off = scene.leftDesc;
  off.intensity = 0.0f;
  scene.r.setLight(scene.left, off);
  scene.r.commit();
  FrameView f;
  for (uint32_t frame = 24; frame < 26; ++frame) {
    s.seed = frame;
    f = scene.r.render(TwoLamps::camera(), s);
  }
  // Pixels the left lamp lit (x < 28: world x < 0, out of the right lamp's reach) are dark: below
  // 1% of the brightest lit pixel.
  float brightest = 0.0f;
  for (float v : lit) brightest = std::max(brightest, v);
  size_t checked = 0;
  for (uint32_t y = 0; y < 64; ++y) {
    for (uint32_t x = 0; x < 28; ++x) {
      const size_t i = size_t{y} * 64 + x;
      if (!(lit[i] > 0.01f * brightest)) continue;
      ++checked;
      EXPECT_LT(f.radiance[i].g, 0.01f * brightest) << x << "," << y << " was " << lit[i];
    }
  }
  EXPECT_GT(checked, 200u);
}

/// Cornell-like corner with a sphere and a point light (shadows, gradients), grey sky.
void buildLitScene(Renderer& r) {
  const MaterialId grey = r.addMaterial(test::diffuse(0.7f));
  test::addMesh(r, test::quad({-3, -3, 0}, {6, 0, 0}, {0, 6, 0}), grey);
  test::addMesh(r, test::quad({-3, 3, 0}, {6, 0, 0}, {0, 0, 4}), grey);
  test::addMesh(r, test::sphere({0, 0.5f, 1}, 1.0f, 12, 24), grey);
  LightDesc point;
  point.position = {2, -2, 3};
  point.intensity = 6.0f;
  point.radius = 0.3f;
  r.addLight(point);
  SkyDesc sky;
  sky.color = glm::vec3(0.2f);
  r.setSky(sky);
  r.commit();
}

Camera litCamera() { return lookAt({0, -6, 2}, {0, 0, 1}, 50.0f); }

double rmsError(std::span<const glm::vec3> a, const std::vector<glm::vec3>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += std::pow(static_cast<double>(a[i].g - b[i].g), 2.0);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

double meanGreen(std::span<const glm::vec3> a) {
  double sum = 0.0;
  for (const glm::vec3& c : a) sum += c.g;
  return sum / static_cast<double>(a.size());
}

TEST(TemporalAccumulation, StillCameraConvergesTowardTheAccumulatedMean) {
  const uint32_t size = 48;
  Renderer reference({2});
  buildLitScene(reference);
  const FrameView ref = reference.render(litCamera(), settingsFor(Integrator::Direct, size, 1024, 1));
  const std::vector<glm::vec3> truth(ref.radiance.begin(), ref.radiance.end());

  for (const bool denoise : {false, true}) {
    Renderer r({2});
    buildLitScene(r);
    RenderSettings s = settingsFor(Integrator::Direct, size, 1, 1);
    s.accumulate = false;
    s.denoise = denoise;
    s.seed = 1000;
    const double single = rmsError(r.render(litCamera(), s).radiance, truth);
    s.temporal = true;
    FrameView f;
    for (uint32_t frame = 0; frame < 40; ++frame) {
      s.seed = frame;
      f = r.render(litCamera(), s);
    }
    const double temporal = rmsError(f.radiance, truth);
    EXPECT_LT(temporal, (denoise ? 0.7 : 0.35) * single) << "denoise " << denoise;
    EXPECT_NEAR(meanGreen(f.radiance) / meanGreen(truth), 1.0, 0.03) << "denoise " << denoise;
  }
}

TEST(TemporalAccumulation, MovingCameraSameImageWithOneAndTwoThreads) {
  const auto run = [](uint32_t threads) {
    Renderer r({threads});
    buildLitScene(r);
    RenderSettings s = settingsFor(Integrator::Path, 40, 1, 2);
    s.accumulate = false;
    s.denoise = true;
    s.temporal = true;
    FrameView f;
    for (uint32_t frame = 0; frame < 4; ++frame) {
      s.seed = frame;
      f = r.render(lookAt({0.1f * static_cast<float>(frame), -6, 2}, {0, 0, 1}, 50.0f), s);
    }
    return std::vector<glm::vec3>(f.radiance.begin(), f.radiance.end());
  };
  const auto one = run(1), two = run(2);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(glm::vec3)), 0);
}

TEST(Reprojection, FrameWithoutMotionVectorsWritesTheIdsAndTheNextFrameIsAlike) {
  // motionVectors off (the game's lightmap preset without TAAU): no motion handed out, the same
  // picture and ids; the next frame, with motion, moves as if every frame had had it.
  const auto build = [](Renderer& r, InstanceDesc& moving, InstanceId& id) {
    const MaterialId grey = r.addMaterial(test::diffuse(0.5f));
    test::addMesh(r, test::quad({-6, -6, 0}, {12, 0, 0}, {0, 12, 0}), grey);
    test::MeshArrays box = test::quad({-0.5f, -0.5f, 0.01f}, {1, 0, 0}, {0, 1, 0});
    box.setMaterial(grey);
    moving = InstanceDesc{r.addMesh(box.desc())};
    id = r.addInstance(moving);
    r.commit();
  };
  Renderer with({2}), without({2});
  InstanceDesc movingWith, movingWithout;
  InstanceId idWith = kNoId, idWithout = kNoId;
  build(with, movingWith, idWith);
  build(without, movingWithout, idWithout);
  RenderSettings s = settingsFor(Integrator::Lightmap, 64, 1);
  s.accumulate = false;
  s.pixelCentres = true;
  const Camera top = lookAt({0, 0, 10}, {0, 0, 0}, 40.0f);
  const FrameView a = with.render(top, s);
  const std::vector<uint8_t> radianceA = bytesOf(a.radiance), instanceA = bytesOf(a.instance),
                             materialA = bytesOf(a.material);
  EXPECT_FALSE(a.motion.empty());
  s.motionVectors = false;
  const FrameView b = without.render(top, s);
  EXPECT_TRUE(b.motion.empty());
  EXPECT_EQ(bytesOf(b.radiance), radianceA);
  EXPECT_EQ(bytesOf(b.instance), instanceA);
  EXPECT_EQ(bytesOf(b.material), materialA);

  for (auto [r, moving, id] : {std::tuple{&with, &movingWith, idWith}, std::tuple{&without, &movingWithout, idWithout}}) {
    moving->objectToWorld[3] = glm::vec3(0.0f, 1.0f, 0.0f);
    r->setInstance(id, *moving);
    r->commit();
  }
  s.motionVectors = true;
  const FrameView next = with.render(top, s);
  const std::vector<uint8_t> motion = bytesOf(next.motion), radiance = bytesOf(next.radiance);
  const FrameView nextWithout = without.render(top, s);
  EXPECT_EQ(bytesOf(nextWithout.motion), motion);
  EXPECT_EQ(bytesOf(nextWithout.radiance), radiance);
  test::expectMotionOnlyOn(nextWithout, idWithout, test::pixelsPerUnitAt10(64), 30, 1000);
}

TEST(TemporalAccumulation, MotionVectorsOffChangesNoTemporalFrame) {
  // The temporal stage reads the motion and the previous depth and normal: they are written for
  // it whatever motionVectors says.
  const auto run = [](bool motionVectors) {
    Renderer r({2});
    buildLitScene(r);
    RenderSettings s = settingsFor(Integrator::Path, 40, 1, 2);
    s.accumulate = false;
    s.denoise = true;
    s.temporal = true;
    s.motionVectors = motionVectors;
    FrameView f;
    for (uint32_t frame = 0; frame < 4; ++frame) {
      s.seed = frame;
      f = r.render(lookAt({0.1f * static_cast<float>(frame), -6, 2}, {0, 0, 1}, 50.0f), s);
      EXPECT_FALSE(f.motion.empty());
    }
    return bytesOf(f.radiance);
  };
  EXPECT_EQ(run(false), run(true));
}

}  // namespace
}  // namespace pa
