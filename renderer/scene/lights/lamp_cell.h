#pragma once
// Lamp weights shared by the shading points of a small cell of the world (LampCell): the first
// hits of neighbouring pixels weigh the lamps once per cell and plane instead of once each. The
// weighing itself is LightSampler's (light_sampler.h); LightSampler::lampWeightsFor, in
// lamp_cell.cpp, finds a point's cell, its anchor and the bounds that keep the choice unbiased.
#include <cstdint>

#include <glm/vec3.hpp>

namespace pa {

/// The weights of the first kBufferedLamps lamps at a shading point and the running sum at the
/// end of each group of eight, kept by LightSampler::sample() so that choosing a lamp does not
/// recompute them.
struct LampPrefix {
  static constexpr uint32_t kBufferedLamps = 512;
  float weight[kBufferedLamps];          ///< Weight of lamp k (the sampler's lamp order) at the point.
  double groupEnd[kBufferedLamps / 8];   ///< weight[0] + ... + weight[8g + 7], summed as the sampler sums.
  uint32_t count = 0;                    ///< Lamps stored (whole groups, at most kBufferedLamps).
};

class LampCellMemo;

/// Where LightSampler::sample() weighs the lamps for a shading point. size 0: at the point.
/// size > 0: at one anchor per cell of the world grid of that side and per plane (the point's
/// normal in steps of 1/1024, its offset along it in steps of kPlaneStep), with bounds over them:
/// a lamp gets weight 0 only when it lies wholly below the plane or beyond its range from every
/// point of the cell there, so every lamp that can light the point stays selectable (unbiased).
/// The choice is a pure function of p, n and size; `memo` keeps the last anchors' weights, so
/// that the next point in one of those cells and planes (a neighbouring pixel's first hit) does
/// not weigh the lamps again.
struct LampCell {
  static constexpr float kPlaneStep = 0.125f;   ///< Plane offsets are binned in these world units.
  float size = 0.0f;                             ///< Cell side in world units (0: weights at the point).
  LampCellMemo* memo = nullptr;                  ///< The calling thread's memo, or null.
};

/// The lamp weights of the last anchors a LightSampler weighed with a LampCell (one memo per
/// thread): the first hits of a 4 x 4 pixel block fall in a few cells, visited in turn.
class LampCellMemo {
 public:
  LampCellMemo() = default;

 private:
  friend class LightSampler;
  struct Entry {
    const void* sampler = nullptr;   ///< The sampler and its build that filled it (null: empty).
    uint64_t build = 0;
    glm::ivec3 cell{0};
    int64_t plane = 0;
    float size = 0.0f;
    glm::vec3 normal{0.0f};
    double total = 0.0;   ///< The summed weights.
    LampPrefix prefix;
  };
  static constexpr uint32_t kEntries = 4;
  Entry entries[kEntries];
  uint32_t next = 0;   ///< The entry the next new anchor replaces.
};

}  // namespace pa
