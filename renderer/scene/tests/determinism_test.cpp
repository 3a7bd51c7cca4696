// The image is a pure function of (scene, camera, seed, frame index, spp): independent of the
// thread count, repeatable, and accumulation over frames equals one render of the total spp.
#include <gtest/gtest.h>

#include <cstring>
#include <span>
#include <vector>

#include "renderer/scene/world/scene_store.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::frameBytes;
using test::lookAt;
using test::settingsFor;

/// A small Cornell-like scene: floor, back wall, a sphere, an emissive quad, a point light, sky.
void buildScene(Renderer& r) {
  const MaterialId grey = r.addMaterial(test::diffuse(0.7f));
  MaterialDesc shiny = test::diffuse(0.5f);
  shiny.specular = 0.5f;
  shiny.roughness = 0.4f;
  const MaterialId glossy = r.addMaterial(shiny);
  MaterialDesc lamp;
  lamp.emission = glm::vec3(4.0f, 3.0f, 2.0f);
  const MaterialId light = r.addMaterial(lamp);
  test::addMesh(r, test::quad({-3, -3, 0}, {6, 0, 0}, {0, 6, 0}), grey);
  test::addMesh(r, test::quad({-3, 3, 0}, {6, 0, 0}, {0, 0, 4}), grey);
  test::addMesh(r, test::sphere({0, 0.5f, 1}, 1.0f, 12, 24), glossy);
  test::addMesh(r, test::quad({-0.5f, -0.5f, 3.5f}, {0, 1, 0}, {1, 0, 0}), light);
  LightDesc point;
  point.position = {2, -2, 3};
  point.intensity = 5.0f;
  r.addLight(point);
  SkyDesc sky;
  sky.color = glm::vec3(0.2f, 0.3f, 0.5f);
  r.setSky(sky);
  r.commit();
}

Camera camera() { return lookAt({0, -6, 2}, {0, 0, 1}, 50.0f); }

std::vector<glm::vec3> renderWith(uint32_t threads, RenderSettings settings, uint32_t frames = 1) {
  Renderer r({threads});
  buildScene(r);
  FrameView f;
  for (uint32_t i = 0; i < frames; ++i) f = r.render(camera(), settings);
  return {f.radiance.begin(), f.radiance.end()};
}

bool bitIdentical(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)) == 0;
}

TEST(Determinism, OneAndTwoThreadsGiveBitIdenticalImages) {
  const RenderSettings s = settingsFor(Integrator::Path, 48, 2, 4);
  EXPECT_TRUE(bitIdentical(renderWith(1, s, 2), renderWith(2, s, 2)));
}

TEST(Determinism, PixelCentresDoNotDependOnTheSeed) {
  // One-sample Lightmap frames: jittered samples change with the seed along every edge, samples
  // through the pixel centres do not.
  RenderSettings s = settingsFor(Integrator::Lightmap, 48, 1, 1);
  s.seed = 1;
  const auto jittered = renderWith(2, s);
  s.seed = 2;
  EXPECT_FALSE(bitIdentical(jittered, renderWith(2, s)));
  s.pixelCentres = true;
  const auto centred = renderWith(2, s);
  s.seed = 1;
  EXPECT_TRUE(bitIdentical(centred, renderWith(2, s)));
  EXPECT_FALSE(bitIdentical(centred, jittered));
}

TEST(Determinism, SameSeedSameImageOtherSeedOtherImage) {
  RenderSettings s = settingsFor(Integrator::Path, 32, 1, 3);
  const auto a = renderWith(2, s);
  EXPECT_TRUE(bitIdentical(a, renderWith(2, s)));
  s.seed = 7;
  EXPECT_FALSE(bitIdentical(a, renderWith(2, s)));
}

TEST(Determinism, AccumulatedFramesEqualOneRenderOfTheTotalSpp) {
  // Frame k with 1 spp uses sample index k, exactly the samples of one 16-spp render: the
  // means agree to float rounding of the conversion (the sums are in double).
  RenderSettings one = settingsFor(Integrator::Path, 24, 1, 3);
  RenderSettings sixteen = one;
  sixteen.samplesPerPixel = 16;
  Renderer r({2});
  buildScene(r);
  FrameView f;
  for (int i = 0; i < 16; ++i) f = r.render(camera(), one);
  EXPECT_EQ(f.accumulatedFrames, 16u);
  const std::vector<glm::vec3> accumulated(f.radiance.begin(), f.radiance.end());
  const auto single = renderWith(2, sixteen);
  ASSERT_EQ(accumulated.size(), single.size());
  for (size_t i = 0; i < single.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(accumulated[i][c], single[i][c], 1e-6f * std::max(1.0f, single[i][c])) << i;
    }
  }
}

