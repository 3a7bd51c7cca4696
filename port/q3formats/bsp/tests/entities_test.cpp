// Entity lump parser and typed views.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/entities.h"
#include "port/q3formats/common/format_error.h"

namespace q3 {
namespace {

void expectVec(const glm::vec3& actual, const glm::vec3& expected, float eps = 1e-5f) {
  EXPECT_NEAR(actual.x, expected.x, eps);
  EXPECT_NEAR(actual.y, expected.y, eps);
  EXPECT_NEAR(actual.z, expected.z, eps);
}

TEST(Entities, ParsesKeysCommentsAndBareTokens) {
  const auto e = parseEntities(
      "// header comment\n{\n\"classname\" \"worldspawn\" /* inline */ \"message\" \"Hello { } world\"\n}\n"
      "{ classname light \"origin\" \"1 2 3\" \"empty\" \"\" }",
      "m.bsp");
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0].className(), "worldspawn");
  EXPECT_EQ(e[0].get("message"), "Hello { } world");
  EXPECT_EQ(e[1].get("CLASSNAME"), "light");  // keys are case-insensitive
  EXPECT_EQ(e[1].get("empty", "x"), "");
  EXPECT_EQ(e[1].get("missing", "fallback"), "fallback");
  expectVec(*e[1].getVec3("origin"), {1, 2, 3});
  EXPECT_FALSE(e[1].getVec3("empty").has_value());
  EXPECT_EQ(e[1].getFloat("origin", 7), 1.0f);  // first number of the value
  EXPECT_TRUE(parseEntities("", "m.bsp").empty());
  EXPECT_TRUE(parseEntities("  \n// only a comment", "m.bsp").empty());
}

TEST(Entities, DuplicateKeysKeepTheFirstForLookupAndAllInOrder) {
  const auto e = parseEntities("{ \"a\" \"1\" \"a\" \"2\" }", "m.bsp");
  EXPECT_EQ(e[0].get("a"), "1");
  EXPECT_EQ(e[0].keys.size(), 2u);
}

