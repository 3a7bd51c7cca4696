// Per-triangle hit rules (HitRule) and per-ray face culling (HitFilter::cull) with known
// answers: the watertight det's sign convention, a one-sided quad seen from its front and from
// behind by rays that cull the back face (camera, bounce), none (shadow) or the front face,
// alone, in packets and as any-hit queries; a pack mixing the three rules; and mirrored
// instances (negative determinant), whose object-space winding is the opposite of the world's.
// Every layout and kernel this CPU runs.
#include <array>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <gtest/gtest.h>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/watertight.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/wide_bvh.h"

namespace pa::testing {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// The front face is seen where dot(cross(v1 - v0, v2 - v0), dir) < 0: there the watertight
/// det is positive, in all six shear classes (dominant axis, either sign).
TEST(HitRules, WatertightDetIsPositiveOnTheFrontFace) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-1.0f, 1.0f);
  uint32_t front = 0, back = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 v0(coord(rng), coord(rng), coord(rng)), v1(coord(rng), coord(rng), coord(rng)),
        v2(coord(rng), coord(rng), coord(rng));
    const glm::vec3 centre = (v0 + v1 + v2) / 3.0f;
    const glm::vec3 origin = centre + 3.0f * glm::vec3(coord(rng), coord(rng), coord(rng));
    const glm::vec3 dir = centre - origin;   // through the centroid: always a hit
    const glm::dvec3 n = glm::cross(glm::dvec3(v1) - glm::dvec3(v0), glm::dvec3(v2) - glm::dvec3(v0));
    const double facing = glm::dot(n, glm::dvec3(dir));
    if (std::abs(facing) < 1e-3 * glm::length(n) * glm::length(glm::dvec3(dir))) continue;   // grazing
    bvh_detail::TriangleHit hit;
    ASSERT_TRUE(bvh_detail::intersectTriangleWatertight(origin, dir, bvh_detail::RayShear(dir), 0.0f, kInf, v0,
                                                        v1, v2, hit));
    EXPECT_EQ(hit.det > 0.0f, facing < 0.0) << "triangle " << i;
    (facing < 0.0 ? front : back) += 1;
  }
  EXPECT_GT(front, 5000u);
  EXPECT_GT(back, 5000u);
}

/// One traversal kernel: node width and whether the 8-wide layout may take the AVX-512 kernel.
struct Kernel {
  uint32_t nodeWidth;
  bool allowAvx512;
};

class HitRuleKernels : public ::testing::TestWithParam<Kernel> {
 protected:
  void SetUp() override {
    if (GetParam().nodeWidth == 16 && !bvh_detail::wide16Available()) GTEST_SKIP() << "no AVX-512 on this CPU";
  }
  BvhBuildConfig config() const {
    BvhBuildConfig c;
    c.nodeWidth = GetParam().nodeWidth;
    c.allowAvx512 = GetParam().allowAvx512;
    return c;
  }
};

