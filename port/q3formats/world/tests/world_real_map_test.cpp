// WorldScene of the real oa_dm1 (OpenArena data, skipped when not installed).
#include <algorithm>
#include <filesystem>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "port/q3formats/world/world_game.h"

namespace q3 {
namespace {

const std::filesystem::path kGameDir = "/usr/share/games/openarena/baseoa";

class RealMapTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!std::filesystem::exists(kGameDir / "pak1-maps.pk3")) return;
    game_ = new GameWorlds(kGameDir);
    scene_ = new WorldScene(game_->load("oa_dm1"));
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete game_;
  }
  void SetUp() override {
    if (!scene_) GTEST_SKIP() << "OpenArena data not installed at " << kGameDir;
  }
  static GameWorlds* game_;
  static WorldScene* scene_;
};
GameWorlds* RealMapTest::game_ = nullptr;
WorldScene* RealMapTest::scene_ = nullptr;

TEST_F(RealMapTest, Oa_dm1HasWorldSubModelsMaterialsAndNoMissingContent) {
  const WorldScene& s = *scene_;
  ASSERT_GE(s.models.size(), 2u);
  EXPECT_FALSE(s.models[0].meshes.empty());
  EXPECT_FALSE(s.models[1].meshes.empty());   // *1: a door
  EXPECT_GE(s.materials.size(), 20u);
  EXPECT_GE(s.lightmaps.size(), 1u);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  size_t triangles = 0;
  for (const auto& model : s.models)
    for (const auto& mesh : model.meshes) triangles += mesh.indices.size() / 3;
  EXPECT_GT(triangles, 7000u);   // 7532 drawable triangles in the file, minus nodraw
  EXPECT_EQ(s.cameras.size(), 9u);   // 7 info_player_deathmatch, info_player_start, info_player_intermission
  EXPECT_EQ(s.fogs.size(), 1u);           // the lava fog
  bool emissive = false;
  for (const auto& m : s.materials) emissive = emissive || m.surfaceLight > 0.0f;
  EXPECT_TRUE(emissive);
}

TEST_F(RealMapTest, Oa_dm1LavaFogIsItsBrush) {
  ASSERT_EQ(scene_->fogs.size(), 1u);
  const WorldFog& fog = scene_->fogs[0];
  EXPECT_EQ(fog.shaderName, "textures/liquids/lavahell");
  EXPECT_GT(fog.depthForOpaque, 0.0f);
  ASSERT_GE(fog.planes.size(), 6u);
  ASSERT_FALSE(fog.bounds.empty());
  // The brush's planes enclose the middle of its bounds and exclude points just outside them.
  const glm::vec3 middle = 0.5f * (fog.bounds.mins + fog.bounds.maxs);
  const glm::vec3 above(middle.x, middle.y, fog.bounds.maxs.z + 1.0f);
  bool inside = true, outside = false;
  for (const glm::vec4& p : fog.planes) {
    EXPECT_NEAR(glm::length(glm::vec3(p)), 1.0f, 1e-5f);
    inside = inside && glm::dot(glm::vec3(p), middle) <= p.w;
    outside = outside || glm::dot(glm::vec3(p), above) > p.w;
  }
  EXPECT_TRUE(inside);
  EXPECT_TRUE(outside);
  // The lava shader is a fog shader with stages: its surface is drawn.
  const auto lava = std::find_if(scene_->materials.begin(), scene_->materials.end(),
                                 [](const WorldMaterial& m) { return m.shaderName == "textures/liquids/lavahell"; });
  ASSERT_NE(lava, scene_->materials.end());
  EXPECT_TRUE(lava->fog);
  EXPECT_TRUE(lava->visible);
}

TEST_F(RealMapTest, TrianglesFaceTheirNormals) {
  // Counter-clockwise winding: the geometric normal agrees with the stored vertex normals on
  // every brush face and patch; baked misc_models ("models/...") carry smoothed normals that
  // disagree at silhouettes (oa_dm1's torch: 100 of 3080 triangles).
  size_t agree[2] = {0, 0}, total[2] = {0, 0};
  for (const auto& model : scene_->models)
    for (const auto& mesh : model.meshes) {
      const int soup = scene_->materials[mesh.material].shaderName.rfind("models/", 0) == 0 ? 1 : 0;
      for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        glm::vec3 face = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
        if (glm::length(face) < 1e-4f) continue;
        glm::vec3 n = mesh.normals[a] + mesh.normals[b] + mesh.normals[c];
        agree[soup] += glm::dot(face, n) > 0.0f;
        ++total[soup];
      }
    }
  ASSERT_GT(total[0], 0u);
  EXPECT_EQ(agree[0], total[0]);
  EXPECT_GT(double(agree[1]) / double(std::max<size_t>(total[1], 1)), 0.95) << agree[1] << " of " << total[1];
}

TEST_F(RealMapTest, SampleOfTheGamesMapsBuildsWithoutThrowing) {
  // Every 5th map keeps the test short; `assets_converter --all` covers every map.
  size_t built = 0;
  const std::vector<std::string> maps = game_->maps();
  for (size_t i = 0; i < maps.size(); i += 5) {
    const std::string& map = maps[i];
    WorldBuildOptions options;
    options.loadTextures = false;   // geometry, materials, entities: fast
    EXPECT_NO_THROW({
      WorldScene s = game_->load(map, options);
      EXPECT_FALSE(s.models.empty()) << map;
    }) << map;
    ++built;
  }
  EXPECT_GE(built, 8u);
}

}  // namespace
}  // namespace q3
