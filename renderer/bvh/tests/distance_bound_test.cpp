// shearedDistanceBound (wide_traversal_loop.h): on triangles of the shapes maps hold and of worse
// ones (slivers thousands of units long and a hundredth wide, rays grazing them, coordinates far
// from the origin, rays leaving a surface), the watertight test's float distance lies within the
// bound of the accurate plane distance, so a lane the kernels decide from the bound is decided as
// the plane distance decides it; and on ordinary hits the bound is tight enough to decide nearly
// every lane. The kernels against the reference at the boundary itself: identical_hits.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#define PA_BVH_KERNEL
#include "renderer/bvh/wide_traversal_loop.h"

namespace pa::testing {
namespace {

using namespace pa::bvh_detail;

/// The watertight test's pieces of one hit, as intersectTriangleWatertight rounds them.
struct ShearedHit {
  bool hit = false;
  float t = 0.0f;       ///< tScaled / det: the sheared-space distance.
  float absRcp = 0.0f;  ///< |1 / det|.
  float maxXY = 0.0f, maxZ = 0.0f, absSz = 0.0f;
};

ShearedHit shearedHit(const glm::vec3& o, const glm::vec3& d, const glm::vec3& v0, const glm::vec3& v1,
                      const glm::vec3& v2) {
  const RayShear s(d);
  const ShearedTriangle tri(o, s, v0, v1, v2);
  ShearedHit out;
  if (!tri.crossed()) return out;
  const float det = tri.u + tri.v + tri.w;
  if (!(det != 0.0f)) return out;
  const float rcp = 1.0f / det;
  out.hit = true;
  out.t = tri.shearedDistance(s, rcp);
  out.absRcp = std::fabs(rcp);
  out.maxXY = std::max({std::fabs(tri.ax), std::fabs(tri.ay), std::fabs(tri.bx), std::fabs(tri.by),
                        std::fabs(tri.cx), std::fabs(tri.cy)});
  out.maxZ = std::max({std::fabs(tri.a[s.kz]), std::fabs(tri.b[s.kz]), std::fabs(tri.c[s.kz])});
  out.absSz = std::fabs(s.sz);
  return out;
}

/// What the checks saw.
struct Tally {
  int hits = 0;          ///< Rays whose watertight test hit.
  int bounded = 0;       ///< Of them, with a finite bound.
  int tight = 0;         ///< Of them, with a bound below 1% of the distance.
  double worstUse = 0;   ///< Largest |t - tPlane| / bound seen.
};

/// One ray against one triangle: |t - tPlane| within the bound, and the lane decisions a kernel
/// takes with it (inside / outside of [tmin, tmax]) equal to the plane distance's for ranges
/// that end at tPlane or one bit either side of it.
void check(const glm::vec3& o, const glm::vec3& d, const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2,
           Tally& tally) {
  const ShearedHit h = shearedHit(o, d, v0, v1, v2);
  if (!h.hit) return;
  ++tally.hits;
  const float bound = shearedDistanceBound(h.absRcp, h.maxXY, h.maxZ, h.absSz);
  const float tPlane = planeHitDistance(o, d, v0, v1, v2, h.t);
  if (!(bound < std::numeric_limits<float>::infinity())) return;
  ++tally.bounded;
  if (bound < 1e-2f * std::fabs(tPlane)) ++tally.tight;
  const double error = std::fabs(double(h.t) - double(tPlane));
  tally.worstUse = std::max(tally.worstUse, error / double(bound));
  ASSERT_LE(error, double(bound)) << "t " << h.t << " plane " << tPlane << " bound " << bound;
  const float ends[] = {std::nextafter(tPlane, -std::numeric_limits<float>::infinity()), tPlane,
                        std::nextafter(tPlane, std::numeric_limits<float>::infinity())};
  for (const float tmin : {0.0f, ends[0], ends[1], ends[2]})
    for (const float tmax : {ends[0], ends[1], ends[2], std::numeric_limits<float>::infinity()}) {
      const bool accepted = tPlane >= tmin && tPlane <= tmax;
      const bool inside = h.t - bound >= tmin && h.t + bound <= tmax;
      const bool outside = h.t + bound < tmin || h.t - bound > tmax;
      ASSERT_TRUE(!inside || accepted) << "decided inside: t " << h.t << " plane " << tPlane;
      ASSERT_TRUE(!outside || !accepted) << "decided outside: t " << h.t << " plane " << tPlane;
    }
}

glm::vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> n;
  for (;;) {
    const glm::vec3 v(n(rng), n(rng), n(rng));
    if (glm::length(v) > 1e-3f) return glm::normalize(v);
  }
}

/// A point of the triangle (random barycentrics).
glm::vec3 pointOn(std::mt19937& rng, const glm::vec3& v0, const glm::vec3& v1, const glm::vec3& v2) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  float b1 = unit(rng), b2 = unit(rng);
  if (b1 + b2 > 1.0f) b1 = 1.0f - b1, b2 = 1.0f - b2;
  return v0 + b1 * (v1 - v0) + b2 * (v2 - v0);
}

