#pragma once
// The loaded map, read once per LoadWorld: the parsed BSP, its surfaces tessellated once and
// the shader library of the registration it was loaded in. The traced views build their scene
// from it (views_traced.cpp: q3::buildWorldScene over these surfaces and shaders), and it
// answers the module's game-side queries on top of the formats library (port/q3formats/bsp):
// GetEntityToken over the entity lump, brush sub-model bounds (ModelBounds of "*N"),
// LightForPoint (light grid), inPVS (BSP tree + visibility rows) and MarkFragments (decals
// clipped against the same tessellated triangles the tracer draws).
// Every query follows the stock opengl1 renderer of ioquake3 (see the comments in
// world_queries.cpp for the engine behaviour each one keeps).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "port/engine_glue/ioq3_abi.h"
#include "port/q3formats/bsp/bsp_file.h"
#include "port/q3formats/bsp/surface_mesh.h"
#include "port/q3formats/common/tokenizer.h"
#include "port/q3formats/shader/shader_library.h"

namespace glue {

/// How a BSP surface takes decals (the engine's R_BoxSurfaces_r / R_MarkFragments rules).
enum class MarkKind : uint8_t {
  None,   ///< never listed: SURF_NOIMPACT / SURF_NOMARKS / fog, flares, brush-model surfaces
  Face,   ///< planar face: listed when its plane crosses the decal box and faces the projector
  Patch,  ///< curved patch: always listed, each triangle tested for facing
  Soup,   ///< triangle soup: listed (it takes one of the 64 places) but never marked
};

/// One surface's decal data: its triangles in Quake winding (clockwise seen from the front).
struct MarkSurface {
  MarkKind kind = MarkKind::None;
  glm::vec3 planeNormal{0.0f};   ///< Face: the plane the engine tests (lightmapVecs[2])
  float planeDist = 0.0f;        ///< Face: planeNormal . first vertex
  uint32_t firstCorner = 0;      ///< into World::markCorners_, 3 per triangle
  uint32_t numCorners = 0;
};

/// One BSP file, parsed and validated by q3::parseBsp, with its tessellation and shaders.
class World {
 public:
  /// Parses and tessellates the map (throws q3::FormatError naming the file and field);
  /// `shaders` are the scripts it is drawn with (the module's, ShaderScripts::shared()).
  World(const std::vector<uint8_t>& bytes, const std::string& name,
        std::shared_ptr<const q3::ShaderLibrary> shaders = std::make_shared<const q3::ShaderLibrary>());
  World(const World&) = delete;             // the entity tokenizer views bsp_.entities
  World& operator=(const World&) = delete;

  /// "maps/NAME.bsp" as given to LoadWorld.
  const std::string& name() const { return bsp_.fileName; }
  /// The parsed map.
  const q3::BspFile& bsp() const { return bsp_; }
  /// Its drawable surfaces, tessellated as q3::buildWorldScene does by default
  /// (q3::worldTessellation()), counter-clockwise.
  const std::vector<q3::SurfaceMesh>& surfaces() const { return surfaces_; }
  /// The shader scripts the map is drawn with.
  const q3::ShaderLibrary& shaders() const { return *shaders_; }
  /// The same, shared (for what keeps the library beyond this map's load).
  const std::shared_ptr<const q3::ShaderLibrary>& sharedShaders() const { return shaders_; }
  /// Sub-models, index 0 = the world ("*N" is index N).
  const std::vector<q3::BspModel>& brushModels() const { return bsp_.models; }
  /// GetEntityToken: copies the next token of the entity string (COM_Parse rules, truncated to
  /// size - 1). At the end it writes "", rewinds to the start and returns false.
  bool nextEntityToken(char* buffer, int size);
  /// LightForPoint: the light grid at a point in the engine's 0..255 scale (map overbright
  /// shift applied, ambient x r_ambientScale); false when the map has no usable grid.
  bool lightForPoint(const float* point, float* ambient, float* directed, float* direction) const;
  /// inPVS: is p2's cluster in the potentially visible set of p1's cluster?
  bool inPVS(const float* p1, const float* p2) const;
  /// MarkFragments: clips the decal polygon `points`, swept along `projection`, against the
  /// world's faces and patches; writes at most maxPoints points and maxFragments fragments.
  int markFragments(int numPoints, const float (*points)[3], const float* projection,
                    int maxPoints, float* pointBuffer, int maxFragments,
                    q3abi::markFragment_t* fragments) const;
  /// Leaf index containing a point (the engine's R_PointInLeaf).
  int leafAt(const glm::vec3& point) const;
  /// Cluster of a leaf (-1 = solid / outside / no such leaf).
  int clusterOf(int leaf) const;

 private:
  /// BSP surfaces the box [mins, maxs] reaches through the tree, in the engine's order, that
  /// may take a decal projected along `dir` (at most 64, as the engine's list). The list lives
  /// in this World's scratch until the next call.
  const std::vector<uint32_t>& surfacesInBox(const glm::vec3& mins, const glm::vec3& maxs,
                                             const glm::vec3& dir) const;

  q3::BspFile bsp_;
  std::vector<q3::SurfaceMesh> surfaces_;
  std::shared_ptr<const q3::ShaderLibrary> shaders_;
  q3::Tokenizer entityTokens_;
  q3::BspLightGrid shiftedGrid_;          ///< colours brightened as the engine does at load
  std::vector<MarkSurface> markSurfaces_;  ///< per BSP surface
  std::vector<glm::vec3> markCorners_;
  /// surfacesInBox's working memory, kept between the engine's (main-thread) mark queries so
  /// that they allocate nothing.
  struct MarkScratch {
    std::vector<uint32_t> listed;
    std::vector<bool> seen;
    std::vector<int32_t> pending;
  };
  mutable MarkScratch markScratch_;
};

}  // namespace glue
