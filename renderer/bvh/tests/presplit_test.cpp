// Triangle pre-splitting: the conservative clipped boxes (known answers and containment of
// sampled points), the splitter on a long diagonal triangle, and that splitting changes
// neither hits nor distances, nor the build's independence of the thread count.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "renderer/bvh/binary_bvh.h"
#include "renderer/bvh/bvh.h"
#include "renderer/bvh/presplit.h"
#include "renderer/bvh/reference_traversal.h"
#include "renderer/bvh/testing/identical_hits.h"
#include "renderer/bvh/tests/same_tree.h"
#include "renderer/bvh/testing/scene_generators.h"
#include "renderer/bvh/triangle_mesh.h"

namespace pa::testing {
namespace {

using namespace pa::bvh_detail;

Bounds box(glm::vec3 lo, glm::vec3 hi) { return Bounds{lo, hi}; }

void expectBox(const Bounds& got, const Bounds& want, float tolerance = 1e-5f) {
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(got.min[a], want.min[a], tolerance) << "axis " << a;
    EXPECT_NEAR(got.max[a], want.max[a], tolerance) << "axis " << a;
    EXPECT_LE(got.min[a], want.min[a]) << "axis " << a;   // conservative
    EXPECT_GE(got.max[a], want.max[a]) << "axis " << a;
  }
}

TEST(ClippedTriangleBounds, KnownAnswers) {
  const glm::vec3 o(0, 0, 0), x4(4, 0, 0), y4(0, 4, 0);
  // Flat right triangle cut at x = 1: the left part keeps the full height, the right loses it.
  expectBox(clippedTriangleBounds(o, x4, y4, box({0, 0, 0}, {1, 4, 0})), box({0, 0, 0}, {1, 4, 0}));
  expectBox(clippedTriangleBounds(o, x4, y4, box({1, 0, 0}, {4, 4, 0})), box({1, 0, 0}, {4, 3, 0}));
  // Slanted (z = x) triangle: the cut bounds z as well.
  expectBox(clippedTriangleBounds(o, {4, 0, 4}, y4, box({0, 0, 0}, {1, 4, 4})), box({0, 0, 0}, {1, 4, 1}));
  // Plane z = y; the cell [1,2]^2 (x, y) lies inside the triangle's projection, so the part's
  // corners are where the cell's z-edges pierce the plane (no vertex or edge of the triangle).
  expectBox(clippedTriangleBounds(o, x4, {0, 4, 4}, box({1, 1, -9}, {2, 2, 9})), box({1, 1, 1}, {2, 2, 2}));
  // A cell the triangle misses gives an empty box; a cell holding it gives its box exactly.
  EXPECT_TRUE(clippedTriangleBounds(o, x4, y4, box({3, 3, -1}, {4, 4, 1})).empty());
  const Bounds whole = clippedTriangleBounds(o, x4, y4, box({-1, -1, -1}, {5, 5, 5}));
  EXPECT_EQ(whole.min, glm::vec3(0, 0, 0));
  EXPECT_EQ(whole.max, glm::vec3(4, 4, 0));
}

/// Points of triangle (a, b, c) in double, on a barycentric grid including edges and corners.
std::vector<glm::dvec3> samplePoints(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, int steps) {
  std::vector<glm::dvec3> points;
  const glm::dvec3 da(a), db(b), dc(c);
  for (int i = 0; i <= steps; ++i)
    for (int j = 0; i + j <= steps; ++j) {
      const double u = double(i) / steps, v = double(j) / steps;
      points.push_back(da + u * (db - da) + v * (dc - da));
    }
  return points;
}

bool contains(const Bounds& b, const glm::dvec3& p) {
  for (int a = 0; a < 3; ++a)
    if (p[a] < double(b.min[a]) || p[a] > double(b.max[a])) return false;
  return true;
}

TEST(ClippedTriangleBounds, ContainsEveryPointOfThePartInRandomCells) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), f(0.0f, 1.0f);
  for (int trial = 0; trial < 400; ++trial) {
    glm::vec3 v[3];
    const float scale = trial % 3 == 0 ? 1000.0f : 1.0f;
    for (glm::vec3& p : v) p = scale * glm::vec3(u(rng), u(rng), u(rng));
    if (trial % 4 == 1) v[2] = v[0] + 1e-3f * (v[2] - v[0]);   // long and thin
    if (trial % 4 == 2) v[0].z = v[1].z = v[2].z;                // axis aligned
    Bounds tri;
    for (const glm::vec3& p : v) tri.extend(p);
    Bounds cell;
    for (int a = 0; a < 3; ++a) {
      const float s = tri.min[a] + f(rng) * (tri.max[a] - tri.min[a]);
      const float t = tri.min[a] + f(rng) * (tri.max[a] - tri.min[a]);
      cell.min[a] = std::min(s, t);
      cell.max[a] = trial % 2 ? std::max(s, t) : tri.max[a];
    }
    const Bounds clipped = clippedTriangleBounds(v[0], v[1], v[2], cell);
    uint32_t inside = 0;
    for (const glm::dvec3& p : samplePoints(v[0], v[1], v[2], 60)) {
      if (!contains(cell, p)) continue;
      ++inside;
      ASSERT_TRUE(contains(clipped, p)) << "trial " << trial;
    }
    if (!clipped.empty()) {
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(clipped.min[a], cell.min[a]);
        EXPECT_LE(clipped.max[a], cell.max[a]);
      }
    } else {
      EXPECT_EQ(inside, 0u) << "trial " << trial;
    }
  }
}

