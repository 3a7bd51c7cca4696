// Game-side queries on the loaded map, as the stock opengl1 renderer answers them:
// LightForPoint (R_LightForPoint), inPVS (R_inPVS), MarkFragments (R_MarkFragments).
#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "port/engine_glue/world.h"
#include "port/q3formats/bsp/light_grid.h"

namespace glue {
namespace {

/// r_ambientScale's default: the engine scales the grid's ambient colour by it.
constexpr float kAmbientScale = 0.6f;
/// MAX_VERTS_ON_POLY: decal polygons and clipped fragments have at most this many corners.
constexpr int kMaxPolygonPoints = 64;
/// The engine lists at most 64 surfaces per decal.
constexpr size_t kMaxMarkSurfaces = 64;
/// Clip planes treat points this close as on the plane.
constexpr float kClipEpsilon = 0.5f;
/// The decal volume reaches this far in front of the first point and behind it.
constexpr float kMarkNear = 32.0f, kMarkFar = 20.0f;
/// The decal box is extended this far against the projection to reach the leaves in front.
constexpr float kMarkBoxBack = 20.0f;
/// Facing thresholds: a face must meet the projection within 60 degrees, a patch triangle
/// must face against it at all (the engine's -0.1 / -0.05 per half of a grid quad).
constexpr float kFaceFacing = -0.5f, kPatchFacing = -0.1f;

struct ClipPlane {
  glm::vec3 normal;
  float dist;
};
/// A convex polygon of at most kMaxPolygonPoints corners, on the stack.
class Polygon {
 public:
  Polygon() = default;
  Polygon(const glm::vec3* first, const glm::vec3* last) {
    for (; first != last; ++first) push_back(*first);
  }
  /// Appends a corner; corners beyond the capacity are dropped (the chop refuses such polygons).
  void push_back(const glm::vec3& p) {
    if (count_ < points_.size()) points_[count_++] = p;
  }
  size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  void clear() { count_ = 0; }
  const glm::vec3& operator[](size_t i) const { return points_[i]; }
  const glm::vec3* begin() const { return points_.data(); }
  const glm::vec3* end() const { return points_.data() + count_; }

