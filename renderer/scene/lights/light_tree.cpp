#include "renderer/scene/lights/light_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include <immintrin.h>

#include <glm/geometric.hpp>

#include "renderer/core/finite.h"

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
  // Exact plane tests against the box (sharper than the cones near the box): nothing reflects
  // when the whole box lies below the point's tangent plane, and one-sided emitters sharing one
  // normal send nothing when the point lies behind all of them.
  if (n != glm::vec3(0.0f) && glm::dot(centre - p, n) + glm::dot(halfDiagonal, glm::abs(n)) <= 0.0f) return 0.0f;
  if (!b.twoSided && b.normals.cosTheta >= 1.0f && b.cosEmission >= 0.0f &&
      glm::dot(p - centre, b.normals.axis) + glm::dot(halfDiagonal, glm::abs(b.normals.axis)) <= 0.0f)
    return 0.0f;
  if (inside && finite(n) && finite(b.normals.axis) && !std::isnan(b.normals.cosTheta)) {
    // Inside the bounding sphere its cone spans every direction (cosB = -1, an angle of pi):
    // the clamped emission and reception angles below are 0 and both cosines 1, whatever wi is
    // (the tree's root is weighed at every shading point, and points inside skip the direction).
    if (1.0f <= b.cosEmission) return 0.0f;
    const float importance = b.power / radius2;   // max(dist2, radius2) inside
    return std::isfinite(importance) ? std::max(importance, 0.0f) : 0.0f;
  }
  const glm::vec3 wi = dist2 > 0.0f ? fromCentre / std::sqrt(dist2) : glm::vec3(0.0f, 0.0f, 1.0f);
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
  wide_.clear();
  root_ = {};
  leafOfLight_.assign(lights.size(), UINT32_MAX);
  std::vector<uint32_t>& ids = ids_;
  ids.clear();
  for (uint32_t i = 0; i < lights.size(); ++i) {
    if (lights[i].power > 0.0f && std::isfinite(lights[i].power) && finiteBounds(lights[i])) ids.push_back(i);
  }
  if (ids.empty()) return;
  nodes_.reserve(2 * ids.size() - 1);
  build(lights, ids, 0);
  root_ = nodes_[0].bounds;
  // A wide node holds at least two children unless the tree has one emitter: at most n - 1 nodes.
  wide_.reserve(std::max<size_t>(1, ids.size() - 1));
  collapse(0, UINT32_MAX);
}

