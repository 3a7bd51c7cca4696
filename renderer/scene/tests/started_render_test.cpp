// Renderer::startRender / finishRender: the same frames as commit() + render(), errors where
// they belong, and a renderer destroyed with a render in flight.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <vector>

#include "scene_builders.h"

namespace pa {
namespace {

using test::lookAt;
using test::settingsFor;

/// Floor, wall, an emissive quad, a point light, a sky; returns the sphere's instance (it moves).
InstanceId buildScene(Renderer& r, MeshId& sphereMesh) {
  const MaterialId grey = r.addMaterial(test::diffuse(0.7f));
  MaterialDesc lamp;
  lamp.emission = glm::vec3(4.0f, 3.0f, 2.0f);
  const MaterialId light = r.addMaterial(lamp);
  test::addMesh(r, test::quad({-3, -3, 0}, {6, 0, 0}, {0, 6, 0}), grey);
  test::addMesh(r, test::quad({-3, 3, 0}, {6, 0, 0}, {0, 0, 4}), grey);
  test::addMesh(r, test::quad({-0.5f, -0.5f, 3.5f}, {0, 1, 0}, {1, 0, 0}), light);
  test::MeshArrays sphere = test::sphere({0, 0.5f, 1}, 1.0f, 8, 16);
  sphere.setMaterial(grey);
  MeshDesc dynamic = sphere.desc();
  dynamic.dynamic = true;
  sphereMesh = r.addMesh(dynamic);
  LightDesc point;
  point.position = {2, -2, 3};
  point.intensity = 5.0f;
  r.addLight(point);
  SkyDesc sky;
  sky.color = glm::vec3(0.2f, 0.3f, 0.5f);
  r.setSky(sky);
  return r.addInstance({sphereMesh});
}

/// Every buffer of a frame, the temporal ones too.
std::vector<uint8_t> frameBytes(const FrameView& f) { return test::frameBytes(f, true); }

/// Frame `i` of a short game-like sequence: the sphere and the camera move every frame.
void editFrame(Renderer& r, InstanceId sphere, MeshId sphereMesh, int i) {
  InstanceDesc moved{sphereMesh};
  moved.objectToWorld[3] = glm::vec3(0.1f * float(i), 0.0f, 0.0f);
  r.setInstance(sphere, moved);
}

Camera cameraOf(int i) { return lookAt({0.05f * float(i), -6, 2}, {0, 0, 1}, 50.0f); }

TEST(StartedRender, GivesTheFramesOfCommitAndRender) {
  // Temporal accumulation, the denoiser and TAAU carry state from frame to frame: a started
  // render must leave it as render() does.
  for (const uint32_t threads : {1u, 2u}) {
    for (const Integrator integrator : {Integrator::Lightmap, Integrator::Path}) {
      RenderSettings s = settingsFor(integrator, 24, 1, 2);
      s.accumulate = false;
      s.temporal = true;
      s.denoise = integrator != Integrator::Lightmap;
      s.taau = true;
      s.outputWidth = 48;
      s.outputHeight = 48;
      Renderer plain({threads}), started({threads});
      MeshId plainMesh = kNoId, startedMesh = kNoId;
      const InstanceId plainSphere = buildScene(plain, plainMesh);
      const InstanceId startedSphere = buildScene(started, startedMesh);
      for (int i = 0; i < 4; ++i) {
        editFrame(plain, plainSphere, plainMesh, i);
        editFrame(started, startedSphere, startedMesh, i);
        s.seed = uint32_t(i);
        plain.commit();
        const std::vector<uint8_t> expected = frameBytes(plain.render(cameraOf(i), s));
        started.startRender(cameraOf(i), s);
        EXPECT_TRUE(started.rendering());
        const FrameView f = started.finishRender();
        EXPECT_FALSE(started.rendering());
        EXPECT_EQ(f.outputWidth, 48u);
        EXPECT_TRUE(frameBytes(f) == expected) << "threads " << threads << ", integrator "
                                               << static_cast<int>(integrator) << ", frame " << i;
      }
    }
  }
}

TEST(StartedRender, LightsPreparedBeforeTheFirstRenderGiveTheSameFrames) {
  // A loading screen gathers the lights and the sun/sky visibility map (prepareLights); the
  // frames that follow are those of a renderer that gathers them in its first render, and
  // later edits are gathered again.
  for (const Integrator integrator : {Integrator::Direct, Integrator::Path, Integrator::Lightmap}) {
    const RenderSettings s = settingsFor(integrator, 16, 1, 2);
    Renderer plain({2}), prepared({2});
    MeshId plainMesh = kNoId, preparedMesh = kNoId;
    const InstanceId plainSphere = buildScene(plain, plainMesh);
    const InstanceId preparedSphere = buildScene(prepared, preparedMesh);
    prepared.prepareLights();
    prepared.prepareLights();   // twice: nothing changed, nothing done
    for (int i = 0; i < 3; ++i) {
      if (i > 0) {
        editFrame(plain, plainSphere, plainMesh, i);
        editFrame(prepared, preparedSphere, preparedMesh, i);
      }
      plain.commit();
      prepared.commit();
      const std::vector<uint8_t> expected = frameBytes(plain.render(cameraOf(i), s));
      EXPECT_TRUE(frameBytes(prepared.render(cameraOf(i), s)) == expected)
          << "integrator " << static_cast<int>(integrator) << ", frame " << i;
    }
  }
}

TEST(StartedRender, BadSettingsThrowAtTheStart) {
  Renderer r({2});
  MeshId mesh = kNoId;
  buildScene(r, mesh);
  RenderSettings s = settingsFor(Integrator::Path, 16, 1, 1);
  s.samplesPerPixel = 0;
  EXPECT_THROW(r.startRender(cameraOf(0), s), SceneError);
  EXPECT_FALSE(r.rendering());
  EXPECT_THROW(r.finishRender(), SceneError);   // nothing was started
}

TEST(StartedRender, ACommitErrorIsThrownByFinishAndTheRendererGoesOn) {
  Renderer r({2});
  MeshId mesh = kNoId;
  const InstanceId sphere = buildScene(r, mesh);
  const RenderSettings s = settingsFor(Integrator::Direct, 16, 1, 1);
  r.commit();
  const std::vector<uint8_t> before = frameBytes(r.render(cameraOf(0), s));
  r.removeMesh(mesh);   // the sphere's instance still uses it: commit() refuses the scene
  r.startRender(cameraOf(0), s);
  EXPECT_THROW(r.startRender(cameraOf(0), s), SceneError);   // one at a time
  EXPECT_THROW(r.finishRender(), SceneError);
  EXPECT_FALSE(r.rendering());
  r.removeInstance(sphere);
  r.startRender(cameraOf(0), s);
  const FrameView f = r.finishRender();
  EXPECT_EQ(f.width, 16u);
  EXPECT_FALSE(frameBytes(f) == before);   // the sphere is gone
}

TEST(StartedRender, ARendererDestroyedWhileRenderingWaitsForIt) {
  for (int i = 0; i < 4; ++i) {
    auto r = std::make_unique<Renderer>(RendererConfig{.threads = 2});
    MeshId mesh = kNoId;
    buildScene(*r, mesh);
    r->startRender(cameraOf(i), settingsFor(Integrator::Path, 48, 2, 3));
    r.reset();   // must not free the scene and film under the render
  }
  SUCCEED();
}

}  // namespace
}  // namespace pa