TEST(Determinism, SingleSampleFramesWrittenDirectlyEqualAccumulatedOnes) {
  // A fresh one-sample frame that is not accumulated skips the film's accumulators; its
  // buffers equal those of the same frame resolved through them, and a frame that then
  // accumulates goes on from it as from an accumulated one.
  for (const Integrator integrator : {Integrator::Lightmap, Integrator::Direct}) {
    RenderSettings direct = settingsFor(integrator, 30, 1, 2);
    direct.accumulate = false;
    RenderSettings accumulated = direct;
    accumulated.accumulate = true;
    Renderer a({2}), b({2});
    buildScene(a);
    buildScene(b);
    const std::vector<uint8_t> first = frameBytes(a.render(camera(), direct));
    EXPECT_EQ(first, frameBytes(b.render(camera(), accumulated))) << "integrator " << static_cast<int>(integrator);
    const FrameView second = a.render(camera(), accumulated);
    EXPECT_EQ(second.accumulatedFrames, 2u);
    EXPECT_EQ(frameBytes(second), frameBytes(b.render(camera(), accumulated)))
        << "integrator " << static_cast<int>(integrator);
  }
}

TEST(Determinism, FilteredSingleSampleFramesEqualAccumulatedOnesAndAreNotResumed) {
  // A one-sample frame the denoiser (or the temporal stage) filters is written without the
  // film's accumulators too: denoised, it equals the same frame resolved through them (the first
  // frame of an accumulating render); and since the filter changed its radiance in place, a
  // frame that then accumulates starts again instead of going on from the filtered picture.
  for (const Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    for (const bool temporal : {false, true}) {
      RenderSettings filtered = settingsFor(integrator, 30, 1, 2);
      filtered.accumulate = false;
      filtered.denoise = true;
      filtered.temporal = temporal;
      RenderSettings accumulated = filtered;
      accumulated.accumulate = true;
      accumulated.temporal = false;
      Renderer a({2}), b({2}), c({2});
      buildScene(a);
      buildScene(b);
      buildScene(c);
      const FrameView first = a.render(camera(), filtered);
      if (!temporal) {
        EXPECT_EQ(frameBytes(first), frameBytes(b.render(camera(), accumulated)))
            << "integrator " << static_cast<int>(integrator);
      }
      accumulated.denoise = false;
      const FrameView next = a.render(camera(), accumulated);
      EXPECT_EQ(next.accumulatedFrames, 1u);
      EXPECT_EQ(frameBytes(next), frameBytes(c.render(camera(), accumulated)))
          << "integrator " << static_cast<int>(integrator) << (temporal ? ", temporal" : "");
    }
  }
}

TEST(Determinism, SingleSampleFramesWithoutSurfaceAovsShowTheSamePicture) {
  // RenderSettings::surfaceAovs false: a one-sample frame that nothing filters leaves the albedo,
  // normal and emission planes out; what it hands out (radiance, depth, variance, rgba8) is the
  // same bytes, albedo and normal come out empty, and a frame that then accumulates starts again
  // (as a fresh renderer's first) instead of resuming from planes it did not write.
  for (const Integrator integrator : {Integrator::Lightmap, Integrator::Direct}) {
    RenderSettings with = settingsFor(integrator, 30, 1, 2);
    with.accumulate = false;
    with.tonemap = Tonemap::Clamp;
    RenderSettings without = with;
    without.surfaceAovs = false;
    Renderer a({2}), b({2}), c({2});
    buildScene(a);
    buildScene(b);
    buildScene(c);
    for (int frame = 0; frame < 2; ++frame) {
      const FrameView full = a.render(camera(), with);
      const FrameView lean = b.render(camera(), without);
      EXPECT_TRUE(lean.albedo.empty());
      EXPECT_TRUE(lean.normal.empty());
      ASSERT_EQ(full.albedo.size(), size_t{30 * 30});
      const auto same = [](auto x, auto y) {
        return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size_bytes()) == 0;
      };
      EXPECT_TRUE(same(full.radiance, lean.radiance)) << "integrator " << static_cast<int>(integrator);
      EXPECT_TRUE(same(full.depth, lean.depth));
      EXPECT_TRUE(same(full.variance, lean.variance));
      EXPECT_TRUE(same(full.rgba8, lean.rgba8));
    }
    RenderSettings accumulated = with;
    accumulated.accumulate = true;
    without.accumulate = true;   // surfaceAovs is moot when accumulating: every plane is filled
    const FrameView resumed = b.render(camera(), without);
    EXPECT_EQ(resumed.accumulatedFrames, 1u);
    EXPECT_EQ(frameBytes(resumed), frameBytes(c.render(camera(), accumulated)))
        << "integrator " << static_cast<int>(integrator);
  }
}