uint32_t LightTree::build(std::span<const LightBounds> lights, std::span<uint32_t> ids, int depth) {
  const auto index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back(Node{});
  if (ids.size() == 1) {
    nodes_[index].bounds = lights[ids[0]];
    nodes_[index].light = ids[0];
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

  build(lights, ids.subspan(0, middle), depth + 1);
  const uint32_t second = build(lights, ids.subspan(middle), depth + 1);
  nodes_[index].bounds = boundsUnion(nodes_[index + 1].bounds, nodes_[second].bounds);
  nodes_[index].secondChild = second;
  return index;
}

uint32_t LightTree::collapse(uint32_t node, uint32_t parent) {
  // The node's children, each interior child replaced by its own two: two to four lanes.
  uint32_t lanes[4];
  uint32_t count = 0;
  if (nodes_[node].light != UINT32_MAX) {
    lanes[count++] = node;   // a tree of one emitter
  } else {
    for (const uint32_t child : {node + 1, nodes_[node].secondChild}) {
      if (nodes_[child].light != UINT32_MAX) {
        lanes[count++] = child;
      } else {
        lanes[count++] = child + 1;
        lanes[count++] = nodes_[child].secondChild;
      }
    }
  }
  const auto index = static_cast<uint32_t>(wide_.size());
  wide_.push_back(WideNode{});   // zeros: lanes past `count` keep power 0 and are never chosen
  WideNode& w = wide_[index];    // no push_back until the lanes are written
  w.parent = parent;
  for (uint32_t lane = 0; lane < count; ++lane) {
    const LightBounds& b = nodes_[lanes[lane]].bounds;
    const glm::vec3 centre = b.bounds.center();
    const glm::vec3 half = 0.5f * (b.bounds.max - b.bounds.min);
    w.centreX[lane] = centre.x;
    w.centreY[lane] = centre.y;
    w.centreZ[lane] = centre.z;
    w.halfX[lane] = half.x;
    w.halfY[lane] = half.y;
    w.halfZ[lane] = half.z;
    w.radius2[lane] = glm::dot(half, half);
    w.power[lane] = b.power > 0.0f ? b.power : 0.0f;
    w.axisX[lane] = b.normals.axis.x;
    w.axisY[lane] = b.normals.axis.y;
    w.axisZ[lane] = b.normals.axis.z;
    const float cosO = std::clamp(b.normals.cosTheta, -1.0f, 1.0f);
    w.cosO[lane] = cosO;
    w.sinO[lane] = safeSqrt(1.0f - cosO * cosO);
    w.cosEmission[lane] = b.cosEmission;
    w.range[lane] = b.range > 0.0f ? b.range : 0.0f;
    const bool flatOneSided = !b.twoSided && b.normals.cosTheta >= 1.0f && b.cosEmission >= 0.0f;
    w.axisExtent[lane] =
        flatOneSided ? glm::dot(half, glm::abs(b.normals.axis)) : std::numeric_limits<float>::infinity();
    w.twoSided[lane] = b.twoSided ? -1 : 0;
  }
  for (uint32_t lane = 0; lane < count; ++lane) {
    const uint32_t link = (index << 2) | lane;
    const Node& child = nodes_[lanes[lane]];
    if (child.light != UINT32_MAX) {
      wide_[index].child[lane] = kLeaf | child.light;
      leafOfLight_[child.light] = link;
    } else {
      const uint32_t below = collapse(lanes[lane], link);
      wide_[index].child[lane] = below;
    }
  }
  return index;
}

namespace {

/// Four floats, four int lanes (GCC/Clang vector extensions: one SSE register each).
using F4 = float __attribute__((vector_size(16)));
using I4 = int32_t __attribute__((vector_size(16)));

F4 loadF4(const float* p) {
  F4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

F4 sqrtF4(F4 v) { return reinterpret_cast<F4>(_mm_sqrt_ps(reinterpret_cast<__m128>(v))); }
// a > b ? a : b and a < b ? a : b lane by lane: exactly MAXPS and MINPS (b where either is NaN).
F4 maxF4(F4 a, F4 b) {
  return reinterpret_cast<F4>(_mm_max_ps(reinterpret_cast<__m128>(a), reinterpret_cast<__m128>(b)));
}
F4 minF4(F4 a, F4 b) {
  return reinterpret_cast<F4>(_mm_min_ps(reinterpret_cast<__m128>(a), reinterpret_cast<__m128>(b)));
}
F4 safeSqrtF4(F4 v) { return sqrtF4(maxF4(v, F4{})); }
F4 absF4(F4 v) { return v < 0.0f ? -v : v; }

}  // namespace

void LightTree::childProbabilities(const WideNode& w, const glm::vec3& p, const glm::vec3& n, bool hasNormal,
                                   float (&probability)[4]) const {
  // lightImportance() for the four lanes at once, with the same tests.
  const F4 cx = loadF4(w.centreX), cy = loadF4(w.centreY), cz = loadF4(w.centreZ);
  const F4 hx = loadF4(w.halfX), hy = loadF4(w.halfY), hz = loadF4(w.halfZ);
  const F4 radius2 = loadF4(w.radius2), power = loadF4(w.power), range = loadF4(w.range);
  const F4 fx = p.x - cx, fy = p.y - cy, fz = p.z - cz;   // from the centre to p
  I4 zero = ~(power > 0.0f);
  {
    // Beyond reach: the distance from p to the box exceeds the range.
    const F4 outX = maxF4(absF4(fx) - hx, F4{}), outY = maxF4(absF4(fy) - hy, F4{}),
             outZ = maxF4(absF4(fz) - hz, F4{});
    zero |= (range > 0.0f) & (outX * outX + outY * outY + outZ * outZ > range * range);
  }
  const F4 dist2 = fx * fx + fy * fy + fz * fz;
  const I4 inside = dist2 <= radius2;
  const F4 invDistance = 1.0f / sqrtF4(dist2);
  const I4 away = dist2 > 0.0f;
  const F4 wx = away ? fx * invDistance : F4{}, wy = away ? fy * invDistance : F4{},
           wz = away ? fz * invDistance : F4{} + 1.0f;
  if (hasNormal) {
    // The whole box below the tangent plane.
    const F4 extent = hx * std::abs(n.x) + hy * std::abs(n.y) + hz * std::abs(n.z);
    zero |= -(fx * n.x + fy * n.y + fz * n.z) + extent <= 0.0f;
  }
  const F4 ax = loadF4(w.axisX), ay = loadF4(w.axisY), az = loadF4(w.axisZ);
  zero |= fx * ax + fy * ay + fz * az + loadF4(w.axisExtent) <= 0.0f;   // behind one-sided emitters
  const F4 cosB = inside ? F4{} - 1.0f : safeSqrtF4(1.0f - radius2 / dist2);
  const F4 sinB = safeSqrtF4(1.0f - cosB * cosB);
  F4 cosW = ax * wx + ay * wy + az * wz;
  I4 twoSided;
  std::memcpy(&twoSided, w.twoSided, sizeof twoSided);
  cosW = (twoSided != 0) & (cosW < 0.0f) ? -cosW : cosW;
  const F4 sinW = safeSqrtF4(1.0f - cosW * cosW);
  const F4 cosO = loadF4(w.cosO), sinO = loadF4(w.sinO);
  // cos and sin of max(0, W - O), then cos of max(0, X - B) (cosOfClampedDifference).
  const I4 withinCone = cosW > cosO;
  const F4 cosX = withinCone ? F4{} + 1.0f : cosW * cosO + sinW * sinO;
  const F4 sinX = withinCone ? F4{} : sinW * cosO - cosW * sinO;
  const F4 cosEmit = cosX > cosB ? F4{} + 1.0f : cosX * cosB + sinX * sinB;
  zero |= cosEmit <= loadF4(w.cosEmission);
  F4 importance = power * cosEmit / maxF4(dist2, radius2);
  if (hasNormal) {
    const F4 dot = -(wx * n.x + wy * n.y + wz * n.z);
    const F4 cosI = minF4(maxF4(dot, F4{} - 1.0f), F4{} + 1.0f);
    const F4 sinI = safeSqrtF4(1.0f - cosI * cosI);
    const F4 cosReceive = cosI > cosB ? F4{} + 1.0f : cosI * cosB + sinI * sinB;
    zero |= ~(cosReceive > 0.0f);
    importance *= cosReceive;
  }
  // Only positive finite importances (NaN fails both comparisons).
  importance = (zero == 0) & (importance > 0.0f) & (importance <= std::numeric_limits<float>::max()) ? importance : F4{};
  float total = (importance[0] + importance[1]) + (importance[2] + importance[3]);
  if (total > std::numeric_limits<float>::max()) {
    // Finite lanes whose sum overflows: the same shares from lanes scaled down.
    importance *= 0x1p-64f;
    total = (importance[0] + importance[1]) + (importance[2] + importance[3]);
  }
  if (total > 0.0f) {
    const F4 share = importance / total;
    std::memcpy(probability, &share, sizeof share);
    return;
  }
  // No child reaches p (the bounds are tighter than the parent's): nothing below contributes,
  // so any choice is unbiased; a uniform one keeps the pmf summing to 1 wherever the root reaches p.
  const I4 used = power > 0.0f;
  const int count = -(used[0] + used[1] + used[2] + used[3]);
  const F4 uniform = used ? F4{} + 1.0f / float(count) : F4{};
  std::memcpy(probability, &uniform, sizeof uniform);
}

bool LightTree::sample(const glm::vec3& p, const glm::vec3& n, float u, uint32_t& index, float& pmf,
                       bool rootReaches) const {
  if (wide_.empty() || !(rootReaches || lightImportance(root_, p, n) > 0.0f)) return false;
  const bool hasNormal = n != glm::vec3(0.0f);
  uint32_t node = 0;
  float probability = 1.0f;
  u = std::clamp(u, 0.0f, kOneMinusEpsilon);
  for (;;) {
    const WideNode& w = wide_[node];
    float q[4];
    childProbabilities(w, p, n, hasNormal, q);
    // The lane where the running sum of the probabilities passes u; the last lane of positive
    // probability catches rounding at the top end.
    int chosen = -1;
    float below = 0.0f;
    for (int lane = 0; lane < 4; ++lane) {
      if (!(q[lane] > 0.0f)) continue;
      chosen = lane;
      if (u < below + q[lane]) break;
      below += q[lane];
    }
    if (chosen < 0) return false;
    const float taken = q[chosen];
    u = std::clamp((u - std::min(below, u)) / taken, 0.0f, kOneMinusEpsilon);
    probability *= taken;
    const uint32_t child = w.child[chosen];
    if (child & kLeaf) {
      index = child & ~kLeaf;
      break;
    }
    node = child;
  }
  pmf = probability;
  return pmf > 0.0f;
}

float LightTree::pmf(uint32_t index, const glm::vec3& p, const glm::vec3& n, bool rootReaches) const {
  if (index >= leafOfLight_.size() || leafOfLight_[index] == UINT32_MAX) return 0.0f;
  if (!rootReaches && !(lightImportance(root_, p, n) > 0.0f)) return 0.0f;
  const bool hasNormal = n != glm::vec3(0.0f);
  // Branch probabilities from the leaf up, multiplied from the root down as sample() does.
  std::array<float, 128> branch{};
  size_t depth = 0;
  for (uint32_t link = leafOfLight_[index]; link != UINT32_MAX; link = wide_[link >> 2].parent) {
    float q[4];
    childProbabilities(wide_[link >> 2], p, n, hasNormal, q);
    if (depth == branch.size()) return 0.0f;   // cannot happen: build() bounds the depth
    branch[depth++] = q[link & 3];
  }
  float probability = 1.0f;
  while (depth > 0) probability *= branch[--depth];
  return probability;
}

}  // namespace pa
