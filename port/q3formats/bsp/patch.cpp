// Bezier patch tessellation (see patch.h for the scheme). This file is compiled with
// -ffp-contract=off: shared edges are bit-identical only if no multiply-add is fused.
#include "port/q3formats/bsp/patch.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

namespace q3 {
namespace {

/// Bernstein weights of a quadratic at t. The middle weight is (2t)(1-t) and 1 - (1 - t) == t
/// for the dyadic parameters we use, so evaluating a curve backwards gives the same weights.
struct QuadWeights {
  float w0, w1, w2;
};
QuadWeights bernstein(float t) {
  const float s = 1.0f - t;
  return {s * s, (2.0f * t) * s, t * t};
}
QuadWeights bernsteinDerivative(float t) { return {-2.0f * (1.0f - t), 2.0f - 4.0f * t, 2.0f * t}; }

/// Symmetric evaluation order: the two end terms first, so (p0, p1, p2) at t and
/// (p2, p1, p0) at 1 - t round identically.
template <class T>
T blend(const T& p0, const T& p1, const T& p2, const QuadWeights& w) {
  return (w.w0 * p0 + w.w2 * p2) + w.w1 * p1;
}

/// Second differences of one piece's control net, as maxima of the surface derivatives.
struct PieceCurvature {
  float maxUU = 0, maxVV = 0, maxUV = 0;
};
PieceCurvature pieceCurvature(const PatchControlGrid& grid, int i, int j) {
  auto p = [&](int a, int b) { return grid.at(2 * i + a, 2 * j + b).position; };
  PieceCurvature c;
  for (int k = 0; k < 3; ++k) {
    c.maxUU = std::max(c.maxUU, glm::length(p(0, k) - 2.0f * p(1, k) + p(2, k)));
    c.maxVV = std::max(c.maxVV, glm::length(p(k, 0) - 2.0f * p(k, 1) + p(k, 2)));
  }
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      c.maxUV = std::max(c.maxUV, glm::length(p(a + 1, b + 1) - p(a, b + 1) - p(a + 1, b) + p(a, b)));
  // |S_uu| <= 2 max|second difference|, |S_vv| likewise, |S_uv| <= 4 max|twist|.
  c.maxUU *= 2;
  c.maxVV *= 2;
  c.maxUV *= 4;
  return c;
}

/// Bilinear interpolation error (h^2/8 per direction) plus the split of the bilinear cell
/// into two triangles (hu*hv/4 times the twist); parameters per piece span [0, 1].
float errorBound(const PieceCurvature& c, int nu, int nv) {
  const float hu = 1.0f / static_cast<float>(nu), hv = 1.0f / static_cast<float>(nv);
  return c.maxUU * hu * hu / 8 + c.maxVV * hv * hv / 8 + c.maxUV * hu * hv / 4;
}

/// Boundary curve identity: the three control positions, in a canonical direction.
using EdgeKey = std::array<uint32_t, 9>;
struct EdgeKeyHash {
  size_t operator()(const EdgeKey& k) const {
    size_t h = 1469598103934665603ull;
    for (uint32_t v : k) h = (h ^ v) * 1099511628211ull;
    return h;
  }
};
bool makeEdgeKey(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, EdgeKey& key) {
  if (p0 == p1 && p1 == p2) return false;  // collapsed edge (cone tip): nothing to stitch
  EdgeKey forward{}, backward{};
  const glm::vec3 pts[3] = {p0, p1, p2};
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) {
      forward[k * 3 + c] = std::bit_cast<uint32_t>(pts[k][c] + 0.0f);  // -0 -> +0
      backward[k * 3 + c] = std::bit_cast<uint32_t>(pts[2 - k][c] + 0.0f);
    }
  key = std::min(forward, backward);
  return true;
}

int findRoot(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

/// Parameters of grid lines along one direction: (span, t) with t = k / segments.
std::vector<std::pair<int, float>> gridLines(const std::vector<int>& segments) {
  std::vector<std::pair<int, float>> lines;
  for (size_t span = 0; span < segments.size(); ++span)
    for (int k = 0; k < segments[span]; ++k)
      lines.emplace_back(static_cast<int>(span), static_cast<float>(k) / static_cast<float>(segments[span]));
  lines.emplace_back(static_cast<int>(segments.size()) - 1, 1.0f);
  return lines;
}

/// Every attribute of the surface at (t, s) in piece (i, j); the normal is the unit analytic
/// S_u x S_v (zero where it vanishes), `stored` the interpolated file normal (not normalised).
MeshVertex evaluatePieceVertex(const PatchControlGrid& grid, int i, float t, int j, float s, glm::vec3& stored) {
  const auto wu = bernstein(t), du = bernsteinDerivative(t);
  const auto wv = bernstein(s), dv = bernsteinDerivative(s);
  glm::vec3 pos[3], dpos[3], nrm[3];
  glm::vec2 st[3], lm[3];
  glm::vec4 col[3];
  auto rgba = [](const BspDrawVert& d) { return glm::vec4(d.color[0], d.color[1], d.color[2], d.color[3]); };
  for (int b = 0; b < 3; ++b) {
    const auto& c0 = grid.at(2 * i, 2 * j + b);
    const auto& c1 = grid.at(2 * i + 1, 2 * j + b);
    const auto& c2 = grid.at(2 * i + 2, 2 * j + b);
    pos[b] = blend(c0.position, c1.position, c2.position, wu);
    dpos[b] = blend(c0.position, c1.position, c2.position, du);
    nrm[b] = blend(c0.normal, c1.normal, c2.normal, wu);
    st[b] = blend(c0.st, c1.st, c2.st, wu);
    lm[b] = blend(c0.lightmap, c1.lightmap, c2.lightmap, wu);
    col[b] = blend(rgba(c0), rgba(c1), rgba(c2), wu);
  }
  MeshVertex vertex;
  vertex.position = blend(pos[0], pos[1], pos[2], wv);
  vertex.uv = blend(st[0], st[1], st[2], wv);
  vertex.lightmapUv = blend(lm[0], lm[1], lm[2], wv);
  const glm::vec4 color = blend(col[0], col[1], col[2], wv);
  for (int k = 0; k < 4; ++k)
    vertex.color[k] = static_cast<uint8_t>(std::clamp(std::round(color[k]), 0.0f, 255.0f));
  const glm::vec3 analytic = glm::cross(blend(dpos[0], dpos[1], dpos[2], wv), blend(pos[0], pos[1], pos[2], dv));
  const float len = glm::length(analytic);
  vertex.normal = (len > 1e-6f && std::isfinite(len)) ? analytic / len : glm::vec3(0);
  stored = blend(nrm[0], nrm[1], nrm[2], wv);
  return vertex;
}

/// Piece index and local parameter of a patch parameter in [0, spans].
std::pair<int, float> pieceOf(float x, int spans) {
  const int i = std::clamp(static_cast<int>(std::floor(x)), 0, spans - 1);
  return {i, x - static_cast<float>(i)};
}

}  // namespace

float patchPieceErrorBound(const PatchControlGrid& grid, int i, int j, int nu, int nv) {
  return errorBound(pieceCurvature(grid, i, j), nu, nv);
}

PatchSubdivision requiredSubdivision(const PatchControlGrid& grid, float maxError, int maxSegmentsPerSpan) {
  PatchSubdivision sub;
  sub.uSegments.assign(grid.spansU(), 1);
  sub.vSegments.assign(grid.spansV(), 1);
  const int cap = std::max(1, maxSegmentsPerSpan);
  for (int j = 0; j < grid.spansV(); ++j)
    for (int i = 0; i < grid.spansU(); ++i) {
      const auto curvature = pieceCurvature(grid, i, j);
      int nu = 1, nv = 1;
      // Greedy: double the direction whose refinement lowers the bound most.
      while (errorBound(curvature, nu, nv) > maxError) {
        const float inf = std::numeric_limits<float>::infinity();
        const float eu = nu * 2 <= cap ? errorBound(curvature, nu * 2, nv) : inf;
        const float ev = nv * 2 <= cap ? errorBound(curvature, nu, nv * 2) : inf;
        if (eu == inf && ev == inf) break;
        if (eu <= ev) nu *= 2;
        else nv *= 2;
      }
      sub.uSegments[i] = std::max(sub.uSegments[i], nu);
      sub.vSegments[j] = std::max(sub.vSegments[j], nv);
    }
  return sub;
}

void matchSharedPatchEdges(std::span<const PatchControlGrid> grids, std::span<PatchSubdivision> subdivisions) {
  // One variable per span column and span row of every patch; boundary curves with the same
  // key unite their variables; each group takes its largest segment count.
  std::vector<int> firstU(grids.size()), firstV(grids.size());
  int count = 0;
  for (size_t p = 0; p < grids.size(); ++p) {
    firstU[p] = count;
    count += grids[p].spansU();
    firstV[p] = count;
    count += grids[p].spansV();
  }
  std::vector<int> parent(count);
  std::iota(parent.begin(), parent.end(), 0);
  std::unordered_map<EdgeKey, int, EdgeKeyHash> owner;
  auto visit = [&](const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, int variable) {
    EdgeKey key;
    if (!makeEdgeKey(a, b, c, key)) return;
    const auto [it, inserted] = owner.emplace(key, variable);
    if (!inserted) parent[findRoot(parent, variable)] = findRoot(parent, it->second);
  };
  for (size_t p = 0; p < grids.size(); ++p) {
    const auto& g = grids[p];
    for (int i = 0; i < g.spansU(); ++i)
      for (int row : {0, g.height - 1})
        visit(g.at(2 * i, row).position, g.at(2 * i + 1, row).position, g.at(2 * i + 2, row).position,
              firstU[p] + i);
    for (int j = 0; j < g.spansV(); ++j)
      for (int col : {0, g.width - 1})
        visit(g.at(col, 2 * j).position, g.at(col, 2 * j + 1).position, g.at(col, 2 * j + 2).position,
              firstV[p] + j);
  }
  std::vector<int> groupMax(count, 1);
  auto segmentsOf = [&](size_t p, int variable) -> int& {
    return variable < firstV[p] ? subdivisions[p].uSegments[variable - firstU[p]]
                                : subdivisions[p].vSegments[variable - firstV[p]];
  };
  for (int pass = 0; pass < 2; ++pass)
    for (size_t p = 0; p < grids.size(); ++p)
      for (int v = firstU[p]; v < firstU[p] + grids[p].spansU() + grids[p].spansV(); ++v) {
        int& segments = segmentsOf(p, v);
        int& group = groupMax[findRoot(parent, v)];
        if (pass == 0) group = std::max(group, segments);
        else segments = group;
      }
}

glm::vec3 evaluatePatchPosition(const PatchControlGrid& grid, float u, float v) {
  const auto [i, t] = pieceOf(u, grid.spansU());
  const auto [j, s] = pieceOf(v, grid.spansV());
  const auto wu = bernstein(t), wv = bernstein(s);
  glm::vec3 rows[3];
  for (int b = 0; b < 3; ++b)
    rows[b] = blend(grid.at(2 * i, 2 * j + b).position, grid.at(2 * i + 1, 2 * j + b).position,
                    grid.at(2 * i + 2, 2 * j + b).position, wu);
  return blend(rows[0], rows[1], rows[2], wv);
}

MeshVertex evaluatePatchVertex(const PatchControlGrid& grid, float u, float v, glm::vec3* storedNormal) {
  const auto [i, t] = pieceOf(u, grid.spansU());
  const auto [j, s] = pieceOf(v, grid.spansV());
  glm::vec3 stored;
  MeshVertex vertex = evaluatePieceVertex(grid, i, t, j, s, stored);
  if (storedNormal) *storedNormal = stored;
  return vertex;
}

std::vector<float> patchGridParameters(const std::vector<int>& segments) {
  std::vector<float> out;
  for (const auto& [span, t] : gridLines(segments)) out.push_back(static_cast<float>(span) + t);
  return out;
}

size_t patchVertexCount(const PatchSubdivision& subdivision) {
  const size_t cols = std::accumulate(subdivision.uSegments.begin(), subdivision.uSegments.end(), size_t{1});
  const size_t rows = std::accumulate(subdivision.vSegments.begin(), subdivision.vSegments.end(), size_t{1});
  return cols * rows;
}

void tessellatePatch(const PatchControlGrid& grid, const PatchSubdivision& subdivision, SurfaceMesh& mesh) {
  const auto columns = gridLines(subdivision.uSegments);
  const auto rows = gridLines(subdivision.vSegments);
  const size_t base = mesh.vertices.size();
  mesh.vertices.reserve(base + columns.size() * rows.size());
  std::vector<glm::vec3> storedNormals;  // interpolated file normals: they say which side is front
  storedNormals.reserve(columns.size() * rows.size());
  double orientation = 0;

  for (const auto& [j, s] : rows)
    for (const auto& [i, t] : columns) {
      glm::vec3 stored;
      mesh.vertices.push_back(evaluatePieceVertex(grid, i, t, j, s, stored));
      orientation += glm::dot(mesh.vertices.back().normal, stored);
      storedNormals.push_back(stored);
    }

  // S_u x S_v is the front of a CCW (u, v) triangle; flip when the file's normals disagree.
  const bool flip = orientation < 0;
  for (size_t k = base; k < mesh.vertices.size(); ++k) {
    auto& n = mesh.vertices[k].normal;
    if (n == glm::vec3(0)) {  // degenerate point (collapsed edge): fall back to the file normal
      const glm::vec3 stored = storedNormals[k - base];
      const float len = glm::length(stored);
      n = (len > 1e-6f && std::isfinite(len)) ? stored / len : glm::vec3(0, 0, 1);
    } else if (flip) {
      n = -n;
    }
  }

  const uint32_t cols = static_cast<uint32_t>(columns.size());
  auto same = [&](uint32_t a, uint32_t b) { return mesh.vertices[a].position == mesh.vertices[b].position; };
  auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (same(a, b) || same(b, c) || same(a, c)) return;  // collapsed rows/columns
    if (flip) std::swap(b, c);
    mesh.indices.insert(mesh.indices.end(), {a, b, c});
  };
  for (uint32_t r = 0; r + 1 < rows.size(); ++r)
    for (uint32_t c = 0; c + 1 < cols; ++c) {
      const uint32_t v00 = static_cast<uint32_t>(base) + r * cols + c;
      const uint32_t v10 = v00 + 1, v01 = v00 + cols, v11 = v01 + 1;
      emit(v00, v10, v11);
      emit(v00, v11, v01);
    }
}

}  // namespace q3
