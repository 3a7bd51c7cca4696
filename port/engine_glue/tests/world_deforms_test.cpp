// deformVertexes wave / bulge / move / normal: vertex positions at a given shader time against
// the formulas, the batch and world-mesh plumbing, and the tracer upload.
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "port/engine_glue/world_deforms.h"
#include "port/q3formats/shader/shader_library.h"

namespace glue {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

q3::Deform wave(float div, q3::WaveFunc func, float base, float amplitude, float phase, float frequency) {
  q3::Deform d;
  d.kind = q3::DeformKind::Wave;
  d.spread = div;
  d.wave = {func, base, amplitude, phase, frequency};
  return d;
}

struct Vertices {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  void add(const glm::vec3& p, const glm::vec3& n, const glm::vec2& uv = {0, 0}) {
    positions.push_back(p);
    normals.push_back(n);
    uvs.push_back(uv);
  }
  void apply(const std::vector<q3::Deform>& deforms, double seconds) {
    deformVertices(deforms, seconds, positions, normals, uvs);
  }
};

TEST(WorldDeforms, WaveMovesAlongTheNormalWithAPerVertexPhase) {
  Vertices v;
  v.add({10, 20, 30}, {0, 0, 1});
  v.add({0, 0, 0}, {1, 0, 0});
  v.apply({wave(100.0f, q3::WaveFunc::Sin, 0.0f, 4.0f, 0.0f, 1.0f)}, 0.15);
  // Spread 1/100: phase (10 + 20 + 30) / 100 = 0.6, plus 0.15 s x 1 Hz: sin(2 pi 0.75) = -1.
  EXPECT_NEAR(v.positions[0].z, 30.0f - 4.0f, 1e-4f);
  // The stock sin table's entry trunc(0.15 x 1024) = 153, which holds sin(153 x 360 / 1023 degrees).
  EXPECT_NEAR(v.positions[1].x, 4.0f * std::sin(kTwoPi * 153 / 1023), 1e-4f);
  EXPECT_EQ(v.normals[0], glm::vec3(0, 0, 1));   // wave leaves normals alone
}

TEST(WorldDeforms, WaveWithoutFrequencyMovesEveryVertexAlike) {
  Vertices v;
  v.add({10, 20, 30}, {0, 0, 1});
  v.add({-7, 3, 0}, {0, 0, 1});
  v.apply({wave(64.0f, q3::WaveFunc::Sin, 3.0f, 2.0f, 0.25f, 0.0f)}, 12.3);
  EXPECT_NEAR(v.positions[0].z, 35.0f, 1e-4f);   // 3 + 2 sin(2 pi 0.25)
  EXPECT_NEAR(v.positions[1].z, 5.0f, 1e-4f);
}

TEST(WorldDeforms, WaveWithZeroDivUsesTheStockSpreadOf100) {
  Vertices v;
  v.add({0.0025f, 0, 0}, {0, 0, 1});   // phase offset 0.0025 x 100 = 0.25
  v.apply({wave(0.0f, q3::WaveFunc::Square, 0.0f, 1.0f, 0.0f, 1.0f)}, 0.3);
  EXPECT_NEAR(v.positions[0].z, -1.0f, 1e-5f);   // square at 0.55: second half
}

TEST(WorldDeforms, BulgeFollowsTheTextureS) {
  q3::Deform bulge;
  bulge.kind = q3::DeformKind::Bulge;
  bulge.params = {2.0f, 3.0f, 4.0f};   // width, height, speed
  Vertices v;
  v.add({1, 1, 1}, {0, 1, 0}, {0.5f, 9.0f});
  v.apply({bulge}, 0.25);
  EXPECT_NEAR(v.positions[0].y, 1.0f + 3.0f * std::sin(0.5 * 2.0 + 0.25 * 4.0), 1e-5f);
  EXPECT_FLOAT_EQ(v.positions[0].x, 1.0f);
}

TEST(WorldDeforms, MoveShiftsEveryVertexByTheWave) {
  q3::Deform move;
  move.kind = q3::DeformKind::Move;
  move.params = {1.0f, 2.0f, 3.0f};
  move.wave = {q3::WaveFunc::Sin, 0.0f, 1.0f, 0.0f, 0.5f};
  Vertices v;
  v.add({0, 0, 0}, {0, 0, 1});
  v.add({5, 5, 5}, {1, 0, 0});
  v.apply({move}, 0.5);   // sin(2 pi 0.25) = 1
  EXPECT_NEAR(glm::length(v.positions[0] - glm::vec3(1, 2, 3)), 0.0f, 1e-5f);
  EXPECT_NEAR(glm::length(v.positions[1] - glm::vec3(6, 7, 8)), 0.0f, 1e-5f);
}

TEST(WorldDeforms, NormalBendsUnitNormalsOverTimeAndKeepsPositions) {
  q3::Deform normal;
  normal.kind = q3::DeformKind::Normal;
  normal.params = {0.5f, 2.0f};   // amplitude, frequency
  Vertices a, b;
  a.add({10, 20, 30}, {0, 0, 1});
  b = a;
  a.apply({normal}, 0.0);
  b.apply({normal}, 0.4);
  EXPECT_EQ(a.positions[0], glm::vec3(10, 20, 30));
  EXPECT_NEAR(glm::length(a.normals[0]), 1.0f, 1e-5f);
  EXPECT_NEAR(glm::length(b.normals[0]), 1.0f, 1e-5f);
  EXPECT_GT(glm::length(a.normals[0] - b.normals[0]), 1e-3f);
  EXPECT_GT(a.normals[0].z, 0.5f);   // bent, not flipped
}

TEST(WorldDeforms, DeformsApplyInScriptOrderAndHostileNumbersStayFinite) {
  Vertices v;
  v.add({0, 0, 0}, {0, 0, 1});
  v.apply({wave(1.0f, q3::WaveFunc::Sin, 3.0e38f, 3.0e38f, 0.0f, 0.0f),
           wave(1.0f, q3::WaveFunc::Sin, 3.0e38f, 3.0e38f, 0.0f, 0.0f)},
          1.0);
  EXPECT_TRUE(std::isfinite(v.positions[0].z));
}

TEST(WorldDeforms, VertexDeformsLeaveAutospriteShadersToTheSprites) {
  q3::ShaderLibrary library;
  library.addScript(
      "textures/t/lava { deformVertexes wave 100 sin 3 2 0.1 0.1 deformVertexes text0 { map $whiteimage } }\n"
      "textures/t/flame { deformVertexes autosprite deformVertexes move 0 0 1 sin 0 1 0 1 { map $whiteimage } }\n",
      "test.shader");
  ASSERT_NE(library.find("textures/t/lava"), nullptr);
  const std::vector<q3::Deform> lava = vertexDeforms(*library.find("textures/t/lava"));
  ASSERT_EQ(lava.size(), 1u);
  EXPECT_EQ(lava[0].kind, q3::DeformKind::Wave);
  EXPECT_FLOAT_EQ(lava[0].wave.amplitude, 2.0f);
  EXPECT_TRUE(vertexDeforms(*library.find("textures/t/flame")).empty());
}

TEST(WorldDeforms, BatchDeformsOnlyTheDeformedShadersVerticesOnce) {
  GeometryBatch batch;
  batch.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  batch.normals.assign(4, glm::vec3(0, 0, 1));
  batch.uvs.assign(4, glm::vec2(0));
  batch.colors.assign(4, glm::vec4(1));
  batch.indices = {0, 1, 2, 1, 3, 2, 0, 1, 2};   // triangles 0 and 1 share vertices 1 and 2
  batch.triangleShaders = {7, 7, 9};
  const std::vector<q3::Deform> lift = {wave(1.0f, q3::WaveFunc::Sin, 2.0f, 0.0f, 0.0f, 0.0f)};
  deformBatch(batch, 0.0, [&](q3abi::qhandle_t h) { return h == 7 ? &lift : nullptr; });
  for (const glm::vec3& p : batch.positions) EXPECT_FLOAT_EQ(p.z, 2.0f);   // each once, not twice
}

TEST(WorldDeforms, WorldMeshesLeaveTheStaticMeshAndAreUploadedDeformed) {
  q3::ShaderLibrary library;
  library.addScript("textures/t/lava { deformVertexes move 0 0 1 sin 0 8 0 1 { map $whiteimage } }\n", "t.shader");
  q3::WorldScene scene;
  q3::WorldMaterial lava;
  lava.shaderName = "textures/t/lava";
  lava.fromScript = true;
  q3::WorldMaterial wall = lava;
  wall.shaderName = "textures/t/wall";
  scene.materials = {lava, wall};
  q3::WorldMesh mesh;
  mesh.positions = {{0, 0, 0}, {64, 0, 0}, {64, 64, 0}};
  mesh.normals.assign(3, glm::vec3(0, 0, 1));
  mesh.uvs.assign(3, glm::vec2(0));
  mesh.lightmapUvs = mesh.uvs;
  mesh.colors.assign(3, glm::vec4(1));
  mesh.indices = {0, 1, 2};
  scene.models.resize(1);
  scene.models[0].meshes = {mesh, mesh};
  scene.models[0].meshes[1].material = 1;
  mesh.material = 0;

  WorldDeforms deforms;
  EXPECT_EQ(deforms.extract(scene, library), 1u);
  EXPECT_TRUE(scene.models[0].meshes[0].indices.empty());   // left to the dynamic mesh
  EXPECT_EQ(scene.models[0].meshes[1].indices.size(), 3u);  // the wall stays static
  EXPECT_EQ(deforms.triangles(), 1u);

  pa::Renderer renderer(pa::RendererConfig{1});
  const pa::bridge::WorldHandles handles = pa::bridge::uploadWorld(scene, renderer);
  pa::bridge::showSkyAndFog(handles, renderer);
  EXPECT_EQ(handles.triangles, 1u);   // only the wall in the static mesh
  deforms.bind(scene, handles);
  const glm::mat4x3 identity(1.0f);
  const auto place = [&](uint32_t model) -> const glm::mat4x3* { return model == 0 ? &identity : nullptr; };
  // At 0.25 s the lava is lifted 8 units: a camera looking down at z = 4 sees it only then.
  pa::Camera camera;
  camera.origin = {40, 16, 100};
  camera.forward = {0, 0, -1};
  camera.left = {0, 1, 0};
  camera.up = {1, 0, 0};
  camera.fovX = camera.fovY = 1.0f;
  pa::RenderSettings settings;
  settings.width = settings.height = 1;
  settings.integrator = pa::Integrator::Lightmap;
  for (const double seconds : {0.0, 0.25}) {
    deforms.update(seconds, place, renderer);
    renderer.commit();
    const pa::FrameView frame = renderer.render(camera, settings);
    EXPECT_NEAR(frame.depth[0], 100.0f - (seconds == 0.0 ? 0.0f : 8.0f), 1e-2f) << seconds;
  }
}

}  // namespace
}  // namespace glue