TEST(Presplit, LongDiagonalTriangleSplitsIntoSmallerCoveringBoxes) {
  TestMesh m;
  m.positions = {{0, 0, 0}, {100, 100, 100}, {0.5f, 0, 0}};
  m.indices = {0, 1, 2};
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  PresplitScratch scratch;
  const std::span<const SplitRef> refs = presplitTriangles(mesh, 4.0f, scratch);   // up to 4 more
  ASSERT_EQ(refs.size(), 5u);
  const Bounds whole = triangleBounds(mesh)[0];
  float area = 0.0f;
  for (const SplitRef& r : refs) {
    EXPECT_EQ(r.tri, 0u);
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(r.min[a], whole.min[a]);
      EXPECT_LE(r.max[a], whole.max[a]);
    }
    area += Bounds{r.min, r.max}.halfArea();
  }
  EXPECT_LT(area, 0.5f * whole.halfArea());   // a diagonal sliver: the pieces' boxes are far smaller
  // The cuts are planes of the power-of-two grid over the mesh box [0, 100]^3: 50 (the middle),
  // then 25 and 75, then 12.5 (the outer eighths of a box are not cut), here all across y (exact
  // ends); z = y on this triangle, x follows the edge from (0.5, 0, 0): 0.5 + 0.995 y.
  const float cuts[6] = {0.0f, 12.5f, 25.0f, 50.0f, 75.0f, 100.0f};
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(refs[k].min.y, cuts[k]);
    EXPECT_EQ(refs[k].max.y, cuts[k + 1]);
    EXPECT_NEAR(refs[k].min.z, cuts[k], 1e-4f);       // z and x are clipped (rounded outwards)
    EXPECT_NEAR(refs[k].max.z, cuts[k + 1], 1e-4f);
    EXPECT_NEAR(refs[k].min.x, cuts[k], 1e-4f);
    EXPECT_NEAR(refs[k].max.x, k == 4 ? 100.0f : 0.5f + 0.995f * cuts[k + 1], 1e-4f);
  }
  for (const glm::dvec3& p : samplePoints(m.positions[0], m.positions[1], m.positions[2], 200))
    ASSERT_TRUE(std::any_of(refs.begin(), refs.end(), [&](const SplitRef& r) { return contains({r.min, r.max}, p); }));
  // No budget: one reference, the triangle's box.
  const std::span<const SplitRef> none = presplitTriangles(mesh, 0.0f, scratch);
  ASSERT_EQ(none.size(), 1u);
  EXPECT_EQ(none[0].min, whole.min);
  EXPECT_EQ(none[0].max, whole.max);
}

TEST(Presplit, BudgetIsRespectedAndLeavesListATriangleOnce) {
  TestMesh m = makeThinTriangles(20000, 41);
  m.append(makeTriangleSoup(5000, 42));
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  for (const float budget : {0.1f, 0.5f}) {
    PresplitScratch scratch;
    const size_t refs = presplitTriangles(mesh, budget, scratch).size();
    EXPECT_GT(refs, size_t(mesh.triangleCount()));
    EXPECT_LE(refs, size_t(mesh.triangleCount() * (1.0f + budget)));
    BvhBuildConfig config;
    config.splitBudget = budget;
    const BinaryBvh bvh = buildBinaryBvh(mesh, config);
    std::vector<uint8_t> seen(mesh.triangleCount(), 0);
    for (const BinaryNode& n : bvh.nodes) {
      if (!n.isLeaf()) continue;
      std::set<uint32_t> inLeaf(bvh.primIndices.begin() + n.first, bvh.primIndices.begin() + n.first + n.count);
      EXPECT_EQ(inLeaf.size(), n.count);
      for (const uint32_t t : inLeaf) seen[t] = 1;
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(mesh.triangleCount()));
  }
}

