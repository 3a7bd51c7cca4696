// Maps compiled with lightmaps beside them, built through buildWorldScene as every tool does:
// q3map2 -external (empty lump, lm_NNNN.tga numbered like pages), lightmaps of other sizes named
// by the shaders q3map2 writes, and lightmap numbers that select nothing (vertex light, one warning).
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/tests/external_lightmap_map.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/world/world_external_lightmaps.h"
#include "port/q3formats/world/world_scene.h"

namespace q3 {
namespace {

constexpr const char* kCustomShader = R"(
maps/ext/textures/test/wall_0a1b2c3d
{
  { map textures/test/wall.tga rgbGen identity }
  { map maps/ext/lm_0000.tga blendFunc GL_DST_COLOR GL_ZERO
    tcgen lightmap }
}
)";

class ExternalLightmapsTest : public ::testing::Test {
 protected:
  WorldScene build(const testing::BspWriter& w, const std::string& name = "maps/ext.bsp") {
    const auto bytes = w.build();
    const BspFile bsp = parseBsp(bytes, name);
    FileLoader loader = [this](std::string_view path) -> std::optional<std::vector<std::byte>> {
      const auto it = files_.find(std::string(path));
      if (it == files_.end()) return std::nullopt;
      return it->second;
    };
    return buildWorldScene(bsp, library_, loader);
  }
  static size_t countWarnings(const WorldScene& scene, const std::string& text) {
    size_t n = 0;
    for (const std::string& warning : scene.warnings) n += warning.find(text) != std::string::npos;
    return n;
  }
  static std::array<uint8_t, 3> texelAt(const WorldImage& image, glm::vec2 uv) {
    const size_t x = size_t(uv.x * float(image.width)), y = size_t(uv.y * float(image.height));
    const size_t i = (y * image.width + x) * 4;
    return {image.rgba8[i], image.rgba8[i + 1], image.rgba8[i + 2]};
  }

