#pragma once
// Writes IBSP 46 files from the decoded structs, for tests and the fuzz seed generator.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "port/q3formats/bsp/bsp_file.h"

namespace q3::testing {

/// Builds a BSP byte image. Lumps are laid out in order after the header; `rawLumps`
/// replaces a lump's bytes and `lumpOverride` forces a table entry (for malformed files).
struct BspWriter {
  std::string entities;
  std::vector<BspShader> shaders;
  std::vector<BspPlane> planes;
  std::vector<BspNode> nodes;
  std::vector<BspLeaf> leafs;
  std::vector<int32_t> leafSurfaces, leafBrushes;
  std::vector<BspModel> models;
  std::vector<BspBrush> brushes;
  std::vector<BspBrushSide> brushSides;
  std::vector<BspDrawVert> drawVerts;
  std::vector<int32_t> drawIndexes;
  std::vector<BspFog> fogs;
  std::vector<BspSurface> surfaces;
  std::vector<uint8_t> lightmaps, lightGrid, visibility;
  int32_t version = 46;
  std::map<int, std::vector<std::byte>> rawLumps;
  std::map<int, std::pair<int32_t, int32_t>> lumpOverride;  ///< lump -> (offset, length)

  std::vector<std::byte> build() const {
    std::array<std::vector<std::byte>, 17> lumps;
    lumps[0] = text(entities);
    for (const auto& s : shaders) {
      name(lumps[1], s.name);
      put(lumps[1], s.surfaceFlags, s.contentFlags);
    }
    for (const auto& p : planes) put(lumps[2], p.normal.x, p.normal.y, p.normal.z, p.dist);
    for (const auto& n : nodes)
      put(lumps[3], n.plane, n.children[0], n.children[1], n.mins.x, n.mins.y, n.mins.z, n.maxs.x, n.maxs.y,
          n.maxs.z);
    for (const auto& f : leafs)
      put(lumps[4], f.cluster, f.area, f.mins.x, f.mins.y, f.mins.z, f.maxs.x, f.maxs.y, f.maxs.z,
          f.firstLeafSurface, f.numLeafSurfaces, f.firstLeafBrush, f.numLeafBrushes);
    for (int32_t v : leafSurfaces) put(lumps[5], v);
    for (int32_t v : leafBrushes) put(lumps[6], v);
    for (const auto& m : models)
      put(lumps[7], m.mins.x, m.mins.y, m.mins.z, m.maxs.x, m.maxs.y, m.maxs.z, m.firstSurface, m.numSurfaces,
          m.firstBrush, m.numBrushes);
    for (const auto& b : brushes) put(lumps[8], b.firstSide, b.numSides, b.shader);
    for (const auto& s : brushSides) put(lumps[9], s.plane, s.shader);
    for (const auto& v : drawVerts) {
      put(lumps[10], v.position.x, v.position.y, v.position.z, v.st.x, v.st.y, v.lightmap.x, v.lightmap.y,
          v.normal.x, v.normal.y, v.normal.z);
      put(lumps[10], v.color);
    }
    for (int32_t v : drawIndexes) put(lumps[11], v);
    for (const auto& f : fogs) {
      name(lumps[12], f.shaderName);
      put(lumps[12], f.brush, f.visibleSide);
    }
    for (const auto& s : surfaces) {
      put(lumps[13], s.shader, s.fog, static_cast<int32_t>(s.type), s.firstVert, s.numVerts, s.firstIndex,
          s.numIndexes, s.lightmap, s.lightmapX, s.lightmapY, s.lightmapWidth, s.lightmapHeight);
      put(lumps[13], s.lightmapOrigin.x, s.lightmapOrigin.y, s.lightmapOrigin.z);
      for (const auto& v : s.lightmapVecs) put(lumps[13], v.x, v.y, v.z);
      put(lumps[13], s.patchWidth, s.patchHeight);
    }
    lumps[14] = bytes(lightmaps);
    lumps[15] = bytes(lightGrid);
    lumps[16] = bytes(visibility);
    for (const auto& [index, raw] : rawLumps) lumps[index] = raw;

    std::vector<std::byte> out(8 + 17 * 8);
    std::memcpy(out.data(), "IBSP", 4);
    std::memcpy(out.data() + 4, &version, 4);
    for (int i = 0; i < 17; ++i) {
      int32_t offset = static_cast<int32_t>(out.size()), length = static_cast<int32_t>(lumps[i].size());
      out.insert(out.end(), lumps[i].begin(), lumps[i].end());
      while (out.size() % 4) out.push_back(std::byte{0});
      if (auto it = lumpOverride.find(i); it != lumpOverride.end()) std::tie(offset, length) = it->second;
      std::memcpy(out.data() + 8 + i * 8, &offset, 4);
      std::memcpy(out.data() + 12 + i * 8, &length, 4);
    }
    return out;
  }

