#pragma once
// The loaded map as the glue needs it: the entity string (GetEntityToken), brush sub-model
// bounds (ModelBounds, "*N" models), and the data behind LightForPoint / inPVS / MarkFragments.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "port/engine_glue/ioq3_abi.h"

namespace glue {

/// A brush sub-model of the map ("*0" is the world itself).
struct BrushModel {
  glm::vec3 mins{0.0f};
  glm::vec3 maxs{0.0f};
  int firstSurface = 0;
  int numSurfaces = 0;
};

/// A BSP plane.
struct WorldPlane {
  glm::vec3 normal{0.0f};
  float dist = 0.0f;
};

/// A BSP node: children >= 0 are nodes, < 0 are leaves (-1 - leaf).
struct WorldNode {
  int plane = 0;
  int children[2] = {0, 0};
};

/// The triangles of one drawable surface, for MarkFragments.
struct MarkSurface {
  glm::vec3 mins{0.0f};
  glm::vec3 maxs{0.0f};
  uint32_t firstIndex = 0;       ///< into World::markIndices_
  uint32_t numIndices = 0;
  bool planar = false;
};

/// One BSP file, validated.
class World {
 public:
  /// Parses the map's header and the lumps the glue reads itself (throws q3::FormatError).
  World(const std::vector<uint8_t>& bytes, const std::string& name);

  /// "maps/NAME.bsp" as given to LoadWorld.
  const std::string& name() const { return name_; }
  /// Sub-models, index 0 = the world.
  const std::vector<BrushModel>& brushModels() const { return brushModels_; }
  /// GetEntityToken: copies the next token of the entity string; false at the end.
  bool nextEntityToken(char* buffer, int size);
  /// The raw entity string.
  const std::string& entityString() const { return entities_; }
  /// LightForPoint: trilinear light-grid sample (0..255 scale); false without a grid.
  bool lightForPoint(const float* point, float* ambient, float* directed, float* direction) const;
  /// inPVS: can a point in p1's cluster see p2's cluster? True when the map has no vis data.
  bool inPVS(const float* p1, const float* p2) const;
  /// MarkFragments: clips a decal polygon projected along `projection` against the world's
  /// triangles; returns the number of fragments written.
  int markFragments(int numPoints, const float (*points)[3], const float* projection,
                    int maxPoints, float* pointBuffer, int maxFragments,
                    q3abi::markFragment_t* fragments) const;
  /// Leaf index containing a point.
  int leafAt(const glm::vec3& point) const;
  /// Cluster of a leaf (-1 = solid / outside).
  int clusterOf(int leaf) const;

 private:
  std::string name_;
  std::string entities_;
  size_t entityParsePoint_ = 0;
  std::vector<BrushModel> brushModels_;
  std::vector<WorldPlane> planes_;
  std::vector<WorldNode> nodes_;
  std::vector<int> leafClusters_;
  int numClusters_ = 0;
  int clusterBytes_ = 0;
  std::vector<uint8_t> vis_;
  glm::vec3 gridOrigin_{0.0f};
  glm::vec3 gridSize_{64.0f, 64.0f, 128.0f};
  int gridBounds_[3] = {0, 0, 0};
  std::vector<uint8_t> grid_;          ///< 8 bytes per point, colours already overbright-shifted
  std::vector<glm::vec3> markVertices_;
  std::vector<uint32_t> markIndices_;
  std::vector<MarkSurface> markSurfaces_;
};

}  // namespace glue
