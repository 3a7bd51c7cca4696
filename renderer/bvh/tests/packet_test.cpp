// Packet queries (Blas::intersectPacket, Tlas::intersectPacket, and the any-hit
// Blas::occludedPacket, Tlas::occludedPacket) against tracing the same rays one by one: per ray
// the same occlusion answer, or the same hit or miss, the same distance bit for bit and the same instance, the
// same triangle and barycentrics unless two triangles are hit at exactly the same distance, and
// each ray's own filter and face culling (lanes mixing HitFilter::cull). Packets of camera rays (one origin, one octant), of rays spanning
// octants, of rays along axis planes (zero direction components), partly active packets, and
// instanced scenes with flat and hierarchical TLASes (mirrored instances among them), on both node
// widths and both 8-wide kernels.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/wide16_bvh.h"

namespace pa::testing {
namespace {

/// Per-ray alpha test stand-in: the ray's lane (ctx) changes which hits count, so a kernel that
/// gave one ray another ray's filter would be caught.
bool rejectByLane(const void* ctx, uint32_t, uint32_t prim, float u, float, float) {
  const auto lane = static_cast<uint32_t>(reinterpret_cast<uintptr_t>(ctx));
  return (prim + lane) % 3 != 0 && u <= 0.7f;
}

/// Camera rays through a width x height image from eye towards target, in 4x4 tiles (16
/// consecutive rays = one tile), as the renderer's tiles make them.
std::vector<Ray> cameraTiles(const glm::vec3& eye, const glm::vec3& target, uint32_t width, uint32_t height,
                             float tmax = std::numeric_limits<float>::infinity()) {
  const glm::vec3 forward = glm::normalize(target - eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0.0f, 0.0f, 1.0f)));
  const glm::vec3 up = glm::cross(right, forward);
  std::vector<Ray> rays;
  for (uint32_t ty = 0; ty < height; ty += 4)
    for (uint32_t tx = 0; tx < width; tx += 4)
      for (uint32_t y = ty; y < ty + 4; ++y)
        for (uint32_t x = tx; x < tx + 4; ++x) {
          Ray r;
          r.origin = eye;
          r.dir = glm::normalize(forward + (2.0f * (x + 0.5f) / width - 1.0f) * right +
                                 (1.0f - 2.0f * (y + 0.5f) / height) * up);
          r.tmax = tmax;
          rays.push_back(r);
        }
  return rays;
}

/// Some rays with exactly zero direction components, with subnormal ones and with the least
/// normal one (the packets' limit: invertibleLanes), and axis-aligned rays, mixed into packets.
std::vector<Ray> axisPlaneRays(const Bounds& region, uint32_t count, uint32_t seed) {
  std::vector<Ray> rays = makeRandomRays(region, count, seed);
  const float tiny[] = {0.0f, std::numeric_limits<float>::denorm_min(), -0x1.000002p-128f,
                        std::nextafter(std::numeric_limits<float>::min(), 0.0f), -std::numeric_limits<float>::min()};
  for (size_t i = 0; i < rays.size(); ++i) {
    if (i % 3 == 0) rays[i].dir[i % 9 / 3] = tiny[i / 3 % 5];
    if (i % 7 == 0) rays[i].dir = glm::vec3(0.0f, 0.0f, i % 2 ? 1.0f : -1.0f);
  }
  return rays;
}

/// Each lane's filter: its own alpha-test stand-in (when filtered), and no face, the back or the
/// front of one-sided triangles culled, lane by lane in turn.
std::array<HitFilter, kMaxPacketRays> laneFilters(bool filtered) {
  std::array<HitFilter, kMaxPacketRays> filters;
  for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
    filters[lane] = filtered ? HitFilter{rejectByLane, reinterpret_cast<const void*>(uintptr_t{lane})} : HitFilter{};
    filters[lane].cull = std::array{FaceCull::None, FaceCull::Back, FaceCull::Front}[lane % 3];
  }
  return filters;
}

/// Calls f(base, packet) for each whole packet of 16 consecutive rays (packet: a copy of
/// rays[base .. base + 15], which f may trace).
template <class F>
void forEachPacket(const std::vector<Ray>& rays, F&& f) {
  for (size_t base = 0; base + kMaxPacketRays <= rays.size(); base += kMaxPacketRays) {
    std::array<Ray, kMaxPacketRays> packet;
    std::copy_n(rays.begin() + base, kMaxPacketRays, packet.begin());
    f(base, packet);
  }
}