  /// Appends a planar quad (two triangles, Quake clockwise winding seen from +normal).
  int addQuad(const std::array<glm::vec3, 4>& corners, const glm::vec3& normal, int32_t shader = 0) {
    BspSurface s;
    s.shader = shader;
    s.type = SurfaceType::Planar;
    s.firstVert = static_cast<int32_t>(drawVerts.size());
    s.numVerts = 4;
    s.firstIndex = static_cast<int32_t>(drawIndexes.size());
    s.numIndexes = 6;
    s.lightmapVecs[2] = normal;
    for (int k = 0; k < 4; ++k) {
      BspDrawVert v;
      v.position = corners[k];
      v.normal = normal;
      v.st = {static_cast<float>(k & 1), static_cast<float>(k >> 1)};
      v.color = {255, 255, 255, 255};
      drawVerts.push_back(v);
    }
    drawIndexes.insert(drawIndexes.end(), {0, 2, 1, 1, 2, 3});
    surfaces.push_back(s);
    return static_cast<int>(surfaces.size()) - 1;
  }

  /// Appends a patch with row-major control points (normals default to `normal`).
  int addPatch(int width, int height, const std::vector<glm::vec3>& controls, const glm::vec3& normal = {0, 0, 1},
               int32_t shader = 0) {
    BspSurface s;
    s.shader = shader;
    s.type = SurfaceType::Patch;
    s.firstVert = static_cast<int32_t>(drawVerts.size());
    s.numVerts = width * height;
    s.patchWidth = width;
    s.patchHeight = height;
    for (int k = 0; k < width * height; ++k) {
      BspDrawVert v;
      v.position = controls[k];
      v.normal = normal;
      v.st = {static_cast<float>(k % width) / (width - 1), static_cast<float>(k / width) / (height - 1)};
      v.color = {200, 100, 50, 255};
      drawVerts.push_back(v);
    }
    surfaces.push_back(s);
    return static_cast<int>(surfaces.size()) - 1;
  }

  /// Model 0 covering every surface added so far, with one leaf and no nodes.
  void finishWorld(const glm::vec3& mins, const glm::vec3& maxs) {
    if (shaders.empty()) shaders.push_back({"textures/test/wall", 0, 1});
    BspModel world;
    world.mins = mins;
    world.maxs = maxs;
    world.numSurfaces = static_cast<int32_t>(surfaces.size());
    models.insert(models.begin(), world);
    BspLeaf leaf;
    leaf.cluster = 0;
    leaf.area = 0;
    leaf.numLeafSurfaces = static_cast<int32_t>(surfaces.size());
    for (int32_t i = 0; i < static_cast<int32_t>(surfaces.size()); ++i) leafSurfaces.push_back(i);
    leafs.push_back(leaf);
  }