 private:
  std::array<glm::vec3, kMaxPolygonPoints> points_;
  size_t count_ = 0;
};

/// The engine's BoxOnPlaneSide: 1 = box in front (or touching), 2 = behind, 3 = crossing.
int boxOnPlaneSide(const glm::vec3& mins, const glm::vec3& maxs, const glm::vec3& normal, float dist) {
  float nearest = 0.0f, farthest = 0.0f;
  for (int k = 0; k < 3; ++k) {
    nearest += normal[k] * (normal[k] < 0.0f ? maxs[k] : mins[k]);
    farthest += normal[k] * (normal[k] < 0.0f ? mins[k] : maxs[k]);
  }
  int sides = 0;
  if (farthest >= dist) sides = 1;
  if (nearest < dist) sides |= 2;
  return sides;
}

/// R_ChopPolyBehindPlane: keeps the part in front of the plane; points within the epsilon
/// count as on it. A polygon with no point in front vanishes; one near the corner limit too.
Polygon chopBehindPlane(const Polygon& in, const ClipPlane& plane) {
  enum Side { Front, Back, On };
  const size_t n = in.size();
  if (n >= kMaxPolygonPoints - 2) return {};
  std::array<float, kMaxPolygonPoints> dists{};
  std::array<Side, kMaxPolygonPoints> sides{};
  int counts[3] = {0, 0, 0};
  for (size_t i = 0; i < n; ++i) {
    dists[i] = glm::dot(in[i], plane.normal) - plane.dist;
    sides[i] = dists[i] > kClipEpsilon ? Front : (dists[i] < -kClipEpsilon ? Back : On);
    ++counts[sides[i]];
  }
  if (counts[Front] == 0) return {};
  if (counts[Back] == 0) return in;
  Polygon out;
  for (size_t i = 0; i < n; ++i) {
    const size_t next = (i + 1) % n;
    if (sides[i] != Back) out.push_back(in[i]);
    if (sides[i] == On || sides[next] == On || sides[next] == sides[i]) continue;
    const float denominator = dists[i] - dists[next];
    const float t = denominator == 0.0f ? 0.0f : dists[i] / denominator;
    out.push_back(in[i] + t * (in[next] - in[i]));
  }
  return out;
}

}  // namespace

int World::leafAt(const glm::vec3& point) const {
  if (bsp_.nodes.empty()) return bsp_.leafs.empty() ? -1 : 0;
  int32_t node = 0;
  // parseBsp checked that children point forward, so the walk ends.
  while (node >= 0) {
    const q3::BspNode& n = bsp_.nodes[static_cast<size_t>(node)];
    const q3::BspPlane& plane = bsp_.planes[static_cast<size_t>(n.plane)];
    node = glm::dot(plane.normal, point) - plane.dist > 0.0f ? n.children[0] : n.children[1];
  }
  return -1 - node;
}

int World::clusterOf(int leaf) const {
  if (leaf < 0 || static_cast<size_t>(leaf) >= bsp_.leafs.size()) return -1;
  return bsp_.leafs[static_cast<size_t>(leaf)].cluster;
}

bool World::inPVS(const float* p1, const float* p2) const {
  // The engine reads p1's row through the collision model (CM_ClusterPVS): a map without vis
  // data sees everything, and a point outside the level (cluster -1) gets cluster 0's row.
  const q3::BspVisibility& vis = bsp_.visibility;
  if (vis.numClusters <= 0) return true;
  int from = clusterOf(leafAt({p1[0], p1[1], p1[2]}));
  if (from < 0 || from >= vis.numClusters) from = 0;
  const int to = clusterOf(leafAt({p2[0], p2[1], p2[2]}));
  // The engine indexes the row with cluster -1 (reading out of bounds): call it not visible.
  if (to < 0 || to >= vis.numClusters) return false;
  return vis.clusterVisible(from, to);
}

bool World::lightForPoint(const float* point, float* ambient, float* directed,
                          float* direction) const {
  if (!shiftedGrid_.valid) return false;
  const q3::LightGridSample sample = q3::sampleLightGrid(shiftedGrid_, {point[0], point[1], point[2]});
  // No neighbour lit (all in solid): the engine returns zero light and a zero direction.
  const glm::vec3 dir = sample.valid ? sample.direction : glm::vec3(0.0f);
  for (int k = 0; k < 3; ++k) {
    ambient[k] = sample.ambient[k] * kAmbientScale;
    directed[k] = sample.directed[k];
    direction[k] = dir[k];
  }
  return true;
}

const std::vector<uint32_t>& World::surfacesInBox(const glm::vec3& mins, const glm::vec3& maxs,
                                                  const glm::vec3& dir) const {
  std::vector<uint32_t>& listed = markScratch_.listed;
  std::vector<bool>& seen = markScratch_.seen;
  std::vector<int32_t>& pending = markScratch_.pending;   // nodes (>= 0) and leaves (-1 - leaf), front child first
  listed.clear();
  seen.assign(bsp_.surfaces.size(), false);
  pending.assign(1, bsp_.nodes.empty() ? -1 : 0);
  while (!pending.empty() && listed.size() < kMaxMarkSurfaces) {
    const int32_t at = pending.back();
    pending.pop_back();
    if (at >= 0) {
      const q3::BspNode& node = bsp_.nodes[static_cast<size_t>(at)];
      const q3::BspPlane& plane = bsp_.planes[static_cast<size_t>(node.plane)];
      const int side = boxOnPlaneSide(mins, maxs, plane.normal, plane.dist);
      if (side != 1) pending.push_back(node.children[1]);
      if (side != 2) pending.push_back(node.children[0]);
      continue;
    }
    const size_t leafIndex = static_cast<size_t>(-1 - static_cast<int64_t>(at));
    if (leafIndex >= bsp_.leafs.size()) continue;
    const q3::BspLeaf& leaf = bsp_.leafs[leafIndex];
    for (int32_t i = 0; i < leaf.numLeafSurfaces && listed.size() < kMaxMarkSurfaces; ++i) {
      const auto slot = static_cast<size_t>(leaf.firstLeafSurface) + static_cast<size_t>(i);
      if (slot >= bsp_.leafSurfaces.size()) break;
      const int32_t surfaceIndex = bsp_.leafSurfaces[slot];
      if (surfaceIndex < 0 || static_cast<size_t>(surfaceIndex) >= seen.size() || seen[surfaceIndex]) continue;
      seen[surfaceIndex] = true;
      const MarkSurface& surface = markSurfaces_[static_cast<size_t>(surfaceIndex)];
      if (surface.kind == MarkKind::None) continue;
      if (surface.kind == MarkKind::Face &&
          (boxOnPlaneSide(mins, maxs, surface.planeNormal, surface.planeDist) != 3 ||
           glm::dot(surface.planeNormal, dir) > kFaceFacing))
        continue;
      listed.push_back(static_cast<uint32_t>(surfaceIndex));
    }
  }
  return listed;
}

int World::markFragments(int numPoints, const float (*points)[3], const float* projection,
                         int maxPoints, float* pointBuffer, int maxFragments,
                         q3abi::markFragment_t* fragments) const {
  if (numPoints <= 0 || maxPoints <= 0 || maxFragments <= 0) return 0;
  const glm::vec3 project(projection[0], projection[1], projection[2]);
  const float reach = glm::length(project);
  if (!std::isfinite(reach)) return 0;
  const glm::vec3 dir = reach > 0.0f ? project / reach : glm::vec3(0.0f);

  numPoints = std::min(numPoints, kMaxPolygonPoints);
  Polygon decal;
  glm::vec3 mins(3e38f), maxs(-3e38f);
  for (int i = 0; i < numPoints; ++i) {
    const glm::vec3 p(points[i][0], points[i][1], points[i][2]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return 0;
    decal.push_back(p);
    for (const glm::vec3& q : {p, p + project, p - kMarkBoxBack * dir}) {
      mins = glm::min(mins, q);
      maxs = glm::max(maxs, q);
    }
  }

  // The volume swept by the decal: one plane per edge (the decal's winding, clockwise seen along
  // the projection, puts the inside in front), then near and far caps at the first point.
  std::array<ClipPlane, kMaxPolygonPoints + 2> planeStore;
  size_t planeCount = 0;
  const auto addPlane = [&](const ClipPlane& plane) { planeStore[planeCount++] = plane; };
  for (int i = 0; i < numPoints; ++i) {
    glm::vec3 normal = glm::cross(decal[(i + 1) % numPoints] - decal[i], -project);
    const float length = glm::length(normal);
    normal = length > 0.0f ? normal / length : glm::vec3(0.0f);   // degenerate edge: clips all
    addPlane({normal, glm::dot(normal, decal[i])});
  }
  addPlane({dir, glm::dot(dir, decal[0]) - kMarkNear});
  addPlane({-dir, -glm::dot(dir, decal[0]) - kMarkFar});
  const std::span<const ClipPlane> planes(planeStore.data(), planeCount);

  // Triangles wholly outside the volume's box (padded for on-plane slack) cannot give a fragment.
  glm::vec3 volumeMins(3e38f), volumeMaxs(-3e38f);
  const float start = glm::dot(dir, decal[0]);
  for (const glm::vec3& p : decal) {
    for (const float along : {start - kMarkNear, start + kMarkFar}) {
      const glm::vec3 q = p + (along - glm::dot(dir, p)) * dir;
      volumeMins = glm::min(volumeMins, q);
      volumeMaxs = glm::max(volumeMaxs, q);
    }
  }
  volumeMins -= glm::vec3(2.0f);
  volumeMaxs += glm::vec3(2.0f);

  int fragmentCount = 0, pointCount = 0;
  for (const uint32_t surfaceIndex : surfacesInBox(mins, maxs, dir)) {
    const MarkSurface& surface = markSurfaces_[surfaceIndex];
    if (surface.kind == MarkKind::Soup) continue;   // r_marksOnTriangleMeshes 0
    for (uint32_t c = 0; c < surface.numCorners; c += 3) {
      const glm::vec3* corner = &markCorners_[surface.firstCorner + c];
      const glm::vec3 lo = glm::min(corner[0], glm::min(corner[1], corner[2]));
      const glm::vec3 hi = glm::max(corner[0], glm::max(corner[1], corner[2]));
      if (glm::any(glm::lessThan(hi, volumeMins)) || glm::any(glm::greaterThan(lo, volumeMaxs))) continue;
      if (surface.kind == MarkKind::Patch) {
        // Front normal of a clockwise triangle.
        const glm::vec3 normal = glm::cross(corner[2] - corner[0], corner[1] - corner[0]);
        const float length = glm::length(normal);
        if (!(length > 0.0f) || glm::dot(normal / length, dir) >= kPatchFacing) continue;
      }
      Polygon fragment(corner, corner + 3);
      for (const ClipPlane& plane : planes) {
        fragment = chopBehindPlane(fragment, plane);
        if (fragment.empty()) break;
      }
      const int size = static_cast<int>(fragment.size());
      if (size == 0 || pointCount + size > maxPoints) continue;   // no room: the next may fit
      fragments[fragmentCount] = {pointCount, size};
      for (const glm::vec3& p : fragment) {
        for (int k = 0; k < 3; ++k) pointBuffer[pointCount * 3 + k] = p[k];
        ++pointCount;
      }
      if (++fragmentCount == maxFragments) return fragmentCount;
    }
  }
  return fragmentCount;
}

}  // namespace glue
