#include "renderer/scene/lights/light_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <glm/geometric.hpp>

namespace pa {

namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
/// Below this depth splits follow the orientation-aware cost; deeper ones halve the set, which
/// bounds the depth (and the build's recursion) on any input.
constexpr int kMaxCostSplitDepth = 40;
constexpr int kBuckets = 12;

float safeSqrt(float x) { return std::sqrt(std::max(0.0f, x)); }

/// cos(max(0, a - b)) from the sines and cosines of angles a, b in [0, pi].
float cosOfClampedDifference(float sinA, float cosA, float sinB, float cosB) {
  if (cosA > cosB) return 1.0f;   // a < b
  return cosA * cosB + sinA * sinB;
}

/// sin(max(0, a - b)) likewise.
float sinOfClampedDifference(float sinA, float cosA, float sinB, float cosB) {
  if (cosA > cosB) return 0.0f;
  return sinA * cosB - cosA * sinB;
}

/// The measure of directions the emitters can send light into (the orientation term of the
/// split cost in Conty Estevez and Kulla).
float orientationMeasure(const LightBounds& b) {
  const float thetaO = std::acos(std::clamp(b.normals.cosTheta, -1.0f, 1.0f));
  const float thetaE = std::acos(std::clamp(b.cosEmission, -1.0f, 1.0f));
  const float thetaW = std::min(thetaO + thetaE, kPi);
  const float sinO = std::sin(thetaO);
  return 2.0f * kPi * (1.0f - std::cos(thetaO)) +
         0.5f * kPi * (2.0f * thetaW * sinO - std::cos(thetaO - 2.0f * thetaW) - 2.0f * thetaO * sinO + std::cos(thetaO));
}

float surfaceArea(const Bounds& b) { return 2.0f * b.halfArea(); }

bool finiteBounds(const LightBounds& b) {
  return !b.bounds.empty() && std::isfinite(b.bounds.min.x) && std::isfinite(b.bounds.min.y) &&
         std::isfinite(b.bounds.min.z) && std::isfinite(b.bounds.max.x) && std::isfinite(b.bounds.max.y) &&
         std::isfinite(b.bounds.max.z);
}

}  // namespace

DirectionCone coneUnion(const DirectionCone& a, const DirectionCone& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  const float thetaA = std::acos(std::clamp(a.cosTheta, -1.0f, 1.0f));
  const float thetaB = std::acos(std::clamp(b.cosTheta, -1.0f, 1.0f));
  const float thetaD = std::acos(std::clamp(glm::dot(a.axis, b.axis), -1.0f, 1.0f));
  if (std::min(thetaD + thetaB, kPi) <= thetaA) return a;
  if (std::min(thetaD + thetaA, kPi) <= thetaB) return b;
  const float thetaO = 0.5f * (thetaA + thetaD + thetaB);
  if (thetaO >= kPi) return DirectionCone::entireSphere();
  // Turn a's axis toward b's by thetaO - thetaA about their common perpendicular.
  const glm::vec3 perpendicular = glm::cross(a.axis, b.axis);
  const float length = glm::length(perpendicular);
  if (!(length > 1e-7f)) return DirectionCone::entireSphere();
  const glm::vec3 k = perpendicular / length;
  const float turn = thetaO - thetaA;
  const glm::vec3 axis = glm::normalize(a.axis * std::cos(turn) + glm::cross(k, a.axis) * std::sin(turn));
  return {axis, std::cos(thetaO)};
}

LightBounds boundsUnion(const LightBounds& a, const LightBounds& b) {
  if (!(a.power > 0.0f)) return b;
  if (!(b.power > 0.0f)) return a;
  LightBounds u;
  u.bounds = a.bounds;
  u.bounds.extend(b.bounds);
  u.power = a.power + b.power;
  u.normals = coneUnion(a.normals, b.normals);
  u.cosEmission = std::min(a.cosEmission, b.cosEmission);
  u.twoSided = a.twoSided || b.twoSided;
  u.range = a.range > 0.0f && b.range > 0.0f ? std::max(a.range, b.range) : 0.0f;
  return u;
}

