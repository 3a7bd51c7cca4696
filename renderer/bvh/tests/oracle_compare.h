#pragma once
// Comparison of our hits with Embree's, with the tolerances the oracle tests state.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <glm/geometric.hpp>

#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/core/ray.h"

namespace pa::testing {

/// Tallies of one oracle run; `unexplained` must be zero.
struct OracleTally {
  uint64_t rays = 0, hits = 0, sameHits = 0, edgeCases = 0, unexplained = 0;
  std::string firstProblem;
};

/// Smallest barycentric of a hit: near 0 means the hit is on an edge or vertex.
inline float minBarycentric(const Hit& h) { return std::min({h.u, h.v, 1.0f - h.u - h.v}); }

/// Hit point from a hit's barycentrics on the triangle of `mesh`.
inline glm::vec3 hitPoint(const TestMesh& mesh, const Hit& h) {
  const glm::vec3 a = mesh.positions[mesh.indices[3 * h.prim]];
  const glm::vec3 b = mesh.positions[mesh.indices[3 * h.prim + 1]];
  const glm::vec3 c = mesh.positions[mesh.indices[3 * h.prim + 2]];
  return (1.0f - h.u - h.v) * a + h.u * b + h.v * c;
}

/// Closest-hit agreement: t within 1e-4 relative (plus 1e-5 of the scene size, the absolute
/// rounding of the coordinates, which dominates for hits very near the origin or at grazing
/// angles) and the same triangle. Exceptions, counted as edge cases: at a shared edge or vertex
/// (smallest barycentric < edgeEps on both hits) the t must agree but the triangle may differ;
/// and a hit only one side found, or found nearer, must lie on an edge of its triangle.
inline void compareClosest(OracleTally& tally, bool oursHit, const Hit& ours, bool embreeHit,
                           const Hit& embree, float sceneScale, float edgeEps = 1e-3f) {
  ++tally.rays;
  auto problem = [&](const std::string& what) {
    ++tally.unexplained;
    if (tally.firstProblem.empty())
      tally.firstProblem = what + " ours(t=" + std::to_string(ours.t) + " prim=" + std::to_string(ours.prim) +
                           " inst=" + std::to_string(ours.instance) + ") embree(t=" + std::to_string(embree.t) +
                           " prim=" + std::to_string(embree.prim) + " inst=" + std::to_string(embree.instance) + ")";
  };
  if (!oursHit && !embreeHit) return;
  if (oursHit != embreeHit) {
    const Hit& h = oursHit ? ours : embree;
    if (minBarycentric(h) < edgeEps) ++tally.edgeCases;
    else problem(oursHit ? "only ours hit" : "only embree hit");
    return;
  }
  ++tally.hits;
  const float tol = 1e-4f * embree.t + 1e-5f * sceneScale;
  if (ours.prim == embree.prim && ours.instance == embree.instance) {
    if (std::fabs(ours.t - embree.t) <= tol) ++tally.sameHits;
    else problem("same triangle, t differs");
    return;
  }
  // Different triangles: acceptable only at a shared edge/vertex (both hits on an edge, same t).
  const bool sameT = std::fabs(ours.t - embree.t) <= tol;
  const Hit& nearer = ours.t < embree.t ? ours : embree;
  if (sameT && minBarycentric(ours) < edgeEps && minBarycentric(embree) < edgeEps)
    ++tally.edgeCases;   // shared edge or vertex
  else if (!sameT && minBarycentric(nearer) < edgeEps)
    ++tally.edgeCases;   // one side grazed an edge the other missed
  else
    problem("different triangle");
}

}  // namespace pa::testing
