// Game-side queries on the loaded map: LightForPoint (light grid), inPVS (clusters + vis rows)
// and MarkFragments (decal polygons clipped against the world's triangles).
#include <algorithm>
#include <array>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "port/engine_glue/world.h"

namespace glue {
namespace {

constexpr float kTwoPi = 6.28318530718f;
constexpr int kMaxClipPoints = 64;
constexpr float kMarkNearSlack = 32.0f;   // how far in front of the decal plane surfaces are taken
constexpr float kMarkFarSlack = 20.0f;    // and behind the projection's end

using Polygon = std::vector<glm::vec3>;

/// Keeps the part of `in` where dot(normal, p) - dist >= 0.
Polygon clipPolygon(const Polygon& in, const glm::vec3& normal, float dist) {
  Polygon out;
  const size_t n = in.size();
  for (size_t i = 0; i < n; ++i) {
    const glm::vec3& a = in[i];
    const glm::vec3& b = in[(i + 1) % n];
    const float da = glm::dot(normal, a) - dist;
    const float db = glm::dot(normal, b) - dist;
    if (da >= 0.0f) out.push_back(a);
    if ((da >= 0.0f) != (db >= 0.0f)) out.push_back(a + (b - a) * (da / (da - db)));
    if (out.size() >= kMaxClipPoints) break;
  }
  return out;
}

}  // namespace

int World::leafAt(const glm::vec3& point) const {
  if (nodes_.empty()) return 0;
  int node = 0;
  while (node >= 0) {
    const WorldNode& n = nodes_[static_cast<size_t>(node)];
    const WorldPlane& plane = planes_[static_cast<size_t>(n.plane)];
    node = glm::dot(plane.normal, point) - plane.dist > 0.0f ? n.children[0] : n.children[1];
  }
  return -1 - node;
}

int World::clusterOf(int leaf) const {
  if (leaf < 0 || static_cast<size_t>(leaf) >= leafClusters_.size()) return -1;
  return leafClusters_[static_cast<size_t>(leaf)];
}

bool World::inPVS(const float* p1, const float* p2) const {
  if (vis_.empty() || numClusters_ <= 0) return true;
  const int c1 = clusterOf(leafAt({p1[0], p1[1], p1[2]}));
  const int c2 = clusterOf(leafAt({p2[0], p2[1], p2[2]}));
  if (c1 < 0 || c2 < 0 || c1 >= numClusters_ || c2 >= numClusters_) return false;
  const uint8_t row = vis_[static_cast<size_t>(c1) * clusterBytes_ + static_cast<size_t>(c2 >> 3)];
  return (row & (1u << (c2 & 7))) != 0;
}

bool World::lightForPoint(const float* point, float* ambient, float* directed,
                          float* direction) const {
  if (grid_.empty()) return false;
  glm::vec3 ambientSum(0.0f), directedSum(0.0f), directionSum(0.0f);
  int base[3];
  float frac[3];
  for (int k = 0; k < 3; ++k) {
    const float v = (point[k] - gridOrigin_[k]) / gridSize_[k];
    const float cell = std::isfinite(v) ? std::floor(v) : 0.0f;
    frac[k] = std::isfinite(v) ? v - cell : 0.0f;
    base[k] = static_cast<int>(std::clamp(cell, 0.0f, float(gridBounds_[k] - 1)));
  }
  float total = 0.0f;
  for (int corner = 0; corner < 8; ++corner) {
    float factor = 1.0f;
    size_t index = 0, stride = 1;
    for (int k = 0; k < 3; ++k) {
      const bool upper = (corner >> k) & 1;
      factor *= upper ? frac[k] : 1.0f - frac[k];
      const int at = std::min(base[k] + (upper ? 1 : 0), gridBounds_[k] - 1);
      index += static_cast<size_t>(at) * stride;
      stride *= static_cast<size_t>(gridBounds_[k]);
    }
    const uint8_t* sample = &grid_[index * 8];
    if (sample[0] + sample[1] + sample[2] + sample[3] + sample[4] + sample[5] == 0)
      continue;   // inside solid: no light sample
    total += factor;
    ambientSum += factor * glm::vec3(sample[0], sample[1], sample[2]);
    directedSum += factor * glm::vec3(sample[3], sample[4], sample[5]);
    const float longitude = sample[6] * (kTwoPi / 256.0f);
    const float latitude = sample[7] * (kTwoPi / 256.0f);
    directionSum += factor * glm::vec3(std::cos(latitude) * std::sin(longitude),
                                       std::sin(latitude) * std::sin(longitude),
                                       std::cos(longitude));
  }
  if (total > 0.0f && total < 0.99f) {
    ambientSum /= total;
    directedSum /= total;
  }
  const float length = glm::length(directionSum);
  const glm::vec3 dir = length > 1e-6f ? directionSum / length : glm::vec3(0.0f, 0.0f, 1.0f);
  for (int k = 0; k < 3; ++k) {
    ambient[k] = ambientSum[k];
    directed[k] = directedSum[k];
    direction[k] = dir[k];
  }
  return true;
}

int World::markFragments(int numPoints, const float (*points)[3], const float* projection,
                         int maxPoints, float* pointBuffer, int maxFragments,
                         q3abi::markFragment_t* fragments) const {
  numPoints = std::min(numPoints, kMaxClipPoints);
  const glm::vec3 project(projection[0], projection[1], projection[2]);
  const float reach = glm::length(project);
  if (!(reach > 1e-4f) || !std::isfinite(reach)) return 0;
  const glm::vec3 dir = project / reach;

  Polygon decal;
  glm::vec3 centre(0.0f), mins(3e38f), maxs(-3e38f);
  for (int i = 0; i < numPoints; ++i) {
    const glm::vec3 p(points[i][0], points[i][1], points[i][2]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return 0;
    decal.push_back(p);
    centre += p;
    for (const glm::vec3& q : {p - dir * kMarkNearSlack, p + project + dir * kMarkFarSlack}) {
      mins = glm::min(mins, q);
      maxs = glm::max(maxs, q);
    }
  }
  centre /= static_cast<float>(numPoints);

  // The prism swept by the decal: one plane per edge, plus near and far caps.
  std::vector<std::pair<glm::vec3, float>> planes;
  for (int i = 0; i < numPoints; ++i) {
    const glm::vec3 edge = decal[(i + 1) % numPoints] - decal[i];
    glm::vec3 normal = glm::cross(dir, edge);
    const float length = glm::length(normal);
    if (length < 1e-6f) continue;
    normal /= length;
    if (glm::dot(normal, centre - decal[i]) < 0.0f) normal = -normal;
    planes.emplace_back(normal, glm::dot(normal, decal[i]));
  }
  const float start = glm::dot(dir, decal[0]);
  planes.emplace_back(dir, start - kMarkNearSlack);
  planes.emplace_back(-dir, -(start + reach + kMarkFarSlack));

  int fragmentCount = 0, pointCount = 0;
  for (const MarkSurface& surface : markSurfaces_) {
    if (glm::any(glm::lessThan(surface.maxs, mins)) || glm::any(glm::greaterThan(surface.mins, maxs)))
      continue;
    for (uint32_t i = 0; i < surface.numIndices; i += 3) {
      const uint32_t* tri = &markIndices_[surface.firstIndex + i];
      Polygon poly = {markVertices_[tri[0]], markVertices_[tri[1]], markVertices_[tri[2]]};
      // BSP triangles wind clockwise seen from the front.
      const glm::vec3 normal = glm::cross(poly[2] - poly[0], poly[1] - poly[0]);
      const float area = glm::length(normal);
      if (area < 1e-6f) continue;
      // Only faces turned towards the projector take the mark (walls at grazing angles do not).
      if (glm::dot(normal / area, dir) > (surface.planar ? -0.5f : -0.1f)) continue;
      for (const auto& [planeNormal, dist] : planes) {
        poly = clipPolygon(poly, planeNormal, dist);
        if (poly.size() < 3) break;
      }
      if (poly.size() < 3) continue;
      if (pointCount + static_cast<int>(poly.size()) > maxPoints) return fragmentCount;
      fragments[fragmentCount] = {pointCount, static_cast<int>(poly.size())};
      for (const glm::vec3& p : poly) {
        pointBuffer[pointCount * 3 + 0] = p.x;
        pointBuffer[pointCount * 3 + 1] = p.y;
        pointBuffer[pointCount * 3 + 2] = p.z;
        ++pointCount;
      }
      if (++fragmentCount >= maxFragments) return fragmentCount;
    }
  }
  return fragmentCount;
}

}  // namespace glue
