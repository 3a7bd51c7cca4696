// Every traversal kernel this CPU can run (WideKernel::Baseline and, on AVX-512 machines,
// WideKernel::Avx512) against the scalar reference traversal: same hit distances bit for bit,
// same occlusion answers, with and without alpha-masked (and one-sided) triangles.
#include <vector>

#include <gtest/gtest.h>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/reference_traversal.h"
#include "renderer/bvh/testing/identical_hits.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/triangle_mesh.h"
#include "renderer/bvh/wide_bvh.h"

namespace pa::testing {
namespace {

using namespace pa::bvh_detail;

/// Alpha test stand-in: rejects hits on triangles whose index is a multiple of 3, and hits
/// with u > 0.6 (so the decision depends on the barycentrics the kernel computed).
bool rejectSome(const void*, uint32_t, uint32_t prim, float u, float, float) { return prim % 3 != 0 && u <= 0.6f; }

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
    m.rules.assign(m.triangleCount(), HitRule::Opaque);
    for (uint32_t i = 0; i < m.triangleCount(); ++i)   // and one-sided triangles, back faces culled
      m.rules[i] = i % 2 == 0 ? HitRule::Filtered : i % 4 == 1 ? HitRule::OneSided : HitRule::Opaque;
  }
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  const BinaryBvh binary = buildBinaryBvh(mesh, BvhBuildConfig{});
  WideBvh wide = collapseToWide(binary, mesh);
  const HitFilter filter = masked ? HitFilter{rejectSome, nullptr, FaceCull::Back} : HitFilter{};
  Bounds region = m.bounds();
  region.min -= glm::vec3(0.5f);
  region.max += glm::vec3(0.5f);
  const std::vector<Ray> rays = makeRandomRays(region, 100000, seed);
  for (WideKernel kernel : availableKernels()) {
    SCOPED_TRACE(kernel == WideKernel::Avx512 ? "AVX-512 kernel" : "baseline kernel");
    wide.kernel = kernel;
    const Tracer kernelTracer{[&](Ray& r, Hit& h) {
                                const bool hit = intersectWide(wide, r, h, filter, 7);
                                EXPECT_TRUE(!hit || h.instance == 7u) << "hit reports instance " << h.instance;
                                return hit;
                              },
                              [&](const Ray& r) { return occludedWide(wide, r, filter, 7); }};
    const Tracer reference{[&](Ray& r, Hit& h) { return intersectReference(mesh, binary, r, h, filter, 7); },
                           [&](const Ray& r) { return occludedReference(mesh, binary, r, filter, 7); }};
    uint32_t hits = 0;
    expectIdenticalHits(kernelTracer, reference, rays, hits);
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
