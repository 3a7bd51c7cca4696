// Seam closing between patch meshes (see patch_seams.h for the scheme and the error bound).
#include "port/q3formats/bsp/patch_seams.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "port/q3formats/bsp/point_welder.h"

namespace q3 {
namespace {

/// Chord-to-curve distances beyond this are not tessellation error but unrelated geometry.
constexpr float kMaxCurveReach = 16.0f;

/// Bit pattern of a position (-0 folded onto +0): identity of a vertex by where it is.
using PositionKey = std::array<uint32_t, 3>;
PositionKey keyOf(const glm::vec3& p) {
  return {std::bit_cast<uint32_t>(p.x + 0.0f), std::bit_cast<uint32_t>(p.y + 0.0f),
          std::bit_cast<uint32_t>(p.z + 0.0f)};
}
struct PositionKeyHash {
  size_t operator()(const PositionKey& k) const {
    size_t h = 1469598103934665603ull;
    for (uint32_t v : k) h = (h ^ v) * 1099511628211ull;
    return h;
  }
};

/// Edge of triangle `triangle` from its corner `slot` to corner (slot + 1) % 3.
struct TriangleEdge {
  uint32_t triangle;
  uint32_t slot;
};

/// Edges used by exactly one triangle of a grid mesh with `columns` vertices per row, in
/// triangle order. Found by index through the grid (a triangle's edges join grid neighbours:
/// right, down or down-right), then by position among themselves, so that a closed cylinder's
/// seam or the edges beside a collapsed row do not count.
std::vector<TriangleEdge> boundaryEdges(const SurfaceMesh& mesh, uint32_t columns) {
  std::vector<uint8_t> uses(3 * mesh.vertices.size(), 0);  // [3 * lower vertex + direction]
  auto useOf = [&](uint32_t t, uint32_t slot) -> uint8_t* {
    const uint32_t a = mesh.indices[3 * t + slot], b = mesh.indices[3 * t + (slot + 1) % 3];
    const uint32_t lower = std::min(a, b), step = std::max(a, b) - lower;
    const int direction = step == 1 ? 0 : step == columns ? 1 : step == columns + 1 ? 2 : -1;
    return direction < 0 ? nullptr : &uses[3 * size_t{lower} + direction];
  };
  const uint32_t triangles = static_cast<uint32_t>(mesh.indices.size() / 3);
  for (uint32_t t = 0; t < triangles; ++t)
    for (uint32_t slot = 0; slot < 3; ++slot)
      if (uint8_t* use = useOf(t, slot); use && *use < 2) ++*use;
  struct Candidate {
    PositionKey lo, hi;
    TriangleEdge edge;
  };
  std::vector<Candidate> candidates;
  for (uint32_t t = 0; t < triangles; ++t)
    for (uint32_t slot = 0; slot < 3; ++slot)
      if (const uint8_t* use = useOf(t, slot); use && *use == 1) {
        const auto a = keyOf(mesh.vertices[mesh.indices[3 * t + slot]].position);
        const auto b = keyOf(mesh.vertices[mesh.indices[3 * t + (slot + 1) % 3]].position);
        candidates.push_back({std::min(a, b), std::max(a, b), {t, slot}});
      }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& x, const Candidate& y) { return std::tie(x.lo, x.hi) < std::tie(y.lo, y.hi); });
  std::vector<TriangleEdge> out;
  for (size_t k = 0; k < candidates.size(); ++k) {
    const bool samePrevious = k > 0 && candidates[k - 1].lo == candidates[k].lo && candidates[k - 1].hi == candidates[k].hi;
    const bool sameNext = k + 1 < candidates.size() && candidates[k + 1].lo == candidates[k].lo &&
                          candidates[k + 1].hi == candidates[k].hi;
    if (!samePrevious && !sameNext) out.push_back(candidates[k].edge);
  }
  std::sort(out.begin(), out.end(), [](const TriangleEdge& x, const TriangleEdge& y) {
    return std::pair(x.triangle, x.slot) < std::pair(y.triangle, y.slot);
  });
  return out;
}