/// Whether the rays of a packet part by more than wide_packet_loop.h's kPerRayChildSpread (0.03):
/// the widest axis' range of their directions over the largest |direction|_1 (the rays taken
/// as one packet, which those of one octant are).
bool partWidely(std::span<const Ray> rays) {
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  float size = 0.0f;
  for (const Ray& r : rays) {
    lo = glm::min(lo, r.dir);
    hi = glm::max(hi, r.dir);
  }
  for (int axis = 0; axis < 3; ++axis) size += std::max(std::fabs(lo[axis]), std::fabs(hi[axis]));
  const glm::vec3 range = hi - lo;
  return !(std::max({range.x, range.y, range.z}) <= 0.03f * size);
}

/// Any hits of rays in packets of 16 (active lanes per activePattern, filters per laneFilters)
/// with occludePacket against occludeOne ray by ray: the same answer per ray, and none for idle
/// lanes. Returns the number of rays that hit something.
template <class PacketFn, class OneFn>
uint32_t expectSameOcclusionAsOneByOne(const std::vector<Ray>& rays, bool filtered, uint32_t activePattern,
                                       PacketFn&& occludePacket, OneFn&& occludeOne) {
  const std::array<HitFilter, kMaxPacketRays> filters = laneFilters(filtered);
  uint32_t occluded = 0;
  forEachPacket(rays, [&](size_t base, std::array<Ray, kMaxPacketRays>& packet) {
    const uint32_t found = occludePacket(packet, activePattern, filters);
    EXPECT_EQ(found & ~activePattern, 0u);
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
      if (!(activePattern >> lane & 1)) continue;
      const bool alone = occludeOne(rays[base + lane], filters[lane]);
      EXPECT_EQ((found >> lane & 1) != 0, alone) << "ray " << base + lane;
      occluded += alone ? 1 : 0;
    }
  });
  return occluded;
}

/// Shadow rays toward one light point from where `eyeRays` first hit (closest), as a tile's
/// shadow rays to one lamp: origin at the hit, direction to the light unnormalised, t in
/// [1e-4, 1]; a ray that hits nothing keeps its place as a ray from the light's side.
template <class IntersectOne>
std::vector<Ray> shadowRaysToward(const std::vector<Ray>& eyeRays, const glm::vec3& light, IntersectOne&& intersect) {
  std::vector<Ray> shadows;
  for (Ray ray : eyeRays) {
    Hit hit;
    const glm::vec3 from =
        intersect(ray, hit) ? ray.origin + hit.t * ray.dir : light + glm::vec3(0.5f, -0.25f, 0.125f);
    Ray s;
    s.origin = from;
    s.dir = light - from;
    s.tmin = 1e-4f;
    s.tmax = 1.0f;
    shadows.push_back(s);
  }
  return shadows;
}

/// Traces rays in packets of 16 (active lanes per activePattern) with tracePacket and one by
/// one with traceOne, and compares; returns the number of hits. Lanes cull no face, the back
/// or the front of one-sided triangles in turn.
template <class PacketFn, class OneFn>
uint32_t expectSameAsOneByOne(const std::vector<Ray>& rays, bool filtered, uint32_t activePattern,
                              PacketFn&& tracePacket, OneFn&& traceOne) {
  const std::array<HitFilter, kMaxPacketRays> filters = laneFilters(filtered);
  uint32_t hits = 0;
  forEachPacket(rays, [&](size_t base, std::array<Ray, kMaxPacketRays>& packet) {
    std::array<Hit, kMaxPacketRays> packetHits;
    const uint32_t active = activePattern;
    const uint32_t found = tracePacket(packet, packetHits, active, filters);
    EXPECT_EQ(found & ~active, 0u);
    for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
      Ray one = rays[base + lane];
      Hit oneHit;
      if (!(active >> lane & 1)) {
        EXPECT_EQ(packet[lane].tmax, one.tmax) << "an idle lane's ray changed";
        EXPECT_FALSE(packetHits[lane].valid()) << "an idle lane got a hit";
        continue;
      }
      const bool hitOne = traceOne(one, oneHit, filters[lane]);
      const bool hitPacket = (found >> lane & 1) != 0;
      EXPECT_EQ(hitPacket, hitOne) << "ray " << base + lane;
      if (!hitOne || !hitPacket) continue;
      ++hits;
      EXPECT_EQ(packetHits[lane].t, oneHit.t) << "ray " << base + lane;
      EXPECT_EQ(packet[lane].tmax, one.tmax) << "ray " << base + lane;
      EXPECT_EQ(packetHits[lane].instance, oneHit.instance) << "ray " << base + lane;
      if (packetHits[lane].prim == oneHit.prim) {
        EXPECT_EQ(packetHits[lane].u, oneHit.u);
        EXPECT_EQ(packetHits[lane].v, oneHit.v);
      }
    }
  });
  return hits;
}

