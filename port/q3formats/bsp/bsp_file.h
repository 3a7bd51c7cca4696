#pragma once
// Quake III IBSP version 46: every lump decoded into typed, cross-checked vectors.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace q3 {

/// Surface kinds stored in the surfaces lump.
enum class SurfaceType : int32_t { Planar = 1, Patch = 2, TriangleSoup = 3, Flare = 4 };

/// Special lightmap numbers used by the engine (negative = no lightmap page).
inline constexpr int32_t kLightmapNone = -1;
/// Lightmap number of a surface lit through a white image (the engine's fullbright mode).
inline constexpr int32_t kLightmapWhiteImage = -2;
/// Lightmap number of a vertex-lit surface (q3map2 writes it on every unlightmapped surface).
inline constexpr int32_t kLightmapByVertex = -3;
/// Lightmap number of 2D (menu) drawing; the lowest number the engine accepts.
inline constexpr int32_t kLightmap2D = -4;

/// SURF_* bits of the shader lump's surface flags (the game's surfaceflags.h) that maps are read by.
inline constexpr int32_t kSurfSky = 0x4, kSurfNoImpact = 0x10, kSurfNoMarks = 0x20, kSurfNodraw = 0x80,
                         kSurfHint = 0x100, kSurfSkip = 0x200, kSurfNolightmap = 0x400, kSurfNoDlight = 0x20000;
/// CONTENTS_FOG of the shader lump's content flags.
inline constexpr int32_t kContentsFog = 0x40;

/// Edge length in texels of one lightmap page of the lightmaps lump (pages are RGB8, row-major).
inline constexpr int kLightmapSize = 128;

/// The one rule for a surface's lightmap number: the page it selects among `pages` lightmaps,
/// or -1 when the surface is drawn with vertex light instead (negative numbers, and numbers past
/// the last page, as the engine does: maps compiled with external lightmaps number past an empty
/// lump). Never throws; any int32 is acceptable input.
int32_t lightmapPageOf(int32_t lightmap, size_t pages);

/// Largest patch control-grid dimension accepted (engine MAX_PATCH_SIZE).
inline constexpr int kMaxPatchSize = 32;

/// Texture reference with its compile-time flags.
struct BspShader {
  std::string name;          ///< shader or texture path, e.g. "textures/base_wall/concrete"
  int32_t surfaceFlags = 0;  ///< SURF_* flags
  int32_t contentFlags = 0;  ///< CONTENTS_* flags
};

/// Plane n.x = dist.
struct BspPlane {
  glm::vec3 normal{};
  float dist = 0;
};

/// BSP node; a negative child c refers to leaf -(c + 1).
struct BspNode {
  int32_t plane = 0;
  std::array<int32_t, 2> children{};
  glm::ivec3 mins{}, maxs{};
};

/// BSP leaf: PVS cluster, area portal area and its surface/brush lists.
struct BspLeaf {
  int32_t cluster = -1;  ///< -1 = opaque (outside the level)
  int32_t area = -1;
  glm::ivec3 mins{}, maxs{};
  int32_t firstLeafSurface = 0, numLeafSurfaces = 0;
  int32_t firstLeafBrush = 0, numLeafBrushes = 0;
};

/// Model 0 is the world, models 1..N are brush entities ("*1".."*N": doors, platforms).
struct BspModel {
  glm::vec3 mins{}, maxs{};
  int32_t firstSurface = 0, numSurfaces = 0;
  int32_t firstBrush = 0, numBrushes = 0;
};

/// Convex brush: a range of brush sides and its content shader.
struct BspBrush {
  int32_t firstSide = 0, numSides = 0;
  int32_t shader = 0;
};

/// One bounding plane of a brush.
struct BspBrushSide {
  int32_t plane = 0;
  int32_t shader = 0;
};

/// Fog volume: shader name, the brush that bounds it and its visible side (-1 = none).
struct BspFog {
  std::string shaderName;
  int32_t brush = 0;
  int32_t visibleSide = -1;
};

/// Vertex as stored in the file.
struct BspDrawVert {
  glm::vec3 position{};
  glm::vec2 st{};        ///< texture coordinates
  glm::vec2 lightmap{};  ///< lightmap page coordinates in [0, 1]
  glm::vec3 normal{};
  std::array<uint8_t, 4> color{};  ///< RGBA vertex colour (baked vertex lighting)
};