/// Removes triangles with two corners at the same position; returns how many.
size_t dropDegenerateTriangles(SurfaceMesh& mesh) {
  size_t kept = 0;
  const size_t triangles = mesh.indices.size() / 3;
  for (size_t t = 0; t < triangles; ++t) {
    const glm::vec3& a = mesh.vertices[mesh.indices[3 * t]].position;
    const glm::vec3& b = mesh.vertices[mesh.indices[3 * t + 1]].position;
    const glm::vec3& c = mesh.vertices[mesh.indices[3 * t + 2]].position;
    if (a == b || b == c || a == c) continue;
    for (int k = 0; k < 3; ++k) mesh.indices[3 * kept + k] = mesh.indices[3 * t + k];
    ++kept;
  }
  mesh.indices.resize(3 * kept);
  return triangles - kept;
}

/// Patch parameters of every grid vertex of one tessellated patch, and its orientation.
struct PatchFrame {
  std::vector<glm::vec2> parameters;  ///< per grid vertex
  uint32_t columns = 0;               ///< grid vertices per row
  bool flipped = false;               ///< mesh normals are -(S_u x S_v)
};

/// Whether the mesh still is tessellatePatch's grid; fills its parameters and orientation.
bool describeGrid(const TessellatedPatch& patch, PatchFrame& frame) {
  if (!patch.grid || !patch.subdivision || !patch.mesh) return false;
  const PatchControlGrid& grid = *patch.grid;
  if (grid.spansU() < 1 || grid.spansV() < 1 || grid.points.size() < static_cast<size_t>(grid.width) * grid.height ||
      patch.subdivision->uSegments.size() != static_cast<size_t>(grid.spansU()) ||
      patch.subdivision->vSegments.size() != static_cast<size_t>(grid.spansV()))
    return false;
  const auto us = patchGridParameters(patch.subdivision->uSegments);
  const auto vs = patchGridParameters(patch.subdivision->vSegments);
  const auto& mesh = *patch.mesh;
  if (mesh.vertices.size() != us.size() * vs.size()) return false;
  frame.columns = static_cast<uint32_t>(us.size());
  frame.parameters.clear();
  frame.parameters.reserve(mesh.vertices.size());
  for (float v : vs)
    for (float u : us) frame.parameters.emplace_back(u, v);
  for (uint32_t i : mesh.indices)
    if (i >= mesh.vertices.size()) return false;
  for (size_t k = 0; k < mesh.vertices.size(); ++k) {
    const glm::vec3 analytic = evaluatePatchVertex(*patch.grid, frame.parameters[k].x, frame.parameters[k].y).normal;
    if (analytic == glm::vec3(0)) continue;
    frame.flipped = glm::dot(analytic, mesh.vertices[k].normal) < 0;
    break;
  }
  return true;
}

/// A boundary edge of one patch, ready for queries.
struct SeamEdge {
  uint32_t patch;
  TriangleEdge edge;
  glm::vec3 a, b;       ///< end positions
  glm::vec2 pa, pb;     ///< end parameters
  float reach;          ///< how far from the chord the boundary curve (plus tolerance) can be
};

/// A vertex to insert into edge `edge` of a patch at fraction t (parameter space) of it.
struct Insertion {
  TriangleEdge edge;
  float t;
  glm::vec3 position;
};

/// Boundary vertices of all patches, each position once per model, for segment queries.
class PointGrid {
 public:
  PointGrid(float cell, size_t expectedPoints) : cells_(cell, expectedPoints), cell_(cell) {
    lastQuery_.reserve(expectedPoints);
  }