struct PacketCase {
  uint32_t nodeWidth;
  bool filtered;   ///< Triangles of all three rules (else all Opaque) and a callback per ray.
  bool allowAvx512 = true;   ///< false: the 8-wide layout's baseline (AVX2 / SSE) kernel.
};

class BlasPackets : public ::testing::TestWithParam<PacketCase> {};

TEST_P(BlasPackets, SameHitsAsRayByRay) {
  const PacketCase param = GetParam();
  if (param.nodeWidth == 16 && !bvh_detail::wide16Available()) GTEST_SKIP() << "no AVX-512 on this CPU";
  const std::pair<TestMesh, uint32_t> meshes[] = {   // mesh, hits the comparison must see at least
      {makeTriangleSoup(20000, 5), 1500}, {makeThinTriangles(3000, 9), 50}, {makeSphere(5000), 1500}};
  uint32_t occluded = 0, traced = 0;   // any hits, over all meshes
  uint32_t packetsBySpread[2] = {};   // any-hit packets whose rays do not / do part widely
  // Camera rays of 4x4 blocks of a 256x192 view part by less than kPerRayChildSpread (as the
  // game's at 320x180); those of a 64x48 view, shadow rays to one light and random rays by more.
  // The blocks near the view's centre, where the meshes lie.
  std::vector<Ray> narrowTiles;
  const std::vector<Ray> allTiles = cameraTiles({3.0f, -2.5f, 1.5f}, {0.0f, 0.0f, 0.0f}, 256, 192);
  const glm::vec3 forward = glm::normalize(-glm::vec3(3.0f, -2.5f, 1.5f));
  for (size_t base = 0; base + kMaxPacketRays <= allTiles.size(); base += kMaxPacketRays)
    if (glm::dot(allTiles[base].dir, forward) > 0.985f)
      narrowTiles.insert(narrowTiles.end(), allTiles.begin() + base, allTiles.begin() + base + kMaxPacketRays);
  for (const auto& [source, minimumHits] : meshes) {
    TestMesh m = source;
    if (param.filtered) {
      m.rules.assign(m.triangleCount(), HitRule::Opaque);
      for (uint32_t i = 0; i < m.triangleCount(); ++i)
        m.rules[i] = i % 2 == 0 ? HitRule::Filtered : i % 4 == 1 ? HitRule::OneSided : HitRule::Opaque;
    }
    BvhBuildConfig config;
    config.nodeWidth = param.nodeWidth;
    config.allowAvx512 = param.allowAvx512;
    Blas blas;
    blas.build(m.input(), config);
    const auto packet = [&](std::array<Ray, 16>& rays, std::array<Hit, 16>& hits, uint32_t active,
                            const std::array<HitFilter, 16>& filters) {
      return blas.intersectPacket(rays, hits, active, filters, 3);
    };
    const auto one = [&](Ray& r, Hit& h, const HitFilter& f) { return blas.intersect(r, h, f, 3); };
    Bounds region = m.bounds();
    region.min -= glm::vec3(0.5f);
    region.max += glm::vec3(0.5f);
    uint32_t hits = 0;
    // Camera tiles from outside and from inside the mesh's bounds, with a finite tmax too.
    hits += expectSameAsOneByOne(cameraTiles({3.0f, -2.5f, 1.5f}, {0.0f, 0.0f, 0.0f}, 64, 48), param.filtered,
                                 0xffffu, packet, one);
    hits += expectSameAsOneByOne(cameraTiles({0.1f, 0.2f, 0.05f}, {1.0f, -0.3f, 0.2f}, 64, 48, 0.8f), param.filtered,
                                 0xffffu, packet, one);
    // Partly active camera packets, random rays spanning octants, rays along axis planes.
    hits += expectSameAsOneByOne(cameraTiles({-2.0f, 2.0f, -1.0f}, {0.0f, 0.0f, 0.0f}, 32, 32), param.filtered,
                                 0x5a3cu, packet, one);
    // Packets with rays in one half of the sixteen lanes only (the baseline kernel's halves).
    hits += expectSameAsOneByOne(cameraTiles({-2.0f, 2.0f, -1.0f}, {0.0f, 0.0f, 0.0f}, 32, 32), param.filtered,
                                 0x0f00u, packet, one);
    hits += expectSameAsOneByOne(cameraTiles({-2.0f, 2.0f, -1.0f}, {0.0f, 0.0f, 0.0f}, 32, 32), param.filtered,
                                 0x00c3u, packet, one);
    hits += expectSameAsOneByOne(makeRandomRays(region, 4096, 17), param.filtered, 0xffffu, packet, one);
    hits += expectSameAsOneByOne(axisPlaneRays(region, 4096, 23), param.filtered, 0xfff7u, packet, one);
    EXPECT_GT(hits, minimumHits);

    // Any hits: the same rays, and a camera's shadow rays toward one light (inside the mesh's
    // bounds, so that some reach it and some do not).
    const auto occludePacket = [&](const std::array<Ray, 16>& rays, uint32_t active,
                                   const std::array<HitFilter, 16>& filters) {
      return blas.occludedPacket(rays, active, filters, 3);
    };
    const auto occludeOne = [&](const Ray& r, const HitFilter& f) { return blas.occluded(r, f, 3); };
    const auto intersectOne = [&](Ray& r, Hit& h) { return blas.intersect(r, h); };
    const std::vector<Ray> shadows = shadowRaysToward(cameraTiles({3.0f, -2.5f, 1.5f}, {0.0f, 0.0f, 0.0f}, 64, 48),
                                                      glm::mix(region.min, region.max, 0.6f), intersectOne);
    for (const auto& [rays, active] : {std::pair{shadows, 0xffffu}, std::pair{shadows, 0x5a3cu},
                                       std::pair{cameraTiles({0.1f, 0.2f, 0.05f}, {1.0f, -0.3f, 0.2f}, 64, 48, 0.8f),
                                                 0xffffu},
                                       std::pair{makeRandomRays(region, 4096, 17), 0xffffu},
                                       std::pair{axisPlaneRays(region, 4096, 23), 0xfff7u},
                                       std::pair{narrowTiles, 0xffffu}}) {
      occluded += expectSameOcclusionAsOneByOne(rays, param.filtered, active, occludePacket, occludeOne);
      traced += static_cast<uint32_t>(rays.size() / kMaxPacketRays) * std::popcount(active);
      for (size_t base = 0; base + kMaxPacketRays <= rays.size(); base += kMaxPacketRays)
        ++packetsBySpread[partWidely(std::span(rays).subspan(base, kMaxPacketRays))];
    }
  }
  // Any-hit packets take both ways through the nodes (interval alone; each child ray by ray).
  EXPECT_GT(packetsBySpread[0], 100u);
  EXPECT_GT(packetsBySpread[1], 100u);
  EXPECT_GT(occluded, traced / 8) << "too few rays occluded to test any hits";
  EXPECT_LT(occluded, traced - traced / 8) << "too few rays reach their end to test any hits";
}