 private:
  template <class... T>
  static void put(std::vector<std::byte>& out, const T&... values) {
    (append(out, values), ...);
  }
  template <class T>
  static void append(std::vector<std::byte>& out, const T& value) {
    const auto* p = reinterpret_cast<const std::byte*>(&value);
    out.insert(out.end(), p, p + sizeof(T));
  }
  static void name(std::vector<std::byte>& out, const std::string& s) {
    std::array<char, 64> buf{};
    std::memcpy(buf.data(), s.data(), std::min<size_t>(s.size(), 64));
    append(out, buf);
  }
  static std::vector<std::byte> text(const std::string& s) {
    std::vector<std::byte> out(s.size() + 1);
    std::memcpy(out.data(), s.data(), s.size());
    return out;
  }
  static std::vector<std::byte> bytes(const std::vector<uint8_t>& v) {
    std::vector<std::byte> out(v.size());
    if (!v.empty()) std::memcpy(out.data(), v.data(), v.size());
    return out;
  }
};

/// A small valid map: two quads, a 5x3 patch, a brush, a fog, a lightmap, a light grid,
/// visibility for one cluster, a door model (*1) and entities (worldspawn, spawn, lights).
inline BspWriter sampleMap() {
  BspWriter w;
  w.entities =
      "{\n\"classname\" \"worldspawn\"\n\"message\" \"Test Map\"\n\"gridsize\" \"128 128 256\"\n\"_color\" "
      "\"1 0.5 0\"\n\"_ambient\" \"10\"\n}\n"
      "{\n\"classname\" \"info_player_deathmatch\"\n\"origin\" \"16 32 24\"\n\"angle\" \"90\"\n}\n"
      "{\n\"classname\" \"light\"\n\"origin\" \"0 0 128\"\n\"light\" \"500\"\n\"_color\" \"0.5 0.25 "
      "0.25\"\n\"target\" \"spot1\"\n\"spawnflags\" \"1\"\n}\n"
      "{\n\"classname\" \"info_null\"\n\"targetname\" \"spot1\"\n\"origin\" \"0 0 0\"\n}\n"
      "{\n\"classname\" \"func_door\"\n\"model\" \"*1\"\n}\n";
  w.shaders = {{"textures/test/floor", 0, 1}, {"textures/test/fog", 0, 0x40}};
  w.planes = {{{0, 0, 1}, 0}, {{0, 0, -1}, 64}};
  w.addQuad({glm::vec3(0, 0, 0), {256, 0, 0}, {0, 256, 0}, {256, 256, 0}}, {0, 0, 1});
  w.addPatch(5, 3,
             {{0, 0, 0}, {64, 0, 64}, {128, 0, 0}, {192, 0, -64}, {256, 0, 0},
              {0, 64, 0}, {64, 64, 64}, {128, 64, 0}, {192, 64, -64}, {256, 64, 0},
              {0, 128, 0}, {64, 128, 64}, {128, 128, 0}, {192, 128, -64}, {256, 128, 0}});
  w.surfaces[0].lightmap = 0;
  w.surfaces[1].fog = 0;
  w.finishWorld({0, 0, -64}, {256, 256, 64});
  // Door: one more quad owned by model 1.
  w.addQuad({glm::vec3(0, 0, 32), {32, 0, 32}, {0, 32, 32}, {32, 32, 32}}, {0, 0, 1});
  BspModel door;
  door.mins = {0, 0, 32};
  door.maxs = {32, 32, 32};
  door.firstSurface = 2;
  door.numSurfaces = 1;
  w.models.push_back(door);
  w.brushSides = {{0, 0}, {1, 0}};
  w.brushes = {{0, 2, 1}};
  w.models[0].numBrushes = 1;
  w.leafs[0].numLeafBrushes = 1;
  w.leafBrushes = {0};
  w.fogs = {{"textures/test/fog", 0, 1}};
  w.nodes = {{0, {-1, -1}, {0, 0, -64}, {256, 256, 64}}};
  w.lightmaps.assign(kLightmapSize * kLightmapSize * 3, 0);
  w.lightmaps[0] = 255;  // texel (0, 0) red
  // Grid 128 x 128 x 256 over (0,0,-64)-(256,256,64): x,y in {0,128,256}, z in {0}.
  for (int k = 0; k < 9; ++k) w.lightGrid.insert(w.lightGrid.end(), {10, 20, 30, 100, 100, 100, 0, 0});
  w.visibility = {1, 0, 0, 0, 1, 0, 0, 0, 0x01};
  return w;
}

}  // namespace q3::testing