TEST(ShearedDistanceBound, HoldsAndDecidesOrdinaryHits) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  Tally tally;
  for (const float size : {1.0f, 64.0f, 4096.0f})
    for (const float offset : {0.0f, 4096.0f, 100000.0f})
      for (const float away : {0.01f, 1.0f, 30.0f})
        for (int i = 0; i < 2000; ++i) {
          const glm::vec3 centre(offset * unit(rng), offset * unit(rng), offset * unit(rng));
          const glm::vec3 v0 = centre + size * glm::vec3(unit(rng), unit(rng), unit(rng));
          const glm::vec3 v1 = centre + size * glm::vec3(unit(rng), unit(rng), unit(rng));
          const glm::vec3 v2 = centre + size * glm::vec3(unit(rng), unit(rng), unit(rng));
          const glm::vec3 target = pointOn(rng, v0, v1, v2);
          const glm::vec3 origin = target + size * away * randomUnit(rng);
          const float length = std::array<float, 3>{1e-3f, 1.0f, 1e3f}[i % 3];
          check(origin, (target - origin) * (length / size), v0, v1, v2, tally);
          if (HasFatalFailure()) return;
        }
  std::printf("ordinary: %d hits, %d bounded, %d within 1%% of t, worst use of the bound %.3g\n", tally.hits,
              tally.bounded, tally.tight, tally.worstUse);
  EXPECT_GT(tally.hits, 40000);
  EXPECT_GT(tally.tight, tally.hits * 90 / 100);
}

TEST(ShearedDistanceBound, HoldsOnSliversAtGrazingAngles) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Tally tally;
  for (const float length : {100.0f, 2000.0f, 8000.0f})
    for (const float width : {3.0f, 0.01f, 1e-4f})
      for (const float grazing : {0.3f, 1e-3f, 1e-5f})
        for (int i = 0; i < 600; ++i) {
          const glm::vec3 along = randomUnit(rng);
          const glm::vec3 across = glm::normalize(glm::cross(along, randomUnit(rng)));
          const glm::vec3 normal = glm::cross(along, across);
          const glm::vec3 v0 = 3000.0f * glm::vec3(unit(rng), unit(rng), unit(rng));
          const glm::vec3 v1 = v0 + length * along;
          const glm::vec3 v2 = v0 + unit(rng) * length * along + width * across;
          const glm::vec3 target = pointOn(rng, v0, v1, v2);
          const glm::vec3 inPlane = glm::normalize(unit(rng) * along + (unit(rng) - 0.5f) * across);
          const float distance = 10.0f + 2000.0f * unit(rng);
          const glm::vec3 origin = target - distance * inPlane + (i % 2 ? 1.0f : -1.0f) * distance * grazing * normal;
          check(origin, target - origin, v0, v1, v2, tally);
          if (HasFatalFailure()) return;
        }
  std::printf("slivers: %d hits, %d bounded, %d within 1%% of t, worst use of the bound %.3g\n", tally.hits,
              tally.bounded, tally.tight, tally.worstUse);
  EXPECT_GT(tally.bounded, 1000);
}

TEST(ShearedDistanceBound, HoldsForRaysLeavingTheSurface) {
  // Bounce and shadow rays start on a surface (its hit point, rounded to float): the same
  // triangle is crossed again near t = 0, where tmin decides.
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  Tally tally;
  for (const float size : {1.0f, 300.0f, 3000.0f})
    for (int i = 0; i < 6000; ++i) {
      const glm::vec3 centre = 4096.0f * glm::vec3(unit(rng), unit(rng), unit(rng));
      const glm::vec3 v0 = centre + size * glm::vec3(unit(rng), unit(rng), unit(rng));
      const glm::vec3 v1 = centre + size * glm::vec3(unit(rng), unit(rng), unit(rng));
      const glm::vec3 v2 = centre + size * glm::vec3(unit(rng), unit(rng), unit(rng));
      check(pointOn(rng, v0, v1, v2), randomUnit(rng), v0, v1, v2, tally);
      if (HasFatalFailure()) return;
    }
  std::printf("leaving: %d hits, %d bounded, worst use of the bound %.3g\n", tally.hits, tally.bounded,
              tally.worstUse);
  EXPECT_GT(tally.bounded, 1000);
}

TEST(ShearedDistanceBound, IsInfiniteOrNanWhereNothingHolds) {
  const float inf = std::numeric_limits<float>::infinity();
  // Edge functions whose error rivals det: no bound.
  EXPECT_EQ(shearedDistanceBound(1e12f, 1000.0f, 1000.0f, 1.0f), inf);
  EXPECT_FALSE(shearedDistanceBound(inf, 1.0f, 1.0f, 1.0f) < inf);
  EXPECT_FALSE(shearedDistanceBound(0.0f, inf, 1.0f, 1.0f) < inf);
  EXPECT_FALSE(shearedDistanceBound(1.0f, 1.0f, 1.0f, std::numeric_limits<float>::quiet_NaN()) < inf);
  // A unit triangle facing the ray at distance 1: a few ulps.
  const float unitBound = shearedDistanceBound(0.5f, 1.0f, 1.0f, 1.0f);
  EXPECT_GT(unitBound, 0.0f);
  EXPECT_LT(unitBound, 1e-4f);
}

}  // namespace
}  // namespace pa::testing
