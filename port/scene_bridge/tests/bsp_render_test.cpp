// pa-render on a map compiled with external lightmaps (empty lump, maps/ext/lm_0000.tga beside
// it), in a game folder written by code: it renders, and the floor shows the external lightmap.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <stb_image.h>

#include "port/q3formats/bsp/tests/external_lightmap_map.h"

namespace {

namespace fs = std::filesystem;

void write(const fs::path& path, const std::vector<std::byte>& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

TEST(BspRender, MapWithExternalLightmapsRendersWithThem) {
  const fs::path dir = fs::temp_directory_path() / ("pa_bsp_render_" + std::to_string(::getpid()));
  const fs::path game = dir / "game";
  using q3::testing::tga24;
  write(game / "maps/ext.bsp", q3::testing::externalLightmapMap(0).build());
  write(game / "maps/ext/lm_0000.tga", tga24(512, 512, [](int, int) { return std::array<uint8_t, 3>{0, 64, 0}; }));
  write(game / "textures/test/wall.tga", tga24(8, 8, [](int, int) { return std::array<uint8_t, 3>{255, 255, 255}; }));

  const fs::path png = dir / "ext.png", logPath = dir / "log.txt";
  const std::string command = "PA_GAME_DIR=\"" + game.string() + "\" \"" + PA_RENDER + "\" \"" +
                              (game / "maps/ext.bsp").string() + "\" -o \"" + png.string() +
                              "\" --width 32 --height 24 --spp 1 --integrator lightmap > \"" + logPath.string() +
                              "\" 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(logPath);
  const std::string log((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log;
  EXPECT_EQ(log.find("selects none"), std::string::npos) << log;

  int width = 0, height = 0, channels = 0;
  stbi_uc* pixels = stbi_load(png.string().c_str(), &width, &height, &channels, 3);
  ASSERT_NE(pixels, nullptr);
  // The floor fills the lower half of the spawn view: white texture x green lightmap = green
  // (vertex light would be white).
  double sum[3] = {0, 0, 0};
  for (int y = height * 3 / 4; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) sum[c] += pixels[(size_t(y) * width + x) * 3 + c];
  stbi_image_free(pixels);
  EXPECT_GT(sum[1], 4.0 * sum[0] + 1.0) << log;
  EXPECT_GT(sum[1], 4.0 * sum[2] + 1.0) << log;
  fs::remove_all(dir);
}

}  // namespace