INSTANTIATE_TEST_SUITE_P(Widths, BlasPackets,
                         ::testing::Values(PacketCase{16, false}, PacketCase{16, true}, PacketCase{8, false},
                                           PacketCase{8, true}, PacketCase{8, false, false},
                                           PacketCase{8, true, false}));

/// A slanted grid of triangles (two per cell, shared edges) and camera packets whose rays pass
/// exactly through its vertices and along its edges: the packets' edge cull
/// (trianglesPacketMayCross) must keep every triangle such a ray can hit, so each ray hits the
/// grid (watertight) and as it does when traced alone.
TEST_P(BlasPackets, RaysThroughSharedVerticesAndEdgesAllHit) {
  const PacketCase param = GetParam();
  if (param.nodeWidth == 16 && !bvh_detail::wide16Available()) GTEST_SKIP() << "no AVX-512 on this CPU";
  constexpr int kCells = 48;
  TestMesh grid;
  const auto corner = [](int i, int j) {   // integers: exactly representable, slanted plane
    return glm::vec3(float(i), float(j), 0.5f * float(i) + 0.25f * float(j));
  };
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) grid.positions.push_back(corner(i, j));
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const uint32_t a = j * (kCells + 1) + i, b = a + 1, c = a + kCells + 1, d = c + 1;
      grid.indices.insert(grid.indices.end(), {a, b, d, a, d, c});
    }
  BvhBuildConfig config;
  config.nodeWidth = param.nodeWidth;
  config.allowAvx512 = param.allowAvx512;
  Blas blas;
  blas.build(grid.input(), config);
  const std::array<HitFilter, kMaxPacketRays> filters{};
  const glm::vec3 eyes[] = {{24.0f, 24.0f, 60.0f}, {-7.0f, 30.0f, 40.0f}, {13.0f, 5.0f, 80.0f}};
  uint32_t packets = 0;
  for (const glm::vec3& eye : eyes)
    for (int tj = 1; tj + 4 < kCells; tj += 5)
      for (int ti = 1; ti + 4 < kCells; ti += 5) {
        // 4x4 rays per packet: at vertices, at edge midpoints (half-integers) and at cell
        // diagonals' midpoints; directions unnormalised, so each ray's line meets its point.
        std::array<Ray, kMaxPacketRays> rays;
        for (int k = 0; k < 16; ++k) {
          const float x = float(ti) + 0.5f * float(k % 4), y = float(tj) + 0.5f * float(k / 4);
          rays[k].origin = eye;
          rays[k].dir = glm::vec3(x, y, 0.5f * x + 0.25f * y) - eye;
        }
        std::array<Ray, kMaxPacketRays> alone = rays;
        std::array<Hit, kMaxPacketRays> hits;
        const uint32_t found = blas.intersectPacket(rays, hits, 0xffffu, filters);
        ++packets;
        for (int k = 0; k < 16; ++k) {
          Hit one;
          ASSERT_TRUE(blas.intersect(alone[k], one)) << "ray " << k << " leaked through the grid alone";
          ASSERT_TRUE(found >> k & 1) << "ray " << k << " leaked through the grid in a packet";
          EXPECT_EQ(hits[k].t, one.t);
        }
      }
  EXPECT_GT(packets, 200u);
}