/// The square [-1, 1]^2 at height z as two triangles; front face towards +z (up), or -z.
void addSquare(TestMesh& m, float z, bool up, HitRule rule) {
  const auto base = static_cast<uint32_t>(m.positions.size());
  m.positions.insert(m.positions.end(), {{-1, -1, z}, {1, -1, z}, {1, 1, z}, {-1, 1, z}});
  if (up) m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
  else m.indices.insert(m.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
  m.rules.insert(m.rules.end(), {rule, rule});
}

/// What a callback records: the triangles it was asked about; accepts when ctx says so.
struct CallLog {
  bool accept = false;
  std::vector<uint32_t> prims;
};
bool logCall(const void* ctx, uint32_t, uint32_t prim, float, float, float) {
  auto& log = *static_cast<CallLog*>(const_cast<void*>(ctx));
  log.prims.push_back(prim);
  return log.accept;
}

constexpr std::array<FaceCull, 3> kCulls = {FaceCull::None, FaceCull::Back, FaceCull::Front};

const char* name(FaceCull cull) { return cull == FaceCull::None ? "none" : cull == FaceCull::Back ? "back" : "front"; }

/// A one-sided square facing up, hit from above (its front) and from below (its back), with each
/// cull, alone, in a packet (lanes mixing both sides and all culls) and as any hit; as Opaque, the
/// same square is hit by every ray.
TEST_P(HitRuleKernels, OneSidedSquareFromFrontAndBehind) {
  for (const HitRule rule : {HitRule::OneSided, HitRule::Opaque}) {
    TestMesh m;
    addSquare(m, 0.0f, true, rule);
    Blas blas;
    blas.build(m.input(), config());
    std::array<Ray, kMaxPacketRays> rays;
    std::array<HitFilter, kMaxPacketRays> filters;
    std::array<bool, kMaxPacketRays> expected;
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
      const bool fromAbove = lane % 2 == 0;
      const glm::vec3 target(-0.7f + 0.09f * lane, 0.3f - 0.05f * lane, 0.0f);
      rays[lane].origin = glm::vec3(0.1f, 0.2f, fromAbove ? 4.0f : -4.0f);
      rays[lane].dir = target - rays[lane].origin;
      filters[lane].cull = kCulls[lane / 2 % 3];
      const bool culled = rule == HitRule::OneSided && ((filters[lane].cull == FaceCull::Back && !fromAbove) ||
                                                        (filters[lane].cull == FaceCull::Front && fromAbove));
      expected[lane] = !culled;
      SCOPED_TRACE(std::string("lane ") + std::to_string(lane) + (fromAbove ? " from above" : " from below") +
                   ", cull " + name(filters[lane].cull));
      Ray alone = rays[lane];
      Hit hit;
      EXPECT_EQ(blas.intersect(alone, hit, filters[lane]), expected[lane]);
      if (expected[lane]) {
        EXPECT_NEAR(hit.t, 1.0f, 1e-6f);
      }
      EXPECT_EQ(blas.occluded(rays[lane], filters[lane]), expected[lane]);
    }
    // Two packets: the rays from above, then those from below (a packet takes one octant).
    for (const uint32_t active : {0x5555u, 0xaaaau}) {
      std::array<Ray, kMaxPacketRays> packet = rays;
      std::array<Hit, kMaxPacketRays> hits;
      const uint32_t found = blas.intersectPacket(packet, hits, active, filters);
      for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane)
        if (active >> lane & 1) {
          EXPECT_EQ(found >> lane & 1, uint32_t{expected[lane]}) << "packet lane " << lane;
        }
    }
  }
}

/// One pack holding all three rules: squares at z = 1 (one-sided, facing up), 2 (filtered),
/// 3 (opaque) and 4 (one-sided, facing down). The callback is asked about the filtered square
/// only, and each rule decides as stated, alone, in packets and as any hit.
TEST_P(HitRuleKernels, MixedRulesInOnePack) {
  TestMesh m;
  addSquare(m, 1.0f, true, HitRule::OneSided);    // prims 0, 1
  addSquare(m, 2.0f, true, HitRule::Filtered);    // prims 2, 3
  addSquare(m, 3.0f, true, HitRule::Opaque);      // prims 4, 5
  addSquare(m, 4.0f, false, HitRule::OneSided);   // prims 6, 7
  Blas blas;
  blas.build(m.input(), config());
  struct Case {
    bool up;          // ray going up from z = 0, else down from z = 5
    FaceCull cull;
    bool accept;      // the callback's answer on the filtered square
    float height;     // expected hit's z
  };
  const Case cases[] = {
      // Going up: the back of every square but the last.
      {true, FaceCull::Back, false, 3.0f}, {true, FaceCull::Back, true, 2.0f}, {true, FaceCull::None, false, 1.0f},
      {true, FaceCull::Front, false, 1.0f},
      // Going down: the back of the square at 4, then the front of the others.
      {false, FaceCull::Back, false, 3.0f}, {false, FaceCull::None, false, 4.0f},
      {false, FaceCull::Front, false, 4.0f}, {false, FaceCull::Front, true, 4.0f}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(c.up ? "up" : "down") + ", cull " + name(c.cull) + (c.accept ? ", accepting" : ""));
    CallLog log;
    log.accept = c.accept;
    const HitFilter filter{logCall, &log, c.cull};
    std::array<Ray, kMaxPacketRays> rays;
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
      rays[lane].origin = glm::vec3(0.0f, 0.0f, c.up ? 0.0f : 5.0f);
      rays[lane].dir = glm::vec3(-0.3f + 0.04f * lane, 0.2f - 0.03f * lane, c.up ? 1.0f : -1.0f);
    }
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
      Ray ray = rays[lane];
      Hit hit;
      ASSERT_TRUE(blas.intersect(ray, hit, filter));
      EXPECT_NEAR(hit.t, std::abs(c.height - rays[lane].origin.z), 1e-5f);
    }
    const std::array<HitFilter, kMaxPacketRays> filters = [&] {
      std::array<HitFilter, kMaxPacketRays> f;
      f.fill(filter);
      return f;
    }();
    std::array<Ray, kMaxPacketRays> packet = rays;
    std::array<Hit, kMaxPacketRays> hits;
    ASSERT_EQ(blas.intersectPacket(packet, hits, 0xffffu, filters), 0xffffu);
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane)
      EXPECT_NEAR(hits[lane].t, std::abs(c.height - rays[lane].origin.z), 1e-5f) << "packet lane " << lane;
    // Any hit over the first square met only (z = 1 going up, z = 4 going down: both seen from
    // behind): occluded unless the ray culls back faces.
    Ray firstOnly = rays[0];
    firstOnly.tmax = 1.5f;
    EXPECT_EQ(blas.occluded(firstOnly, filter), c.cull != FaceCull::Back);
    for (const uint32_t prim : log.prims) EXPECT_TRUE(prim == 2 || prim == 3) << "callback asked about " << prim;
  }
}