  void add(int32_t model, const glm::vec3& p) {
    modelPoints_[model].push_back(cells_.add(p, model));
    lastQuery_.push_back(0);
  }
  /// Every point within `reach` of the segment (a, b), and some farther ones, each once.
  void near(int32_t model, const glm::vec3& a, const glm::vec3& b, float reach, std::vector<glm::vec3>& out) {
    out.clear();
    ++query_;
    auto collect = [&](const PointCells::Cell& lo, const PointCells::Cell& hi) {
      cells_.forEachIn(model, lo, hi, [&](uint32_t id) {
        if (lastQuery_[id] == query_) return;
        lastQuery_[id] = query_;
        out.push_back(cells_.point(id));
      });
    };
    const auto lo = cells_.cellOf(glm::min(a, b) - reach), hi = cells_.cellOf(glm::max(a, b) + reach);
    const double boxCells = static_cast<double>(hi[0] - lo[0] + 1) * static_cast<double>(hi[1] - lo[1] + 1) *
                            static_cast<double>(hi[2] - lo[2] + 1);
    if (boxCells <= 64) {
      collect(lo, hi);
      return;
    }
    // A long slanted edge: boxes around samples one cell apart (each point within reach of the
    // segment is within reach + cell/2 of a sample).
    const float radius = reach + 0.5f * cell_;
    const int samples = static_cast<int>(std::min(std::ceil(glm::distance(a, b) / cell_), 1e6f));
    // A walk of more than kMaxWalkCells cell reads (hostile patches with far-apart control points
    // made edges of a million samples) tests the model's points directly when they are fewer, so
    // a query costs at most max(kMaxWalkCells, model points). The 85 OpenArena maps need at most
    // 18,684 reads a query, so they keep the walk and its results.
    const double sampleCells = std::pow(std::ceil(2.0 * static_cast<double>(radius) / cell_) + 1.0, 3.0);
    const double walkCells = static_cast<double>(samples + 1) * sampleCells;
    const auto found = modelPoints_.find(model);
    if (found == modelPoints_.end()) return;
    if (walkCells > kMaxWalkCells && static_cast<double>(found->second.size()) < walkCells) {
      const glm::vec3 d = b - a;
      const float length2 = glm::dot(d, d);
      for (uint32_t id : found->second) {
        const glm::vec3& p = cells_.point(id);
        const float along = length2 > 0 ? std::clamp(glm::dot(p - a, d) / length2, 0.0f, 1.0f) : 0.0f;
        if (glm::distance(a + along * d, p) <= radius) out.push_back(p);
      }
      return;
    }
    for (int k = 0; k <= samples; ++k) {
      const glm::vec3 s = a + (b - a) * (static_cast<float>(k) / static_cast<float>(samples));
      collect(cells_.cellOf(s - radius), cells_.cellOf(s + radius));
    }
  }

 private:
  PointCells cells_;
  float cell_;
  std::vector<uint64_t> lastQuery_;  ///< per point: the last query that reported it
  std::unordered_map<int32_t, std::vector<uint32_t>> modelPoints_;  ///< point ids of each model
  static constexpr double kMaxWalkCells = 65536;
  uint64_t query_ = 0;
};

/// Fraction t in [0, 1] along the edge's parameter segment where the surface comes closest to
/// `target` (Gauss-Newton from `start`), and that distance.
std::pair<float, float> closestOnEdgeCurve(const PatchControlGrid& grid, const SeamEdge& e, const glm::vec3& target,
                                           float start) {
  auto curve = [&](float t) {
    const glm::vec2 p = e.pa + std::clamp(t, 0.0f, 1.0f) * (e.pb - e.pa);
    return evaluatePatchPosition(grid, p.x, p.y);
  };
  float t = start;
  constexpr float h = 1.0f / 4096;
  for (int iteration = 0; iteration < 16; ++iteration) {
    const glm::vec3 tangent = (curve(t + h) - curve(t - h)) / (std::min(t + h, 1.0f) - std::max(t - h, 0.0f));
    const float tangent2 = glm::dot(tangent, tangent);
    if (!(tangent2 > 1e-12f)) break;
    const float step = glm::dot(target - curve(t), tangent) / tangent2;
    t = std::clamp(t + step, 0.0f, 1.0f);
    if (!(std::abs(step) > 1e-7f)) break;
  }
  return {t, glm::distance(curve(t), target)};
}

/// Surface vertex at parameter p of the patch with its position replaced, normal oriented.
MeshVertex surfaceVertex(const PatchControlGrid& grid, glm::vec2 p, bool flipped, const glm::vec3& fallbackNormal) {
  MeshVertex v = evaluatePatchVertex(grid, p.x, p.y);
  if (v.normal == glm::vec3(0)) v.normal = fallbackNormal;
  else if (flipped) v.normal = -v.normal;
  return v;
}

