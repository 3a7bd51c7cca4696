#pragma once
// Motion of each pixel's first hit from the previous frame to this one: where every instance
// was (its previous objectToWorld, by InstanceId) and the G-buffer the temporal stage reads
// (instance, material, screen-space motion, and the depth and normal the hit had then).
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "renderer/scene/film/film.h"
#include "renderer/scene/integrator/camera_rays.h"
#include "renderer/scene/scene_types.h"
#include "renderer/scene/world/render_scene.h"

namespace pa::temporal {

/// Per-instance map from this frame's world space to the previous frame's, and the previous
/// vertex positions of instances whose mesh's vertices moved (MeshRecord::positionsStamp).
class InstanceMotion {
 public:
  /// Starts a frame with the committed instances (those camera rays see); the previous frame is
  /// the last beginFrame's. Copies the positions of dynamic meshes that changed (into memory
  /// kept from frame to frame).
  void beginFrame(std::span<const RenderInstance> world, std::span<const RenderInstance> overlay);
  /// Forgets the previous frame: every instance counts as new (disoccluded) in the next one.
  void reset();
  /// Moves a hit of instance `id` on this frame (world point and normal, on triangle `prim` at
  /// barycentrics `bary`) to where it was on the previous one; false when the instance did not
  /// exist then, its transform is not invertible, or its mesh changed in a way that has no
  /// previous position (another mesh, another vertex count or indices, a non-dynamic mesh's
  /// vertices changed). Where the vertices moved, the point is the same barycentrics on the
  /// previous vertices through the previous transform; the normal follows the transform only.
  bool toPrevious(InstanceId id, uint32_t prim, glm::vec2 bary, glm::vec3& point, glm::vec3& normal) const {
    if (id >= valid_.size() || valid_[id] == 0) return false;
    normal = normalToPrevious_[id] * normal;
    if (valid_[id] == kRigid) {
      point = pointToPrevious_[id] * glm::vec4(point, 1.0f);
      return true;
    }
    return previousOnVertices(id, prim, bary, point);
  }

 private:
  static constexpr uint8_t kRigid = 1;      ///< valid_: the mesh's vertices did not move.
  static constexpr uint8_t kVertices = 2;   ///< valid_: they moved; history_[id].then holds where.
  /// A dynamic mesh's vertices as an instance showed them.
  struct VertexHistory {
    const MeshRecord* mesh = nullptr;
    uint64_t positionsStamp = 0;
    uint64_t topologyStamp = 0;
    std::vector<glm::vec3> now;    ///< The positions at positionsStamp (dynamic meshes only).
    std::vector<glm::vec3> then;   ///< The positions before (valid when valid_ is kVertices).
    bool hasNow = false;           ///< `now` holds the positions at positionsStamp.
  };
  void record(std::span<const RenderInstance> instances);
  /// Makes room in every per-id array for the highest instance id of this frame.
  void reserveIds(std::span<const RenderInstance> world, std::span<const RenderInstance> overlay);
  bool previousOnVertices(InstanceId id, uint32_t prim, glm::vec2 bary, glm::vec3& point) const;
  std::vector<glm::mat4x3> current_, previous_;
  std::vector<uint8_t> currentKnown_, previousKnown_;
  std::vector<uint8_t> vertexState_;   ///< This frame, per id: 0 no previous vertices, kRigid, kVertices.
  std::vector<VertexHistory> history_;
  std::vector<glm::mat4x3> pointToPrevious_;
  std::vector<glm::mat3> normalToPrevious_;
  std::vector<uint8_t> valid_;   ///< 0 (no previous position), kRigid or kVertices.
};

/// Per-pixel reprojection data of one frame (width * height each, row-major from the top row).
struct GBuffer {
  /// Marks a pixel without a previous position (sky, portal views, new instances).
  static constexpr float kNoMotion = std::numeric_limits<float>::quiet_NaN();
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<InstanceId> instance;      ///< First camera-visible hit's instance (kNoId = none).
  std::vector<MaterialId> material;      ///< Its material index (kNoId = default material or none).
  std::vector<glm::vec2> motion;         ///< Previous film position minus this one, pixels (NaN = none).
  std::vector<float> previousDepth;      ///< Distance from the previous eye to where the hit was then.
  std::vector<glm::vec3> previousNormal; ///< The hit's shading normal as it was then.

  /// Sizes every array (contents unspecified until written).
  void resize(uint32_t w, uint32_t h);
  /// Writes pixel i from a camera sample taken at film position (px, py): its instance and
  /// material and, where the hit has a previous position (InstanceMotion::toPrevious), its motion;
  /// with `previousSurface`, also previousDepth and previousNormal (read by the temporal stage).
  void write(size_t i, const PixelSample& sample, float px, float py, const InstanceMotion& motions,
             const CameraRays* previousCamera, bool previousSurface = true);
  /// Writes only pixel i's instance and material (a frame whose motion nothing reads).
  void writeIds(size_t i, const PixelSample& sample) {
    instance[i] = sample.instance;
    material[i] = sample.material;
  }
};

}  // namespace pa::temporal
