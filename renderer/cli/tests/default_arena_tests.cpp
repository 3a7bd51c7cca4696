// The bundled default scene: the generator reproduces the committed file, and the file holds
// everything it is meant to exercise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "renderer/gltf_io/gltf_loader.h"

namespace {

namespace fs = std::filesystem;

std::string readAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(DefaultArena, CommittedFileMatchesItsGenerator) {
  const fs::path fresh = fs::temp_directory_path() / ("pa_default_arena_" + std::to_string(::getpid()) + ".gltf");
  const std::string command = std::string("\"") + PA_MAKE_DEFAULT_ARENA + "\" \"" + fresh.string() + "\"";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const bool same = readAll(fresh) == readAll(PA_DEFAULT_ARENA);
  fs::remove(fresh);
  EXPECT_TRUE(same) << "regenerate: pa-make-default-arena renderer/cli/scenes/default_arena.gltf";
  EXPECT_LT(fs::file_size(PA_DEFAULT_ARENA), 200u * 1024u);
}

TEST(DefaultArena, HoldsEveryFeatureItShowsOff) {
  const pa::gltf::GltfScene scene = pa::gltf::loadScene(PA_DEFAULT_ARENA);
  EXPECT_TRUE(scene.warnings.empty());
  ASSERT_EQ(scene.cameras.size(), 1u);
  EXPECT_NEAR(scene.cameras[0].aspectRatio, 16.0f / 9.0f, 1e-5f);
  ASSERT_EQ(scene.lights.size(), 2u);
  EXPECT_EQ(scene.lights[0].type, pa::gltf::LightType::Point);
  EXPECT_EQ(scene.lights[1].type, pa::gltf::LightType::Directional);
  EXPECT_NEAR(scene.lights[1].direction.z, std::cos(0.5236f), 1e-4f);   // into the room, through the window
  EXPECT_NEAR(scene.lights[1].direction.y, -0.5f, 1e-4f);
  bool masked = false, emissive = false, textured = false;
  for (const pa::gltf::GltfMaterial& m : scene.materials) {
    masked |= m.alphaMode == pa::gltf::AlphaMode::Mask && m.baseColorTexture != pa::gltf::kNone;
    emissive |= m.emissive.x > 1.0f;
    textured |= m.name == "floor_checker" && m.baseColorTexture != pa::gltf::kNone;
  }
  EXPECT_TRUE(masked);
  EXPECT_TRUE(emissive);
  EXPECT_TRUE(textured);
  EXPECT_EQ(scene.sceneExtras.count("sky_color"), 1u);
  size_t pillars = 0;
  for (const pa::gltf::GltfInstance& instance : scene.instances) pillars += instance.nodeName.starts_with("pillar_");
  EXPECT_EQ(pillars, 4u);
}

}  // namespace
