#pragma once
// For tests (needs GoogleTest): two ways of tracing the same triangles with the same triangle
// test (two layouts, two trees, with and without pre-splitting) must give identical answers.
// Header-only so the testing library itself stays free of GoogleTest (the bench links it).
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>

#include <gtest/gtest.h>

#include "renderer/core/ray.h"

namespace pa::testing {

/// One way of tracing: closest hit (shortens ray.tmax, fills hit) and any hit.
struct Tracer {
  std::function<bool(Ray&, Hit&)> closest;
  std::function<bool(const Ray&)> occluded;
};

/// The Tracer of a structure with intersect(ray, hit) and occluded(ray) (a Blas), which must
/// outlive it.
template <class Traceable>
Tracer tracerOf(const Traceable& t) {
  return Tracer{[&t](Ray& r, Hit& h) { return t.intersect(r, h); }, [&t](const Ray& r) { return t.occluded(r); }};
}

/// Same hit or miss, same t bit for bit and instance, same barycentrics when the triangle is the
/// same (it may differ only on an exact tie); any hit over the whole ray exactly when there is a
/// closest hit, the same any-hit answer half way to the hit, just short of it and from one bit
/// before or at it, and occlusion just past it and up to it. `hits` receives the
/// number of rays that hit (callers check the comparison saw enough of them).
inline void expectIdenticalHits(const Tracer& a, const Tracer& b, std::span<const Ray> rays, uint32_t& hits) {
  hits = 0;
  for (const Ray& r : rays) {
    Ray ra = r, rb = r;
    Hit ha, hb;
    const bool hitA = a.closest(ra, ha), hitB = b.closest(rb, hb);
    ASSERT_EQ(hitA, hitB);
    ASSERT_EQ(a.occluded(r), hitA);
    ASSERT_EQ(b.occluded(r), hitB);
    if (!hitA) continue;
    ++hits;
    ASSERT_EQ(ha.t, hb.t);
    ASSERT_EQ(ha.instance, hb.instance);
    if (ha.prim == hb.prim) {
      ASSERT_EQ(ha.u, hb.u);
      ASSERT_EQ(ha.v, hb.v);
    }
    Ray s = r;
    for (const float fraction : {0.5f, 0.999f}) {
      s.tmax = ha.t * fraction;
      ASSERT_EQ(a.occluded(s), b.occluded(s));
    }
    s.tmax = ha.t * 1.0001f;
    ASSERT_TRUE(a.occluded(s));
    ASSERT_TRUE(b.occluded(s));
    // At the hit's distance to the last bit, from both ends (kernels may decide a lane from its
    // sheared distance and an error bound, which must never decide otherwise).
    s.tmax = ha.t;
    ASSERT_TRUE(a.occluded(s));
    ASSERT_TRUE(b.occluded(s));
    s.tmax = std::nextafter(ha.t, -1.0f);
    ASSERT_EQ(a.occluded(s), b.occluded(s));
    s = r;
    for (const float tmin : {ha.t, std::nextafter(ha.t, 2.0f * ha.t + 1.0f)}) {
      s.tmin = tmin;
      ASSERT_EQ(a.occluded(s), b.occluded(s));
    }
  }
}

}  // namespace pa::testing