TEST(Entities, MalformedTextThrowsWithFileAndLine) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{ \"classname\" \"worldspawn }", "unterminated quoted string at line 1"},
      {"{\n\"a\" \"b\"\n", "not closed"},
      {"{ \"a\" }", "has no value"},
      {"{ \"a\" \"b\" { }", "'{' inside entity"},
      {"\"a\" \"b\"", "expected '{'"},
      {"}", "expected '{'"},
      {"{ /* never closed", "unterminated block comment"},
      {"{ \"a\" \"b\" }\n\n{ \"c\" \"d }", "line 3"},
  };
  for (const auto& [text, message] : cases) {
    SCOPED_TRACE(text);
    try {
      parseEntities(text, "bad.bsp");
      ADD_FAILURE() << "accepted";
    } catch (const FormatError& e) {
      EXPECT_EQ(e.file(), "bad.bsp");
      EXPECT_EQ(e.field(), "entities");
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

TEST(Entities, HostileSizesHitTheLimits) {
  const std::string huge = "{ \"k\" \"" + std::string(100000, 'x') + "\" }";
  EXPECT_THROW(parseEntities(huge, "m.bsp"), FormatError);
  EntityParseLimits roomy;
  roomy.maxTokenLength = 200000;
  EXPECT_EQ(parseEntities(huge, "m.bsp", roomy)[0].get("k").size(), 100000u);

  std::string many;
  for (int i = 0; i < 20; ++i) many += "{ }";
  EntityParseLimits few;
  few.maxEntities = 10;
  EXPECT_THROW(parseEntities(many, "m.bsp", few), FormatError);
  few = {};
  few.maxKeysPerEntity = 2;
  EXPECT_THROW(parseEntities("{ \"a\" \"1\" \"b\" \"2\" \"c\" \"3\" }", "m.bsp", few), FormatError);
  // Embedded NUL bytes are whitespace, not terminators.
  const std::string withNul("{ \"a\" \"1\" }\0{ \"b\" \"2\" }", 23);
  EXPECT_EQ(parseEntities(withNul, "m.bsp").size(), 2u);
}

TEST(Entities, WorldspawnKeys) {
  const auto e = parseEntities(
      "{ \"classname\" \"worldspawn\" \"message\" \"Arena\" \"gridsize\" \"32 32 64\" \"_color\" \"2 1 0\" "
      "\"_ambient\" \"20\" \"_minlight\" \"8\" }",
      "m.bsp");
  const auto w = readWorldspawn(e);
  expectVec(w.minlight, {8, 4, 0});
  const auto plain = readWorldspawn(parseEntities("{ \"classname\" \"worldspawn\" \"minlight\" \"40\" }", "m.bsp"));
  expectVec(plain.minlight, {40, 40, 40});
  const auto negative = readWorldspawn(parseEntities("{ \"classname\" \"worldspawn\" \"_minlight\" \"-3\" }", "m.bsp"));
  expectVec(negative.minlight, {0, 0, 0});
  EXPECT_EQ(w.message, "Arena");
  expectVec(w.gridSize, {32, 32, 64});
  expectVec(w.color, {1, 0.5f, 0});
  expectVec(w.ambient, {20, 10, 0});
  EXPECT_TRUE(w.warnings.empty());

  const auto bad = readWorldspawn(parseEntities("{ \"classname\" \"worldspawn\" \"gridsize\" \"0 a\" }", "m.bsp"));
  expectVec(bad.gridSize, {64, 64, 128});
  EXPECT_EQ(bad.warnings.size(), 1u);
  expectVec(readWorldspawn({}).gridSize, {64, 64, 128});
}

TEST(Entities, PointAndSpotLights) {
  const auto e = parseEntities(
      "{ \"classname\" \"light\" \"origin\" \"0 0 100\" }"
      "{ \"classname\" \"light\" \"origin\" \"0 0 100\" \"_light\" \"750\" \"light\" \"10\" \"_color\" \"0 0 0.5\" "
      "\"spawnflags\" \"3\" }"
      "{ \"classname\" \"light\" \"origin\" \"0 0 100\" \"target\" \"t1\" \"radius\" \"100\" }"
      "{ \"classname\" \"light\" \"origin\" \"0 0 100\" \"target\" \"t1\" \"_cone\" \"15\" }"
      "{ \"classname\" \"light\" \"origin\" \"0 0 100\" \"target\" \"nobody\" }"
      "{ \"classname\" \"info_null\" \"targetname\" \"t1\" \"origin\" \"100 0 100\" }",
      "m.bsp");
  const auto lights = readLights(e);
  ASSERT_EQ(lights.size(), 5u);
  EXPECT_EQ(lights[0].intensity, 300.0f);
  expectVec(lights[0].color, {1, 1, 1});
  EXPECT_FALSE(lights[0].isSpot);
  EXPECT_FALSE(lights[0].linearFalloff);
  EXPECT_EQ(lights[1].intensity, 750.0f);
  expectVec(lights[1].color, {0, 0, 1});
  EXPECT_TRUE(lights[1].linearFalloff);
  EXPECT_TRUE(lights[1].noIncidence);
  EXPECT_TRUE(lights[2].isSpot);
  expectVec(lights[2].spotDirection, {1, 0, 0});
  EXPECT_NEAR(lights[2].spotConeHalfAngleDeg, 45.0f, 1e-4f);  // atan(100 / 100)
  EXPECT_NEAR(lights[3].spotConeHalfAngleDeg, 15.0f, 1e-6f);
  EXPECT_FALSE(lights[4].isSpot);  // unresolved target: a point light
}

TEST(Entities, SpawnPointsBecomeCameras) {
  const auto e = parseEntities(
      "{ \"classname\" \"info_player_deathmatch\" \"origin\" \"10 20 30\" \"angle\" \"90\" }"
      "{ \"classname\" \"info_player_start\" \"origin\" \"0 0 0\" \"angles\" \"45 0 0\" }"
      "{ \"classname\" \"info_player_intermission\" \"origin\" \"5 5 5\" \"angles\" \"0 180 30\" }"
      "{ \"classname\" \"team_CTF_redspawn\" \"origin\" \"0 0 0\" }",
      "m.bsp");
  const auto cams = readSpawnCameras(e);
  ASSERT_EQ(cams.size(), 4u);
  EXPECT_EQ(cams[3].className, "team_CTF_redspawn");
  expectVec(cams[0].eye, {10, 20, 30 + kSpawnEyeHeight});
  expectVec(cams[0].forward, {0, 1, 0});
  expectVec(cams[0].left, {-1, 0, 0});
  expectVec(cams[0].up, {0, 0, 1});
  const float h = std::sqrt(0.5f);
  expectVec(cams[1].forward, {h, 0, -h});  // positive pitch looks down
  expectVec(cams[1].up, {h, 0, h});
  expectVec(cams[2].eye, {5, 5, 5});
  for (const auto& c : cams) {
    expectVec(glm::cross(c.forward, c.left), c.up);  // right-handed, orthonormal
    EXPECT_NEAR(glm::dot(c.forward, c.left), 0, 1e-6f);
    EXPECT_NEAR(glm::length(c.left), 1, 1e-6f);
  }
  // Roll 30 about forward (-x): left tilts towards +z... up and left stay perpendicular to forward.
  expectVec(cams[2].forward, {-1, 0, 0});
  EXPECT_NEAR(std::abs(cams[2].up.z), std::cos(30.0f * 3.14159265f / 180.0f), 1e-5f);
}

TEST(Entities, CtfTeamSpawnsBecomeCamerasAfterTheDeathmatchOnes) {
  const auto e = parseEntities(
      "{ \"classname\" \"team_CTF_bluespawn\" \"origin\" \"1 0 0\" \"angle\" \"180\" }"
      "{ \"classname\" \"team_ctf_redplayer\" \"origin\" \"2 0 0\" }"
      "{ \"classname\" \"info_player_deathmatch\" \"origin\" \"3 0 0\" }"
      "{ \"classname\" \"team_CTF_blueplayer\" \"origin\" \"4 0 0\" }"
      "{ \"classname\" \"team_CTF_redflag\" \"origin\" \"5 0 0\" }"
      "{ \"classname\" \"team_CTF_redspawn\" \"origin\" \"6 0 0\" }",
      "ctf.bsp");
  const auto cams = readSpawnCameras(e);
  ASSERT_EQ(cams.size(), 5u);  // the flag is not a spawn point
  const float expectedX[] = {3, 1, 2, 4, 6};
  for (size_t k = 0; k < cams.size(); ++k) {
    EXPECT_EQ(cams[k].origin.x, expectedX[k]);
    expectVec(cams[k].eye, cams[k].origin + glm::vec3(0, 0, kSpawnEyeHeight));  // standing eye height
  }
  EXPECT_EQ(cams[1].className, "team_CTF_bluespawn");
  expectVec(cams[1].forward, {-1, 0, 0});

  // A CTF-only map still gets cameras.
  const auto ctfOnly = parseEntities("{ \"classname\" \"team_CTF_redplayer\" \"origin\" \"0 0 8\" }", "ctf.bsp");
  ASSERT_EQ(readSpawnCameras(ctfOnly).size(), 1u);
  expectVec(readSpawnCameras(ctfOnly)[0].eye, {0, 0, 8 + kSpawnEyeHeight});
}

}  // namespace
}  // namespace q3
