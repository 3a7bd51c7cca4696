// Hostile or wrong input: every case is a SceneError with a message naming the field, never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "renderer/scene/sampling/sobol_sampler.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::lookAt;
using test::settingsFor;

template <typename F>
void expectSceneError(F&& f, const char* fragment) {
  try {
    f();
    ADD_FAILURE() << "expected SceneError containing '" << fragment << "'";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Validation, BadMeshesAreRejected) {
  Renderer r({1});
  test::MeshArrays q = test::quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  test::MeshArrays nan = q;
  nan.positions[2].y = std::numeric_limits<float>::quiet_NaN();
  expectSceneError([&] { r.addMesh(nan.desc()); }, "positions[2]");
  test::MeshArrays inf = q;
  inf.positions[0].x = std::numeric_limits<float>::infinity();
  expectSceneError([&] { r.addMesh(inf.desc()); }, "positions[0]");
  test::MeshArrays badIndex = q;
  badIndex.indices[4] = 4;
  expectSceneError([&] { r.addMesh(badIndex.desc()); }, "indices[4]");
  test::MeshArrays partial = q;
  partial.indices.pop_back();
  expectSceneError([&] { r.addMesh(partial.desc()); }, "multiple of 3");
  test::MeshArrays shortUvs = q;
  shortUvs.uvs.pop_back();
  expectSceneError([&] { r.addMesh(shortUvs.desc()); }, "uvs");
  test::MeshArrays badMaterials = q;
  badMaterials.materials = {kNoId};
  expectSceneError([&] { r.addMesh(badMaterials.desc()); }, "materials");
  expectSceneError([&] { r.updateMesh(99, q.desc()); }, "mesh 99");
}

TEST(Validation, OutOfRangeIdsAreRejected) {
  Renderer r({1});
  test::MeshArrays q = test::quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  q.materials = {0, 5};   // no materials exist yet: checked at commit, when all are known
  const MeshId mesh = r.addMesh(q.desc());
  r.addInstance({mesh});
  expectSceneError([&] { r.commit(); }, "materials[0]");
  r.addMaterial({});
  expectSceneError([&] { r.commit(); }, "materials[1] = 5");
  MaterialDesc badTexture;
  badTexture.baseTexture = 3;
  expectSceneError([&] { r.addMaterial(badTexture); }, "baseTexture = 3");
  MaterialDesc badCover;
  badCover.coverTexture = 4;
  expectSceneError([&] { r.addMaterial(badCover); }, "coverTexture = 4");
  badCover.coverTexture = kNoId;
  badCover.coverUvTransform[2].x = std::numeric_limits<float>::quiet_NaN();
  expectSceneError([&] { r.addMaterial(badCover); }, "coverUvTransform");
  expectSceneError([&] { r.addInstance({42}); }, "mesh 42");
  InstanceDesc badOverride{mesh};
  badOverride.materialOverride = 77;
  r.addInstance(badOverride);
  expectSceneError([&] { r.commit(); }, "materialOverride = 77");
  SkyDesc sky;
  sky.faces[3] = 9;
  expectSceneError([&] { r.setSky(sky); }, "faces[3]");
  SkyDesc negativeLighting;
  negativeLighting.lightingScale = -1.0f;
  expectSceneError([&] { r.setSky(negativeLighting); }, "lightingScale");
  expectSceneError([&] { r.setLight(4, {}); }, "light 4");
  expectSceneError([&] { r.removeInstance(100); }, "instance 100");
}

TEST(Validation, RemovedMeshStillInstancedFailsAtCommitAndRecovers) {
  Renderer r({1});
  test::MeshArrays q = test::quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
  const MeshId mesh = r.addMesh(q.desc());
  const InstanceId inst = r.addInstance({mesh});
  r.commit();
  r.removeMesh(mesh);
  expectSceneError([&] { r.commit(); }, "uses mesh 0, which was removed");
  // The last good scene still renders; removing the instance makes the commit valid.
  const RenderSettings s = settingsFor(Integrator::Lightmap, 4, 1);
  EXPECT_TRUE(std::isfinite(r.render(lookAt({0, 0, 2}, {0, 0, 0}, 30.0f), s).depth[5]));
  r.removeInstance(inst);
  r.commit();
  EXPECT_TRUE(std::isinf(r.render(lookAt({0, 0, 2}, {0, 0, 0}, 30.0f), s).depth[5]));
  expectSceneError([&] { r.addInstance({mesh}); }, "does not exist");
  // Ids stay stable: the next mesh gets a new id.
  EXPECT_EQ(r.addMesh(q.desc()), mesh + 1);
}

TEST(Validation, BadInstancesLightsAndCameras) {
  Renderer r({1});
  test::MeshArrays q = test::quad({0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const MeshId mesh = r.addMesh(q.desc());
  InstanceDesc singular{mesh};
  singular.objectToWorld[2] = glm::vec3(0.0f);
  expectSceneError([&] { r.addInstance(singular); }, "singular");
  InstanceDesc nanTransform{mesh};
  nanTransform.objectToWorld[3].x = NAN;
  expectSceneError([&] { r.addInstance(nanTransform); }, "objectToWorld");
  LightDesc l;
  l.intensity = -1.0f;
  expectSceneError([&] { r.addLight(l); }, "intensity");
  l.intensity = 1.0f;
  l.falloff = Falloff::Linear;
  expectSceneError([&] { r.addLight(l); }, "range");
  LightDesc spot;
  spot.type = LightType::Spot;
  spot.cosInnerAngle = 0.5f;
  spot.cosOuterAngle = 0.9f;
  expectSceneError([&] { r.addLight(spot); }, "cosOuterAngle");
  Camera cam;
  cam.fovX = 0.0f;
  expectSceneError([&] { r.render(cam, settingsFor(Integrator::Path, 4, 1)); }, "fov");
  cam = Camera{};
  cam.forward = glm::vec3(0.0f);
  expectSceneError([&] { r.render(cam, settingsFor(Integrator::Path, 4, 1)); }, "forward");
  expectSceneError([&] { r.render(Camera{}, settingsFor(Integrator::Path, 4, 0)); }, "samplesPerPixel");
  MaterialDesc negative;
  negative.emission = glm::vec3(-1.0f);
  expectSceneError([&] { r.addMaterial(negative); }, "emission");
}

TEST(Validation, ZeroSizeRenderAndEmptySceneAndDegenerateTriangles) {
  Renderer r({1});
  const FrameView empty = r.render(Camera{}, settingsFor(Integrator::Path, 0, 1));
  EXPECT_EQ(empty.width, 0u);
  EXPECT_TRUE(empty.radiance.empty());
  // Nothing committed yet: the sky (black) everywhere.
  const FrameView black = r.render(Camera{}, settingsFor(Integrator::Path, 4, 1));
  EXPECT_EQ(black.radiance[0], glm::vec3(0.0f));
  // Zero-area triangles (repeated vertices, collinear points) next to a real one are fine.
  test::MeshArrays m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2, 0, 0, 0, 0, 1, 3};
  MaterialDesc lamp;
  lamp.emission = glm::vec3(1.0f);
  m.setMaterial(r.addMaterial(lamp));   // emissive degenerate triangles must not become lights
  r.addInstance({r.addMesh(m.desc())});
  r.commit();
  const FrameView f = r.render(lookAt({0.2f, 0.2f, 2.0f}, {0.2f, 0.2f, 0.0f}, 60.0f),
                               settingsFor(Integrator::Path, 8, 2, 3));
  for (const glm::vec3& v : f.radiance) EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
  expectSceneError([&] { r.render(Camera{}, settingsFor(Integrator::Path, 20000, 1)); }, "exceeds");
}

}  // namespace
}  // namespace pa