/// Splits the triangles of `mesh` named in `insertions`; returns the number of triangles split.
/// edgeVertex(corner, nextCorner, t) makes the vertex at fraction t of an edge (its position is
/// then replaced by the inserted one); centerVertex(corners) the vertex at a triangle's middle.
template <class EdgeVertex, class CenterVertex>
size_t splitTriangles(SurfaceMesh& mesh, std::vector<Insertion>& insertions, EdgeVertex&& edgeVertex,
                      CenterVertex&& centerVertex, PatchSeamRepair& repair) {
  std::sort(insertions.begin(), insertions.end(), [](const Insertion& x, const Insertion& y) {
    return std::tuple(x.edge.triangle, x.edge.slot, x.t) < std::tuple(y.edge.triangle, y.edge.slot, y.t);
  });
  size_t split = 0;
  for (size_t first = 0; first < insertions.size();) {
    const uint32_t triangle = insertions[first].edge.triangle;
    size_t last = first;
    while (last < insertions.size() && insertions[last].edge.triangle == triangle) ++last;
    const std::array<uint32_t, 3> corner = {mesh.indices[3 * triangle], mesh.indices[3 * triangle + 1],
                                            mesh.indices[3 * triangle + 2]};

    // The triangle's outline with the new vertices in order, and which slots got any.
    std::vector<uint32_t> outline;
    int slotsUsed = 0, usedSlot = 0;
    for (uint32_t slot = 0, k = first; slot < 3; ++slot) {
      outline.push_back(corner[slot]);
      bool any = false;
      for (; k < last && insertions[k].edge.slot == slot; ++k) {
        if (any && insertions[k].position == mesh.vertices[outline.back()].position) continue;
        MeshVertex v = edgeVertex(corner[slot], corner[(slot + 1) % 3], insertions[k].t);
        v.position = insertions[k].position;
        outline.push_back(static_cast<uint32_t>(mesh.vertices.size()));
        mesh.vertices.push_back(v);
        ++repair.insertedVertices;
        any = true;
      }
      if (any) ++slotsUsed, usedSlot = static_cast<int>(slot);
    }

    std::vector<std::array<uint32_t, 3>> fan;
    if (slotsUsed == 1) {
      // Fan from the corner opposite the split edge; the cyclic order keeps the winding.
      const size_t n = outline.size();
      const auto start = std::find(outline.begin(), outline.end(), corner[usedSlot]) - outline.begin();
      const uint32_t apex = corner[(usedSlot + 2) % 3];
      for (size_t k = 0; k + 2 < n; ++k) fan.push_back({apex, outline[(start + k) % n], outline[(start + k + 1) % n]});
    } else {
      // Several edges split: fan around a new vertex in the triangle's middle.
      const uint32_t center = static_cast<uint32_t>(mesh.vertices.size());
      mesh.vertices.push_back(centerVertex(corner));
      for (size_t k = 0; k < outline.size(); ++k) fan.push_back({center, outline[k], outline[(k + 1) % outline.size()]});
    }
    for (size_t k = 0; k < fan.size(); ++k) {
      if (k == 0) std::copy(fan[k].begin(), fan[k].end(), mesh.indices.begin() + 3 * triangle);
      else mesh.indices.insert(mesh.indices.end(), fan[k].begin(), fan[k].end());
    }
    repair.addedTriangles += fan.size() - 1;
    ++split;
    first = last;
  }
  return split;
}

/// Splits patch triangles: new vertices are the patch's own surface at their parameters.
size_t splitPatchTriangles(const TessellatedPatch& patch, const PatchFrame& frame, std::vector<Insertion>& insertions,
                           PatchSeamRepair& repair) {
  auto& mesh = *patch.mesh;
  auto fallbackNormal = [&](uint32_t a, uint32_t b, uint32_t c) {
    const glm::vec3 sum = mesh.vertices[a].normal + mesh.vertices[b].normal + mesh.vertices[c].normal;
    const float length = glm::length(sum);
    return length > 1e-6f ? sum / length : mesh.vertices[a].normal;
  };
  auto edgeVertex = [&](uint32_t a, uint32_t b, float t) {
    const glm::vec2 p = frame.parameters[a] + t * (frame.parameters[b] - frame.parameters[a]);
    return surfaceVertex(*patch.grid, p, frame.flipped, fallbackNormal(a, b, a));
  };
  auto centerVertex = [&](const std::array<uint32_t, 3>& c) {
    const glm::vec2 p = (frame.parameters[c[0]] + frame.parameters[c[1]] + frame.parameters[c[2]]) / 3.0f;
    return surfaceVertex(*patch.grid, p, frame.flipped, fallbackNormal(c[0], c[1], c[2]));
  };
  return splitTriangles(mesh, insertions, edgeVertex, centerVertex, repair);
}

