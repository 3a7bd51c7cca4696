// Biquadratic Bezier patch tessellation with per-row/column uniform subdivision.
#include "port/q3formats/world/world_patches.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "port/q3formats/bsp/bsp_file.h"

namespace q3 {
namespace {

constexpr int kMaxSteps = 16;   // per 3x3 piece and direction

/// Control vertex with every attribute as floats (interpolated together).
struct ControlVertex {
  glm::vec3 position, normal;
  glm::vec2 st, lightmap;
  glm::vec4 color;
};

ControlVertex blend(const ControlVertex& a, const ControlVertex& b, const ControlVertex& c, float t) {
  float wa = (1 - t) * (1 - t), wb = 2 * t * (1 - t), wc = t * t;
  return {a.position * wa + b.position * wb + c.position * wc, a.normal * wa + b.normal * wb + c.normal * wc,
          a.st * wa + b.st * wb + c.st * wc, a.lightmap * wa + b.lightmap * wb + c.lightmap * wc,
          a.color * wa + b.color * wb + c.color * wc};
}

/// Steps (a power of two) so that the quadratic's distance to its chords is below tolerance:
/// the midpoint deviation is |p0 - 2 p1 + p2| / 4 and shrinks 4x per halving.
int stepsFor(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, float tolerance) {
  float error = glm::length(p0 - 2.0f * p1 + p2) * 0.25f;
  int steps = 1;
  while (error > tolerance && steps < kMaxSteps) {
    error *= 0.25f;
    steps *= 2;
  }
  return steps;
}

}  // namespace

void PatchTessellator::tessellate(size_t surfaceIndex, SourceSurface& out) const {
  const BspSurface& s = bsp_.surfaces.at(surfaceIndex);
  const int w = s.patchWidth, h = s.patchHeight;
  if (w < 3 || h < 3 || w % 2 == 0 || h % 2 == 0 || w > kMaxPatchSize || h > kMaxPatchSize || w * h > s.numVerts) return;
  std::vector<ControlVertex> cp(size_t(w) * size_t(h));
  for (size_t i = 0; i < cp.size(); ++i) {
    const BspDrawVert& v = bsp_.drawVerts.at(size_t(s.firstVert) + i);
    cp[i] = {v.position, v.normal, v.st, v.lightmap,
             glm::vec4(v.color[0], v.color[1], v.color[2], v.color[3]) / 255.0f};
  }
  auto at = [&](int x, int y) -> const ControlVertex& { return cp[size_t(y) * size_t(w) + size_t(x)]; };
  const int piecesX = (w - 1) / 2, piecesY = (h - 1) / 2;

  // One step count per piece column (shared by all rows) and per piece row.
  std::vector<int> stepsX(size_t(piecesX), 1), stepsY(size_t(piecesY), 1);
  for (int px = 0; px < piecesX; ++px)
    for (int y = 0; y < h; ++y)
      stepsX[size_t(px)] = std::max(stepsX[size_t(px)], stepsFor(at(2 * px, y).position, at(2 * px + 1, y).position,
                                                                 at(2 * px + 2, y).position, tolerance_));
  for (int py = 0; py < piecesY; ++py)
    for (int x = 0; x < w; ++x)
      stepsY[size_t(py)] = std::max(stepsY[size_t(py)], stepsFor(at(x, 2 * py).position, at(x, 2 * py + 1).position,
                                                                 at(x, 2 * py + 2).position, tolerance_));

  // Parameter samples along each direction: (piece, t) pairs, shared edges emitted once.
  auto samples = [](const std::vector<int>& steps) {
    std::vector<std::pair<int, float>> out;
    for (size_t p = 0; p < steps.size(); ++p)
      for (int k = (p == 0 ? 0 : 1); k <= steps[p]; ++k) out.emplace_back(int(p), float(k) / float(steps[p]));
    return out;
  };
  const auto us = samples(stepsX), vs = samples(stepsY);
  const size_t cols = us.size();

  for (const auto& [py, tv] : vs) {
    for (const auto& [px, tu] : us) {
      ControlVertex rows[3];
      for (int r = 0; r < 3; ++r)
        rows[r] = blend(at(2 * px, 2 * py + r), at(2 * px + 1, 2 * py + r), at(2 * px + 2, 2 * py + r), tu);
      ControlVertex v = blend(rows[0], rows[1], rows[2], tv);
      out.positions.push_back(v.position);
      float len = glm::length(v.normal);
      out.normals.push_back(len > 1e-6f ? v.normal / len : glm::vec3(0, 0, 1));
      out.uvs.push_back(v.st);
      out.lightmapUvs.push_back(v.lightmap);
      out.colors.push_back(v.color);
    }
  }
  // Two triangles per cell, wound counter-clockwise around the control normals' side.
  for (size_t r = 0; r + 1 < vs.size(); ++r)
    for (size_t c = 0; c + 1 < cols; ++c) {
      uint32_t a = uint32_t(r * cols + c), b = uint32_t(r * cols + c + 1);
      uint32_t d = uint32_t((r + 1) * cols + c), e = uint32_t((r + 1) * cols + c + 1);
      glm::vec3 face = glm::cross(out.positions[b] - out.positions[a], out.positions[d] - out.positions[a]);
      if (glm::dot(face, out.normals[a] + out.normals[e]) >= 0.0f)
        out.indices.insert(out.indices.end(), {a, b, d, b, e, d});
      else
        out.indices.insert(out.indices.end(), {a, d, b, b, d, e});
    }
}

}  // namespace q3