namespace {

/// lightImportance(), inlined where both children of a node are weighed (their work overlaps).
[[gnu::always_inline]] inline float importanceOf(const LightBounds& b, const glm::vec3& p, const glm::vec3& n) {
  if (!(b.power > 0.0f)) return 0.0f;
  const glm::vec3 centre = b.bounds.center();
  const glm::vec3 halfDiagonal = 0.5f * (b.bounds.max - b.bounds.min);
  const float radius2 = glm::dot(halfDiagonal, halfDiagonal);
  if (b.range > 0.0f) {
    const glm::vec3 outside = glm::max(glm::max(b.bounds.min - p, p - b.bounds.max), glm::vec3(0.0f));
    if (glm::dot(outside, outside) > b.range * b.range) return 0.0f;
  }
  const glm::vec3 fromCentre = p - centre;
  const float dist2 = glm::dot(fromCentre, fromCentre);
  // Inside the bounding sphere every direction is possible and distance is no better than its size.
  const bool inside = dist2 <= radius2;
  const glm::vec3 wi = dist2 > 0.0f ? fromCentre / std::sqrt(dist2) : glm::vec3(0.0f, 0.0f, 1.0f);
  // Exact plane tests against the box (sharper than the cones near the box): nothing reflects
  // when the whole box lies below the point's tangent plane, and one-sided emitters sharing one
  // normal send nothing when the point lies behind all of them.
  if (n != glm::vec3(0.0f) && glm::dot(centre - p, n) + glm::dot(halfDiagonal, glm::abs(n)) <= 0.0f) return 0.0f;
  if (!b.twoSided && b.normals.cosTheta >= 1.0f && b.cosEmission >= 0.0f &&
      glm::dot(p - centre, b.normals.axis) + glm::dot(halfDiagonal, glm::abs(b.normals.axis)) <= 0.0f)
    return 0.0f;
  const float cosB = inside ? -1.0f : safeSqrt(1.0f - radius2 / dist2);
  const float sinB = safeSqrt(1.0f - cosB * cosB);

  // Smallest angle between an emitter normal and a direction toward p.
  float cosW = glm::dot(b.normals.axis, wi);
  if (b.twoSided) cosW = std::abs(cosW);
  const float sinW = safeSqrt(1.0f - cosW * cosW);
  const float cosO = std::clamp(b.normals.cosTheta, -1.0f, 1.0f);
  const float sinO = safeSqrt(1.0f - cosO * cosO);
  const float cosX = cosOfClampedDifference(sinW, cosW, sinO, cosO);
  const float sinX = sinOfClampedDifference(sinW, cosW, sinO, cosO);
  const float cosEmit = cosOfClampedDifference(sinX, cosX, sinB, cosB);
  if (cosEmit <= b.cosEmission) return 0.0f;

  float importance = b.power * cosEmit / std::max(dist2, radius2);
  if (n != glm::vec3(0.0f)) {
    // The point reflects only into its hemisphere: the nearest direction to the emitters counts.
    const float cosI = std::clamp(-glm::dot(wi, n), -1.0f, 1.0f);
    const float sinI = safeSqrt(1.0f - cosI * cosI);
    const float cosReceive = cosOfClampedDifference(sinI, cosI, sinB, cosB);
    if (!(cosReceive > 0.0f)) return 0.0f;
    importance *= cosReceive;
  }
  return std::isfinite(importance) ? std::max(importance, 0.0f) : 0.0f;
}

}  // namespace

float lightImportance(const LightBounds& b, const glm::vec3& p, const glm::vec3& n) { return importanceOf(b, p, n); }

LightTree::LightTree(std::span<const LightBounds> lights) { rebuild(lights); }

void LightTree::rebuild(std::span<const LightBounds> lights) {
  nodes_.clear();
  leafOfLight_.assign(lights.size(), UINT32_MAX);
  std::vector<uint32_t>& ids = ids_;
  ids.clear();
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (lights[i].power > 0.0f && std::isfinite(lights[i].power) && finiteBounds(lights[i])) ids.push_back(i);
  }
  if (ids.empty()) return;
  nodes_.reserve(2 * ids.size() - 1);
  build(lights, ids, UINT32_MAX, 0);
}