TEST(Determinism, AccumulationResetsOnCameraSettingsAndSceneChanges) {
  Renderer r({2});
  buildScene(r);
  RenderSettings s = settingsFor(Integrator::Direct, 16, 1, 1);
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 1u);
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 2u);
  s.exposure = 2.0f;   // display-only: keeps accumulating
  s.tonemap = Tonemap::Reinhard;
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 3u);
  Camera moved = camera();
  moved.origin.x += 0.01f;
  EXPECT_EQ(r.render(moved, s).accumulatedFrames, 1u);
  s.maxBounces = 2;
  EXPECT_EQ(r.render(moved, s).accumulatedFrames, 1u);
  EXPECT_EQ(r.render(moved, s).accumulatedFrames, 2u);
  r.commit();   // nothing changed: no reset
  EXPECT_EQ(r.render(moved, s).accumulatedFrames, 3u);
  LightDesc extra;
  r.addLight(extra);
  r.commit();
  EXPECT_EQ(r.render(moved, s).accumulatedFrames, 1u);
  r.forgetFrames();
  EXPECT_EQ(r.render(moved, s).accumulatedFrames, 1u);
  s.accumulate = false;
  EXPECT_EQ(r.render(moved, s).accumulatedFrames, 1u);
}

TEST(Determinism, FramesAfterForgetFramesAreThoseOfANewRenderer) {
  // The game renders throw-away frames while a map loads (so that play starts with the frame
  // buffers made) and forgets them: what follows must be what a new renderer shows, through the
  // temporal stage, its gradients, the denoiser and TAAU's jitter and history, as the game's
  // traced presets and its lightmap preset (pixel centres moved by TAAU's jitter) set them.
  for (const Integrator integrator : {Integrator::Direct, Integrator::Lightmap}) {
    RenderSettings s = settingsFor(integrator, 24, 1, 1);
    s.height = 16;
    s.outputWidth = 48;
    s.outputHeight = 32;
    s.taau = true;
    s.tonemap = Tonemap::Clamp;
    if (integrator == Integrator::Lightmap) {
      s.pixelCentres = true;
    } else {
      s.temporal = true;
      s.denoise = true;
      s.gradientStratum = 3;
      s.lightingLook = LightingLook::DisplaySpace;
    }
    Renderer fresh({2});
    buildScene(fresh);
    Renderer warmed({2});
    buildScene(warmed);
    RenderSettings other = s;
    other.seed = 99;
    for (uint32_t i = 0; i < 3; ++i) warmed.render(lookAt({1, -5, 3}, {0, 0, 0}, 70.0f), other);
    warmed.forgetFrames();
    for (uint32_t frame = 0; frame < 4; ++frame) {
      Camera c = camera();
      c.origin.x += 0.05f * float(frame);
      s.seed = frame;
      const std::vector<uint8_t> expected = frameBytes(fresh.render(c, s), true);
      EXPECT_EQ(frameBytes(warmed.render(c, s), true), expected)
          << "integrator " << static_cast<int>(integrator) << ", frame " << frame;
    }
  }
}

