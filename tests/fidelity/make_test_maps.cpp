// pa-make-test-maps GAME_DIR: writes small maps, built by code (no game data), that the real engine
// loads with `devmap`, for tests/fidelity/test_maps_test.sh:
//   maps/pa_ext.bsp     lightmap lump empty, every face numbers lightmap 0, maps/pa_ext/lm_0000.tga
//                       (128x128) beside it: the layout DarkPlaces reads as external lightmaps
//   maps/pa_lm512.bsp   faces drawn by a q3map2-style shader naming maps/pa_lm512/lm_0000.tga
//                       (512x512, `tcGen lightmap`), lightmap number -3 (by vertex)
//   maps/pa_oor.bsp     a lump of one page, every face numbers lightmap 5 (out of range)
//   maps/pa_flare.bsp   the pa_oor room lit by vertex, with two flare surfaces (one in the open,
//                       one behind a screen) and one lump page
//   textures/pa_test/wall.tga, scripts/pa_test_maps.shader
// Every map is a closed 512x512x256 room (six inward faces, one leaf, one node) with a spawn
// point inside; the faces' vertex colours follow the same gradient as the lightmaps, so that a
// vertex-lit face looks like its lightmap at the corners.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "port/q3formats/bsp/tests/bsp_writer.h"
#include "port/q3formats/bsp/tests/external_lightmap_map.h"

namespace {

using q3::testing::BspWriter;
using Rgb = std::array<uint8_t, 3>;

void write(const std::filesystem::path& path, const std::vector<std::byte>& bytes) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

/// The lightmap gradient at page coordinates (u, v) in [0, 1]: warm towards +u, cool towards +v,
/// never black, never saturated (so that overbright scaling stays visible).
Rgb lightAt(float u, float v) {
  return {static_cast<uint8_t>(40 + 80 * u), static_cast<uint8_t>(40 + 40 * (u + v) / 2),
          static_cast<uint8_t>(40 + 80 * v)};
}

/// A 24-bit TGA stored bottom row first (descriptor 0): the stock loader ignores the top-down
/// flag of q3::testing::tga24 and would show those images upside down.
std::vector<std::byte> tgaBottomUp(int width, int height, const std::function<Rgb(int, int)>& texel) {
  return q3::testing::tga24(width, height, [&](int x, int y) { return texel(x, height - 1 - y); });
}

std::vector<std::byte> withBottomUpFlag(std::vector<std::byte> tga) {
  tga[17] = std::byte{0};
  return tga;
}

std::vector<std::byte> lightmapTga(int size) {
  return withBottomUpFlag(tgaBottomUp(size, size, [size](int x, int y) {
    return lightAt((x + 0.5f) / static_cast<float>(size), (y + 0.5f) / static_cast<float>(size));
  }));
}

/// The room's six inward faces (Quake clockwise winding seen from inside); lightmap coordinates
/// span the whole page on every face; vertex colours follow lightAt at the corners.
BspWriter room(int32_t lightmap, int32_t shader = 0) {
  constexpr float X = 512, Y = 512, Z = 256;
  BspWriter w;
  w.entities =
      "{\n\"classname\" \"worldspawn\"\n}\n"
      "{\n\"classname\" \"info_player_deathmatch\"\n\"origin\" \"64 256 64\"\n\"angle\" \"0\"\n}\n";
  w.shaders = {{"textures/pa_test/wall", 0, 1}};
  w.planes = {{{0, 0, 1}, 0}};
  using glm::vec3;
  // addQuad corners: c0, c1 = c0 + s, c2 = c0 + t, c3 = c0 + s + t.
  const auto quad = [&](vec3 c0, vec3 s, vec3 t, vec3 n) {
    const int index = w.addQuad({c0, c0 + s, c0 + t, c0 + s + t}, n, shader);
    for (int k = 0; k < 4; ++k) {
      q3::BspDrawVert& v = w.drawVerts[w.surfaces[index].firstVert + k];
      v.lightmap = {static_cast<float>(k & 1), static_cast<float>(k >> 1)};
      const Rgb c = lightAt(v.lightmap.x, v.lightmap.y);
      v.color = {c[0], c[1], c[2], 255};
    }
    w.surfaces[index].lightmap = lightmap;
    return index;
  };
  // Winding: s x t is the face's normal (the writer's triangles are clockwise seen from it).
  quad({0, 0, 0}, {X, 0, 0}, {0, Y, 0}, {0, 0, 1});    // floor
  quad({0, 0, Z}, {0, Y, 0}, {X, 0, 0}, {0, 0, -1});   // ceiling
  quad({X, 0, 0}, {0, 0, Z}, {0, Y, 0}, {-1, 0, 0});   // wall the spawn faces (+X)
  quad({0, 0, 0}, {0, Y, 0}, {0, 0, Z}, {1, 0, 0});    // wall behind the spawn
  quad({0, 0, 0}, {0, 0, Z}, {X, 0, 0}, {0, 1, 0});    // -Y wall
  quad({0, Y, 0}, {X, 0, 0}, {0, 0, Z}, {0, -1, 0});   // +Y wall
  return w;
}

/// Closes the map: model 0 over every surface, one leaf (cluster 0, area 0) with the room's
/// bounds (the engine culls leaves by their bounds), and one node above it (the engine refuses
/// maps without nodes).
std::vector<std::byte> finish(BspWriter& w) {
  w.finishWorld({-16, -16, -16}, {528, 528, 272});
  w.leafs[0].mins = {-16, -16, -16};
  w.leafs[0].maxs = {528, 528, 272};
  w.nodes = {{0, {-1, -1}, {-16, -16, -16}, {528, 528, 272}}};
  return w.build();
}

/// Appends a flare surface at `origin` facing `normal` (zero: every direction) with `colour`.
void addFlare(BspWriter& w, glm::vec3 origin, glm::vec3 normal, glm::vec3 colour, int32_t shader) {
  q3::BspSurface s;
  s.type = q3::SurfaceType::Flare;
  s.shader = shader;
  s.lightmap = q3::kLightmapByVertex;
  s.lightmapOrigin = origin;
  s.lightmapVecs[0] = colour;
  s.lightmapVecs[2] = normal;
  w.surfaces.push_back(s);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s GAME_DIR\n", argv[0]);
    return 2;
  }
  const std::filesystem::path game = argv[1];

