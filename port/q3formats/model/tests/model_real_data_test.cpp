// Every MD3 and .skin in the installed OpenArena archives parses (skipped if absent).
#include <gtest/gtest.h>

#include <filesystem>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/common/tokenizer.h"
#include "port/q3formats/model/md3.h"
#include "port/q3formats/model/skin.h"
#include "port/q3formats/vfs/game_filesystem.h"

namespace {

const std::filesystem::path kBase = "/usr/share/games/openarena/baseoa";

TEST(ModelRealData, EveryMd3AndSkinParses) {
  if (!std::filesystem::exists(kBase / "pak0.pk3")) GTEST_SKIP() << "OpenArena data not installed";
  q3::GameFileSystem fs(kBase);
  size_t md3Count = 0, skinCount = 0, surfaces = 0, frames = 0;
  std::vector<std::string> failures;
  for (const auto& path : fs.allFiles()) {
    const std::string lower = q3::toLowerAscii(path);
    const bool isMd3 = lower.ends_with(".md3"), isSkin = lower.ends_with(".skin");
    if (!isMd3 && !isSkin) continue;
    auto bytes = fs.readFile(path);
    ASSERT_TRUE(bytes) << path;
    if (isMd3) {
      try {
        q3::Md3Model m = q3::parseMd3(*bytes, path);
        ++md3Count;
        surfaces += m.surfaces.size();
        frames += m.frames.size();
      } catch (const q3::FormatError& e) {
        failures.push_back(e.what());
      }
    } else {
      q3::Skin skin = q3::parseSkin({reinterpret_cast<const char*>(bytes->data()), bytes->size()}, path);
      ++skinCount;
      for (const auto& w : skin.warnings) std::printf("[ skin warning ] %s\n", w.c_str());
      EXPECT_FALSE(skin.surfaces.empty()) << path;
    }
  }
  for (const auto& f : failures) ADD_FAILURE() << f;
  std::printf("md3 %zu (surfaces %zu, frames %zu), skins %zu\n", md3Count, surfaces, frames, skinCount);
  EXPECT_GT(md3Count, 200u);
  EXPECT_GT(skinCount, 50u);
}

}  // namespace
