// Every image referenced by the OpenArena shader scripts decodes, or is reported missing.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "port/q3formats/common/format_error.h"
#include "port/q3formats/common/tokenizer.h"
#include "port/q3formats/image/image.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/vfs/game_filesystem.h"

namespace {

TEST(ImageRealData, ShaderImagesDecodeOrAreReported) {
  const std::filesystem::path base = "/usr/share/games/openarena/baseoa";
  if (!std::filesystem::exists(base / "pak0.pk3")) GTEST_SKIP() << "OpenArena data not installed";
  q3::GameFileSystem fs(base);
  q3::ShaderLibrary lib;
  lib.addScriptsInEngineOrder(fs.listFiles("scripts", ".shader"), [&](const std::string& f) { return fs.readFile(f); });
  std::set<std::string> referenced;
  for (const auto& def : lib.shaders()) {
    for (const auto& stage : def.stages)
      if (stage.source == q3::TextureSource::Image)
        for (const auto& t : stage.textures) referenced.insert(q3::toLowerAscii(t));
    if (def.sky && !def.sky->farBox.empty())
      for (const char* s : {"_rt", "_bk", "_lf", "_ft", "_up", "_dn"}) referenced.insert(def.sky->farBox + s);
  }
  size_t decoded = 0, missing = 0;
  std::vector<std::string> failures;
  for (const auto& t : referenced) {
    std::string found;
    for (const auto& candidate : q3::imageCandidates(t))
      if (fs.exists(candidate)) {
        found = candidate;
        break;
      }
    if (found.empty()) {
      ++missing;  // names in the game's scripts whose images OpenArena does not ship
      continue;
    }
    try {
      auto bytes = fs.readFile(found);
      q3::Image img = q3::decodeImage(*bytes, found);
      EXPECT_EQ(img.rgba.size(), size_t(img.width) * size_t(img.height) * 4);
      ++decoded;
    } catch (const q3::FormatError& e) {
      failures.push_back(e.what());
    }
  }
  for (const auto& f : failures) ADD_FAILURE() << f;
  std::printf("referenced %zu, decoded %zu, missing from the data %zu, failed %zu\n", referenced.size(),
              decoded, missing, failures.size());
  EXPECT_GT(decoded, 1000u);
}

}  // namespace