class TlasPackets : public ::testing::TestWithParam<uint32_t> {};

TEST_P(TlasPackets, SameHitsAsRayByRay) {
  const uint32_t instanceCount = GetParam();
  std::mt19937 rng(instanceCount);
  TestMesh soup = makeTriangleSoup(3000, 41, 0.2f);
  TestMesh sphere = makeSphere(800);
  for (TestMesh* m : {&soup, &sphere}) {   // one-sided triangles, culled by each lane's own rule
    m->rules.assign(m->triangleCount(), HitRule::Opaque);
    for (uint32_t i = 0; i < m->triangleCount(); i += 2) m->rules[i] = HitRule::OneSided;
  }
  Blas soupBlas, sphereBlas;
  soupBlas.build(soup.input());
  sphereBlas.build(sphere.input());
  std::vector<TlasInstance> instances(instanceCount);
  for (uint32_t i = 0; i < instanceCount; ++i) {
    instances[i].blas = i % 2 ? &sphereBlas : &soupBlas;
    // A big "world", an untransformed one (traced without a copy of its rays), then movers.
    instances[i].objectToWorld = i == 0 ? glm::mat4x3(4.0f) : i == 6 ? glm::mat4x3(1.0f) : makeRandomTransform(rng, 6.0f);
    if (i % 3 == 2) instances[i].objectToWorld[1] = -instances[i].objectToWorld[1];   // mirrored
    instances[i].mask = i % 5 == 4 ? 2u : 1u;
  }
  Tlas tlas;
  tlas.build(instances);
  for (const uint32_t rayMask : {1u, 3u}) {
    const auto packet = [&](std::array<Ray, 16>& rays, std::array<Hit, 16>& hits, uint32_t active,
                            const std::array<HitFilter, 16>& filters) {
      return tlas.intersectPacket(rays, hits, active, rayMask, filters);
    };
    const auto one = [&](Ray& r, Hit& h, const HitFilter& f) { return tlas.intersect(r, h, rayMask, f); };
    uint32_t hits = 0;
    hits += expectSameAsOneByOne(cameraTiles({15.0f, -12.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, 64, 64), false, 0xffffu,
                                 packet, one);
    hits += expectSameAsOneByOne(cameraTiles({0.5f, 0.5f, 0.5f}, {3.0f, 1.0f, -1.0f}, 32, 32), false, 0xbeefu,
                                 packet, one);
    hits += expectSameAsOneByOne(makeRandomRays(tlas.bounds(), 2048, 7), false, 0xffffu, packet, one);
    hits += expectSameAsOneByOne(axisPlaneRays(tlas.bounds(), 1024, 29), false, 0xfff7u, packet, one);
    // Untraceable rays among a camera's: the packet's lanes must leave them out as a ray alone does.
    std::vector<Ray> mixed = cameraTiles({15.0f, -12.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, 32, 32);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (size_t k = 0; k < mixed.size(); k += 3) {
      switch (k / 3 % 5) {
        case 0: mixed[k].dir = glm::vec3(0.0f); break;
        case 1: mixed[k].dir.y = nan; break;
        case 2: mixed[k].origin.z = inf; break;
        case 3: mixed[k].tmin = mixed[k].tmax = nan; break;
        default: mixed[k].tmin = 2.0f, mixed[k].tmax = 1.0f; break;
      }
    }
    hits += expectSameAsOneByOne(mixed, false, 0xffffu, packet, one);
    // Rays that end partway (a box beyond the farthest tmax of a packet is culled, none nearer).
    std::vector<Ray> segments = cameraTiles({15.0f, -12.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, 64, 64);
    for (size_t k = 0; k < segments.size(); ++k) segments[k].tmax = 14.0f + float(k % 11);
    hits += expectSameAsOneByOne(segments, false, 0xffffu, packet, one);
    EXPECT_GT(hits, 500u);

    // Any hits: the world's packet, then the movers ray by ray.
    const auto occludePacket = [&](const std::array<Ray, 16>& rays, uint32_t active,
                                   const std::array<HitFilter, 16>& filters) {
      return tlas.occludedPacket(rays, active, rayMask, filters);
    };
    const auto occludeOne = [&](const Ray& r, const HitFilter& f) { return tlas.occluded(r, rayMask, f); };
    const auto intersectOne = [&](Ray& r, Hit& h) { return tlas.intersect(r, h, rayMask); };
    uint32_t occluded = 0, traced = 0;
    for (const glm::vec3& light : {glm::vec3(0.0f), glm::vec3(2.0f, -3.0f, 4.0f)}) {
      const std::vector<Ray> shadows =
          shadowRaysToward(cameraTiles({15.0f, -12.0f, 6.0f}, {0.0f, 0.0f, 0.0f}, 64, 64), light, intersectOne);
      occluded += expectSameOcclusionAsOneByOne(shadows, true, 0xffffu, occludePacket, occludeOne);
      traced += static_cast<uint32_t>(shadows.size());
    }
    occluded += expectSameOcclusionAsOneByOne(mixed, false, 0xfff7u, occludePacket, occludeOne);
    occluded += expectSameOcclusionAsOneByOne(segments, true, 0xffffu, occludePacket, occludeOne);
    traced += static_cast<uint32_t>(mixed.size() / kMaxPacketRays * 15 + segments.size());
    EXPECT_GT(occluded, 200u) << "too few rays occluded to test any hits";
    EXPECT_LT(occluded, traced - 200u) << "too few rays reach their end to test any hits";
  }
}

// One to four levels of instance groups (1, 9..64, 65..512, 600).
INSTANTIATE_TEST_SUITE_P(InstanceCounts, TlasPackets, ::testing::Values(1u, 9u, 64u, 65u, 600u));

// Tlas::raysMayHit, the cull before a packet query few rays need (the first-person weapon's):
// it keeps every ray that hits, and drops the rays that point away, end before the box or start
// past it.
TEST(TlasPackets, RaysMayHitKeepsEveryRayThatHits) {
  std::mt19937 rng(5);
  const TestMesh sphere = makeSphere(400);
  Blas blas;
  blas.build(sphere.input());
  std::vector<TlasInstance> instances(3, TlasInstance{&blas});
  for (TlasInstance& in : instances) in.objectToWorld = makeRandomTransform(rng, 3.0f);
  Tlas tlas;
  EXPECT_EQ(tlas.raysMayHit({}, 0u), 0u);   // before any build: nothing to hit
  tlas.build(instances);
  uint32_t hitCount = 0, dropped = 0;
  for (const std::vector<Ray>& rays : {cameraTiles({9.0f, -7.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, 64, 64),
                                       makeRandomRays(tlas.bounds(), 2048, 3), axisPlaneRays(tlas.bounds(), 1024, 8)}) {
    for (size_t first = 0; first + kMaxPacketRays <= rays.size(); first += kMaxPacketRays) {
      const std::span<const Ray> packet(rays.data() + first, kMaxPacketRays);
      const uint32_t may = tlas.raysMayHit(packet, 0xffffu);
      EXPECT_EQ(tlas.raysMayHit(packet, 0x00f0u), may & 0x00f0u) << "inactive lanes are never kept";
      for (uint32_t lane = 0; lane < kMaxPacketRays; ++lane) {
        Ray ray = packet[lane];
        Hit hit;
        if (tlas.intersect(ray, hit)) {
          ++hitCount;
          EXPECT_TRUE(may >> lane & 1) << "ray " << first + lane << " hits but was culled";
        }
        dropped += !(may >> lane & 1);
      }
    }
  }
  EXPECT_GT(hitCount, 500u);
  EXPECT_GT(dropped, 500u) << "the camera looks at the instances from outside their box: most rays miss it";
  // Known answers at one moved instance's box: a ray along its face plane enters it; one that
  // ends short of it, starts past it or points away does not.
  TlasInstance moved{&blas};
  moved.objectToWorld[3] = glm::vec3(10.0f, -4.0f, 2.0f);
  Tlas one;
  one.build(std::span(&moved, 1));
  const Bounds box = one.bounds();
  const glm::vec3 centre = box.center();
  std::array<Ray, 5> known;
  known[0].origin = glm::vec3(box.min.x - 1.0f, box.max.y, centre.z), known[0].dir = glm::vec3(1.0f, 0.0f, 0.0f);
  known[1].origin = glm::vec3(box.min.x - 1.0f, centre.y, centre.z), known[1].dir = glm::vec3(1.0f, 0.0f, 0.0f);
  known[1].tmax = 0.5f;
  known[2].origin = known[1].origin, known[2].dir = known[1].dir, known[2].tmin = box.max.x - box.min.x + 2.0f;
  known[3].origin = known[1].origin, known[3].dir = glm::vec3(-1.0f, 0.1f, 0.0f);
  known[4].origin = known[1].origin, known[4].dir = glm::vec3(1.0f, 0.01f, -0.01f);
  EXPECT_EQ(one.raysMayHit(known, 0x1fu), 0b10001u);
  EXPECT_THROW(one.raysMayHit(known, 0x3fu), std::invalid_argument);
}

TEST(Packets, ShortSpansAreRejected) {
  Blas blas;
  blas.build(makeSphere(100).input());
  std::array<Ray, 4> rays;
  std::array<Hit, 4> hits;
  std::array<HitFilter, 4> filters;
  EXPECT_THROW(blas.intersectPacket(rays, hits, 0x1fu, filters), std::invalid_argument);
  EXPECT_EQ(blas.intersectPacket(rays, hits, 0u, filters), 0u);
  EXPECT_THROW(blas.occludedPacket(rays, 0x1fu, filters), std::invalid_argument);
  EXPECT_EQ(blas.occludedPacket(rays, 0u, filters), 0u);
  const TlasInstance instance{&blas};
  Tlas tlas;
  tlas.build(std::span(&instance, 1));
  EXPECT_THROW(tlas.occludedPacket(rays, 0x1fu, 1u, filters), std::invalid_argument);
}

}  // namespace
}  // namespace pa::testing
