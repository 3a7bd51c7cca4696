// LightSampler::lampWeightsFor: where the lamps are weighed for a shading point with a LampCell
// (lamp_cell.h), and the memo of the last cells' weights.
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "renderer/scene/lights/light_sampler.h"

namespace pa {

LightSampler::LampWeights LightSampler::lampWeightsFor(const glm::vec3& p, const glm::vec3& n, const LampCell& cell,
                                                       LampPrefix* scratch) const {
  LampWeights out;
  out.at = WeighingPoint{p, n};
  // The cell of p, its normal rounded to steps of kNormalStep (not renormalised: within
  // kNormalStep of n, which is what the bounds need) and its plane; weighed at the point where a
  // cell cannot be formed. Cell sides are powers of two: p / size is exact.
  constexpr float kNormalStep = 1.0f / 1024.0f;
  const float size = cell.size;
  const glm::vec3 scaled = p * (1.0f / size);
  const glm::vec3 rounded = glm::round(n * (1.0f / kNormalStep));
  const glm::vec3 normal = rounded * kNormalStep;
  const float offset = glm::dot(normal, p) * (1.0f / LampCell::kPlaneStep);
  constexpr float kLargest = 0x1p30f;   // cell and plane indices stay exact integers
  const bool cellular = size > 0.0f && !anySpotLamp_ && std::abs(glm::dot(n, n) - 1.0f) < 1e-3f &&
                        std::abs(scaled.x) < kLargest && std::abs(scaled.y) < kLargest &&
                        std::abs(scaled.z) < kLargest && std::abs(offset) < kLargest;
  if (!cellular) {
    out.total = weighLamps(out.at, scratch);
    out.prefix = scratch;
    return out;
  }
  const glm::ivec3 index(glm::floor(scaled));
  const int64_t plane = static_cast<int64_t>(std::floor(offset));
  // The anchor: the cell's centre moved along the rounded normal onto the middle of the plane's
  // bin. A point of the cell on that plane lies within sqrt(3) size + kPlaneStep of it; a lamp's
  // height above its tangent plane differs from the anchor's by at most kPlaneStep / 2, the
  // rounding of these sums, and kNormalStep x (the lamp's distance + that of the point).
  const glm::vec3 centre = (glm::vec3(index) + 0.5f) * size;
  const float planeOffset = (float(plane) + 0.5f) * LampCell::kPlaneStep;
  out.at.p = centre - normal * ((glm::dot(normal, centre) - planeOffset) / glm::dot(normal, normal));
  out.at.n = normal;
  const float magnitude = std::abs(centre.x) + std::abs(centre.y) + std::abs(centre.z) + size;
  out.at.distanceSlack = 2.0f * size + LampCell::kPlaneStep + 1e-5f * magnitude;
  out.at.normalSlack = kNormalStep;
  out.at.heightSlack = 0.5f * LampCell::kPlaneStep + 1e-5f * magnitude + out.at.distanceSlack * kNormalStep;
  LampCellMemo* memo = cell.memo;
  if (memo == nullptr) {
    out.total = weighLamps(out.at, scratch);
    out.prefix = scratch;
    return out;
  }
  for (LampCellMemo::Entry& e : memo->entries) {
    if (e.sampler == this && e.build == build_ && e.cell == index && e.plane == plane && e.size == size &&
        e.normal == normal) {
      out.total = e.total;
      out.prefix = &e.prefix;
      return out;
    }
  }
  LampCellMemo::Entry& e = memo->entries[memo->next];
  memo->next = (memo->next + 1) % LampCellMemo::kEntries;
  e.sampler = this;
  e.build = build_;
  e.cell = index;
  e.plane = plane;
  e.size = size;
  e.normal = normal;
  e.total = weighLamps(out.at, &e.prefix);
  out.total = e.total;
  out.prefix = &e.prefix;
  return out;
}

}  // namespace pa
