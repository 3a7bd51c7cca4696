// Writes a seed corpus of small valid BSPs (built by code, no game data) for fuzz_bsp.
//   make_bsp_seeds OUTPUT_DIR
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "port/q3formats/bsp/tests/bsp_writer.h"
#include "port/q3formats/bsp/tests/external_lightmap_map.h"

namespace {

void write(const std::filesystem::path& dir, const std::string& name, const std::vector<std::byte>& bytes) {
  std::ofstream out(dir / name, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  using q3::testing::BspWriter;

  write(dir, "sample.bsp", q3::testing::sampleMap().build());

  BspWriter empty;
  empty.finishWorld({0, 0, 0}, {0, 0, 0});
  write(dir, "empty_world.bsp", empty.build());

  // Patches of every shape class: flat, curved, collapsed, large, and a shared edge.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> h(-200, 200);
  for (int variant = 0; variant < 6; ++variant) {
    BspWriter w;
    w.entities = "{ \"classname\" \"worldspawn\" }\n{ \"classname\" \"info_player_start\" \"origin\" \"0 0 0\" }";
    const int width = 3 + 2 * (variant % 3), height = 3 + 2 * (variant / 3);
    std::vector<glm::vec3> controls;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        controls.push_back({x * 64.0f, y * 64.0f, variant == 0 ? 0 : (y == 0 && variant == 5 ? 0 : h(rng))});
    if (variant == 5)
      for (int x = 0; x < width; ++x) controls[x] = controls[0];  // collapsed row
    w.addPatch(width, height, controls);
    // A neighbour sharing the patch's right column.
    std::vector<glm::vec3> right;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < 3; ++x) right.push_back(controls[y * width + width - 1] + glm::vec3(x * 64.0f, 0, x * h(rng)));
    w.addPatch(3, height, right);
    w.addQuad({glm::vec3(0, 0, 0), {64, 0, 0}, {0, 64, 0}, {64, 64, 0}}, {0, 0, 1});
    w.finishWorld({-512, -512, -512}, {512, 512, 512});
    write(dir, "patches_" + std::to_string(variant) + ".bsp", w.build());
  }

  // Loaded as leniently as the engine: q3map2 -external (empty lump, numbers past it), numbers
  // below the engine's, and a lump with a partial last page.
  write(dir, "external_lightmaps.bsp", q3::testing::externalLightmapMap(3).build());
  BspWriter odd = q3::testing::externalLightmapMap(-1000);
  odd.lightmaps.assign(q3::kLightmapSize * q3::kLightmapSize * 3 + 100, 50);
  write(dir, "odd_lightmaps.bsp", odd.build());

  std::ofstream(dir / "entities.txt") << "{ \"classname\" \"light\" \"origin\" \"1 2 3\" \"target\" \"t\" }\n"
                                         "// comment\n{ \"targetname\" \"t\" \"origin\" \"0 0 0\" /* c */ }";
  std::printf("seed corpus written to %s\n", dir.c_str());
  return 0;
}