/// Vertex attributes blended linearly (planar faces); the normal is renormalised.
MeshVertex blendVertices(const MeshVertex* v[3], const float w[3]) {
  MeshVertex out;
  glm::vec4 color(0);
  for (int k = 0; k < 3; ++k) {
    out.position += w[k] * v[k]->position;
    out.normal += w[k] * v[k]->normal;
    out.uv += w[k] * v[k]->uv;
    out.lightmapUv += w[k] * v[k]->lightmapUv;
    color += w[k] * glm::vec4(v[k]->color[0], v[k]->color[1], v[k]->color[2], v[k]->color[3]);
  }
  const float length = glm::length(out.normal);
  out.normal = length > 1e-6f ? out.normal / length : v[0]->normal;
  for (int c = 0; c < 4; ++c) out.color[c] = static_cast<uint8_t>(std::clamp(std::round(color[c]), 0.0f, 255.0f));
  return out;
}

/// Splits planar-face triangles: new vertices interpolate their edge (or corners) linearly.
size_t splitFaceTriangles(SurfaceMesh& mesh, std::vector<Insertion>& insertions, PatchSeamRepair& repair) {
  auto edgeVertex = [&](uint32_t a, uint32_t b, float t) {
    const MeshVertex* v[3] = {&mesh.vertices[a], &mesh.vertices[b], &mesh.vertices[b]};
    const float w[3] = {1 - t, t, 0};
    return blendVertices(v, w);
  };
  auto centerVertex = [&](const std::array<uint32_t, 3>& c) {
    const MeshVertex* v[3] = {&mesh.vertices[c[0]], &mesh.vertices[c[1]], &mesh.vertices[c[2]]};
    const float w[3] = {1.0f / 3, 1.0f / 3, 1.0f / 3};
    return blendVertices(v, w);
  };
  return splitTriangles(mesh, insertions, edgeVertex, centerVertex, repair);
}

/// Edges of an arbitrary triangle mesh used by one triangle (vertices compared by position).
std::vector<TriangleEdge> meshBoundaryEdges(const SurfaceMesh& mesh) {
  struct Use {
    PositionKey lo, hi;
    TriangleEdge edge;
  };
  std::vector<Use> uses;
  const uint32_t triangles = static_cast<uint32_t>(mesh.indices.size() / 3);
  for (uint32_t t = 0; t < triangles; ++t)
    for (uint32_t slot = 0; slot < 3; ++slot) {
      const uint32_t ia = mesh.indices[3 * t + slot], ib = mesh.indices[3 * t + (slot + 1) % 3];
      if (ia >= mesh.vertices.size() || ib >= mesh.vertices.size()) return {};
      const auto a = keyOf(mesh.vertices[ia].position), b = keyOf(mesh.vertices[ib].position);
      if (a == b) continue;
      uses.push_back({std::min(a, b), std::max(a, b), {t, slot}});
    }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) { return std::tie(x.lo, x.hi) < std::tie(y.lo, y.hi); });
  std::vector<TriangleEdge> out;
  for (size_t k = 0; k < uses.size(); ++k) {
    const bool samePrevious = k > 0 && uses[k - 1].lo == uses[k].lo && uses[k - 1].hi == uses[k].hi;
    const bool sameNext = k + 1 < uses.size() && uses[k + 1].lo == uses[k].lo && uses[k + 1].hi == uses[k].hi;
    if (!samePrevious && !sameNext) out.push_back(uses[k].edge);
  }
  return out;
}

}  // namespace