TEST(Determinism, AMovingCameraOnlyOverlayRestartsOnlyThePixelsItCovers) {
  // The first-person weapon case: a drawOnTop instance seen only by camera rays moves while the
  // camera and the world stay. Accumulation goes on; pixels it covered or covers start again.
  const RenderSettings s = settingsFor(Integrator::Direct, 16, 1, 1);
  Renderer reference({2});   // the same world without the overlay
  buildScene(reference);
  Renderer r({2});
  buildScene(r);
  MaterialDesc grip = test::diffuse(0.25f);
  grip.twoSided = true;
  const MaterialId gripMaterial = r.addMaterial(grip);
  test::MeshArrays plate = test::quad({-0.45f, -5, -1}, {0.3f, 0, 0}, {0, 0, 6});   // 1 in front, a third of the view
  plate.setMaterial(gripMaterial);
  const MeshDesc plateDesc = plate.desc();
  InstanceDesc weapon;
  weapon.mesh = r.addMesh(plateDesc);
  weapon.mask = kMaskCamera;
  weapon.drawOnTop = true;
  const InstanceId weaponId = r.addInstance(weapon);
  r.commit();
  const auto covered = [](std::span<const float> depth) {   // pixels the plate covers, grown by one pixel for jitter
    std::vector<bool> near(depth.size()), grown(depth.size());
    for (size_t i = 0; i < near.size(); ++i) near[i] = depth[i] < 2.0f;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 16; ++x)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx >= 0 && nx < 16 && ny >= 0 && ny < 16 && near[size_t(ny * 16 + nx)]) grown[size_t(y * 16 + x)] = true;
          }
    return grown;
  };
  r.render(camera(), s);
  const FrameView second = r.render(camera(), s);   // its views show the film: keep a copy
  const std::vector<float> depthBefore(second.depth.begin(), second.depth.end());
  const std::vector<bool> coveredBefore = covered(depthBefore);
  // The same mesh data again changes nothing: no restart at all.
  r.updateMesh(weapon.mesh, plateDesc);
  r.setInstance(weaponId, weapon);
  r.commit();
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 3u);
  weapon.objectToWorld[3] = glm::vec3(0.3f, 0, 0);   // the next third
  r.setInstance(weaponId, weapon);
  r.commit();
  const FrameView after = r.render(camera(), s);
  EXPECT_EQ(after.accumulatedFrames, 4u);
  const std::vector<bool> coveredAfter = covered(after.depth);
  FrameView expected;
  for (int i = 0; i < 4; ++i) expected = reference.render(camera(), s);
  size_t untouched = 0, nowCovered = 0;
  for (size_t i = 0; i < after.radiance.size(); ++i) {
    if (!coveredBefore[i] && !coveredAfter[i]) {   // four frames of the world, as without the plate
      ++untouched;
      EXPECT_EQ(after.radiance[i], expected.radiance[i]) << "pixel " << i;
    } else if (after.depth[i] < 2.0f && depthBefore[i] > 2.0f) {   // the plate alone: no world history
      ++nowCovered;
      EXPECT_EQ(after.albedo[i], glm::vec3(0.25f)) << "pixel " << i;
    } else if (depthBefore[i] < 2.0f && !coveredAfter[i]) {   // uncovered: the world alone
      EXPECT_GT(after.depth[i], 2.0f) << "pixel " << i;
      EXPECT_NE(after.albedo[i], glm::vec3(0.25f)) << "pixel " << i;
    }
  }
  EXPECT_GT(untouched, 16u);
  EXPECT_GT(nowCovered, 16u);
  // A change to the world restarts everything.
  r.setMaterial(gripMaterial, test::diffuse(0.5f));
  r.commit();
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 1u);
}

TEST(Determinism, AovsDescribeTheFirstHit) {
  Renderer r({2});
  buildScene(r);
  // Straight down at the floor beside everything else from z = 5.
  FrameView f = r.render(lookAt({2, -2, 5}, {2, -2, 0}, 10.0f), settingsFor(Integrator::Path, 8, 4, 2));
  EXPECT_NEAR(f.depth[0], 5.0f, 0.1f);
  EXPECT_NEAR(f.normal[0].z, 1.0f, 1e-4f);
  EXPECT_NEAR(f.albedo[0].g, 0.7f, 1e-5f);
  EXPECT_EQ(f.rgba8.size(), 8u * 8u * 4u);
  EXPECT_EQ(f.rgba8[3], 255);
  // Straight down at the lamp (white, 1.5 below the camera); its normal faces the camera.
  f = r.render(lookAt({0, 0, 5}, {0, 0, 0}, 10.0f), settingsFor(Integrator::Path, 8, 4, 2));
  EXPECT_NEAR(f.depth[8 * 4 + 4], 1.5f, 0.05f);
  EXPECT_NEAR(f.albedo[8 * 4 + 4].r, 1.0f, 1e-5f);
  EXPECT_NEAR(f.normal[8 * 4 + 4].z, 1.0f, 1e-4f);
}

}  // namespace
}  // namespace pa