INSTANTIATE_TEST_SUITE_P(Kernels, HitRuleKernels,
                         ::testing::Values(Kernel{8, false}, Kernel{8, true}, Kernel{16, true}));

/// Whether the world-space triangle (a, b, c) is hit by the ray with the given cull (the
/// renderer's callback rule: back face where dot(cross(b - a, c - a), dir) > 0 in world space).
bool facesOpen(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& dir, FaceCull cull) {
  const float facing = glm::dot(glm::cross(b - a, c - a), dir);
  return !(cull == FaceCull::Back && facing > 0.0f) && !(cull == FaceCull::Front && facing < 0.0f);
}

/// Instances of a one-sided square, plain and mirrored (negative determinant, with and without
/// rotation and scale): which rays hit follows the world-space winding, as the renderer's filter
/// decides, alone, in packets and as any hit.
TEST(HitRules, MirroredInstancesCullTheWorldBackFace) {
  TestMesh square;
  addSquare(square, 0.0f, true, HitRule::OneSided);
  for (const uint32_t width : {8u, 16u}) {
    if (width == 16 && !bvh_detail::wide16Available()) continue;
    SCOPED_TRACE("node width " + std::to_string(width));
    BvhBuildConfig config;
    config.nodeWidth = width;
    Blas blas;
    blas.build(square.input(), config);
    const glm::mat3 mirrors[] = {glm::mat3(1.0f), glm::mat3(glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)),
                                 glm::mat3(glm::vec3(0, 2, 0), glm::vec3(2, 0, 0), glm::vec3(0, 0, 2)),   // swap x, y
                                 glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(0, 1, 0))};  // swap y, z
    for (const glm::mat3& linear : mirrors) {
      const bool mirrored = glm::determinant(linear) < 0.0f;
      SCOPED_TRACE(mirrored ? "mirrored" : "plain");
      glm::mat4x3 transform(linear);
      transform[3] = glm::vec3(10.0f, 0.0f, 0.0f);
      Tlas tlas;
      const TlasInstance instance{&blas, transform};
      tlas.build(std::span<const TlasInstance>(&instance, 1));
      const auto world = [&](uint32_t prim, int corner) {
        return transform * glm::vec4(square.positions[square.indices[3 * prim + corner]], 1.0f);
      };
      const glm::vec3 centre = transform * glm::vec4(0.1f, 0.2f, 0.0f, 1.0f);
      const glm::vec3 normal = glm::normalize(glm::cross(world(0, 1) - world(0, 0), world(0, 2) - world(0, 0)));
      for (const float side : {1.0f, -1.0f}) {
        for (const FaceCull cull : kCulls) {
          std::array<Ray, kMaxPacketRays> rays;
          std::array<HitFilter, kMaxPacketRays> filters;
          filters.fill(HitFilter{nullptr, nullptr, cull});
          for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
            rays[lane].origin = centre + 3.0f * side * normal;
            rays[lane].dir = centre + glm::vec3(0.02f * lane - 0.15f, 0.0f, 0.0f) - rays[lane].origin;
          }
          const bool expected = facesOpen(world(0, 0), world(0, 1), world(0, 2), rays[0].dir, cull);
          EXPECT_EQ(expected, cull == FaceCull::None || (cull == FaceCull::Back) == (side > 0.0f))
              << "the expectation itself";
          SCOPED_TRACE(std::string(side > 0.0f ? "front" : "back") + " side, cull " + name(cull));
          for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
            Ray ray = rays[lane];
            Hit hit;
            EXPECT_EQ(tlas.intersect(ray, hit, ~0u, filters[lane]), expected) << "lane " << lane;
            EXPECT_EQ(tlas.occluded(rays[lane], ~0u, filters[lane]), expected) << "lane " << lane;
          }
          std::array<Hit, kMaxPacketRays> hits;
          EXPECT_EQ(tlas.intersectPacket(rays, hits, 0xffffu, ~0u, filters), expected ? 0xffffu : 0u);
        }
      }
    }
  }
}