TEST(Presplit, BudgetZeroGivesTheUnsplitTree) {
  const TriangleMesh mesh = makeTriangleMesh(makeThinTriangles(8000, 43).input());
  BvhBuildConfig config;
  config.splitBudget = 0.0f;
  const BinaryBvh fromMesh = buildBinaryBvh(mesh, config), fromBounds = buildBinaryBvh(triangleBounds(mesh), config);
  ASSERT_EQ(fromMesh.primIndices, fromBounds.primIndices);
  ASSERT_EQ(fromMesh.nodes.size(), fromBounds.nodes.size());
  for (size_t i = 0; i < fromMesh.nodes.size(); ++i) {
    ASSERT_EQ(fromMesh.nodes[i].count, fromBounds.nodes[i].count);
    ASSERT_EQ(fromMesh.nodes[i].bounds.min, fromBounds.nodes[i].bounds.min);
    ASSERT_EQ(fromMesh.nodes[i].bounds.max, fromBounds.nodes[i].bounds.max);
  }
}

TEST(Presplit, RejectsBadBudgets) {
  const TestMesh m = makeTriangleSoup(10, 44);
  for (const float bad : {-0.1f, 4.5f, std::numeric_limits<float>::quiet_NaN()}) {
    BvhBuildConfig config;
    config.splitBudget = bad;
    Blas blas;
    EXPECT_THROW(blas.build(m.input(), config), std::invalid_argument);
  }
}

/// Two Blas over the same mesh must answer every ray identically (identical_hits.h).
void expectSameHits(const Blas& a, const Blas& b, const Bounds& region, uint32_t seed, const HitFilter& filter = {}) {
  auto tracer = [&](const Blas& blas) {
    return Tracer{[&blas, &filter](Ray& r, Hit& h) { return blas.intersect(r, h, filter); },
                  [&blas, &filter](const Ray& r) { return blas.occluded(r, filter); }};
  };
  uint32_t hits = 0;
  expectIdenticalHits(tracer(a), tracer(b), makeRandomRays(region, 100000, seed), hits);
  EXPECT_GT(hits, 1000u);
}

TEST(Presplit, SameHitsWithAndWithoutSplitting) {
  TestMesh m = makeThinTriangles(30000, 45);
  m.append(makeTriangleSoup(20000, 46));
  Bounds region = m.bounds();
  region.min -= glm::vec3(0.5f);
  region.max += glm::vec3(0.5f);
  Blas plain, split;
  BvhBuildConfig off, on;
  off.splitBudget = 0.0f;
  on.splitBudget = 1.0f;
  plain.build(m.input(), off);
  split.build(m.input(), on);
  EXPECT_EQ(plain.bounds().min, split.bounds().min);
  EXPECT_EQ(plain.bounds().max, split.bounds().max);
  expectSameHits(plain, split, region, 47);
  // The reference traversal of the split binary tree agrees as well.
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  const BinaryBvh bvh = buildBinaryBvh(mesh, on);
  const Tracer blas{[&](Ray& r, Hit& h) { return plain.intersect(r, h); },
                    [&](const Ray& r) { return plain.occluded(r); }};
  const Tracer reference{[&](Ray& r, Hit& h) { return intersectReference(mesh, bvh, r, h, {}, 0); },
                         [&](const Ray& r) { return occludedReference(mesh, bvh, r, {}, 0); }};
  uint32_t referenceHits = 0;
  expectIdenticalHits(blas, reference, makeRandomRays(region, 20000, 48), referenceHits);
}

TEST(Presplit, SameHitsThroughTheHitFilter) {
  // Alpha-masked triangles: a split triangle may reach the filter from several leaves; the
  // filter is a pure function of (prim, u, v), so the answers must not change.
  TestMesh m = makeThinTriangles(20000, 54);
  m.append(makeTriangleSoup(10000, 55, 0.2f));
  m.rules.assign(m.triangleCount(), HitRule::Opaque);
  for (uint32_t t = 0; t < m.triangleCount(); t += 2) m.rules[t] = HitRule::Filtered;
  const HitFilter filter{[](const void*, uint32_t, uint32_t prim, float u, float v, float) { return prim % 4 == 0 || u < v; },
                         nullptr};
  Blas plain, split;
  BvhBuildConfig on;
  on.splitBudget = 1.0f;
  plain.build(m.input());
  split.build(m.input(), on);
  expectSameHits(plain, split, {glm::vec3(-1.5f), glm::vec3(1.5f)}, 56, filter);
}

