// Embree 3 as the oracle: the same random rays against the same scenes give the same closest
// hits (t within 1e-4 relative, same triangle except at shared edges/vertices) and the same
// any-hit answers, alone and (one group in eight) in packets of 16 (Blas::occludedPacket,
// Tlas::occludedPacket), for every layout this CPU traverses (8-wide, and 16-wide with
// AVX-512); and with one-sided triangles whose back faces the rays cull (Embree filter
// functions as oracle).
#include <array>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/testing/embree_oracle.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/tests/oracle_compare.h"
#include "renderer/bvh/wide16_bvh.h"

namespace pa::testing {
namespace {

constexpr uint32_t kRayCount = 1u << 20;   // >= 1M rays per scene
constexpr uint32_t kPacketEvery = 8;       // any hits in packets: one group of 16 rays in 8

/// Any-hit disagreement is acceptable only when one side's closest hit sits on the segment's
/// end (within tolerance) or on an edge.
void compareOcclusion(OracleTally& tally, bool ours, bool embree, std::span<const std::pair<bool, Hit>> closest,
                      float segmentEnd, float sceneScale) {
  ++tally.rays;
  if (ours == embree) return;
  bool explained = false;
  for (const auto& [hit, h] : closest) {
    const bool atEnd = hit && std::fabs(h.t - segmentEnd) <= 1e-4f * segmentEnd + 1e-5f * sceneScale;
    const bool atEdge = hit && h.t <= segmentEnd && minBarycentric(h) < 1e-3f;
    explained = explained || atEnd || atEdge;
  }
  if (explained) {
    ++tally.edgeCases;
  } else {
    ++tally.unexplained;
    if (tally.firstProblem.empty())
      tally.firstProblem = std::string("occlusion disagrees: ours ") + (ours ? "occluded" : "clear") +
                           " segment end " + std::to_string(segmentEnd) + " closest ours t " +
                           std::to_string(closest[0].second.t) + " embree t " + std::to_string(closest[1].second.t);
  }
}

struct OracleResult {
  OracleTally closest, anyHit, packetAnyHit;
};

/// Runs kRayCount rays through both, any hits also in packets of sixteen consecutive rays; Ours
/// wraps a Blas or a Tlas (intersect, occluded, occludedPacket).
template <typename Ours>
OracleResult runOracle(const Ours& ours, const EmbreeScene& embree, const Bounds& sceneBounds, uint32_t seed) {
  Bounds region = sceneBounds;
  const glm::vec3 pad = 0.25f * (region.max - region.min);
  region.min -= pad;
  region.max += pad;
  const std::vector<Ray> rays = makeRandomRays(region, kRayCount, seed);
  const float scale = glm::length(sceneBounds.max - sceneBounds.min);
  OracleResult result;
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<float> segment(0.0f, 0.5f * scale);
  std::vector<float> ends(rays.size());
  for (float& e : ends) e = segment(rng);
  // Trace in parallel in fixed chunks, merge tallies in order.
  constexpr uint32_t chunk = 1u << 14;
  std::vector<OracleResult> parts(rays.size() / chunk);
  static_assert(chunk % kMaxPacketRays == 0);
  tbb::parallel_for(size_t(0), parts.size(), [&](size_t c) {
    for (uint32_t first = uint32_t(c) * chunk; first < uint32_t(c + 1) * chunk; first += kMaxPacketRays) {
      std::array<Ray, kMaxPacketRays> segments;
      std::array<bool, kMaxPacketRays> embreeOccluded;
      std::array<std::array<std::pair<bool, Hit>, 2>, kMaxPacketRays> closest;
      for (uint32_t k = 0; k < kMaxPacketRays; ++k) {
        const uint32_t i = first + k;
        Ray a = rays[i], b = rays[i];
        Hit ha, hb;
        const bool hitA = ours.intersect(a, ha);
        const bool hitB = embree.intersect(b, hb);
        compareClosest(parts[c].closest, hitA, ha, hitB, hb, scale);
        segments[k] = rays[i];
        segments[k].tmax = ends[i];
        closest[k] = {std::pair{hitA, ha}, std::pair{hitB, hb}};
        embreeOccluded[k] = embree.occluded(segments[k]);
        compareOcclusion(parts[c].anyHit, ours.occluded(segments[k]), embreeOccluded[k], closest[k], ends[i], scale);
      }
      // Random rays make packets whose interval bounds cull nothing: one packet in kPacketEvery.
      if (first / kMaxPacketRays % kPacketEvery != 0) continue;
      const uint32_t packet = ours.occludedPacket(segments);
      for (uint32_t k = 0; k < kMaxPacketRays; ++k)
        compareOcclusion(parts[c].packetAnyHit, (packet >> k & 1) != 0, embreeOccluded[k], closest[k], ends[first + k],
                         scale);
    }
  });
  for (const OracleResult& p : parts) {
    for (auto [dst, src] : {std::pair{&result.closest, &p.closest}, std::pair{&result.anyHit, &p.anyHit},
                            std::pair{&result.packetAnyHit, &p.packetAnyHit}}) {
      dst->rays += src->rays;
      dst->hits += src->hits;
      dst->sameHits += src->sameHits;
      dst->edgeCases += src->edgeCases;
      dst->unexplained += src->unexplained;
      if (dst->firstProblem.empty()) dst->firstProblem = src->firstProblem;
    }
  }
  return result;
}

void expectAgreement(const OracleResult& r) {
  EXPECT_EQ(r.closest.rays, kRayCount);
  EXPECT_EQ(r.closest.unexplained, 0u) << r.closest.firstProblem;
  EXPECT_EQ(r.anyHit.unexplained, 0u) << r.anyHit.firstProblem;
  EXPECT_EQ(r.packetAnyHit.rays, kRayCount / kPacketEvery);
  EXPECT_EQ(r.packetAnyHit.unexplained, 0u) << "in packets: " << r.packetAnyHit.firstProblem;
  EXPECT_GT(r.closest.hits, kRayCount / 20) << "scene should be hit by a fair share of rays";
  EXPECT_LT(r.closest.edgeCases, r.closest.hits / 1000 + 10) << "edge cases should be rare";
  ::testing::Test::RecordProperty("hits", std::to_string(r.closest.hits));
  ::testing::Test::RecordProperty("edge_cases", std::to_string(r.closest.edgeCases));
}

/// Every layout this CPU can traverse: 8-wide, and 16-wide where AVX-512 is available.
std::vector<uint32_t> availableNodeWidths() {
  std::vector<uint32_t> widths{8};
  if (bvh_detail::wide16Available()) widths.push_back(16);
  return widths;
}

/// A Blas traced by rays that cull `cull` (HitFilter::cull).
struct BlasAdapter {
  const Blas& blas;
  FaceCull cull = FaceCull::None;
  bool intersect(Ray& r, Hit& h) const { return blas.intersect(r, h, HitFilter{nullptr, nullptr, cull}); }
  bool occluded(const Ray& r) const { return blas.occluded(r, HitFilter{nullptr, nullptr, cull}); }
  uint32_t occludedPacket(const std::array<Ray, kMaxPacketRays>& rays) const {
    std::array<HitFilter, kMaxPacketRays> filters;
    filters.fill(HitFilter{nullptr, nullptr, cull});
    return blas.occludedPacket(rays, 0xffffu, filters);
  }
};

/// Our Blas over `mesh` on every layout against Embree's; with `cullBackFaces`, rays cull back
/// faces on both sides (our HitFilter::cull, Embree's filter functions by the world winding).
void checkMesh(const TestMesh& mesh, uint32_t seed, bool cullBackFaces = false) {
  EmbreeDevice device;
  EmbreeScene embree(device);
  embree.addMesh(mesh, cullBackFaces);
  embree.commit();
  for (const uint32_t width : availableNodeWidths()) {
    SCOPED_TRACE("node width " + std::to_string(width));
    BvhBuildConfig config;
    config.nodeWidth = width;
    Blas blas;
    blas.build(mesh.input(), config);
    expectAgreement(
        runOracle(BlasAdapter{blas, cullBackFaces ? FaceCull::Back : FaceCull::None}, embree, mesh.bounds(), seed));
  }
}

TEST(EmbreeOracle, RandomTriangleSoup) { checkMesh(makeTriangleSoup(100000, 1), 11); }

TEST(EmbreeOracle, LongThinTriangles) { checkMesh(makeThinTriangles(50000, 2), 12); }

TEST(EmbreeOracle, TessellatedSphere) { checkMesh(makeSphere(20000), 13); }

/// One-sided triangles (two in three) among opaque ones, rays culling back faces: Embree's
/// filter functions reject back-face hits by the world winding, as the renderer's callback did.
TEST(EmbreeOracle, OneSidedTrianglesCulledByFace) {
  TestMesh mesh = makeTriangleSoup(100000, 15);
  mesh.append(makeSphere(20000, glm::vec3(0.3f, -0.2f, 0.1f), 0.5f));   // closed: back faces behind front ones
  mesh.rules.assign(mesh.triangleCount(), HitRule::OneSided);
  for (uint32_t t = 0; t < mesh.triangleCount(); t += 3) mesh.rules[t] = HitRule::Opaque;
  checkMesh(mesh, 16, true);
}

/// Our Tlas with Blas instances vs Embree instances of one scene.
struct TlasAdapter {
  const Tlas& tlas;
  bool intersect(Ray& r, Hit& h) const { return tlas.intersect(r, h); }
  bool occluded(const Ray& r) const { return tlas.occluded(r); }
  uint32_t occludedPacket(const std::array<Ray, kMaxPacketRays>& rays) const {
    return tlas.occludedPacket(rays, 0xffffu, 0xffffffffu, std::array<HitFilter, kMaxPacketRays>{});
  }
};

TEST(EmbreeOracle, InstancedCopies) {
  const TestMesh soup = makeTriangleSoup(5000, 3, 0.1f);
  const TestMesh sphere = makeSphere(4000, glm::vec3(0.0f), 0.8f);
  Blas blasSoup, blasSphere;
  blasSoup.build(soup.input());
  blasSphere.build(sphere.input());
  EmbreeDevice device;
  EmbreeScene embreeSoup(device), embreeSphere(device), embreeTop(device);
  embreeSoup.addMesh(soup);
  embreeSoup.commit();
  embreeSphere.addMesh(sphere);
  embreeSphere.commit();
  std::mt19937 rng(5);
  // An untransformed copy first: the static world that Tlas::occludedPacket traces as packets.
  std::vector<TlasInstance> instances{{&blasSoup, glm::mat4x3(1.0f), 0xffffffffu}};
  embreeTop.addInstance(embreeSoup, glm::mat4x3(1.0f));
  for (uint32_t i = 0; i < 64; ++i) {
    const glm::mat4x3 m = makeRandomTransform(rng, 8.0f);
    const bool isSphere = i % 3 == 0;
    instances.push_back({isSphere ? &blasSphere : &blasSoup, m, 0xffffffffu});
    embreeTop.addInstance(isSphere ? embreeSphere : embreeSoup, m);
  }
  embreeTop.commit();
  Tlas tlas;
  tlas.build(instances);
  expectAgreement(runOracle(TlasAdapter{tlas}, embreeTop, tlas.bounds(), 14));
}

}  // namespace
}  // namespace pa::testing