namespace pa {
namespace {

TEST(Validation, RandomHostileInputNeverCrashes) {
  // Deterministic garbage: random sizes, indices (some out of range), NaN/Inf/huge positions,
  // random material ids. Every call either throws SceneError or succeeds; renders stay finite.
  Renderer r({2});
  uint32_t state = 12345;
  auto next = [&] { return state = sampling::hash32(state + 0x9e3779b9u); };
  auto unit = [&] { return sampling::toUnitFloat(next()); };
  for (int m = 0; m < 4; ++m) r.addMaterial(test::diffuse(unit()));
  MaterialDesc masked;
  masked.alphaMode = AlphaMode::Mask;
  r.addMaterial(masked);
  uint32_t accepted = 0, rejected = 0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    test::MeshArrays mesh;
    const uint32_t vertices = next() % 40;
    const uint32_t triangles = next() % 30;
    for (uint32_t v = 0; v < vertices; ++v) {
      glm::vec3 p(unit() * 10 - 5, unit() * 10 - 5, unit() * 10 - 5);
      const uint32_t roll = next() % 200;
      if (roll == 0) p.x = std::numeric_limits<float>::quiet_NaN();
      if (roll == 1) p.y = std::numeric_limits<float>::infinity();
      if (roll == 2) p.z = 3e38f;
      mesh.positions.push_back(p);
    }
    for (uint32_t t = 0; t < 3 * triangles; ++t) mesh.indices.push_back(next() % (vertices + 2));
    if (next() % 2) {
      for (uint32_t t = 0; t < triangles; ++t) mesh.materials.push_back(next() % 7);
    }
    mesh.uvs.clear();
    MeshId id = kNoId;
    InstanceId inst = kNoId;
    try {
      id = r.addMesh(mesh.desc());
      InstanceDesc desc{id};
      desc.objectToWorld[3] = glm::vec3(unit(), unit(), unit());
      inst = r.addInstance(desc);
      r.commit();
      ++accepted;
    } catch (const SceneError&) {
      ++rejected;
      // Bad material ids are found at commit: removing the culprit makes the scene valid again.
      if (inst != kNoId) r.removeInstance(inst);
      if (id != kNoId) r.removeMesh(id);
      r.commit();
    }
  }
  EXPECT_GT(accepted, 10u);
  EXPECT_GT(rejected, 10u);
  const FrameView f = r.render(test::lookAt({0, -12, 0}, {0, 0, 0}, 60.0f), test::settingsFor(Integrator::Path, 16, 1, 3));
  for (const glm::vec3& v : f.radiance) EXPECT_TRUE(std::isfinite(v.x + v.y + v.z));
}

}  // namespace
}  // namespace pa
