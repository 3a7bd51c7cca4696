#pragma once
// EmitterIndex: the calibrations' emitting triangles prepared once (centre, unit normal, area,
// light scale) with a bounding-volume tree over the spheres beyond which each gives less than the
// traced threshold, so a texel visits only the emitters that can count instead of all of them.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "port/light_recovery/calibration.h"

namespace pa::recovery {

/// One emitting triangle with what every texel's light sum needs precomputed.
struct PreparedEmitter {
  glm::vec3 centre{0.0f};       ///< Mean of the corners; shadow rays aim here.
  glm::vec3 unitNormal{0.0f};   ///< Counter-clockwise front.
  float area = 0.0f;            ///< Triangle area (Quake units squared).
  float power = 0.0f;           ///< Light value at unit cosines and distance: 64/pi x radiance x area.
  bool twoSided = false;        ///< Emits from both faces.
  int32_t group = -1;           ///< CalibrationEmitter::group.
};

/// The emitters a calibration sums, with the ones near a point found in O(log n + k).
class EmitterIndex {
 public:
  /// No emitters.
  EmitterIndex() = default;
  /// Prepares `emitters` (those that can give no light, degenerate or dark or non-finite, are
  /// left out) for sums that ignore contributions below `minTracedValue`.
  EmitterIndex(const std::vector<CalibrationEmitter>& emitters, float minTracedValue);

  /// The prepared emitters, in the order of the input (left-out ones skipped).
  const std::vector<PreparedEmitter>& emitters() const { return emitters_; }
  /// The threshold the reach spheres were made for.
  float minTracedValue() const { return minTracedValue_; }
  /// Replaces `out` with the indices into emitters(), ascending, of every emitter whose light at
  /// `point` can reach `threshold` (a superset: the caller's exact test decides). A threshold
  /// other than the index's, or not positive, lists every emitter.
  void near(const glm::vec3& point, float threshold, std::vector<uint32_t>& out) const;

 private:
  struct Node {
    glm::vec3 lower, upper;   ///< Bounds of the reach spheres below.
    uint32_t first = 0;       ///< Leaf: first item in order_; inner: left child (right = left + 1).
    uint32_t count = 0;       ///< Items in the leaf; 0 for an inner node.
  };
  /// Fills node `self` over order_[begin, end), splitting at the median centre.
  void build(uint32_t self, uint32_t begin, uint32_t end, const std::vector<glm::vec3>& lower,
             const std::vector<glm::vec3>& upper);

  std::vector<PreparedEmitter> emitters_;
  std::vector<float> reach2_;      ///< Squared distance from the centre past which light < threshold.
  std::vector<uint32_t> order_;    ///< Emitter indices, grouped by leaf.
  std::vector<Node> nodes_;        ///< nodes_[0] is the root when not empty.
  float minTracedValue_ = 0.0f;
};

}  // namespace pa::recovery