  // Wall texture: 64x64 light grey with a darker 8-texel border (shows texture placement).
  write(game / "textures/pa_test/wall.tga", withBottomUpFlag(tgaBottomUp(64, 64, [](int x, int y) {
          const bool border = x < 8 || y < 8 || x >= 56 || y >= 56;
          return border ? Rgb{120, 120, 130} : Rgb{220, 215, 205};
        })));
  // The q3map2-style shader of the 512x512 map, the screen in front of the hidden flare.
  writeText(game / "scripts/pa_test_maps.shader",
            "textures/pa_test/wall_lm512\n{\n\t{\n\t\tmap maps/pa_lm512/lm_0000.tga\n\t\trgbGen identity\n"
            "\t\ttcGen lightmap\n\t}\n\t{\n\t\tmap textures/pa_test/wall.tga\n\t\tblendFunc GL_DST_COLOR GL_ZERO\n"
            "\t\trgbGen identity\n\t}\n}\n");

  {
    BspWriter w = room(0);
    write(game / "maps/pa_ext.bsp", finish(w));
    write(game / "maps/pa_ext/lm_0000.tga", lightmapTga(128));
  }
  {
    BspWriter w = room(q3::kLightmapByVertex, 0);
    w.shaders = {{"textures/pa_test/wall_lm512", 0, 1}};
    write(game / "maps/pa_lm512.bsp", finish(w));
    write(game / "maps/pa_lm512/lm_0000.tga", lightmapTga(512));
  }
  const auto withPage = [](BspWriter& w) {
    w.lightmaps.resize(q3::kLightmapSize * q3::kLightmapSize * 3);
    for (int y = 0; y < q3::kLightmapSize; ++y)
      for (int x = 0; x < q3::kLightmapSize; ++x) {
        const Rgb c = lightAt((x + 0.5f) / q3::kLightmapSize, (y + 0.5f) / q3::kLightmapSize);
        std::copy(c.begin(), c.end(), w.lightmaps.begin() + (y * q3::kLightmapSize + x) * 3);
      }
  };
  {
    BspWriter w = room(5);
    withPage(w);
    write(game / "maps/pa_oor.bsp", finish(w));
  }
  {
    BspWriter w = room(q3::kLightmapByVertex);
    withPage(w);
    w.shaders.push_back({"flareShader", 0, 0});
    // A screen standing on the floor at x = 320, covering y 300..420, z 0..160 (faces -X).
    w.addQuad({glm::vec3(320, 300, 0), {320, 300, 160}, {320, 420, 0}, {320, 420, 160}}, {-1, 0, 0});
    w.surfaces.back().lightmap = q3::kLightmapByVertex;
    addFlare(w, {448, 200, 128}, {-1, 0, 0}, {1.0f, 0.9f, 0.6f}, 1);   // in the open, facing the spawn
    addFlare(w, {448, 360, 112}, {-1, 0, 0}, {0.6f, 0.8f, 1.0f}, 1);   // behind the screen
    write(game / "maps/pa_flare.bsp", finish(w));
  }
  std::printf("test maps written to %s\n", game.c_str());
  return 0;
}