/// Drawable surface. Index/vertex ranges are validated against the lumps.
struct BspSurface {
  int32_t shader = 0;
  int32_t fog = -1;
  SurfaceType type = SurfaceType::Planar;
  int32_t firstVert = 0, numVerts = 0;
  int32_t firstIndex = 0, numIndexes = 0;  ///< indexes are relative to firstVert
  int32_t lightmap = kLightmapNone;        ///< page index, or negative for none
  int32_t lightmapX = 0, lightmapY = 0, lightmapWidth = 0, lightmapHeight = 0;
  glm::vec3 lightmapOrigin{};
  std::array<glm::vec3, 3> lightmapVecs{};  ///< planar: s, t axes and the face normal
  int32_t patchWidth = 0, patchHeight = 0;  ///< patch control grid size (odd, >= 3)
};

/// Baked light grid: 8 bytes per point (ambient RGB, directed RGB, longitude, latitude).
struct BspLightGrid {
  std::vector<uint8_t> raw;
  glm::vec3 gridSize{64, 64, 128};  ///< world units between points (worldspawn "gridsize")
  glm::vec3 origin{};               ///< world position of point (0, 0, 0)
  glm::ivec3 dims{};                ///< points along x, y, z (from model 0's bounds)
  bool valid = false;               ///< raw.size() == 8 * dims.x * dims.y * dims.z and non-empty
};

/// Potentially visible sets: one bit row per cluster.
struct BspVisibility {
  int32_t numClusters = 0;
  int32_t bytesPerCluster = 0;
  std::vector<uint8_t> rows;  ///< numClusters * bytesPerCluster bytes
  /// True if cluster `to` is potentially visible from cluster `from` (true when no vis data).
  bool clusterVisible(int32_t from, int32_t to) const;
};

/// A whole decoded map. Every cross reference has been checked by parseBsp.
struct BspFile {
  std::string fileName;
  std::string entities;  ///< raw entity lump text (see entities.h)
  std::vector<BspShader> shaders;
  std::vector<BspPlane> planes;
  std::vector<BspNode> nodes;
  std::vector<BspLeaf> leafs;
  std::vector<int32_t> leafSurfaces;
  std::vector<int32_t> leafBrushes;
  std::vector<BspModel> models;
  std::vector<BspBrush> brushes;
  std::vector<BspBrushSide> brushSides;
  std::vector<BspDrawVert> drawVerts;
  std::vector<int32_t> drawIndexes;
  std::vector<BspFog> fogs;
  std::vector<BspSurface> surfaces;
  std::vector<uint8_t> lightmaps;  ///< numLightmaps() pages of 128x128 RGB8 (a partial last page dropped)
  BspLightGrid lightGrid;
  BspVisibility visibility;
  std::vector<std::string> warnings;  ///< non-fatal oddities (e.g. light grid size mismatch)

  /// Number of 128x128 RGB lightmap pages.
  size_t numLightmaps() const { return lightmaps.size() / (kLightmapSize * kLightmapSize * 3); }
  /// Bytes of lightmap page `index` (RGB8, row-major); throws std::out_of_range if absent.
  std::span<const uint8_t> lightmapPage(size_t index) const;
  /// Index of the model a surface belongs to (0 = world), or -1 if no model lists it.
  int32_t modelOfSurface(size_t surfaceIndex) const;
};

/// Lump indices of IBSP 46, in file order.
enum class BspLump : int {
  Entities, Shaders, Planes, Nodes, Leafs, LeafSurfaces, LeafBrushes, Models, Brushes,
  BrushSides, DrawVerts, DrawIndexes, Fogs, Surfaces, Lightmaps, LightGrid, Visibility, Count
};

/// On-disk element size of each lump (0 = free-form bytes).
inline constexpr std::array<size_t, 17> kBspLumpElementSize = {
    0, 72, 16, 36, 48, 4, 4, 40, 12, 8, 44, 4, 72, 104, 128 * 128 * 3, 0, 0};

/// Human-readable lump name, e.g. "surfaces".
const char* bspLumpName(BspLump lump);

/// Parses an IBSP 46 file. Throws FormatError (file + field) on malformed or inconsistent data
/// the engine would refuse too; never reads outside `bytes`. What the engine tolerates loads with
/// one line in `warnings` (a lightmaps lump that is not whole pages, fog numbers past the fogs
/// lump); lightmap numbers are kept as written, whatever their value (see lightmapPageOf).
BspFile parseBsp(std::span<const std::byte> bytes, std::string fileName);

}  // namespace q3