/// Splits m with the largest budget and checks the references and the hits against no split.
void expectSafeSplit(const TestMesh& m, size_t minRefs) {
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  PresplitScratch scratch;
  const std::span<const SplitRef> refs = presplitTriangles(mesh, 4.0f, scratch);
  EXPECT_GE(refs.size(), minRefs);
  const std::vector<Bounds> boxes = triangleBounds(mesh);
  for (const SplitRef& r : refs)
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(r.min[a], boxes[r.tri].min[a]);
      EXPECT_LE(r.max[a], boxes[r.tri].max[a]);
      EXPECT_LE(r.min[a], r.max[a]);
    }
  Blas plain, split;
  BvhBuildConfig on;
  on.splitBudget = 4.0f;
  plain.build(m.input());
  split.build(m.input(), on);
  uint32_t hits = 0;
  for (const Ray& r : makeRaysFromPoint(glm::vec3(0.0f, 0.0f, -1.0f), 20000, 57)) {
    Ray ra = r, rb = r;
    Hit ha, hb;
    ASSERT_EQ(plain.intersect(ra, ha), split.intersect(rb, hb));
    ASSERT_EQ(ha.t, hb.t);
    hits += ha.valid();
  }
  EXPECT_GT(hits, 0u);
}

TEST(Presplit, ExtremeCoordinatesSplitSafely) {
  // A long diagonal across 1e30, a small triangle far out and a tiny one at the origin: split,
  // with references inside their triangles' boxes and the same hits.
  TestMesh m;
  m.positions = {{-1e30f, 0, 0},       {1e30f, 1e30f, 1e30f},         {1e30f, 0, 1e-30f},
                 {1e20f, 1e20f, 1e20f}, {1e20f + 1e13f, 1e20f, 1e20f}, {1e20f, 1e20f + 1e13f, 1e20f + 1e13f},
                 {1e-30f, 0, 0},        {0, 1e-30f, 0},                {0, 0, 1e-30f}};
  m.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  expectSafeSplit(m, 4);
  // Add a triangle whose box area (and the mesh box's extent) overflows float: the grid has no
  // planes on those axes and priorities are not finite, so nothing is split; still no crash.
  constexpr float kHuge = 3e38f;
  m.positions.insert(m.positions.end(), {{-kHuge, -kHuge, 0}, {kHuge, kHuge, 1}, {kHuge, -kHuge, 2}});
  m.indices.insert(m.indices.end(), {9, 10, 11});
  expectSafeSplit(m, 4);
}

TEST(Presplit, RefitOfASplitTreeEqualsRebuild) {
  TestMesh base = makeThinTriangles(6000, 49);
  base.append(makeSphere(4000));
  TestMesh moved = base;
  for (glm::vec3& p : moved.positions) p += 0.3f * glm::vec3(std::sin(4.0f * p.y), std::cos(3.0f * p.z), 0.5f * p.x);
  BvhBuildConfig on;
  on.splitBudget = 0.5f;
  Blas refitted, rebuilt;
  refitted.build(base.input(), on);
  refitted.refit(moved.positions);
  rebuilt.build(moved.input(), on);
  expectSameHits(refitted, rebuilt, {glm::vec3(-2.0f), glm::vec3(2.0f)}, 50);
}

TEST(Presplit, DeterministicForAnyThreadCount) {
  TestMesh m = makeThinTriangles(40000, 51);
  m.append(makeTriangleSoup(20000, 52));
  const TriangleMesh mesh = makeTriangleMesh(m.input());
  BvhBuildConfig config;
  config.parallelThreshold = 1024;
  config.splitBudget = 0.3f;
  auto buildWith = [&](int threads) {
    BinaryBvh out;
    tbb::task_arena(threads).execute([&] { out = buildBinaryBvh(mesh, config); });
    return out;
  };
  const BinaryBvh one = buildWith(1), two = buildWith(2), four = buildWith(4);
  // Reused scratch (left over from another mesh) must not change the tree either.
  BinaryBuildScratch scratch;
  BinaryBvh reused;
  const TriangleMesh other = makeTriangleMesh(makeThinTriangles(50000, 53).input());
  tbb::task_arena(2).execute([&] {
    for (const TriangleMesh* mm : {&other, &mesh}) buildBinaryBvh(*mm, config, scratch, reused);
  });
  for (const BinaryBvh* b : std::initializer_list<const BinaryBvh*>{&two, &four, &reused}) expectSameTree(one, *b);
}

}  // namespace
}  // namespace pa::testing