PatchSeamRepair closePatchSeams(std::span<const TessellatedPatch> patches, float tolerance,
                                std::span<SurfaceMesh* const> faces) {
  PatchSeamRepair repair;
  if (!(tolerance > 0) || !std::isfinite(tolerance)) return repair;
  std::vector<PatchFrame> frames(patches.size());
  std::vector<bool> usable(patches.size());
  for (size_t p = 0; p < patches.size(); ++p) usable[p] = describeGrid(patches[p], frames[p]);

  size_t boundaryEstimate = 0;  // grid vertices on the outline of every patch
  for (const auto& frame : frames)
    if (frame.columns > 0) boundaryEstimate += 2 * (frame.columns + frame.parameters.size() / frame.columns);

  // 0. Planar faces are fixed geometry: their boundary vertices come first in the welders, so
  //    patch vertices within tolerance snap onto them. (They are not inserted into patch edges:
  //    at pinched patches that folds triangles over, +250 on the OpenArena maps.)
  std::map<int32_t, PointWelder> welders;
  std::vector<std::vector<TriangleEdge>> faceBoundaries(faces.size());
  std::vector<uint8_t> seen;
  for (size_t f = 0; f < faces.size(); ++f) {
    if (!faces[f]) continue;
    const auto& mesh = *faces[f];
    faceBoundaries[f] = meshBoundaryEdges(mesh);
    auto& welder = welders.try_emplace(mesh.model, tolerance, mesh.model == 0 ? boundaryEstimate : 0).first->second;
    seen.assign(mesh.vertices.size(), 0);
    for (const auto& e : faceBoundaries[f])
      for (uint32_t corner : {e.slot, (e.slot + 1) % 3}) {
        const uint32_t k = mesh.indices[3 * e.triangle + corner];
        if (seen[k]) continue;
        seen[k] = 1;
        welder.weld(mesh.vertices[k].position);
      }
  }

  // 1. Per patch: weld its boundary vertices onto those of patches before it (same model), then
  //    list its boundary edges, with how far their curve strays from the chord, and vertices.
  std::vector<SeamEdge> edges;
  edges.reserve(boundaryEstimate);
  std::vector<std::pair<glm::vec3, int32_t>> boundaryPoints;  // (position, model), once per patch
  boundaryPoints.reserve(boundaryEstimate);
  double totalLength = 0;
  float meanReach = 0;
  for (size_t p = 0; p < patches.size(); ++p) {
    if (!usable[p]) continue;
    auto& mesh = *patches[p].mesh;
    auto& welder = welders.try_emplace(mesh.model, tolerance, mesh.model == 0 ? boundaryEstimate : 0).first->second;
    // welder.weld is a function of the position, so coincident vertices stay coincident.
    auto boundary = boundaryEdges(mesh, frames[p].columns);
    seen.assign(mesh.vertices.size(), 0);
    bool moved = false;
    for (const auto& e : boundary)
      for (uint32_t corner : {e.slot, (e.slot + 1) % 3}) {
        const uint32_t k = mesh.indices[3 * e.triangle + corner];
        if (seen[k]) continue;
        seen[k] = 1;
        glm::vec3& position = mesh.vertices[k].position;
        const glm::vec3 welded = welder.weld(position);
        if (welded == position) continue;
        position = welded;
        moved = true;
        ++repair.weldedVertices;
      }
    if (moved) {  // welding may have closed triangles or made two boundary edges coincide
      repair.droppedTriangles += dropDegenerateTriangles(mesh);
      boundary = boundaryEdges(mesh, frames[p].columns);
    }
    seen.assign(mesh.vertices.size(), 0);
    for (const auto& te : boundary) {
      const uint32_t ia = mesh.indices[3 * te.triangle + te.slot], ib = mesh.indices[3 * te.triangle + (te.slot + 1) % 3];
      for (uint32_t k : {ia, ib})
        if (!seen[k]) {
          seen[k] = 1;
          boundaryPoints.emplace_back(mesh.vertices[k].position, mesh.model);
        }
      SeamEdge e{static_cast<uint32_t>(p), te, mesh.vertices[ia].position, mesh.vertices[ib].position,
                 frames[p].parameters[ia], frames[p].parameters[ib], 0};
      const glm::vec2 mid = 0.5f * (e.pa + e.pb);
      const float deviation = 0.5f * glm::length(e.a + e.b - 2.0f * evaluatePatchPosition(*patches[p].grid, mid.x, mid.y));
      if (!(deviation <= kMaxCurveReach)) continue;
      // Exact for the sides (quadratic curves); a margin for diagonals (collapsed rows).
      const bool side = e.pa.x == e.pb.x || e.pa.y == e.pb.y;
      e.reach = 2 * tolerance + (side ? 1.0f : 2.0f) * deviation;
      meanReach += e.reach;
      totalLength += glm::distance(e.a, e.b);
      edges.push_back(e);
    }
  }
  if (edges.empty()) return repair;
  meanReach /= static_cast<float>(edges.size());
  // Cells of twice the mean edge length and reach: a typical query reads a few cells.
  const float cellSize =
      std::max(static_cast<float>(2 * totalLength / static_cast<double>(edges.size())) + 2 * meanReach, 1e-3f);
  PointGrid points(cellSize, boundaryPoints.size());
  for (const auto& [position, model] : boundaryPoints) points.add(model, position);

  // 3. Boundary points lying on a boundary's curve, strictly inside an edge. (A patch's own
  // vertex qualifies only where its surface folds into a sliver thinner than the tolerance; the
  // sliver then closes into degenerate triangles, dropped below.)
  std::vector<std::vector<Insertion>> insertions(patches.size());
  std::vector<glm::vec3> candidates;
  for (const auto& e : edges) {
    const glm::vec3 d = e.b - e.a;
    const float length2 = glm::dot(d, d);
    if (!(length2 > 4 * tolerance * tolerance)) continue;
    const auto& mesh = *patches[e.patch].mesh;
    points.near(mesh.model, e.a, e.b, e.reach, candidates);
    for (const glm::vec3& v : candidates) {
      if (glm::distance(v, e.a) <= tolerance || glm::distance(v, e.b) <= tolerance) continue;
      const float along = glm::dot(v - e.a, d) / length2;
      if (!(along > 0 && along < 1) || glm::distance(e.a + along * d, v) > e.reach) continue;
      const auto [t, distance] = closestOnEdgeCurve(*patches[e.patch].grid, e, v, along);
      if (distance <= tolerance && t > 0 && t < 1) insertions[e.patch].push_back({e.edge, t, v});
    }
  }

  // 3b. Patch boundary points lying on a planar face's boundary edge (straight), strictly inside.
  std::vector<std::vector<Insertion>> faceInsertions(faces.size());
  {
    for (size_t f = 0; f < faces.size(); ++f)
      for (const auto& te : faceBoundaries[f]) {
        const auto& mesh = *faces[f];
        const glm::vec3 a = mesh.vertices[mesh.indices[3 * te.triangle + te.slot]].position;
        const glm::vec3 b = mesh.vertices[mesh.indices[3 * te.triangle + (te.slot + 1) % 3]].position;
        const glm::vec3 d = b - a;
        const float length2 = glm::dot(d, d);
        if (!(length2 > 4 * tolerance * tolerance)) continue;
        points.near(mesh.model, a, b, tolerance, candidates);
        for (const glm::vec3& v : candidates) {
          if (glm::distance(v, a) <= tolerance || glm::distance(v, b) <= tolerance) continue;
          const float along = glm::dot(v - a, d) / length2;
          if (along > 0 && along < 1 && glm::distance(a + along * d, v) <= tolerance)
            faceInsertions[f].push_back({te, along, v});
        }
      }
  }

  // 4. Split the triangles of those edges.
  for (size_t p = 0; p < patches.size(); ++p) {
    if (insertions[p].empty()) continue;
    repair.splitTriangles += splitPatchTriangles(patches[p], frames[p], insertions[p], repair);
    repair.droppedTriangles += dropDegenerateTriangles(*patches[p].mesh);
  }
  for (size_t f = 0; f < faces.size(); ++f) {
    if (faceInsertions[f].empty()) continue;
    repair.splitTriangles += splitFaceTriangles(*faces[f], faceInsertions[f], repair);
    repair.droppedTriangles += dropDegenerateTriangles(*faces[f]);
  }
  return repair;
}

}  // namespace q3
