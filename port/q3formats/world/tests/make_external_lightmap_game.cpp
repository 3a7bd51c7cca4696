// Writes a tiny game folder holding a map compiled with external lightmaps, for the converter's
// and pa-render's end-to-end tests (built by code, no game data):
//   GAME/maps/ext.bsp            one floor quad, empty lightmap lump, lightmap number 0
//   GAME/maps/ext/lm_0000.tga    512x512, green (0, 64, 0): stored "full bright" green
//   GAME/textures/test/wall.tga  white
// usage: q3-make-external-lightmap-game GAME_DIR
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "port/q3formats/bsp/tests/external_lightmap_map.h"

namespace {

void write(const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s GAME_DIR\n", argv[0]);
    return 2;
  }
  const std::filesystem::path game = argv[1];
  using q3::testing::tga24;
  write(game / "maps/ext.bsp", q3::testing::externalLightmapMap(0).build());
  write(game / "maps/ext/lm_0000.tga", tga24(512, 512, [](int, int) { return std::array<uint8_t, 3>{0, 64, 0}; }));
  write(game / "textures/test/wall.tga", tga24(8, 8, [](int, int) { return std::array<uint8_t, 3>{255, 255, 255}; }));
  std::printf("game folder written to %s\n", game.c_str());
  return 0;
}
