#pragma once
// Watertight ray/triangle intersection (Woop, Benthin, Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2013): per-ray shear into a space where the ray runs along +z, then
// 2D edge functions with a double-precision fallback on exact zeros, so rays through shared
// edges and vertices hit exactly one of the adjacent triangles and never slip between them.
#include <cmath>
#include <cstdint>
#include <utility>

#include <glm/vec3.hpp>

#include "renderer/core/ray.h"

namespace pa::bvh_detail {

/// Per-ray constants of the watertight test.
struct RayShear {
  int kx = 0, ky = 1, kz = 2;   ///< Axis permutation: kz is the dominant direction axis.
  float sx = 0.0f, sy = 0.0f, sz = 1.0f;

  explicit RayShear(const glm::vec3& dir) {
    const glm::vec3 a{std::fabs(dir.x), std::fabs(dir.y), std::fabs(dir.z)};
    kz = (a.x > a.y) ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (dir[kz] < 0.0f) std::swap(kx, ky);   // keep the winding so the edge signs stay meaningful
    sx = dir[kx] / dir[kz];
    sy = dir[ky] / dir[kz];
    sz = 1.0f / dir[kz];
  }
};

/// Ray distance to the triangle's plane, in double: dot(v0 - o, n) / dot(n, d). The watertight
/// test decides *whether* a triangle is hit; its sheared-space distance loses digits on long,
/// thin triangles hit at grazing angles (2000x3-unit slivers in real maps were off by 0.08
/// units), so accepted hits take their distance from the plane, as Embree does.
/// Returns `fallback` when the ray runs parallel to the plane in double precision.
inline float planeHitDistance(const glm::vec3& origin, const glm::vec3& dir, const glm::vec3& v0,
                              const glm::vec3& v1, const glm::vec3& v2, float fallback) {
  const double e1x = double(v1.x) - v0.x, e1y = double(v1.y) - v0.y, e1z = double(v1.z) - v0.z;
  const double e2x = double(v2.x) - v0.x, e2y = double(v2.y) - v0.y, e2z = double(v2.z) - v0.z;
  const double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
  const double denom = nx * dir.x + ny * dir.y + nz * dir.z;
  if (denom == 0.0) return fallback;
  const double num = nx * (double(v0.x) - origin.x) + ny * (double(v0.y) - origin.y) + nz * (double(v0.z) - origin.z);
  return static_cast<float>(num / denom);
}

/// Result of a successful triangle test: distance and barycentrics of v1 (u) and v2 (v), and
/// the test's det (the sum of the edge functions, never 0 on a hit): det > 0 where the ray sees
/// the front face, dot(cross(v1 - v0, v2 - v0), dir) < 0 (edge functions in sheared space, whose
/// axis order keeps the winding: det = -dot(n, dir) / |dir[kz]| up to rounding).
struct TriangleHit {
  float t, u, v;
  float det = 0.0f;
};

/// FaceCull as the factor of the watertight det: a one-sided triangle's hit is skipped where
/// det x cullSign < 0 (Back: det < 0, the back face; Front: det > 0; None: never).
inline float cullSign(FaceCull cull) {
  return cull == FaceCull::Back ? 1.0f : cull == FaceCull::Front ? -1.0f : 0.0f;
}

/// One triangle in a ray's sheared space, rounded as intersectTriangleWatertight (and the wide
/// kernels, lane for lane) round it: its vertices relative to the ray origin, their sheared x and
/// y, and the 2D edge functions (recomputed in double where float gives an exact zero).
struct ShearedTriangle {
  glm::vec3 a, b, c;              ///< v0, v1, v2 minus the origin.
  float ax, ay, bx, by, cx, cy;   ///< Their sheared x and y (axes kx, ky).
  float u, v, w;                  ///< Edge functions: barycentrics times det.

  ShearedTriangle(const glm::vec3& origin, const RayShear& s, const glm::vec3& v0, const glm::vec3& v1,
                  const glm::vec3& v2)
      : a(v0 - origin), b(v1 - origin), c(v2 - origin), ax(a[s.kx] - s.sx * a[s.kz]), ay(a[s.ky] - s.sy * a[s.kz]),
        bx(b[s.kx] - s.sx * b[s.kz]), by(b[s.ky] - s.sy * b[s.kz]), cx(c[s.kx] - s.sx * c[s.kz]),
        cy(c[s.ky] - s.sy * c[s.kz]), u(cx * by - cy * bx), v(ax * cy - ay * cx), w(bx * ay - by * ax) {
    if (u == 0.0f || v == 0.0f || w == 0.0f) {   // on an edge in float: decide exactly in double
      u = static_cast<float>(double(cx) * double(by) - double(cy) * double(bx));
      v = static_cast<float>(double(ax) * double(cy) - double(ay) * double(cx));
      w = static_cast<float>(double(bx) * double(ay) - double(by) * double(ax));
    }
  }
  /// True when the ray's line passes through the triangle or its edges (no two edge functions of
  /// opposite sign); det may still be 0.
  bool crossed() const { return !((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)); }
  /// The sheared-space distance tScaled / det, given 1 / det.
  float shearedDistance(const RayShear& s, float rcp) const {
    const float az = s.sz * a[s.kz], bz = s.sz * b[s.kz], cz = s.sz * c[s.kz];
    return (u * az + v * bz + w * cz) * rcp;
  }
};

/// Tests one triangle; true when hit at t in [tmin, tmax]. Degenerate triangles
/// (det == 0) never hit. Both faces are hit.
inline bool intersectTriangleWatertight(const glm::vec3& origin, const glm::vec3& dir, const RayShear& s,
                                        float tmin, float tmax, const glm::vec3& v0, const glm::vec3& v1,
                                        const glm::vec3& v2, TriangleHit& out) {
  const ShearedTriangle tri(origin, s, v0, v1, v2);
  if (!tri.crossed()) return false;
  const float det = tri.u + tri.v + tri.w;
  if (!(det != 0.0f)) return false;
  // The range test uses the accurate plane distance only: the sheared-space distance can be
  // far off on slivers, so culling with it would reject hits whose true t is in range.
  const float rcp = 1.0f / det;
  out = {planeHitDistance(origin, dir, v0, v1, v2, tri.shearedDistance(s, rcp)), tri.v * rcp, tri.w * rcp, det};
  return out.t >= tmin && out.t <= tmax;
}

/// True when the triangle has zero area (computed in double so only exact degeneracy counts).
inline bool isDegenerateTriangle(const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2) {
  const double e1x = double(v1.x) - v0.x, e1y = double(v1.y) - v0.y, e1z = double(v1.z) - v0.z;
  const double e2x = double(v2.x) - v0.x, e2y = double(v2.y) - v0.y, e2z = double(v2.z) - v0.z;
  const double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
  return nx == 0.0 && ny == 0.0 && nz == 0.0;
}

}  // namespace pa::bvh_detail
