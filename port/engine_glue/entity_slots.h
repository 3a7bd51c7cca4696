#pragma once
// Which dynamic slot (renderer instance) each model entity of a frame uses. The engine gives
// entities no ids, so an entity takes the slot of last frame's entity with the same model, skin
// and custom shader whose origin lies nearest (within a reach); the renderer then sees the same
// InstanceId move from its previous transform to this one and writes motion vectors for it. An
// entity with no such match takes a slot that showed nothing last frame (one that last showed the
// same model first, else the smallest that has held as many triangles, so that slot meshes stop
// growing): the renderer has no
// previous transform for it (hidden instances are not recorded), so its pixels count as
// disoccluded. Deterministic: entities are matched in submission order.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace glue {

/// What must agree for two entities of consecutive frames to be the same one.
struct EntityKey {
  int model = 0;
  int skin = 0;
  int shader = 0;
  int kind = 0;   ///< Caller's category (e.g. model entity vs the frame's effects batch).
  bool operator==(const EntityKey&) const = default;
};

/// EntityKey::kind of the frame's effects batch (sprites, polys, world autosprites in one slot of
/// its own); model entities are kind 0, or 1 when drawn on top.
inline constexpr int kEffectsBatchKind = 2;

/// Slot assignment across frames.
class EntitySlots {
 public:
  /// Farthest an entity may have moved between frames and still be matched (world units).
  static constexpr float kReach = 256.0f;
  /// Starts a frame: every slot is unclaimed.
  void beginFrame();
  /// The slot for an entity of this frame (claimed until the next beginFrame) that shows
  /// `triangles` triangles.
  size_t claim(const EntityKey& key, const glm::vec3& origin, size_t triangles = 0);
  /// True when `slot` was claimed this frame.
  bool claimed(size_t slot) const { return slot < claimed_.size() && claimed_[slot] != 0; }
  /// Number of slots ever used.
  size_t size() const { return owners_.size(); }

 private:
  struct Owner {
    bool used = false;   ///< Showed an entity in the frame it was last claimed in.
    EntityKey key;
    glm::vec3 origin{0.0f};
  };
  /// The free slot an unmatched entity takes (owners_.size(): none, make one).
  size_t freeSlotFor(const EntityKey& key, size_t triangles) const;

  std::vector<Owner> owners_;     ///< Last frame's owner of each slot (this frame's once claimed).
  std::vector<Owner> previous_;   ///< Last frame's owners, read while matching.
  std::vector<uint8_t> claimed_;
  std::vector<size_t> capacity_;   ///< Most triangles each slot has shown (its mesh's size).
};

}  // namespace glue