uint32_t LightTree::build(std::span<const LightBounds> lights, std::span<uint32_t> ids, uint32_t parent,
                          int depth) {
  const auto index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back(Node{});
  nodes_[index].parent = parent;
  if (ids.size() == 1) {
    nodes_[index].bounds = lights[ids[0]];
    nodes_[index].light = ids[0];
    leafOfLight_[ids[0]] = index;
    return index;
  }

  Bounds all, centroids;
  for (uint32_t id : ids) {
    all.extend(lights[id].bounds);
    centroids.extend(lights[id].bounds.center());
  }
  const glm::vec3 extent = centroids.max - centroids.min;
  const glm::vec3 fullExtent = all.max - all.min;
  const float longest = std::max({fullExtent.x, fullExtent.y, fullExtent.z});

  size_t middle = ids.size() / 2;
  bool split = false;
  if (depth < kMaxCostSplitDepth) {
    // Bucketed split minimising power x orientation measure x surface area on each side.
    float bestCost = std::numeric_limits<float>::infinity();
    int bestAxis = -1, bestBucket = 0;
    const auto bucketOf = [&](uint32_t id, int axis) {
      const float c = lights[id].bounds.center()[axis];
      const int b = int(float(kBuckets) * (c - centroids.min[axis]) / extent[axis]);
      return std::clamp(b, 0, kBuckets - 1);
    };
    for (int axis = 0; axis < 3; ++axis) {
      if (!(extent[axis] > 0.0f)) continue;
      std::array<LightBounds, kBuckets> buckets{};
      for (uint32_t id : ids) {
        LightBounds& b = buckets[size_t(bucketOf(id, axis))];
        b = boundsUnion(b, lights[id]);
      }
      // Suffix unions, then sweep prefixes.
      std::array<LightBounds, kBuckets> above{};
      above[kBuckets - 1] = buckets[kBuckets - 1];
      for (int i = kBuckets - 2; i >= 0; --i) above[size_t(i)] = boundsUnion(buckets[size_t(i)], above[size_t(i) + 1]);
      const float thinness = longest / std::max(fullExtent[axis], 1e-20f);
      LightBounds below;
      for (int i = 0; i + 1 < kBuckets; ++i) {
        below = boundsUnion(below, buckets[size_t(i)]);
        const LightBounds& right = above[size_t(i) + 1];
        if (!(below.power > 0.0f) || !(right.power > 0.0f)) continue;
        const float cost = thinness * (below.power * orientationMeasure(below) * surfaceArea(below.bounds) +
                                       right.power * orientationMeasure(right) * surfaceArea(right.bounds));
        if (cost < bestCost) {
          bestCost = cost;
          bestAxis = axis;
          bestBucket = i;
        }
      }
    }
    if (bestAxis >= 0) {
      const auto it = std::partition(ids.begin(), ids.end(),
                                     [&](uint32_t id) { return bucketOf(id, bestAxis) <= bestBucket; });
      middle = size_t(it - ids.begin());
      split = middle > 0 && middle < ids.size();
    }
  }
  if (!split) {
    middle = ids.size() / 2;
    int axis = 0;
    if (extent.y > extent[axis]) axis = 1;
    if (extent.z > extent[axis]) axis = 2;
    std::nth_element(ids.begin(), ids.begin() + std::ptrdiff_t(middle), ids.end(), [&](uint32_t a, uint32_t b) {
      const float ca = lights[a].bounds.center()[axis], cb = lights[b].bounds.center()[axis];
      return ca < cb || (ca == cb && a < b);
    });
  }

  const uint32_t first = build(lights, ids.subspan(0, middle), index, depth + 1);
  const uint32_t second = build(lights, ids.subspan(middle), index, depth + 1);
  (void)first;
  nodes_[index].bounds = boundsUnion(nodes_[index + 1].bounds, nodes_[second].bounds);
  nodes_[index].secondChild = second;
  return index;
}

float LightTree::firstChildProbability(const Node& node, const glm::vec3& p, const glm::vec3& n) const {
  const auto self = static_cast<uint32_t>(&node - nodes_.data());
  const float first = importanceOf(nodes_[self + 1].bounds, p, n);
  const float second = importanceOf(nodes_[node.secondChild].bounds, p, n);
  const float total = first + second;
  // Both bounds tighter than the parent's and neither reaches p: nothing below contributes, so
  // any choice is unbiased; halving keeps the pmf summing to 1 wherever the root reaches p.
  if (!(total > 0.0f)) return 0.5f;
  return first / total;
}

bool LightTree::sample(const glm::vec3& p, const glm::vec3& n, float u, uint32_t& index, float& pmf,
                       bool rootReaches) const {
  if (nodes_.empty() || !(rootReaches || lightImportance(nodes_[0].bounds, p, n) > 0.0f)) return false;
  uint32_t node = 0;
  float probability = 1.0f;
  u = std::clamp(u, 0.0f, kOneMinusEpsilon);
  while (nodes_[node].light == UINT32_MAX) {
    const float q = firstChildProbability(nodes_[node], p, n);
    if (u < q) {
      u = std::min(u / q, kOneMinusEpsilon);
      probability *= q;
      node = node + 1;
    } else {
      u = std::min((u - q) / (1.0f - q), kOneMinusEpsilon);
      probability *= 1.0f - q;
      node = nodes_[node].secondChild;
    }
  }
  index = nodes_[node].light;
  pmf = probability;
  return pmf > 0.0f;
}

float LightTree::pmf(uint32_t index, const glm::vec3& p, const glm::vec3& n, bool rootReaches) const {
  if (index >= leafOfLight_.size() || leafOfLight_[index] == UINT32_MAX) return 0.0f;
  if (!rootReaches && !(lightImportance(nodes_[0].bounds, p, n) > 0.0f)) return 0.0f;
  uint32_t node = leafOfLight_[index];
  // Branch probabilities from the leaf up, multiplied from the root down as sample() does.
  std::array<float, 128> branch{};
  size_t depth = 0;
  while (nodes_[node].parent != UINT32_MAX) {
    const uint32_t parent = nodes_[node].parent;
    const float q = firstChildProbability(nodes_[parent], p, n);
    if (depth == branch.size()) return 0.0f;   // cannot happen: build() bounds the depth
    branch[depth++] = node == parent + 1 ? q : 1.0f - q;
    node = parent;
  }
  float probability = 1.0f;
  while (depth > 0) probability *= branch[--depth];
  return probability;
}

}  // namespace pa