namespace pa {
namespace {

/// The determinism scene plus what camera rays treat specially: a translucent (stochastic) pane,
/// a one-sided quad seen from behind, an additive glow, and a drawOnTop quad near the camera.
void buildSceneWithCameraRules(Renderer& r) {
  buildScene(r);
  MaterialDesc glass = test::diffuse(0.6f);
  glass.alphaMode = AlphaMode::Blend;
  glass.opacity = 0.5f;
  test::addMesh(r, test::quad({-1.5f, -1.0f, 0.2f}, {1.5f, 0, 0}, {0, 0, 2.0f}), r.addMaterial(glass));
  MaterialDesc oneSided = test::diffuse(0.4f);
  oneSided.twoSided = false;
  test::addMesh(r, test::quad({0.5f, -1.5f, 0.2f}, {0, 0, 1.5f}, {1.2f, 0, 0}), r.addMaterial(oneSided));
  MaterialDesc glow = test::diffuse(0.8f);
  glow.alphaMode = AlphaMode::Additive;
  test::addMesh(r, test::quad({-0.5f, -2.0f, 1.0f}, {1.0f, 0, 0}, {0, 0, 1.0f}), r.addMaterial(glow));
  test::MeshArrays weapon = test::quad({0.2f, -5.0f, 1.3f}, {0.3f, 0, 0}, {0, 0, 0.3f});
  weapon.setMaterial(r.addMaterial(test::diffuse(0.3f)));
  InstanceDesc onTop{r.addMesh(weapon.desc())};
  onTop.drawOnTop = true;
  onTop.mask = kMaskCamera;
  r.addInstance(onTop);
  r.commit();
}

TEST(Determinism, CameraPacketsGiveTheSameImageAsRayByRay) {
  for (const Integrator integrator : {Integrator::Lightmap, Integrator::Direct, Integrator::Path}) {
    std::vector<glm::vec3> images[2];
    for (const bool packets : {false, true}) {
      Renderer r({2});
      buildSceneWithCameraRules(r);
      RenderSettings s = settingsFor(integrator, 50, 2, 3);   // 50: blocks cut by the image edge
      s.cameraPackets = packets;
      FrameView f;
      for (int frame = 0; frame < 2; ++frame) f = r.render(camera(), s);
      images[packets].assign(f.radiance.begin(), f.radiance.end());
    }
    EXPECT_TRUE(bitIdentical(images[0], images[1])) << "integrator " << static_cast<int>(integrator);
  }
}

TEST(Determinism, Avx2KernelsGiveTheSameImage) {
  // RendererConfig::bvh with allowAvx512 false (the glue's r_pt_isa avx2): the meshes' BVHs take
  // the 8-wide layout and AVX2 kernels whatever the CPU has, and trace the same image.
  BvhBuildConfig avx2;
  avx2.allowAvx512 = false;
  SceneStore store;
  store.setBvhConfig(avx2);
  test::addMesh(store, test::quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}), store.addMaterial(MaterialDesc{}));
  const RenderScene scene = store.commit();
  ASSERT_EQ(scene.world.size(), 1u);
  EXPECT_EQ(scene.world[0].mesh->blas.nodeWidth(), 8u);
  for (const Integrator integrator : {Integrator::Lightmap, Integrator::Direct, Integrator::Path}) {
    std::vector<glm::vec3> images[2];
    for (const bool avx2Only : {false, true}) {
      RendererConfig config{.threads = 2};
      config.bvh.allowAvx512 = !avx2Only;
      Renderer r(config);
      buildSceneWithCameraRules(r);
      const FrameView f = r.render(camera(), settingsFor(integrator, 50, 2, 3));
      images[avx2Only].assign(f.radiance.begin(), f.radiance.end());
    }
    EXPECT_TRUE(bitIdentical(images[0], images[1])) << "integrator " << static_cast<int>(integrator);
  }
}

}  // namespace
}  // namespace pa
