// Surfaces -> triangle lists, and a seam (T-junction) diagnostic for patches.
#include "port/q3formats/bsp/tessellate.h"

#include <algorithm>
#include <cmath>
#include <bit>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/patch.h"
#include "port/q3formats/bsp/patch_seams.h"
#include "port/q3formats/bsp/point_welder.h"
#include "port/q3formats/common/format_error.h"

namespace q3 {
namespace {

glm::vec3 unitOrZero(const glm::vec3& n) {
  const float len = glm::length(n);
  return (len > 1e-6f && std::isfinite(len)) ? n / len : glm::vec3(0);
}

void copyIndexedSurface(const BspFile& bsp, const BspSurface& s, SurfaceMesh& mesh) {
  mesh.vertices.reserve(static_cast<size_t>(s.numVerts));
  for (int32_t k = 0; k < s.numVerts; ++k) {
    const auto& d = bsp.drawVerts[static_cast<size_t>(s.firstVert + k)];
    mesh.vertices.push_back({d.position, unitOrZero(d.normal), d.st, d.lightmap, d.color});
  }
  mesh.indices.reserve(static_cast<size_t>(s.numIndexes));
  for (int32_t k = 0; k + 2 < s.numIndexes; k += 3) {
    const auto* tri = &bsp.drawIndexes[static_cast<size_t>(s.firstIndex + k)];
    // Quake stores front faces clockwise; we emit counter-clockwise.
    mesh.indices.insert(mesh.indices.end(), {static_cast<uint32_t>(tri[0]), static_cast<uint32_t>(tri[2]),
                                             static_cast<uint32_t>(tri[1])});
  }
}

std::vector<int32_t> surfaceModels(const BspFile& bsp) {
  std::vector<int32_t> model(bsp.surfaces.size(), -1);
  for (size_t m = 0; m < bsp.models.size(); ++m)
    for (int32_t k = 0; k < bsp.models[m].numSurfaces; ++k) {
      auto& slot = model[static_cast<size_t>(bsp.models[m].firstSurface + k)];
      if (slot < 0) slot = static_cast<int32_t>(m);
    }
  return model;
}

PatchControlGrid controlGrid(const BspFile& bsp, const BspSurface& s) {
  return {s.patchWidth, s.patchHeight,
          std::span<const BspDrawVert>(bsp.drawVerts).subspan(static_cast<size_t>(s.firstVert),
                                                              static_cast<size_t>(s.numVerts))};
}

}  // namespace

std::vector<SurfaceMesh> tessellateSurfaces(const BspFile& bsp, const TessellationOptions& options) {
  if (!(options.maxError > 0) || !std::isfinite(options.maxError))
    throw std::invalid_argument("tessellation maxError must be a positive number");
  if (!(options.weldDistance >= 0 && options.weldDistance <= 1))
    throw std::invalid_argument("tessellation weldDistance must be in [0, 1]");
  if (!(options.seamTolerance >= 0 && options.seamTolerance <= 1))
    throw std::invalid_argument("tessellation seamTolerance must be in [0, 1]");
  if (options.maxSegmentsPerSpan < 1 || options.maxSegmentsPerSpan > 1024)
    throw std::invalid_argument("tessellation maxSegmentsPerSpan must be in [1, 1024]");
  const int segmentCap = std::bit_floor(static_cast<unsigned>(options.maxSegmentsPerSpan));

  // Patches first: their subdivision depends on their neighbours.
  std::vector<std::vector<BspDrawVert>> controls;  // welded copies of the control points
  std::vector<PatchControlGrid> grids;
  std::vector<PatchSubdivision> subdivisions;
  PointWelder welder(options.weldDistance);
  for (const auto& s : bsp.surfaces) {
    if (s.type != SurfaceType::Patch) continue;
    const auto source = controlGrid(bsp, s).points;
    auto& welded = controls.emplace_back(source.begin(), source.end());
    if (options.stitchPatches && options.weldDistance > 0)
      for (auto& v : welded) v.position = welder.weld(v.position);
  }
  for (size_t k = 0, i = 0; i < bsp.surfaces.size(); ++i) {
    const auto& s = bsp.surfaces[i];
    if (s.type != SurfaceType::Patch) continue;
    grids.push_back({s.patchWidth, s.patchHeight, controls[k++]});
    subdivisions.push_back(requiredSubdivision(grids.back(), options.maxError, segmentCap));
  }
  if (options.stitchPatches) matchSharedPatchEdges(grids, subdivisions);

  size_t totalVertices = 0;
  for (const auto& s : bsp.surfaces)
    if (s.type == SurfaceType::Planar || s.type == SurfaceType::TriangleSoup) totalVertices += s.numVerts;
  for (const auto& sub : subdivisions) totalVertices += patchVertexCount(sub);
  if (totalVertices > options.maxTotalVertices)
    throw FormatError(bsp.fileName, "surfaces",
                      "tessellation needs " + std::to_string(totalVertices) + " vertices, budget is " +
                          std::to_string(options.maxTotalVertices));

  const auto models = surfaceModels(bsp);
  std::vector<SurfaceMesh> meshes;
  meshes.reserve(bsp.surfaces.size());
  size_t nextPatch = 0;
  std::vector<std::pair<size_t, size_t>> patchMeshes;  // (mesh, patch)
  for (size_t i = 0; i < bsp.surfaces.size(); ++i) {
    const auto& s = bsp.surfaces[i];
    if (s.type == SurfaceType::Flare) continue;
    SurfaceMesh mesh;
    mesh.surfaceIndex = static_cast<uint32_t>(i);
    mesh.type = s.type;
    mesh.shader = s.shader;
    mesh.lightmap = s.lightmap;
    mesh.fog = s.fog;
    mesh.model = models[i];
    if (s.type == SurfaceType::Patch) {
      tessellatePatch(grids[nextPatch], subdivisions[nextPatch], mesh);
      if (!mesh.indices.empty()) patchMeshes.emplace_back(meshes.size(), nextPatch);
      ++nextPatch;
    } else {
      copyIndexedSurface(bsp, s, mesh);
    }
    if (!mesh.indices.empty()) meshes.push_back(std::move(mesh));
  }
  if (options.stitchPatches && options.seamTolerance > 0) {
    std::vector<TessellatedPatch> patches;
    for (const auto& [m, p] : patchMeshes) patches.push_back({&grids[p], &subdivisions[p], &meshes[m]});
    std::vector<SurfaceMesh*> faces;
    for (auto& mesh : meshes)
      if (mesh.type == SurfaceType::Planar) faces.push_back(&mesh);
    closePatchSeams(patches, options.seamTolerance, faces);
  }
  return meshes;
}

PatchSeamStats measurePatchSeams(const std::vector<SurfaceMesh>& meshes, float tolerance, float gapLimit) {
  struct Edge {
    glm::vec3 a, b;
    size_t mesh;
    int32_t model;
  };
  struct Point {  // a boundary vertex and the direction of one of its boundary edges
    glm::vec3 p, direction;
    size_t mesh;
    int32_t model;
  };
  std::vector<Edge> edges;
  std::vector<Point> points;
  PointWelder welder(std::max(tolerance, 1e-6f));  // near-equal vertices count as shared
  for (size_t m = 0; m < meshes.size(); ++m) {
    const auto& mesh = meshes[m];
    if (mesh.type != SurfaceType::Patch) continue;
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
      for (int e = 0; e < 3; ++e) {
        const uint32_t a = mesh.indices[t + e], b = mesh.indices[t + (e + 1) % 3];
        ++uses[{std::min(a, b), std::max(a, b)}];
      }
    for (const auto& [edge, count] : uses) {
      if (count != 1) continue;
      const glm::vec3 a = welder.weld(mesh.vertices[edge.first].position);
      const glm::vec3 b = welder.weld(mesh.vertices[edge.second].position);
      const glm::vec3 dir = unitOrZero(b - a);
      edges.push_back({a, b, m, mesh.model});
      points.push_back({a, dir, m, mesh.model});
      points.push_back({b, dir, m, mesh.model});
    }
  }
  PatchSeamStats stats;
  stats.boundaryEdges = edges.size();

  const float reach = std::max(tolerance, gapLimit);
  const float cell = std::max(64.0f, 2 * reach);
  auto cellKey = [](int x, int y, int z) {
    return (static_cast<uint64_t>(x & 0x1fffff) << 42) | (static_cast<uint64_t>(y & 0x1fffff) << 21) |
           static_cast<uint64_t>(z & 0x1fffff);
  };
  auto cellOf = [&](float v) { return static_cast<int>(std::floor(std::clamp(v / cell, -1e6f, 1e6f))); };
  std::unordered_map<uint64_t, std::vector<size_t>> cells;
  for (size_t e = 0; e < edges.size(); ++e) {
    const glm::vec3 lo = glm::min(edges[e].a, edges[e].b) - reach;
    const glm::vec3 hi = glm::max(edges[e].a, edges[e].b) + reach;
    const int x0 = cellOf(lo.x), y0 = cellOf(lo.y), z0 = cellOf(lo.z);
    const int x1 = cellOf(hi.x), y1 = cellOf(hi.y), z1 = cellOf(hi.z);
    if (static_cast<int64_t>(x1 - x0 + 1) * (y1 - y0 + 1) * (z1 - z0 + 1) > 4096) continue;  // absurd edge
    for (int x = x0; x <= x1; ++x)
      for (int y = y0; y <= y1; ++y)
        for (int z = z0; z <= z1; ++z) cells[cellKey(x, y, z)].push_back(e);
  }
  // A crack needs the other edge's two ends on this mesh's boundary without this mesh having
  // that edge itself: both patches follow the same curve between the two vertices but cut it
  // differently. (A boundary that only touches tangentially at one vertex is not a crack.)
  using PointKey = std::tuple<float, float, float>;
  auto key = [](const glm::vec3& p) { return PointKey{p.x, p.y, p.z}; };
  std::set<std::pair<size_t, PointKey>> boundaryVertex;
  std::set<std::tuple<size_t, PointKey, PointKey>> boundaryEdge;
  for (const auto& e : edges) {
    boundaryVertex.insert({e.mesh, key(e.a)});
    boundaryVertex.insert({e.mesh, key(e.b)});
    boundaryEdge.insert({e.mesh, std::min(key(e.a), key(e.b)), std::max(key(e.a), key(e.b))});
  }
  auto followsSameCurve = [&](size_t mesh, const Edge& other) {
    return boundaryVertex.contains({mesh, key(other.a)}) && boundaryVertex.contains({mesh, key(other.b)}) &&
           !boundaryEdge.contains({mesh, std::min(key(other.a), key(other.b)), std::max(key(other.a), key(other.b))});
  };
  // A vertex is counted once per mesh even though two boundary edges list it.
  std::set<std::pair<size_t, PointKey>> counted;
  constexpr float kParallel = 0.985f;  // within 10 degrees
  for (const auto& pt : points) {
    const auto it = cells.find(cellKey(cellOf(pt.p.x), cellOf(pt.p.y), cellOf(pt.p.z)));
    if (it == cells.end()) continue;
    for (size_t e : it->second) {
      const auto& edge = edges[e];
      if (edge.mesh == pt.mesh || edge.model != pt.model) continue;
      const glm::vec3 d = edge.b - edge.a;
      const float len2 = glm::dot(d, d);
      if (len2 <= tolerance * tolerance) continue;
      if (std::abs(glm::dot(pt.direction, d)) < kParallel * std::sqrt(len2)) continue;  // crosses
      const float t = glm::dot(pt.p - edge.a, d) / len2;
      const float len = std::sqrt(len2);
      if (t * len <= tolerance || (1 - t) * len <= tolerance) continue;  // at an endpoint
      const float distance = glm::length(edge.a + t * d - pt.p);
      if (distance > reach) continue;
      if (distance > tolerance && !followsSameCurve(pt.mesh, edge)) continue;
      if (!counted.insert({pt.mesh, key(pt.p)}).second) break;
      if (distance <= tolerance) ++stats.tJunctions;
      else ++stats.cracks;
      break;
    }
  }
  return stats;
}

}  // namespace q3
