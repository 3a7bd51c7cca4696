#include "port/engine_glue/world.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <glm/common.hpp>

#include "port/engine_glue/engine.h"

#include "port/q3formats/common/byte_reader.h"
#include "port/q3formats/common/format_error.h"

namespace glue {
namespace {

constexpr int kLumpEntities = 0, kLumpShaders = 1, kLumpPlanes = 2, kLumpNodes = 3, kLumpLeafs = 4,
              kLumpModels = 7, kLumpDrawVerts = 10, kLumpDrawIndexes = 11, kLumpSurfaces = 13,
              kLumpLightGrid = 15, kLumpVisibility = 16, kNumLumps = 17;
constexpr size_t kModelSize = 40, kShaderSize = 72, kPlaneSize = 16, kNodeSize = 36,
                 kLeafSize = 48, kDrawVertSize = 44, kSurfaceSize = 104;
constexpr size_t kMaxEntityString = 4 * 1024 * 1024;
constexpr int kSurfNoImpact = 0x10, kSurfNoMarks = 0x20, kSurfSky = 0x4, kSurfNoDraw = 0x80;
constexpr int kMapOverbrightShift = 2;   // r_mapOverBrightBits, no hardware gamma

/// Quake's load-time brightening of baked light: shift, then scale back if a channel overflows.
void shiftLight(uint8_t* rgb) {
  int r = rgb[0] << kMapOverbrightShift, g = rgb[1] << kMapOverbrightShift,
      b = rgb[2] << kMapOverbrightShift;
  const int top = std::max({r, g, b});
  if (top > 255) {
    r = r * 255 / top;
    g = g * 255 / top;
    b = b * 255 / top;
  }
  rgb[0] = static_cast<uint8_t>(r);
  rgb[1] = static_cast<uint8_t>(g);
  rgb[2] = static_cast<uint8_t>(b);
}

/// The worldspawn "gridsize" key ("x y z"), when present.
bool worldspawnGridSize(const std::string& entities, glm::vec3& size) {
  const size_t open = entities.find('{');
  const size_t close = entities.find('}', open == std::string::npos ? 0 : open);
  if (open == std::string::npos || close == std::string::npos) return false;
  const std::string first = normalizeName(entities.substr(open, close - open));
  const size_t key = first.find("\"gridsize\"");
  if (key == std::string::npos) return false;
  const size_t quote = first.find('"', key + 10);
  if (quote == std::string::npos) return false;
  float x = 0, y = 0, z = 0;
  if (std::sscanf(first.c_str() + quote + 1, "%f %f %f", &x, &y, &z) != 3) return false;
  if (!(x >= 1 && y >= 1 && z >= 1 && x < 65536 && y < 65536 && z < 65536)) return false;
  size = {x, y, z};
  return true;
}

}  // namespace

World::World(const std::vector<uint8_t>& bytes, const std::string& name) : name_(name) {
  const q3::ByteReader reader(std::as_bytes(std::span(bytes)), name);
  reader.require(0, 1, 8 + kNumLumps * 8, "header");
  if (reader.fixedString(0, 4, "ident") != "IBSP") reader.fail("ident", "not an IBSP file");
  const int32_t version = reader.read<int32_t>(4, "version");
  if (version != 46) reader.fail("version", "expected 46, got " + std::to_string(version));
  auto lump = [&](int index, const char* field) {
    const int32_t offset = reader.read<int32_t>(8 + index * 8, field);
    const int32_t length = reader.read<int32_t>(12 + index * 8, field);
    if (offset < 0 || length < 0) reader.fail(field, "negative offset or length");
    reader.require(size_t(offset), size_t(length), 1, field);
    return std::pair<size_t, size_t>(size_t(offset), size_t(length));
  };

  const auto [entOffset, entLength] = lump(kLumpEntities, "lump 0 (entities)");
  if (entLength > kMaxEntityString) reader.fail("lump 0 (entities)", "too long");
  const auto text = reader.bytes(entOffset, entLength, "lump 0 (entities)");
  entities_.assign(reinterpret_cast<const char*>(text.data()), text.size());
  if (const size_t nul = entities_.find('\0'); nul != std::string::npos) entities_.resize(nul);

  const auto [modelOffset, modelLength] = lump(kLumpModels, "lump 7 (models)");
  if (modelLength % kModelSize != 0) reader.fail("lump 7 (models)", "size not a multiple of 40");
  const size_t count = modelLength / kModelSize;
  if (count == 0) reader.fail("lump 7 (models)", "no world model");
  for (size_t i = 0; i < count; ++i) {
    const size_t at = modelOffset + i * kModelSize;
    BrushModel model;
    for (int k = 0; k < 3; ++k) {
      model.mins[k] = reader.read<float>(at + 4 * k, "model mins");
      model.maxs[k] = reader.read<float>(at + 12 + 4 * k, "model maxs");
    }
    model.firstSurface = reader.read<int32_t>(at + 24, "model firstSurface");
    model.numSurfaces = reader.read<int32_t>(at + 28, "model numSurfaces");
    brushModels_.push_back(model);
  }

  // Planes, nodes and leaves: point -> cluster for inPVS.
  const auto [planeOffset, planeLength] = lump(kLumpPlanes, "lump 2 (planes)");
  for (size_t i = 0; i < planeLength / kPlaneSize; ++i) {
    const size_t at = planeOffset + i * kPlaneSize;
    planes_.push_back({{reader.read<float>(at, "plane"), reader.read<float>(at + 4, "plane"),
                        reader.read<float>(at + 8, "plane")},
                       reader.read<float>(at + 12, "plane")});
  }
  const auto [leafOffset, leafLength] = lump(kLumpLeafs, "lump 4 (leafs)");
  for (size_t i = 0; i < leafLength / kLeafSize; ++i)
    leafClusters_.push_back(reader.read<int32_t>(leafOffset + i * kLeafSize, "leaf cluster"));
  const auto [nodeOffset, nodeLength] = lump(kLumpNodes, "lump 3 (nodes)");
  const auto numNodes = static_cast<int64_t>(nodeLength / kNodeSize);
  const auto numLeafs = static_cast<int64_t>(leafClusters_.size());
  for (int64_t i = 0; i < numNodes; ++i) {
    const size_t at = nodeOffset + size_t(i) * kNodeSize;
    WorldNode node;
    node.plane = reader.read<int32_t>(at, "node plane");
    node.children[0] = reader.read<int32_t>(at + 4, "node child");
    node.children[1] = reader.read<int32_t>(at + 8, "node child");
    if (node.plane < 0 || size_t(node.plane) >= planes_.size())
      reader.fail("lump 3 (nodes)", "node " + std::to_string(i) + " plane out of range");
    for (int c : node.children) {
      // Children must point forward (no cycles) or at an existing leaf.
      if (c >= 0 ? (c <= i || c >= numNodes) : (-1 - int64_t(c) >= numLeafs))
        reader.fail("lump 3 (nodes)", "node " + std::to_string(i) + " child out of range");
    }
    nodes_.push_back(node);
  }
  const auto [visOffset, visLength] = lump(kLumpVisibility, "lump 16 (visibility)");
  if (visLength >= 8) {
    numClusters_ = reader.read<int32_t>(visOffset, "vis numClusters");
    clusterBytes_ = reader.read<int32_t>(visOffset + 4, "vis bytesPerCluster");
    if (numClusters_ < 0 || clusterBytes_ < 0 ||
        int64_t(numClusters_) * clusterBytes_ > int64_t(visLength) - 8 ||
        int64_t(clusterBytes_) * 8 < numClusters_)
      reader.fail("lump 16 (visibility)", "cluster table does not fit");
    const auto rows = reader.bytes(visOffset + 8, size_t(numClusters_) * size_t(clusterBytes_), "vis rows");
    vis_.assign(reinterpret_cast<const uint8_t*>(rows.data()),
                reinterpret_cast<const uint8_t*>(rows.data()) + rows.size());
  }

  // Light grid: dimensions follow from the world bounds and the grid size.
  worldspawnGridSize(entities_, gridSize_);
  const auto [gridOffset, gridLength] = lump(kLumpLightGrid, "lump 15 (lightgrid)");
  if (gridLength > 0) {
    const BrushModel& world = brushModels_[0];
    int64_t points = 1;
    for (int k = 0; k < 3; ++k) {
      gridOrigin_[k] = gridSize_[k] * std::ceil(world.mins[k] / gridSize_[k]);
      const float top = gridSize_[k] * std::floor(world.maxs[k] / gridSize_[k]);
      const float cells = (top - gridOrigin_[k]) / gridSize_[k] + 1.0f;
      gridBounds_[k] = std::isfinite(cells) && cells >= 1 && cells < 4096 ? int(cells) : 0;
      points *= gridBounds_[k];
    }
    if (points > 0 && size_t(points) * 8 == gridLength) {
      const auto raw = reader.bytes(gridOffset, gridLength, "lightgrid");
      grid_.assign(reinterpret_cast<const uint8_t*>(raw.data()),
                   reinterpret_cast<const uint8_t*>(raw.data()) + raw.size());
      for (size_t i = 0; i < grid_.size(); i += 8) {
        shiftLight(&grid_[i]);
        shiftLight(&grid_[i + 3]);
      }
    } else {
      gridBounds_[0] = gridBounds_[1] = gridBounds_[2] = 0;   // mismatch: no grid (as stock)
    }
  }

  // Triangles of planar faces and triangle soups, for decals.
  const auto [shaderOffset, shaderLength] = lump(kLumpShaders, "lump 1 (shaders)");
  const size_t numShaders = shaderLength / kShaderSize;
  const auto [vertOffset, vertLength] = lump(kLumpDrawVerts, "lump 10 (drawverts)");
  const size_t numVerts = vertLength / kDrawVertSize;
  const auto [indexOffset, indexLength] = lump(kLumpDrawIndexes, "lump 11 (drawindexes)");
  const size_t numIndexes = indexLength / 4;
  const auto [surfOffset, surfLength] = lump(kLumpSurfaces, "lump 13 (surfaces)");
  const size_t numSurfaces = surfLength / kSurfaceSize;
  // Only the world model's surfaces take marks (brush models move).
  const BrushModel& worldModel = brushModels_[0];
  const size_t worldSurfaceEnd = std::min(
      numSurfaces, size_t(std::max<int64_t>(0, int64_t(worldModel.firstSurface) + worldModel.numSurfaces)));
  for (size_t s = size_t(std::max(0, worldModel.firstSurface)); s < worldSurfaceEnd; ++s) {
    const size_t at = surfOffset + s * kSurfaceSize;
    const int32_t shader = reader.read<int32_t>(at, "surface shaderNum");
    const int32_t type = reader.read<int32_t>(at + 8, "surface type");
    const int32_t firstVert = reader.read<int32_t>(at + 12, "surface firstVert");
    const int32_t nVerts = reader.read<int32_t>(at + 16, "surface numVerts");
    const int32_t firstIndex = reader.read<int32_t>(at + 20, "surface firstIndex");
    const int32_t nIndexes = reader.read<int32_t>(at + 24, "surface numIndexes");
    if (type != 1 && type != 3) continue;   // patches and flares take no marks here
    if (shader < 0 || size_t(shader) >= numShaders) continue;
    const int32_t flags = reader.read<int32_t>(shaderOffset + size_t(shader) * kShaderSize + 64, "shader flags");
    if (flags & (kSurfNoImpact | kSurfNoMarks | kSurfSky | kSurfNoDraw)) continue;
    if (firstVert < 0 || nVerts <= 0 || size_t(firstVert) + size_t(nVerts) > numVerts ||
        firstIndex < 0 || nIndexes < 3 || size_t(firstIndex) + size_t(nIndexes) > numIndexes)
      continue;
    MarkSurface surface;
    surface.planar = type == 1;
    surface.firstIndex = static_cast<uint32_t>(markIndices_.size());
    surface.mins = glm::vec3(3e38f);
    surface.maxs = glm::vec3(-3e38f);
    const auto base = static_cast<uint32_t>(markVertices_.size());
    for (int32_t v = 0; v < nVerts; ++v) {
      const size_t vat = vertOffset + size_t(firstVert + v) * kDrawVertSize;
      const glm::vec3 p(reader.read<float>(vat, "drawvert"), reader.read<float>(vat + 4, "drawvert"),
                        reader.read<float>(vat + 8, "drawvert"));
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        reader.fail("lump 10 (drawverts)", "non-finite position");
      markVertices_.push_back(p);
      surface.mins = glm::min(surface.mins, p);
      surface.maxs = glm::max(surface.maxs, p);
    }
    for (int32_t i = 0; i + 2 < nIndexes; i += 3) {
      uint32_t tri[3];
      bool ok = true;
      for (int k = 0; k < 3; ++k) {
        const int32_t index = reader.read<int32_t>(indexOffset + size_t(firstIndex + i + k) * 4, "drawindex");
        ok = ok && index >= 0 && index < nVerts;
        tri[k] = base + static_cast<uint32_t>(index);
      }
      if (ok) markIndices_.insert(markIndices_.end(), tri, tri + 3);
    }
    surface.numIndices = static_cast<uint32_t>(markIndices_.size()) - surface.firstIndex;
    if (surface.numIndices > 0) markSurfaces_.push_back(surface);
  }
}

bool World::nextEntityToken(char* buffer, int size) {
  if (buffer == nullptr || size <= 0) return false;
  buffer[0] = '\0';
  // Quake's COM_Parse rules: whitespace separated, "quoted strings", // comments.
  const std::string& s = entities_;
  size_t& p = entityParsePoint_;
  for (;;) {
    while (p < s.size() && static_cast<unsigned char>(s[p]) <= ' ') ++p;
    if (p + 1 < s.size() && s[p] == '/' && s[p + 1] == '/') {
      while (p < s.size() && s[p] != '\n') ++p;
      continue;
    }
    break;
  }
  if (p >= s.size()) return false;
  std::string token;
  if (s[p] == '"') {
    ++p;
    while (p < s.size() && s[p] != '"') token += s[p++];
    if (p < s.size()) ++p;
  } else {
    while (p < s.size() && static_cast<unsigned char>(s[p]) > ' ') token += s[p++];
  }
  std::snprintf(buffer, static_cast<size_t>(size), "%s", token.c_str());
  return true;
}

}  // namespace glue