/// Random one-sided triangles under random plain and mirrored instances against a brute-force
/// world-space answer (each triangle transformed, the watertight test and the world winding):
/// the same closest triangle, except where the ray grazes a triangle or meets an edge.
TEST(HitRules, InstancesAgreeWithWorldSpaceBruteForce) {
  TestMesh soup = makeTriangleSoup(300, 21, 0.3f);
  soup.rules.assign(soup.triangleCount(), HitRule::OneSided);
  for (uint32_t t = 0; t < soup.triangleCount(); t += 3) soup.rules[t] = HitRule::Opaque;
  Blas blas;
  blas.build(soup.input());
  std::mt19937 rng(3);
  std::vector<TlasInstance> instances;
  for (int i = 0; i < 6; ++i) {
    glm::mat4x3 m = makeRandomTransform(rng, 4.0f);
    if (i % 2) m[0] = -m[0];   // mirrored
    instances.push_back({&blas, m});
  }
  Tlas tlas;
  tlas.build(instances);
  uint32_t hits = 0, compared = 0;
  for (const Ray& source : makeRandomRays(tlas.bounds(), 20000, 5)) {
    for (const FaceCull cull : kCulls) {
      Ray ray = source;
      Hit hit;
      const bool found = tlas.intersect(ray, hit, ~0u, HitFilter{nullptr, nullptr, cull});
      // Brute force in world space.
      float bestT = kInf;
      Hit best;
      bool ambiguous = false;
      const bvh_detail::RayShear shear(source.dir);
      for (uint32_t k = 0; k < instances.size(); ++k)
        for (uint32_t t = 0; t < soup.triangleCount(); ++t) {
          glm::vec3 v[3];
          for (int c = 0; c < 3; ++c) v[c] = instances[k].objectToWorld * glm::vec4(soup.positions[soup.indices[3 * t + c]], 1.0f);
          bvh_detail::TriangleHit th;
          if (!bvh_detail::intersectTriangleWatertight(source.origin, source.dir, shear, source.tmin, source.tmax, v[0],
                                                       v[1], v[2], th))
            continue;
          const glm::vec3 n = glm::cross(v[1] - v[0], v[2] - v[0]);
          const float cosine = glm::dot(n, source.dir) / (glm::length(n) * glm::length(source.dir));
          const float edge = std::min({th.u, th.v, 1.0f - th.u - th.v});
          if (std::abs(cosine) < 1e-3f || edge < 1e-3f) ambiguous = true;
          if (soup.rules[t] == HitRule::OneSided && !facesOpen(v[0], v[1], v[2], source.dir, cull)) continue;
          if (th.t < bestT) {
            bestT = th.t;
            best = {th.t, th.u, th.v, t, k};
          }
        }
      if (ambiguous) continue;
      ++compared;
      ASSERT_EQ(found, bestT < kInf) << "cull " << name(cull);
      if (!found) continue;
      ++hits;
      EXPECT_EQ(hit.prim, best.prim);
      EXPECT_EQ(hit.instance, best.instance);
      EXPECT_NEAR(hit.t, bestT, 1e-4f * bestT + 1e-5f);
    }
  }
  EXPECT_GT(compared, 50000u);
  EXPECT_GT(hits, 2000u);
}

}  // namespace
}  // namespace pa::testing