  ShaderLibrary library_;
  std::map<std::string, std::vector<std::byte>> files_;
};

TEST(ExternalLightmapNames, FolderAndNumbering) {
  EXPECT_EQ(externalLightmapFolder("maps/ext.bsp"), "maps/ext");
  EXPECT_EQ(externalLightmapFolder("/home/me/q3/baseoa/maps/ext.bsp"), "maps/ext");
  EXPECT_EQ(externalLightmapFolder("ext"), "maps/ext");
  EXPECT_EQ(externalLightmapFolder("maps/"), "");
  EXPECT_EQ(externalLightmapName("maps/ext", 3), "maps/ext/lm_0003");
  EXPECT_EQ(externalLightmapName("maps/ext", 12345), "maps/ext/lm_12345");
}

TEST_F(ExternalLightmapsTest, EmptyLumpUsesTheNumberedImagesBesideTheMap) {
  // Texel (x, y) of the 4x4 lm_0000 is (16x, 16y, 7); lm_0001 is a second, grey page.
  files_["maps/ext/lm_0000.tga"] = testing::tga24(4, 4, [](int x, int y) {
    return std::array<uint8_t, 3>{uint8_t(16 * x), uint8_t(16 * y), 7};
  });
  files_["maps/ext/lm_0001.tga"] = testing::tga24(2, 2, [](int, int) { return std::array<uint8_t, 3>{9, 9, 9}; });
  auto w = testing::externalLightmapMap(1);
  w.addQuad({glm::vec3(0, 0, 8), {64, 0, 8}, {0, 64, 8}, {64, 64, 8}}, {0, 0, 1});
  w.surfaces[1].lightmap = 0;
  w.drawVerts[4].lightmap = {0.6f, 0.3f};   // texel (2, 1)
  w.models[0].numSurfaces = 2;
  w.leafs[0].numLeafSurfaces = 2;
  w.leafSurfaces.push_back(1);
  const WorldScene scene = build(w);
  ASSERT_EQ(scene.lightmaps.size(), 2u);
  EXPECT_EQ(scene.lightmaps[0].width, 4u);
  EXPECT_EQ(scene.lightmaps[1].width, 2u);
  EXPECT_EQ(countWarnings(scene, "lightmap"), 0u);
  ASSERT_EQ(scene.models[0].meshes.size(), 2u);
  const WorldMesh* first = nullptr;
  for (const WorldMesh& mesh : scene.models[0].meshes) {
    EXPECT_FALSE(scene.materials[mesh.material].vertexLit);
    if (mesh.lightmap == 0) first = &mesh;
  }
  ASSERT_NE(first, nullptr);
  const auto texel = texelAt(scene.lightmaps[0], first->lightmapUvs[0]);
  EXPECT_EQ(texel, (std::array<uint8_t, 3>{32, 16, 7}));
  EXPECT_EQ(scene.lightmaps[0].rgba8[3], 255);
}

TEST_F(ExternalLightmapsTest, NumbersSelectingNoLightmapAreVertexLitWithOneWarning) {
  auto w = testing::externalLightmapMap(5);   // no lm_NNNN beside the map
  w.addQuad({glm::vec3(0, 0, 8), {64, 0, 8}, {0, 64, 8}, {64, 64, 8}}, {0, 0, 1});
  w.surfaces[1].lightmap = 9;
  w.addQuad({glm::vec3(0, 0, 16), {64, 0, 16}, {0, 64, 16}, {64, 64, 16}}, {0, 0, 1});
  w.surfaces[2].lightmap = -1000;   // below the engine's numbers: vertex light too
  w.models[0].numSurfaces = 3;
  w.leafs[0].numLeafSurfaces = 3;
  w.leafSurfaces = {0, 1, 2};
  const WorldScene scene = build(w);
  EXPECT_TRUE(scene.lightmaps.empty());
  EXPECT_EQ(countWarnings(scene, "selects none"), 1u);
  ASSERT_FALSE(scene.models[0].meshes.empty());
  for (const WorldMesh& mesh : scene.models[0].meshes) {
    EXPECT_EQ(mesh.lightmap, -1);
    EXPECT_TRUE(scene.materials[mesh.material].vertexLit);
  }
  // The same with a lump: numbers past its pages fall back, the page in range is used.
  auto internal = testing::externalLightmapMap(0);
  internal.lightmaps.assign(size_t(kLightmapSize) * kLightmapSize * 3, 40);
  internal.addQuad({glm::vec3(0, 0, 8), {64, 0, 8}, {0, 64, 8}, {64, 64, 8}}, {0, 0, 1});
  internal.surfaces[1].lightmap = 1;
  internal.models[0].numSurfaces = 2;
  internal.leafs[0].numLeafSurfaces = 2;
  internal.leafSurfaces = {0, 1};
  const WorldScene mixed = build(internal);
  ASSERT_EQ(mixed.lightmaps.size(), 1u);
  EXPECT_EQ(countWarnings(mixed, "selects none"), 1u);
  ASSERT_EQ(mixed.models[0].meshes.size(), 2u);
  EXPECT_EQ(mixed.models[0].meshes[0].lightmap + mixed.models[0].meshes[1].lightmap, -1);   // 0 and -1
}

TEST_F(ExternalLightmapsTest, LargeLightmapIsSampledAtTheRightTexel) {
  // 512x512, grey except texel (300, 100): the quad's first corner samples exactly that texel.
  files_["maps/ext/lm_0000.tga"] = testing::tga24(512, 512, [](int x, int y) {
    return x == 300 && y == 100 ? std::array<uint8_t, 3>{250, 0, 0} : std::array<uint8_t, 3>{20, 20, 20};
  });
  auto w = testing::externalLightmapMap(0);
  w.drawVerts[0].lightmap = {300.5f / 512.0f, 100.5f / 512.0f};
  const WorldScene scene = build(w);
  ASSERT_EQ(scene.lightmaps.size(), 1u);
  ASSERT_EQ(scene.lightmaps[0].width, 512u);
  ASSERT_EQ(scene.lightmaps[0].height, 512u);
  ASSERT_EQ(scene.models[0].meshes.size(), 1u);
  const WorldMesh& mesh = scene.models[0].meshes[0];
  ASSERT_EQ(mesh.lightmap, 0);
  // The builder keeps vertex order; find the corner at the origin.
  for (size_t v = 0; v < mesh.positions.size(); ++v)
    if (mesh.positions[v] == glm::vec3(0.0f))
      EXPECT_EQ(texelAt(scene.lightmaps[0], mesh.lightmapUvs[v]), (std::array<uint8_t, 3>{250, 0, 0}));
}

TEST_F(ExternalLightmapsTest, ShaderNamingItsLightmapImageUsesIt) {
  // q3map2 with a non-128 lightmap size: surface number -3 (by vertex), a custom shader whose
  // $lightmap stage became "maps/ext/lm_0000.tga" + tcgen lightmap. The lump may hold pages too.
  library_.addScript(kCustomShader, "scripts/q3map2_ext.shader");
  files_["textures/test/wall.tga"] = testing::tga24(2, 2, [](int, int) { return std::array<uint8_t, 3>{255, 255, 255}; });
  files_["maps/ext/lm_0000.tga"] = testing::tga24(256, 256, [](int, int) { return std::array<uint8_t, 3>{0, 60, 0}; });
  auto w = testing::externalLightmapMap(kLightmapByVertex);
  w.shaders[0].name = "maps/ext/textures/test/wall_0a1b2c3d";
  w.lightmaps.assign(size_t(kLightmapSize) * kLightmapSize * 3, 40);
  const WorldScene scene = build(w);
  ASSERT_EQ(scene.lightmaps.size(), 2u);   // the lump's page, then the named image
  ASSERT_EQ(scene.models[0].meshes.size(), 1u);
  const WorldMesh& mesh = scene.models[0].meshes[0];
  EXPECT_EQ(mesh.lightmap, 1);
  EXPECT_EQ(scene.lightmaps[1].width, 256u);
  EXPECT_EQ(scene.lightmaps[1].rgba8[1], 60);
  const WorldMaterial& m = scene.materials[mesh.material];
  EXPECT_FALSE(m.vertexLit);
  EXPECT_EQ(m.lightmap, 1);
  EXPECT_EQ(countWarnings(scene, "lightmap"), 0u);
  // Its image missing: vertex light, one warning naming the image.
  files_.erase("maps/ext/lm_0000.tga");
  const WorldScene missing = build(w);
  EXPECT_EQ(missing.models[0].meshes[0].lightmap, -1);
  EXPECT_EQ(countWarnings(missing, "maps/ext/lm_0000.tga"), 1u);
}

}  // namespace
}  // namespace q3
