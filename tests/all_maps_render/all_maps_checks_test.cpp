// Known-answer tests of the all-maps checks: image figures, spawn survey and point-in-leaf on a
// hand-made BSP, known-problems list, reports, contact sheet and the EXR reader.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include <glm/vec3.hpp>

#include "port/q3formats/bsp/bsp_file.h"
#include "renderer/cli/image_output.h"
#include "tests/all_maps_render/contact_sheet.h"
#include "tests/all_maps_render/image_stats.h"
#include "tests/all_maps_render/map_checks.h"
#include "tests/all_maps_render/map_survey.h"
#include "tests/all_maps_render/render_run.h"

namespace pa::allmaps {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(ImageStats, LumaBlackAndSkyOfFourPixels) {
  // black, white, pure green, then grey 128 and black that saw the sky.
  const std::vector<uint8_t> rgba = {0, 0, 0, 255, 255, 255, 255, 255, 0, 255, 0, 255, 128, 128, 128, 255, 0, 0, 0, 255};
  const std::vector<float> depth = {1.0f, 2.0f, 3.0f, kInf, kInf};
  const ImageStats s = computeImageStats(rgba, depth);
  EXPECT_NEAR(s.meanLuma, (0.0 + 1.0 + 0.7152) / 3.0, 1e-9);   // the world pixels only
  EXPECT_DOUBLE_EQ(s.blackFraction, 1.0 / 3.0);   // of the three world pixels; the black sky does not count
  EXPECT_DOUBLE_EQ(s.skyFraction, 0.4);
}

TEST(ImageStats, NanDepthCountsAsSkyAndDarkPixelsAreBlack) {
  PlausibilityThresholds t;
  t.blackLuma = 10.0 / 255.0;
  const std::vector<uint8_t> rgba = {0, 0, 0, 255, 9, 9, 9, 255, 11, 11, 11, 255};   // 9/255 < 10/255 < 11/255
  const std::vector<float> depth = {std::nanf(""), 5.0f, 5.0f};
  const ImageStats s = computeImageStats(rgba, depth, t);
  EXPECT_DOUBLE_EQ(s.blackFraction, 0.5);
  EXPECT_NEAR(s.skyFraction, 1.0 / 3.0, 1e-12);
  const ImageStats allSky = computeImageStats(std::span(rgba).first(4), std::span(depth).first(1), t);
  EXPECT_DOUBLE_EQ(allSky.blackFraction, 0.0);
  EXPECT_DOUBLE_EQ(allSky.meanLuma, 0.0);
  EXPECT_DOUBLE_EQ(allSky.skyFraction, 1.0);
}

TEST(ImageStats, RejectsMismatchedSizes) {
  const std::vector<uint8_t> rgba(8, 0);
  const std::vector<float> depth(3, 1.0f);
  EXPECT_THROW(computeImageStats(rgba, depth), std::invalid_argument);
  EXPECT_THROW(computeImageStats({}, {}), std::invalid_argument);
}

TEST(ImageStats, ReasonsNameEachFailedCheck) {
  const PlausibilityThresholds t;
  EXPECT_TRUE(implausibilityReasons({0.3, 0.1, 0.5}, t).empty());
  const auto dark = implausibilityReasons({0.01, 0.9, 0.0}, t);
  ASSERT_EQ(dark.size(), 2u);
  EXPECT_NE(dark[0].find("dark"), std::string::npos);
  EXPECT_NE(dark[1].find("black"), std::string::npos);
  const auto sky = implausibilityReasons({0.5, 0.0, 0.95}, t);
  ASSERT_EQ(sky.size(), 1u);
  EXPECT_NE(sky[0].find("95.0%"), std::string::npos) << sky[0];
}

/// One plane x = 0: the front leaf (x >= 0) is in cluster 5, the back leaf is opaque.
q3::BspFile halfSpaceBsp(std::string entities) {
  q3::BspFile bsp;
  bsp.fileName = "maps/test.bsp";
  bsp.entities = std::move(entities);
  bsp.planes.push_back({glm::vec3(1, 0, 0), 0.0f});
  q3::BspNode node;
  node.plane = 0;
  node.children = {-1, -2};
  bsp.nodes.push_back(node);
  q3::BspLeaf front, back;
  front.cluster = 5;
  back.cluster = -1;
  bsp.leafs = {front, back};
  return bsp;
}

TEST(MapSurvey, PointInLeafFollowsThePlaneSide) {
  const q3::BspFile bsp = halfSpaceBsp("");
  EXPECT_EQ(clusterAtPoint(bsp, {1, 0, 0}), 5);
  EXPECT_EQ(clusterAtPoint(bsp, {0, 7, 7}), 5);   // on the plane: front
  EXPECT_EQ(clusterAtPoint(bsp, {-1, 0, 0}), -1);
  EXPECT_EQ(clusterAtPoint(q3::BspFile{}, {0, 0, 0}), -1);   // no nodes
}

TEST(MapSurvey, FirstPlayerSpawnNumberedLikeTheImporter) {
  const q3::BspFile bsp = halfSpaceBsp(R"(
{ "classname" "worldspawn" }
{ "classname" "info_player_intermission" "origin" "0 0 0" }
{ "classname" "light" "origin" "1 2 3" }
{ "classname" "info_player_deathmatch" }
{ "classname" "info_player_deathmatch" "origin" "-10 0 4" "angle" "90" }
{ "classname" "info_player_deathmatch" "origin" "10 0 0" }
{ "classname" "light" "origin" "1 2 3" }
)");
  const MapSurvey survey = surveyMap(bsp);
  ASSERT_TRUE(survey.spawn.has_value());
  // Camera 0 is the intermission point; the origin-less spawn is skipped by the importer.
  EXPECT_EQ(survey.spawn->cameraIndex, 1u);
  EXPECT_EQ(survey.spawn->cameraName, "info_player_deathmatch 4");
  EXPECT_EQ(survey.spawn->origin, glm::vec3(-10, 0, 4));
  EXPECT_EQ(survey.spawn->eye, glm::vec3(-10, 0, 39));
  EXPECT_EQ(survey.lightEntities, 2u);
  EXPECT_EQ(survey.eyeCluster, -1);   // x = -10 is behind the plane: opaque
  EXPECT_FALSE(survey.eyeInsideLevel());
}

TEST(MapSurvey, CtfSpawnCountsAndNoSpawnIsReported) {
  const MapSurvey ctf = surveyMap(halfSpaceBsp(R"({ "classname" "team_CTF_redspawn" "origin" "3 0 0" })"));
  ASSERT_TRUE(ctf.spawn.has_value());
  EXPECT_EQ(ctf.spawn->cameraName, "team_CTF_redspawn 0");
  EXPECT_TRUE(ctf.eyeInsideLevel());
  const MapSurvey none = surveyMap(halfSpaceBsp(R"({ "classname" "info_player_intermission" "origin" "3 0 0" })"));
  EXPECT_FALSE(none.spawn.has_value());
}

/// halfSpaceBsp plus one solid box brush x, y in [-100, 100], z in [-16, 0] (shader 0: CONTENTS_SOLID).
q3::BspFile bspWithFloor(std::string entities) {
  q3::BspFile bsp = halfSpaceBsp(std::move(entities));
  bsp.shaders.push_back({"textures/test/floor", 0, 1});
  const std::vector<q3::BspPlane> sides = {{glm::vec3(1, 0, 0), 100},  {glm::vec3(-1, 0, 0), 100},
                                           {glm::vec3(0, 1, 0), 100},  {glm::vec3(0, -1, 0), 100},
                                           {glm::vec3(0, 0, 1), 0},    {glm::vec3(0, 0, -1), 16}};
  for (const q3::BspPlane& plane : sides) {
    bsp.brushSides.push_back({static_cast<int32_t>(bsp.planes.size()), 0});
    bsp.planes.push_back(plane);
  }
  bsp.brushes.push_back({0, 6, 0});
  q3::BspModel world;
  world.numBrushes = 1;
  bsp.models.push_back(world);
  return bsp;
}

TEST(MapSurvey, FloorProbeTracesDownToSolidBrushes) {
  const q3::BspFile bsp = bspWithFloor("");
  const FloorProbe probe(bsp);
  EXPECT_FLOAT_EQ(probe.below(glm::vec3(10, -20, 24), 1000).value_or(-1), 24.0f);
  EXPECT_FLOAT_EQ(probe.below(glm::vec3(0, 0, -8), 1000).value_or(-1), 0.0f);    // inside the brush
  EXPECT_FALSE(probe.below(glm::vec3(150, 0, 24), 1000).has_value());           // beside it
  EXPECT_FALSE(probe.below(glm::vec3(0, 0, 300), 100).has_value());             // beyond the search
  EXPECT_FALSE(probe.below(glm::vec3(0, 0, -40), 1000).has_value());            // under it
  q3::BspFile water = bspWithFloor("");
  water.shaders[0].contentFlags = 32;   // CONTENTS_WATER: nothing to stand on
  EXPECT_FALSE(FloorProbe(water).below(glm::vec3(0, 0, 24), 1000).has_value());
}

TEST(MapSurvey, RendersTheFirstSpawnThatStandsOnAFloor) {
  const q3::BspFile bsp = bspWithFloor(R"(
{ "classname" "worldspawn" }
{ "classname" "info_player_start" "origin" "60 0 24" }
{ "classname" "info_player_deathmatch" "origin" "40 0 24" }
)");
  const MapSurvey survey = surveyMap(bsp);
  ASSERT_TRUE(survey.spawn && survey.firstSpawn);
  EXPECT_EQ(survey.spawn->cameraName, "info_player_start 1");
  EXPECT_EQ(survey.firstSpawn->cameraName, "info_player_start 1");
  EXPECT_FLOAT_EQ(survey.spawn->floorDistance.value_or(-1), 24.0f);
  EXPECT_TRUE(survey.spawn->standsOnFloor());
  EXPECT_EQ(survey.spawnsWithoutFloor, 0u);
  EXPECT_EQ(survey.eyeCluster, 5);
}

TEST(MapSurvey, SpawnsOffTheFloorAreSkippedAndNoFloorKeepsTheFirst) {
  // Spawn 0 has no floor under it, spawn 1 is 300 units up (a fall that hurts), spawn 2 stands.
  const MapSurvey survey = surveyMap(bspWithFloor(R"(
{ "classname" "info_player_start" "origin" "500 0 24" }
{ "classname" "info_player_deathmatch" "origin" "50 0 300" }
{ "classname" "info_player_deathmatch" "origin" "40 0 24" }
)"));
  ASSERT_TRUE(survey.spawn && survey.firstSpawn);
  EXPECT_EQ(survey.firstSpawn->cameraName, "info_player_start 0");
  EXPECT_FALSE(survey.firstSpawn->floorDistance.has_value());
  EXPECT_EQ(survey.spawn->cameraName, "info_player_deathmatch 2");
  EXPECT_EQ(survey.spawnsWithoutFloor, 2u);
  const MapSurvey floating = surveyMap(bspWithFloor(R"({ "classname" "info_player_start" "origin" "500 0 24" })"));
  ASSERT_TRUE(floating.spawn.has_value());
  EXPECT_EQ(floating.spawn->cameraName, "info_player_start 0");
  EXPECT_FALSE(floating.spawn->standsOnFloor());
}

TEST(MapSurvey, TeamGamesPreferTheTeamPlayerSpawns) {
  // A deathmatch start first (on the floor), then a team respawn point and a team start point.
  const q3::BspFile bsp = bspWithFloor(R"(
{ "classname" "info_player_start" "origin" "10 0 24" }
{ "classname" "team_CTF_bluespawn" "origin" "20 0 24" }
{ "classname" "info_player_intermission" "origin" "0 0 300" }
{ "classname" "team_CTF_redplayer" "origin" "30 0 24" }
)");
  const MapSurvey ctf = surveyMap(bsp, SpawnFamily::Team);
  ASSERT_TRUE(ctf.spawn && ctf.firstSpawn);
  EXPECT_EQ(ctf.spawn->cameraName, "team_CTF_redplayer 3");
  EXPECT_EQ(ctf.spawn->cameraIndex, 3u);   // the intermission point is camera 2
  EXPECT_EQ(ctf.spawn->className, "team_CTF_redplayer");
  EXPECT_TRUE(ctf.familyFound);
  EXPECT_EQ(ctf.firstSpawn->cameraName, "info_player_start 0");
  EXPECT_EQ(surveyMap(bsp, SpawnFamily::Deathmatch).spawn->cameraName, "info_player_start 0");
  EXPECT_EQ(surveyMap(bsp).spawn->cameraName, "info_player_start 0");   // no arena entry: first on a floor
}

TEST(MapSurvey, TeamRespawnPointsThenAnyFloorThenTheFirst) {
  // The team start point floats (no floor): the team respawn point is next in preference.
  const MapSurvey respawn = surveyMap(bspWithFloor(R"(
{ "classname" "team_CTF_blueplayer" "origin" "500 0 24" }
{ "classname" "info_player_deathmatch" "origin" "10 0 24" }
{ "classname" "team_CTF_redspawn" "origin" "20 0 24" }
)"), SpawnFamily::Team);
  EXPECT_EQ(respawn.spawn->cameraName, "team_CTF_redspawn 2");
  EXPECT_TRUE(respawn.familyFound);
  // No team spawn stands on a floor: the first player spawn of any class that does.
  const MapSurvey fallback = surveyMap(bspWithFloor(R"(
{ "classname" "team_CTF_blueplayer" "origin" "500 0 24" }
{ "classname" "info_player_deathmatch" "origin" "10 0 24" }
)"), SpawnFamily::Team);
  EXPECT_EQ(fallback.spawn->cameraName, "info_player_deathmatch 1");
  EXPECT_FALSE(fallback.familyFound);
  EXPECT_EQ(fallback.spawnsWithoutFloor, 1u);
  // A deathmatch game skips the team spawns written first.
  const MapSurvey dm = surveyMap(bspWithFloor(R"(
{ "classname" "team_CTF_redplayer" "origin" "30 0 24" }
{ "classname" "info_player_deathmatch" "origin" "10 0 24" }
)"), SpawnFamily::Deathmatch);
  EXPECT_EQ(dm.spawn->cameraName, "info_player_deathmatch 1");
  EXPECT_EQ(dm.spawnsWithoutFloor, 0u);
  // Nothing stands on a floor: the first player spawn.
  const MapSurvey none = surveyMap(bspWithFloor(R"(
{ "classname" "info_player_deathmatch" "origin" "500 0 24" }
{ "classname" "team_CTF_redplayer" "origin" "600 0 24" }
)"), SpawnFamily::Team);
  EXPECT_EQ(none.spawn->cameraName, "info_player_deathmatch 0");
  EXPECT_FALSE(none.familyFound);
}

TEST(Reports, ASpawnChosenByGameTypeIsExplained) {
  MapResult r;
  r.map = "ctfmap";
  r.arena = ArenaEntry{"scripts/arenas.txt", "ctf elimination", "ctf", SpawnFamily::Team};
  r.survey = surveyMap(bspWithFloor(R"(
{ "classname" "info_player_start" "origin" "10 0 24" }
{ "classname" "team_CTF_redplayer" "origin" "30 0 24" }
)"), SpawnFamily::Team);
  std::ostringstream md, tsv;
  writeMarkdownReport(md, {r}, PlausibilityThresholds{});
  EXPECT_NE(md.str().find("- ctfmap: team_CTF_redplayer 1 at (30 0 24) (floor 24 below) is rendered: the map's game "
                          "type is `ctf` (first game type in scripts/arenas.txt)"),
            std::string::npos)
      << md.str();
  EXPECT_NE(md.str().find("the first player spawn is info_player_start 0 at (10 0 24)"), std::string::npos);
  writeTsvReport(tsv, {r});
  EXPECT_NE(tsv.str().find("\tgame_type\t"), std::string::npos);
}

TEST(ImageStats, DarkAtTheLargestGainSaysSo) {
  const auto reasons = implausibilityReasons({0.01, 0.9, 0.0}, PlausibilityThresholds{}, true);
  ASSERT_EQ(reasons.size(), 2u);
  EXPECT_EQ(reasons[0].rfind("dark at the largest auto-exposure gain", 0), 0u) << reasons[0];
}

#if defined(PA_RENDER) && defined(PA_DEFAULT_ARENA)
/// Renders the bundled scene as pa-all-maps renders a map's lightmap picture (auto exposure,
/// clamp) and judges it.
std::pair<RenderResult, std::vector<std::string>> judgedArenaRender(const std::string& name,
                                                                    std::vector<std::string> extra) {
  RenderRequest request;
  request.paRender = PA_RENDER;
  request.scene = PA_DEFAULT_ARENA;
  request.integrators = {{"direct", 4}};
  request.tonemap = "clamp";
  request.exposure = "auto";
  request.width = 64;
  request.height = 36;
  request.threads = 1;
  request.outputStem = std::filesystem::temp_directory_path() / ("pa_all_maps_" + std::to_string(::getpid()) + name);
  request.extraArguments = std::move(extra);
  std::vector<RenderResult> results = runPaRender(request);
  EXPECT_EQ(results.size(), 1u);
  RenderResult result = std::move(results.at(0));
  std::vector<std::string> reasons;
  if (result.ok())
    reasons = implausibilityReasons(computeImageStats(result.image.pixels, result.depth), PlausibilityThresholds{},
                                    result.exposureAtMaxGain);
  for (const char* extension : {".png", ".exr", ".json", ".log"}) {
    std::filesystem::path p = request.outputStem;
    std::filesystem::remove(p += extension);
  }
  return {std::move(result), std::move(reasons)};
}

TEST(BrokenRender, ALitSceneWithAutoExposurePasses) {
  const auto [result, reasons] = judgedArenaRender("lit", {});
  ASSERT_TRUE(result.ok()) << result.error << result.log;
  EXPECT_FALSE(result.exposureAtMaxGain);
  EXPECT_TRUE(reasons.empty()) << reasons.front();
}

TEST(BrokenRender, ABlackRenderFailsAtTheLargestGain) {
  // Every light dimmed a billion-fold: the sky through the window is all that is left. Auto
  // exposure cannot make this plausible: the gain stops at its clamp and the picture stays dark.
  const auto [result, reasons] = judgedArenaRender("black", {"--light-scale", "1e-9"});
  ASSERT_TRUE(result.ok()) << result.error << result.log;
  EXPECT_TRUE(result.exposureAtMaxGain);
  ASSERT_FALSE(reasons.empty());
  EXPECT_NE(reasons.front().find("at the largest auto-exposure gain"), std::string::npos) << reasons.front();
}
#endif

TEST(KnownProblems, ParsesLinesCommentsAndWildcards) {
  const auto known = parseKnownProblems("# header\n\noa_dm1 direct light entities stripped  # why\nfoo * broken\n", "k");
  ASSERT_EQ(known.size(), 2u);
  EXPECT_EQ(known[0].map, "oa_dm1");
  EXPECT_EQ(known[0].integrator, "direct");
  EXPECT_EQ(known[0].reason, "light entities stripped");
  EXPECT_EQ(knownProblemReason(known, "oa_dm1", "direct").value_or(""), "light entities stripped");
  EXPECT_FALSE(knownProblemReason(known, "oa_dm1", "lightmap").has_value());
  EXPECT_EQ(knownProblemReason(known, "foo", "lightmap").value_or(""), "broken");
}

TEST(KnownProblems, PathIsAnIntegratorName) {
  const auto known = parseKnownProblems("czest1tourney path lights missing\n", "k");
  ASSERT_EQ(known.size(), 1u);
  EXPECT_EQ(knownProblemReason(known, "czest1tourney", "path").value_or(""), "lights missing");
  EXPECT_FALSE(knownProblemReason(known, "czest1tourney", "direct").has_value());
}

TEST(KnownProblems, MalformedLinesNameFileAndLine) {
  try {
    parseKnownProblems("ok direct fine\nmap bounces reason\n", "known.txt");
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("known.txt:2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseKnownProblems("map direct\n", "known.txt"), std::runtime_error);
}

MapResult resultWith(const std::string& map, std::vector<std::string> problems, std::string expected) {
  MapResult r;
  r.map = map;
  IntegratorOutcome o;
  o.integrator = "direct";
  o.rendered = true;
  o.stats = {0.02, 0.9, 0.1};
  o.problems = std::move(problems);
  o.expectedBecause = std::move(expected);
  r.renders.push_back(o);
  return r;
}

TEST(Reports, FailuresKnownProblemsAndStalePassesAreListed) {
  const std::vector<MapResult> results = {resultWith("bad", {"dark"}, ""), resultWith("dim", {"dark"}, "no lights"),
                                          resultWith("fixed", {}, "no lights")};
  EXPECT_TRUE(results[0].failed());
  EXPECT_FALSE(results[1].failed());
  EXPECT_FALSE(results[2].failed());
  std::ostringstream md;
  writeMarkdownReport(md, results, PlausibilityThresholds{});
  const std::string text = md.str();
  EXPECT_NE(text.find("| bad | 0 | 0 | none | - | -1 | 1.00 | 0.020 | 0.000 | 90.0% | 10.0% | 0 | FAIL |"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("- bad direct: dark"), std::string::npos) << text;
  EXPECT_NE(text.find("- dim direct: dark (known: no lights)"), std::string::npos) << text;
  EXPECT_NE(text.find("fixed direct passes although listed"), std::string::npos) << text;
  std::ostringstream tsv;
  writeTsvReport(tsv, results);
  EXPECT_NE(tsv.str().find("bad\t\t0\t0\t0\t\t0\t0\t0\t0\tnone\t\t\t-1\tdirect\t1.0000\t0\t0.0200\t0.9000\t0.1000\t0.0000\t0."
                           "0000\t0\t0\tFAIL\tdark\n"),
            std::string::npos)
      << tsv.str();
}

TEST(Reports, AMapLevelProblemFailsUnlessTheMapIsKnown) {
  MapResult r = resultWith("m", {}, "");
  r.mapProblems.push_back("no player spawn point");
  EXPECT_TRUE(r.failed());
  r.mapExpectedBecause = "test map";
  EXPECT_FALSE(r.failed());
}

RgbaImage solid(uint32_t w, uint32_t h, uint8_t r, uint8_t g, uint8_t b) {
  RgbaImage image{w, h, {}};
  for (uint32_t i = 0; i < w * h; ++i) image.pixels.insert(image.pixels.end(), {r, g, b, 255});
  return image;
}

const uint8_t* pixelAt(const RgbaImage& image, uint32_t x, uint32_t y) {
  return &image.pixels[(size_t{y} * image.width + x) * 4];
}

TEST(ContactSheet, LaysOutCellsWithFramesAndScaledThumbnails) {
  ContactSheet sheet(8, 4, 2, 2);
  sheet.addCell("a", {{solid(16, 8, 200, 10, 10), ThumbVerdict::Pass}, {solid(8, 4, 10, 200, 10), ThumbVerdict::Fail}});
  sheet.addCell("b", {{solid(8, 4, 10, 10, 200), ThumbVerdict::ExpectedFail}});   // second thumb missing
  sheet.addCell("c", {});
  const RgbaImage image = sheet.compose();
  // cell = 2 x (8 + 4) + 2 = 26 wide, 11 + 4 + 4 = 19 high; margins 6; 2 columns, 2 rows.
  EXPECT_EQ(image.width, 6u + 2u * (26u + 6u));
  EXPECT_EQ(image.height, 6u + 2u * (19u + 6u));
  // Cell a, thumb 0: frame at (6, 17), picture from (8, 19).
  EXPECT_EQ(pixelAt(image, 8, 19)[0], 200);
  EXPECT_EQ(pixelAt(image, 6, 17)[0], 90);    // pass frame (grey)
  EXPECT_EQ(pixelAt(image, 20, 17)[0], 230);  // fail frame (red) of thumb 1 at x = 6 + 12 + 2
  EXPECT_EQ(pixelAt(image, 22, 19)[1], 200);
  // Cell b (x0 = 38): orange frame, then the missing thumb drawn dark red with a red frame.
  EXPECT_EQ(pixelAt(image, 38, 17)[1], 150);
  EXPECT_EQ(pixelAt(image, 40, 19)[2], 200);
  EXPECT_EQ(pixelAt(image, 55, 20)[0], 70);    // dark red fill off the X
  EXPECT_EQ(pixelAt(image, 55, 19)[0], 230);   // the X
}

TEST(ContactSheet, TextUsesTheFiveBySevenFont) {
  RgbaImage image = solid(20, 9, 0, 0, 0);
  const uint8_t white[3] = {255, 255, 255};
  EXPECT_EQ(drawText(image, 1, 1, "i1", white), 13u);
  EXPECT_EQ(textWidth("i1"), 11u);
  // 'I' = 0x0E top row: columns 1..3 lit, 0 and 4 dark.
  EXPECT_EQ(pixelAt(image, 1, 1)[0], 0);
  EXPECT_EQ(pixelAt(image, 2, 1)[0], 255);
  EXPECT_EQ(pixelAt(image, 4, 1)[0], 255);
  EXPECT_EQ(pixelAt(image, 5, 1)[0], 0);
  EXPECT_EQ(pixelAt(image, 3, 4)[0], 255);     // the stem
  EXPECT_EQ(pixelAt(image, 7 + 2, 2)[0], 255); // '1' second row 0x0C: columns 1, 2
}

TEST(RenderRun, ReadsTheDepthChannelOfAPaRenderExr) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("pa_all_maps_" + std::to_string(::getpid()) + ".exr");
  const std::vector<glm::vec3> radiance(6, glm::vec3(0.5f));
  const std::vector<float> depth = {1, 2, kInf, 4, 5, kInf};
  cli::writeExr(path, {3, 2, radiance, {}, {}, depth, {}});
  uint32_t width = 0, height = 0;
  const std::vector<float> z = readExrChannel(path, "Z", width, height);
  EXPECT_EQ(width, 3u);
  EXPECT_EQ(height, 2u);
  ASSERT_EQ(z.size(), 6u);
  EXPECT_EQ(z[1], 2.0f);
  EXPECT_TRUE(std::isinf(z[5]));
  EXPECT_THROW(readExrChannel(path, "albedo.R", width, height), std::runtime_error);
  std::filesystem::remove(path);
  EXPECT_THROW(readExrChannel(path, "Z", width, height), std::runtime_error);
}

}  // namespace
}  // namespace pa::allmaps
