// Real-data checks over the installed OpenArena archives (skipped if absent).
#include <gtest/gtest.h>

#include <filesystem>

#include "port/q3formats/shader/material.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/vfs/game_filesystem.h"

namespace {

const std::filesystem::path kBase = "/usr/share/games/openarena/baseoa";

TEST(ShaderRealData, EveryOpenArenaScriptParsesWithNoUnknownKeyword) {
  if (!std::filesystem::exists(kBase / "pak0.pk3")) GTEST_SKIP() << "OpenArena data not installed";
  q3::GameFileSystem fs(kBase);
  q3::ShaderLibrary lib;
  const auto scripts = fs.listFiles("scripts", ".shader");
  ASSERT_GT(scripts.size(), 50u);
  EXPECT_EQ(lib.addScriptsInEngineOrder(scripts, [&](const std::string& f) { return fs.readFile(f); }), scripts.size());
  EXPECT_TRUE(lib.errors().empty());
  for (const auto& w : lib.warnings())
    EXPECT_FALSE(w.unknownKeyword) << w.file << ":" << w.line << " " << w.message;
  EXPECT_GT(lib.size(), 1000u);

  // Every definition derives a material; spot-check kinds that OpenArena certainly has.
  size_t skies = 0, lights = 0, masked = 0, additive = 0, env = 0;
  for (const auto& def : lib.shaders()) {
    const auto m = q3::deriveMaterial(def);
    skies += m.sky;
    lights += m.surfaceLight > 0;
    masked += m.alphaMode == q3::AlphaMode::Mask;
    additive += m.alphaMode == q3::AlphaMode::Additive;
    env += m.environmentMapped;
    if (m.sky && def.sky && !def.sky->farBox.empty()) {
      EXPECT_FALSE(m.skyBox.farFaces[0].empty());
    }
  }
  EXPECT_GT(skies, 10u);
  EXPECT_GT(lights, 100u);
  EXPECT_GT(masked, 50u);
  EXPECT_GT(additive, 20u);
  EXPECT_GT(env, 20u);
}

}  // namespace
