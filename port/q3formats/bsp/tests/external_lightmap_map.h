#pragma once
// Test data for maps compiled with lightmaps beside them (q3map2 -external, or lightmaps that
// are not 128x128): a one-quad map with an empty lightmap lump, and the TGA files q3map2 writes.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "port/q3formats/bsp/tests/bsp_writer.h"

namespace q3::testing {

/// A 256x256 floor quad at z = 0 facing +Z (shader "textures/test/wall", lightmap coordinates
/// = (x, y) / 256), a spawn point looking along +X from above it, an empty lightmap lump and
/// the quad's lightmap number `lightmap` (0: the first "maps/<map>/lm_0000.tga").
inline BspWriter externalLightmapMap(int32_t lightmap = 0) {
  BspWriter w;
  w.entities =
      "{\n\"classname\" \"worldspawn\"\n}\n"
      "{\n\"classname\" \"info_player_deathmatch\"\n\"origin\" \"-64 128 24\"\n\"angle\" \"0\"\n}\n";
  w.shaders = {{"textures/test/wall", 0, 1}};
  w.planes = {{{0, 0, 1}, 0}};
  w.addQuad({glm::vec3(0, 0, 0), {256, 0, 0}, {0, 256, 0}, {256, 256, 0}}, {0, 0, 1});
  for (BspDrawVert& v : w.drawVerts) v.lightmap = glm::vec2(v.position.x, v.position.y) / 256.0f;
  w.surfaces[0].lightmap = lightmap;
  w.finishWorld({0, 0, -16}, {256, 256, 64});
  return w;
}

/// An uncompressed 24-bit TGA of width x height texels, first row at the top; texel(x, y) -> RGB.
inline std::vector<std::byte> tga24(int width, int height,
                                    const std::function<std::array<uint8_t, 3>(int, int)>& texel) {
  std::vector<std::byte> out(18);
  out[2] = std::byte{2};   // uncompressed true colour
  out[12] = std::byte(width & 0xff);
  out[13] = std::byte(width >> 8);
  out[14] = std::byte(height & 0xff);
  out[15] = std::byte(height >> 8);
  out[16] = std::byte{24};
  out[17] = std::byte{0x20};   // top-left origin
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const auto rgb = texel(x, y);
      out.insert(out.end(), {std::byte(rgb[2]), std::byte(rgb[1]), std::byte(rgb[0])});   // BGR
    }
  return out;
}

}  // namespace q3::testing
