// Known-answer tests of glue::World, the map behind GetEntityToken, LightForPoint, inPVS and
// MarkFragments: synthetic maps built with q3formats' BspWriter, and oa_dm1 from the installed
// OpenArena data (skipped when absent) with answers measured on the module's previous reader.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "port/engine_glue/world.h"
#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/bsp/tests/bsp_writer.h"
#include "port/q3formats/common/format_error.h"
#include "port/q3formats/vfs/game_filesystem.h"

namespace glue {
namespace {

std::vector<uint8_t> bytesOf(const std::vector<std::byte>& b) {
  const auto* p = reinterpret_cast<const uint8_t*>(b.data());
  return {p, p + b.size()};
}

std::vector<std::string> allTokens(World& world, int size = 1024) {
  std::vector<std::string> tokens;
  std::vector<char> buffer(static_cast<size_t>(size));
  while (world.nextEntityToken(buffer.data(), size)) tokens.emplace_back(buffer.data());
  EXPECT_STREQ(buffer.data(), "");   // the end writes an empty token
  return tokens;
}

/// MarkFragments into fixed buffers; returns the fragments as polygons.
std::vector<std::vector<glm::vec3>> marks(const World& world, const std::vector<glm::vec3>& decal,
                                          const glm::vec3& projection, int maxPoints = 384,
                                          int maxFragments = 128) {
  std::vector<float> in;
  for (const glm::vec3& p : decal) in.insert(in.end(), {p.x, p.y, p.z});
  std::vector<float> points(static_cast<size_t>(std::max(maxPoints, 1)) * 3);
  std::vector<q3abi::markFragment_t> fragments(static_cast<size_t>(std::max(maxFragments, 1)));
  const float project[3] = {projection.x, projection.y, projection.z};
  const int count = world.markFragments(static_cast<int>(decal.size()), reinterpret_cast<const float(*)[3]>(in.data()),
                                        project, maxPoints, points.data(), maxFragments, fragments.data());
  std::vector<std::vector<glm::vec3>> out;
  for (int f = 0; f < count; ++f) {
    auto& polygon = out.emplace_back();
    for (int i = 0; i < fragments[f].numPoints; ++i) {
      const float* p = &points[static_cast<size_t>(fragments[f].firstPoint + i) * 3];
      polygon.emplace_back(p[0], p[1], p[2]);
    }
  }
  return out;
}

/// A square decal of half-size r around `centre` in the plane z = centre.z, clockwise seen from
/// above (the cgame's winding for a projection pointing down).
std::vector<glm::vec3> squareFacingDown(const glm::vec3& centre, float r) {
  return {centre + glm::vec3(-r, -r, 0), centre + glm::vec3(-r, r, 0), centre + glm::vec3(r, r, 0),
          centre + glm::vec3(r, -r, 0)};
}

float area(const std::vector<glm::vec3>& polygon) {
  glm::vec3 sum(0.0f);
  for (size_t i = 1; i + 1 < polygon.size(); ++i)
    sum += glm::cross(polygon[i] - polygon[0], polygon[i + 1] - polygon[0]);
  return 0.5f * glm::length(sum);
}

TEST(WorldEntityTokens, FollowComParseAndRewindAtTheEnd) {
  auto w = q3::testing::sampleMap();
  w.entities = "{ // comment\n\"classname\" \"worldspawn\" /* block\n comment */ bare\"word \"\" }";
  World world(bytesOf(w.build()), "maps/tokens.bsp");
  const std::vector<std::string> expected = {"{", "classname", "worldspawn", "bare\"word", "", "}"};
  EXPECT_EQ(allTokens(world), expected);
  EXPECT_EQ(allTokens(world), expected);   // rewound: a second reader sees it all again
  char small[5];
  ASSERT_TRUE(world.nextEntityToken(small, sizeof small));
  ASSERT_TRUE(world.nextEntityToken(small, sizeof small));
  EXPECT_STREQ(small, "clas");   // truncated to size - 1, the rest of the token consumed
  ASSERT_TRUE(world.nextEntityToken(small, sizeof small));
  EXPECT_STREQ(small, "worl");
  EXPECT_TRUE(world.nextEntityToken(nullptr, 0));   // no buffer: still advances
}

TEST(WorldLight, GridIsShiftedAndAmbientScaledAsTheEngine) {
  auto w = q3::testing::sampleMap();   // every grid point: ambient (10, 20, 30), directed 100
  World world(bytesOf(w.build()), "maps/grid.bsp");
  const float point[3] = {100, 60, 0};
  float ambient[3], directed[3], dir[3];
  ASSERT_TRUE(world.lightForPoint(point, ambient, directed, dir));
  // Overbright shift x4: (40, 80, 120), then r_ambientScale 0.6; (400, 400, 400) saturates to 255.
  EXPECT_FLOAT_EQ(ambient[0], 24.0f);
  EXPECT_FLOAT_EQ(ambient[1], 48.0f);
  EXPECT_FLOAT_EQ(ambient[2], 72.0f);
  EXPECT_FLOAT_EQ(directed[0], 255.0f);
  EXPECT_NEAR(dir[2], 1.0f, 1e-6f);   // longitude 0: straight up

  w.lightGrid.assign(w.lightGrid.size() - 8, 0);   // size mismatch: no grid, as the engine
  World noGrid(bytesOf(w.build()), "maps/nogrid.bsp");
  EXPECT_FALSE(noGrid.lightForPoint(point, ambient, directed, dir));
}

TEST(WorldVisibility, ClustersAndTheEngineFallbacks) {
  auto w = q3::testing::sampleMap();
  // The plane z = 0 splits the map: above is leaf 0 (cluster 0), below leaf 1 (cluster 1);
  // cluster 0 sees only itself, cluster 1 sees both.
  w.nodes = {{0, {-1, -2}, {0, 0, -64}, {256, 256, 64}}};
  q3::BspLeaf below = w.leafs[0];
  below.cluster = 1;
  w.leafs.push_back(below);
  w.visibility = {2, 0, 0, 0, 1, 0, 0, 0, 0x01, 0x03};
  World world(bytesOf(w.build()), "maps/vis.bsp");
  const float above[3] = {10, 10, 10}, under[3] = {10, 10, -10};
  EXPECT_EQ(world.leafAt({10, 10, 10}), 0);
  EXPECT_EQ(world.leafAt({10, 10, -10}), 1);
  EXPECT_EQ(world.clusterOf(1), 1);
  EXPECT_EQ(world.clusterOf(7), -1);
  EXPECT_FALSE(world.inPVS(above, under));
  EXPECT_TRUE(world.inPVS(under, above));
  EXPECT_TRUE(world.inPVS(above, above));

  w.visibility.clear();   // not vised: everything is visible
  World open(bytesOf(w.build()), "maps/novis.bsp");
  EXPECT_TRUE(open.inPVS(above, under));
}

TEST(WorldMarks, DecalOnTheFloorIsClippedToItsSquare) {
  auto w = q3::testing::sampleMap();   // floor quad (0..256)^2 at z = 0, a patch over y < 128
  World world(bytesOf(w.build()), "maps/marks.bsp");
  const auto onFloor = marks(world, squareFacingDown({200, 200, 8}, 8), {0, 0, -20});
  ASSERT_EQ(onFloor.size(), 1u);
  EXPECT_NEAR(area(onFloor[0]), 256.0f, 1e-2f);
  for (const glm::vec3& p : onFloor[0]) {
    EXPECT_FLOAT_EQ(p.z, 0.0f);
    EXPECT_LE(std::fabs(p.x - 200), 8.0f + 1e-3f);
    EXPECT_LE(std::fabs(p.y - 200), 8.0f + 1e-3f);
  }
  // Wound the other way the edge planes face outwards and clip everything (as the engine).
  auto reversed = squareFacingDown({200, 200, 8}, 8);
  std::reverse(reversed.begin(), reversed.end());
  EXPECT_TRUE(marks(world, reversed, {0, 0, -20}).empty());
  // The volume ends 20 units past the first point, whatever the projection's length.
  EXPECT_TRUE(marks(world, squareFacingDown({200, 200, 30}, 8), {0, 0, -64}).empty());
  // Projected along the floor (grazing) or from below: no mark.
  EXPECT_TRUE(marks(world, squareFacingDown({200, 200, -8}, 8), {0, 0, 20}).empty());
  // No room for the fragment's points: none written.
  EXPECT_TRUE(marks(world, squareFacingDown({200, 200, 8}, 8), {0, 0, -20}, 3).empty());
}

TEST(WorldMarks, PatchesTakeMarksOnTheirTessellatedTriangles) {
  auto w = q3::testing::sampleMap();   // the patch bulges up to z = 32 at x = 64
  World world(bytesOf(w.build()), "maps/marks.bsp");
  const auto onPatch = marks(world, squareFacingDown({64, 64, 40}, 4), {0, 0, -20});
  ASSERT_FALSE(onPatch.empty());
  float total = 0;
  for (const auto& fragment : onPatch) {
    total += area(fragment);
    // On the curve within the tessellation tolerance (4 units); the floor is out of reach.
    for (const glm::vec3& p : fragment) EXPECT_NEAR(p.z, 32.0f, 4.0f);
  }
  // The decal's own 8 x 8 seen from above, a little more on the tilted triangles.
  EXPECT_GT(total, 63.9f);
  EXPECT_LT(total, 70.0f);
  // At most maxFragments.
  EXPECT_EQ(marks(world, squareFacingDown({64, 64, 40}, 4), {0, 0, -20}, 384, 1).size(), 1u);
}

TEST(WorldMarks, NoMarksShadersAndMoversAreSkipped) {
  auto w = q3::testing::sampleMap();
  w.shaders[0].surfaceFlags = 0x20;   // SURF_NOMARKS on the floor and the patch
  World world(bytesOf(w.build()), "maps/nomarks.bsp");
  EXPECT_TRUE(marks(world, squareFacingDown({200, 200, 8}, 8), {0, 0, -20}).empty());
  EXPECT_TRUE(marks(world, squareFacingDown({64, 64, 40}, 4), {0, 0, -20}).empty());
  // The door (*1) at z = 32 over (0..32)^2 moves: it takes none (floor and patch are too far).
  auto plain = q3::testing::sampleMap();
  World movers(bytesOf(plain.build()), "maps/door.bsp");
  EXPECT_TRUE(marks(movers, squareFacingDown({16, 16, 40}, 4), {0, 0, -20}).empty());
}

TEST(WorldModels, BrushModelBoundsComeFromTheModelsLump) {
  auto w = q3::testing::sampleMap();   // model 0 the world, model 1 the door
  World world(bytesOf(w.build()), "maps/models.bsp");
  ASSERT_EQ(world.brushModels().size(), 2u);
  EXPECT_EQ(world.brushModels()[0].mins, glm::vec3(0, 0, -64));
  EXPECT_EQ(world.brushModels()[1].mins, glm::vec3(0, 0, 32));
  EXPECT_EQ(world.brushModels()[1].maxs, glm::vec3(32, 32, 32));
  EXPECT_EQ(world.name(), "maps/models.bsp");
}

TEST(WorldHostile, MalformedMapsThrowFormatErrors) {
  auto w = q3::testing::sampleMap();
  w.lumpOverride[3] = {1 << 30, 36};   // nodes lump outside the file
  EXPECT_THROW(World(bytesOf(w.build()), "maps/bad.bsp"), q3::FormatError);
  EXPECT_THROW(World({}, "maps/empty.bsp"), q3::FormatError);
}

/// oa_dm1 from the installed game, or nullptr.
std::unique_ptr<World> loadOaDm1() {
  const std::filesystem::path dir = "/usr/share/games/openarena/baseoa";
  if (!std::filesystem::exists(dir / "pak1-maps.pk3")) return nullptr;
  q3::GameFileSystem game(dir);
  const auto bytes = game.readFile("maps/oa_dm1.bsp");
  if (!bytes) return nullptr;
  const auto* p = reinterpret_cast<const uint8_t*>(bytes->data());
  return std::make_unique<World>(std::vector<uint8_t>(p, p + bytes->size()), "maps/oa_dm1.bsp");
}

TEST(WorldRealMap, EntityTokensAreTheEntityLump) {
  auto world = loadOaDm1();
  if (!world) GTEST_SKIP() << "OpenArena data not installed";
  // The token stream is every entity's braces, keys and values in file order.
  std::vector<std::string> expected;
  for (const q3::Entity& e : q3::parseEntities(world->bsp().entities, "oa_dm1")) {
    expected.push_back("{");
    for (const auto& [key, value] : e.keys) expected.insert(expected.end(), {key, value});
    expected.push_back("}");
  }
  const auto tokens = allTokens(*world);
  EXPECT_EQ(tokens.size(), 560u);   // measured with the previous reader
  EXPECT_EQ(tokens, expected);
}

TEST(WorldRealMap, LightVisibilityAndMarksMatchThePreviousReader) {
  auto world = loadOaDm1();
  if (!world) GTEST_SKIP() << "OpenArena data not installed";
  // The spawn points, in entity order. Light: measured with the previous reader (same grid
  // sampling, no r_ambientScale), ambient x 0.6.
  const auto spawns = q3::readSpawnCameras(q3::parseEntities(world->bsp().entities, "oa_dm1"));
  ASSERT_EQ(spawns.size(), 9u);
  const float at[3] = {spawns[0].origin.x, spawns[0].origin.y, spawns[0].origin.z};
  ASSERT_EQ(spawns[0].origin, glm::vec3(280, 1416, -120));
  float ambient[3], directed[3], dir[3];
  ASSERT_TRUE(world->lightForPoint(at, ambient, directed, dir));
  EXPECT_NEAR(ambient[0], 41.5938f * 0.6f, 1e-3f);
  EXPECT_NEAR(ambient[1], 40.1836f * 0.6f, 1e-3f);
  EXPECT_NEAR(ambient[2], 39.7773f * 0.6f, 1e-3f);
  EXPECT_NEAR(directed[0], 192.7734f, 1e-3f);
  EXPECT_NEAR(directed[2], 181.9561f, 1e-3f);
  EXPECT_NEAR(dir[0], -0.7851f, 1e-4f);
  EXPECT_NEAR(dir[2], 0.5948f, 1e-4f);

  // Who sees whom among the spawn points (rows: from), measured with the previous reader.
  const char* const expected[9] = {"101101000", "010000100", "111100000", "101110000", "000111000",
                                   "100011000", "010000100", "000000011", "000000011"};
  for (size_t a = 0; a < spawns.size(); ++a) {
    std::string row;
    for (size_t b = 0; b < spawns.size(); ++b) {
      const float p[3] = {spawns[a].origin.x, spawns[a].origin.y, spawns[a].origin.z};
      const float q[3] = {spawns[b].origin.x, spawns[b].origin.y, spawns[b].origin.z};
      row += world->inPVS(p, q) ? '1' : '0';
    }
    EXPECT_EQ(row, expected[a]) << "from spawn " << a;
  }
  EXPECT_EQ(world->clusterOf(world->leafAt(spawns[0].origin)), 120);

  // A bullet mark on the floor under spawn 1 (as the cgame asks: 20 units down from just above).
  const glm::vec3 centre = spawns[1].origin - glm::vec3(0, 0, 20);
  const auto floor = marks(*world, squareFacingDown(centre, 8), {0, 0, -20});
  ASSERT_FALSE(floor.empty());
  float total = 0;
  for (const auto& fragment : floor) {
    total += area(fragment);
    for (const glm::vec3& p : fragment) {
      EXPECT_LE(std::fabs(p.x - centre.x), 8.01f);
      EXPECT_LE(std::fabs(p.y - centre.y), 8.01f);
      EXPECT_LE(p.z, centre.z + 0.01f);
    }
  }
  EXPECT_NEAR(total, 256.0f, 1.0f);
}

}  // namespace
}  // namespace glue
