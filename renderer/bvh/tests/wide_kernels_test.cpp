// Every traversal kernel this CPU can run (WideKernel::Baseline and, on AVX-512 machines,
// WideKernel::Avx512) against the scalar reference traversal: same hit distances bit for bit,
// same occlusion answers, with and without alpha-masked triangles.
#include <vector>

#include <gtest/gtest.h>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/reference_traversal.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide_bvh.h"

namespace pa::testing {
namespace {

using namespace pa::bvh_detail;

/// Alpha test stand-in: rejects hits on triangles whose index is a multiple of 3, and hits
/// with u > 0.6 (so the decision depends on the barycentrics the kernel computed).
bool rejectSome(const void*, uint32_t, uint32_t prim, float u, float) { return prim % 3 != 0 && u <= 0.6f; }

std::vector<WideKernel> availableKernels() {
  std::vector<WideKernel> kernels;
  for (WideKernel k : {WideKernel::Baseline, WideKernel::Avx512})
    if (wideKernelAvailable(k)) kernels.push_back(k);
  return kernels;
}

/// Runs rays through every available kernel and the reference; t must match bit for bit (the
/// triangle may differ only on an exact tie, which traversal order decides).
void expectKernelsMatchReference(TestMesh m, uint32_t seed, bool masked) {
  if (masked) {
    m.masked.assign(m.triangleCount(), 0);
    for (uint32_t i = 0; i < m.triangleCount(); i += 2) m.masked[i] = 1;
  }
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  const BinaryBvh binary = buildBinaryBvh(mesh, BvhBuildConfig{});
  WideBvh wide = collapseToWide(binary, mesh);
  const HitFilter filter = masked ? HitFilter{rejectSome, nullptr} : HitFilter{};
  Bounds region = m.bounds();
  region.min -= glm::vec3(0.5f);
  region.max += glm::vec3(0.5f);
  const std::vector<Ray> rays = makeRandomRays(region, 100000, seed);
  for (WideKernel kernel : availableKernels()) {
    SCOPED_TRACE(kernel == WideKernel::Avx512 ? "AVX-512 kernel" : "baseline kernel");
    wide.kernel = kernel;
    uint32_t hits = 0;
    for (const Ray& r : rays) {
      Ray a = r, b = r;
      Hit ha, hb;
      const bool hitA = intersectWide(wide, a, ha, filter, 7);
      const bool hitB = intersectReference(mesh, binary, b, hb, filter, 7);
      ASSERT_EQ(hitA, hitB);
      ASSERT_EQ(occludedWide(wide, r, filter, 7), hitB);
      if (!hitA) continue;
      ++hits;
      ASSERT_EQ(ha.t, hb.t);
      ASSERT_EQ(ha.instance, 7u);
      if (ha.prim == hb.prim) {
        ASSERT_EQ(ha.u, hb.u);
        ASSERT_EQ(ha.v, hb.v);
      }
      Ray s = r;
      s.tmax = ha.t * 0.5f;
      ASSERT_EQ(occludedWide(wide, s, filter, 7), occludedReference(mesh, binary, s, filter, 7));
    }
    EXPECT_GT(hits, rays.size() / 50);
  }
}

TEST(WideKernels, BestKernelIsAvailable) {
  EXPECT_TRUE(wideKernelAvailable(WideKernel::Baseline));
  EXPECT_TRUE(wideKernelAvailable(bestWideKernel()));
}

TEST(WideKernels, MatchReferenceOnSoup) { expectKernelsMatchReference(makeTriangleSoup(20000, 41), 1, false); }

TEST(WideKernels, MatchReferenceOnThinTriangles) { expectKernelsMatchReference(makeThinTriangles(20000, 42), 2, false); }

TEST(WideKernels, MatchReferenceOnSphere) { expectKernelsMatchReference(makeSphere(8000), 3, false); }

TEST(WideKernels, MatchReferenceWithAlphaMaskedTriangles) {
  expectKernelsMatchReference(makeTriangleSoup(20000, 43), 4, true);
}

}  // namespace
}  // namespace pa::testing
