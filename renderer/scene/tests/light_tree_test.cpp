// Light tree and emissive-triangle selection: the pmf is a distribution at every point, sample()
// and pmf() agree (what MIS needs), the estimator stays unbiased, emitters that cannot reach a
// point are not chosen, and everything is deterministic.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/scene/lights/light_sampler.h"
#include "renderer/scene/lights/light_tree.h"

namespace pa {
namespace {

constexpr float kPi = 3.14159265358979323846f;

/// Small deterministic generator (xorshift32) giving floats in [0, 1).
struct Random {
  uint32_t state;
  explicit Random(uint32_t seed) : state(seed ? seed : 1u) {}
  float next() {
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return float(state >> 8) * 0x1p-24f;
  }
  glm::vec3 inBox(float half) { return glm::vec3(next(), next(), next()) * (2.0f * half) - half; }
  glm::vec3 direction() {
    const float z = 1.0f - 2.0f * next();
    const float phi = 2.0f * kPi * next();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
  }
};

EmissiveTriangle makeTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, glm::vec3 emission,
                              bool twoSided) {
  EmissiveTriangle t;
  t.p0 = a;
  t.e1 = b - a;
  t.e2 = c - a;
  const glm::vec3 cross = glm::cross(t.e1, t.e2);
  t.normal = glm::normalize(cross);
  t.area = 0.5f * glm::length(cross);
  t.emission = emission;
  t.twoSided = twoSided;
  return t;
}

/// A soup of emitters of varied size, orientation, sidedness and strength in a 400-unit box.
std::vector<EmissiveTriangle> triangleSoup(uint32_t count, uint32_t seed) {
  Random r(seed);
  std::vector<EmissiveTriangle> tris;
  for (uint32_t i = 0; i < count; ++i) {
    const glm::vec3 centre = r.inBox(200.0f);
    const float size = 2.0f + 30.0f * r.next();
    const glm::vec3 a = centre + size * r.direction();
    const glm::vec3 b = centre + size * r.direction();
    const glm::vec3 c = centre + size * r.direction();
    if (glm::length(glm::cross(b - a, c - a)) < 1e-3f) continue;
    tris.push_back(makeTriangle(a, b, c, glm::vec3(0.5f + 4.0f * r.next()), r.next() < 0.3f));
  }
  return tris;
}

std::vector<LightBounds> boundsOf(const std::vector<EmissiveTriangle>& tris) {
  std::vector<LightBounds> out;
  for (const EmissiveTriangle& t : tris) {
    LightBounds b;
    b.bounds.extend(t.p0);
    b.bounds.extend(t.p0 + t.e1);
    b.bounds.extend(t.p0 + t.e2);
    b.power = kPi * t.area * t.emission.x * (t.twoSided ? 2.0f : 1.0f);
    b.normals = {t.normal, 1.0f};
    b.twoSided = t.twoSided;
    out.push_back(b);
  }
  return out;
}

TEST(DirectionCone, UnionOfKnownCones) {
  const DirectionCone x{glm::vec3(1, 0, 0), 1.0f}, y{glm::vec3(0, 1, 0), 1.0f};
  const DirectionCone xy = coneUnion(x, y);
  EXPECT_NEAR(xy.cosTheta, std::cos(kPi / 4.0f), 1e-5f);
  EXPECT_NEAR(glm::dot(xy.axis, glm::normalize(glm::vec3(1, 1, 0))), 1.0f, 1e-5f);
  // A cone already holding the other is returned as is.
  const DirectionCone wide{glm::vec3(0, 0, 1), 0.0f};
  const DirectionCone inside{glm::normalize(glm::vec3(0.1f, 0, 1)), 0.99f};
  EXPECT_EQ(coneUnion(wide, inside).cosTheta, 0.0f);
  EXPECT_EQ(coneUnion(inside, wide).cosTheta, 0.0f);
  // Opposite directions need the whole sphere; the empty cone is neutral.
  EXPECT_EQ(coneUnion(x, DirectionCone{glm::vec3(-1, 0, 0), 1.0f}).cosTheta, -1.0f);
  EXPECT_EQ(coneUnion(DirectionCone{}, y).cosTheta, 1.0f);
}

TEST(LightTree, PmfSumsToOneAtRandomPoints) {
  const auto tris = triangleSoup(300, 11);
  const LightTree tree(boundsOf(tris));
  ASSERT_FALSE(tree.empty());
  EXPECT_EQ(tree.emitterCount(), tris.size());
  EXPECT_GE(tree.nodeCount(), (tris.size() - 1 + 2) / 3);   // four children per node at most
  EXPECT_LE(tree.nodeCount(), tris.size() - 1);             // two at least
  Random r(5);
  int reached = 0;
  for (int k = 0; k < 200; ++k) {
    const glm::vec3 p = r.inBox(300.0f);
    const glm::vec3 n = k % 4 == 0 ? glm::vec3(0.0f) : r.direction();
    double sum = 0.0;
    for (uint32_t i = 0; i < tris.size(); ++i) {
      const float pmf = tree.pmf(i, p, n);
      ASSERT_GE(pmf, 0.0f);
      sum += pmf;
    }
    uint32_t index;
    float pmf;
    if (tree.sample(p, n, 0.5f, index, pmf)) {
      ++reached;
      EXPECT_NEAR(sum, 1.0, 1e-4) << "point " << k;
    } else {
      EXPECT_EQ(sum, 0.0) << "point " << k;
    }
  }
  EXPECT_GT(reached, 190);   // in a soup of 300 emitters nearly every point sees one
}

TEST(LightTree, SampledPmfIsThePmfOfTheIndex) {
  const auto tris = triangleSoup(500, 3);
  const LightTree tree(boundsOf(tris));
  Random r(9);
  for (int k = 0; k < 2000; ++k) {
    const glm::vec3 p = r.inBox(250.0f);
    const glm::vec3 n = r.direction();
    uint32_t index = 0;
    float pmf = 0.0f;
    if (!tree.sample(p, n, r.next(), index, pmf)) continue;
    ASSERT_LT(index, tris.size());
    EXPECT_NEAR(pmf, tree.pmf(index, p, n), 1e-5f * pmf) << "sample " << k;
  }
}

TEST(LightTree, SampleFrequenciesFollowThePmf) {
  const auto tris = triangleSoup(12, 21);
  const LightTree tree(boundsOf(tris));
  const glm::vec3 p(10.0f, -20.0f, 5.0f), n(0.0f, 0.0f, 1.0f);
  constexpr int kSamples = 200000;
  std::vector<int> hits(tris.size(), 0);
  for (int s = 0; s < kSamples; ++s) {
    uint32_t index;
    float pmf;
    if (tree.sample(p, n, (float(s) + 0.5f) / kSamples, index, pmf)) ++hits[index];
  }
  for (uint32_t i = 0; i < tris.size(); ++i)
    EXPECT_NEAR(double(hits[i]) / kSamples, tree.pmf(i, p, n), 1e-4) << "light " << i;
}

TEST(LightTree, EmitterBehindTheSurfaceIsNotChosen) {
  // The point at the origin faces +z. Six lamps above it face down; six below it face up (bright,
  // near, facing the point, but behind its surface).
  std::vector<EmissiveTriangle> tris;
  for (int i = 0; i < 6; ++i) {
    const float x = 30.0f * float(i) - 75.0f;
    tris.push_back(makeTriangle({x, -5, 50}, {x, 5, 50}, {x + 10, -5, 50}, glm::vec3(1.0f), false));
    tris.push_back(makeTriangle({x, -5, -10}, {x + 10, -5, -10}, {x, 5, -10}, glm::vec3(50.0f), false));
    ASSERT_LT(tris[tris.size() - 2].normal.z, 0.0f);
    ASSERT_GT(tris.back().normal.z, 0.0f);
  }
  const LightSampler sampler({}, tris, Sky{}, Bounds{});
  const glm::vec3 p(0.0f), n(0.0f, 0.0f, 1.0f);
  double above = 0.0, below = 0.0, belowFlipped = 0.0;
  for (uint32_t i = 0; i < tris.size(); ++i) {
    (i % 2 == 0 ? above : below) += sampler.emissiveSelection(i, p, n);
    if (i % 2 == 1) belowFlipped += sampler.emissiveSelection(i, p, -n);
  }
  EXPECT_EQ(below, 0.0);
  EXPECT_NEAR(above, 1.0, 1e-5);
  EXPECT_NEAR(belowFlipped, 1.0, 1e-5);   // upside down, the point sees only the lamps below

  // A lamp above the point facing away from it (one-sided) is not chosen either.
  std::vector<EmissiveTriangle> two = {tris[0], makeTriangle({40, -5, 20}, {50, -5, 20}, {40, 5, 20},
                                                             glm::vec3(50.0f), false)};
  ASSERT_GT(two[1].normal.z, 0.0f);
  const LightSampler pair({}, two, Sky{}, Bounds{});
  EXPECT_EQ(pair.emissiveSelection(1, p, n), 0.0f);
  EXPECT_NEAR(pair.emissiveSelection(0, p, n), 1.0f, 1e-6f);
}

/// The unshadowed integral of L cos_i cos_l / d^2 over a triangle, by the midpoint rule on
/// 4^levels congruent sub-triangles.
double integrateTriangle(const EmissiveTriangle& t, const glm::vec3& p, const glm::vec3& n, int levels) {
  const int cells = 1 << levels;   // cells x cells grid of the barycentric square, half kept
  double sum = 0.0;
  const double cellArea = double(t.area) / (double(cells) * cells);
  for (int i = 0; i < cells; ++i) {
    for (int j = 0; i + j < cells; ++j) {
      // Two sub-triangles per cell except on the diagonal.
      const int kinds = i + j + 1 < cells ? 2 : 1;
      for (int k = 0; k < kinds; ++k) {
        const float b1 = k == 0 ? (float(i) + 1.0f / 3.0f) / float(cells) : (float(i) + 2.0f / 3.0f) / float(cells);
        const float b2 = k == 0 ? (float(j) + 1.0f / 3.0f) / float(cells) : (float(j) + 2.0f / 3.0f) / float(cells);
        const glm::vec3 q = t.p0 + b1 * t.e1 + b2 * t.e2;
        const glm::vec3 d = q - p;
        const float dist2 = glm::dot(d, d);
        const glm::vec3 wi = d / std::sqrt(dist2);
        const float cosI = glm::dot(wi, n);
        const float cosL = -glm::dot(wi, t.normal);
        if (cosI <= 0.0f || (cosL <= 0.0f && !t.twoSided)) continue;
        sum += double(t.emission.x) * cosI * std::abs(cosL) / dist2 * cellArea;
      }
    }
  }
  return sum;
}

TEST(LightSampler, EmissiveEstimatorMeanIsTheSumOverEmitters) {
  auto tris = triangleSoup(40, 17);
  const glm::vec3 p(3.0f, -7.0f, 1.0f), n = glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f));
  double exact = 0.0;
  for (const EmissiveTriangle& t : tris) exact += integrateTriangle(t, p, n, 6);
  ASSERT_GT(exact, 0.0);
  const LightSampler sampler({}, tris, Sky{}, Bounds{});
  Random r(77);
  constexpr int kSamples = 400000;
  double sum = 0.0, sum2 = 0.0;
  for (int s = 0; s < kSamples; ++s) {
    LightSample ls;
    double value = 0.0;
    if (sampler.sample(p, n, glm::vec4(r.next(), r.next(), r.next(), r.next()), ls))
      value = double(ls.radiance.x) * std::max(0.0f, glm::dot(ls.wi, n)) / ls.pdf;
    sum += value;
    sum2 += value * value;
  }
  const double mean = sum / kSamples;
  const double sigma = std::sqrt(std::max(0.0, sum2 / kSamples - mean * mean) / kSamples);
  EXPECT_NEAR(mean, exact, 4.0 * sigma + 2e-3 * exact) << "sigma " << sigma;
}

TEST(LightSampler, TriangleSamplePdfIsTheMisPdf) {
  const auto tris = triangleSoup(60, 29);
  const LightSampler sampler({}, tris, Sky{}, Bounds{});
  Random r(4);
  int checked = 0;
  for (int s = 0; s < 3000; ++s) {
    const glm::vec3 p = r.inBox(150.0f), n = r.direction();
    LightSample ls;
    if (!sampler.sample(p, n, glm::vec4(r.next(), r.next(), r.next(), r.next()), ls)) continue;
    // Find the triangle holding the light point.
    for (uint32_t i = 0; i < tris.size(); ++i) {
      const EmissiveTriangle& t = tris[i];
      const glm::vec3 d = ls.lightPoint - t.p0;
      if (std::abs(glm::dot(d, t.normal)) > 1e-3f) continue;
      const glm::vec3 c = glm::cross(t.e1, t.e2);
      const float b1 = glm::dot(glm::cross(d, t.e2), c) / glm::dot(c, c);
      const float b2 = glm::dot(glm::cross(t.e1, d), c) / glm::dot(c, c);
      if (b1 < -1e-4f || b2 < -1e-4f || b1 + b2 > 1.0f + 1e-4f) continue;
      EXPECT_NEAR(ls.pdf, sampler.emissivePdf(i, p, n, ls.lightPoint), 1e-3f * ls.pdf);
      ++checked;
      break;
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(LightSampler, SkyWindowsBoundTheSkyAndSunShares) {
  // One emitter of power pi * 50 * 1; a constant sky of radiance 1; a sun of irradiance 2.
  const std::vector<EmissiveTriangle> tris = {makeTriangle({0, 0, 0}, {10, 0, 0}, {0, 10, 0}, glm::vec3(1.0f), false)};
  SkyDesc desc;
  desc.color = glm::vec3(1.0f);
  const Sky sky(desc, {});
  LightDesc sun;
  sun.type = LightType::Directional;
  sun.direction = glm::normalize(glm::vec3(0.0f, 0.6f, -0.8f));
  sun.intensity = 2.0f;
  const std::vector<LightDesc> lights = {sun};
  Bounds scene;
  scene.extend(glm::vec3(-1000.0f));
  scene.extend(glm::vec3(1000.0f));
  // A 20 x 20 skylight facing down: the sky brings pi x 1 x 400, the sun 2 x 400 x 0.8.
  const std::vector<glm::vec3> windows = {glm::vec3(0, 0, -200), glm::vec3(0, 0, -200)};
  const LightSampler enclosed(lights, tris, sky, scene, windows);
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  const double skyPower = kPi * 400.0, sunPower = 2.0 * 400.0 * 0.8, emitterPower = kPi * 50.0;
  const double total = skyPower + sunPower + emitterPower;
  // skyPdf(n, n) = share x cosine-lobe pdf (1 / pi) for a constant sky.
  EXPECT_NEAR(enclosed.skyPdf(glm::vec3(3, 3, 5), n, n) * kPi, skyPower / total, 1e-4);
  EXPECT_NEAR(enclosed.emissiveSelection(0, glm::vec3(3, 3, 5), -n), emitterPower / total, 1e-4);
  // Without windows (open scene) the bounding disc of radius 1732 dwarfs the emitter.
  const LightSampler open(lights, tris, sky, scene);
  EXPECT_LT(open.emissiveSelection(0, glm::vec3(3, 3, 5), -n), 1e-4f);
}

TEST(LightTree, FourWideWeighingMatchesTheScalarImportance) {
  // Three emitters make one node of three leaves, so each pmf is its lane's importance over the
  // lanes' sum: the SSE lanes must weigh as lightImportance() does, for cones, emission spreads,
  // one- and two-sided emitters, ranges, points inside the bounds and points without a normal.
  Random r(2024);
  int compared = 0, zeros = 0;
  for (int set = 0; set < 300; ++set) {
    std::vector<LightBounds> lights(3);
    for (LightBounds& b : lights) {
      const glm::vec3 c = r.inBox(100.0f);
      b.bounds = Bounds{};
      b.bounds.extend(c - glm::vec3(r.next(), r.next(), r.next()) * 20.0f);
      b.bounds.extend(c + glm::vec3(r.next(), r.next(), r.next()) * 20.0f);
      b.power = 0.1f + 10.0f * r.next();
      const float kind = r.next();
      b.normals = {r.direction(), kind < 0.4f ? 1.0f : kind < 0.7f ? 2.0f * r.next() - 1.0f : -1.0f};
      b.cosEmission = r.next() < 0.6f ? 0.0f : 2.0f * r.next() - 1.0f;
      b.twoSided = r.next() < 0.3f;
      b.range = r.next() < 0.3f ? 30.0f + 100.0f * r.next() : 0.0f;
    }
    const LightTree tree(lights);
    ASSERT_EQ(tree.nodeCount(), 1u);
    for (int k = 0; k < 20; ++k) {
      const glm::vec3 p = k % 5 == 0 ? lights[0].bounds.center() : r.inBox(150.0f);
      const glm::vec3 n = k % 4 == 0 ? glm::vec3(0.0f) : r.direction();
      double expected[3], sum = 0.0;
      for (int i = 0; i < 3; ++i) sum += expected[i] = lightImportance(lights[size_t(i)], p, n);
      if (!(sum > 0.0)) continue;
      for (uint32_t i = 0; i < 3; ++i) {
        const double want = expected[i] / sum, got = tree.pmf(i, p, n, true);
        EXPECT_NEAR(got, want, 1e-5 + 1e-4 * want) << "set " << set << " point " << k << " emitter " << i;
        zeros += want == 0.0;
        if (want == 0.0) {
          EXPECT_EQ(got, 0.0);
        }
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 6000);
  EXPECT_GT(zeros, 200);   // the tests that cut a lane were exercised
}

TEST(LightTree, HostileEmittersAreLeftOut) {
  auto lights = boundsOf(triangleSoup(10, 2));
  lights[3].power = std::numeric_limits<float>::quiet_NaN();
  lights[5].power = 0.0f;
  lights[7].bounds.max.x = std::numeric_limits<float>::infinity();
  const LightTree tree(lights);
  EXPECT_EQ(tree.emitterCount(), 7u);
  const glm::vec3 p(0.0f), n(0.0f);
  EXPECT_EQ(tree.pmf(3, p, n), 0.0f);
  EXPECT_EQ(tree.pmf(5, p, n), 0.0f);
  EXPECT_EQ(tree.pmf(7, p, n), 0.0f);
  EXPECT_EQ(tree.pmf(99, p, n), 0.0f);
  EXPECT_TRUE(LightTree(std::vector<LightBounds>{}).empty());
  // Many emitters at one spot (no extent to split on) still make a valid tree.
  std::vector<LightBounds> same(1000, lights[0]);
  const LightTree stacked(same);
  double sum = 0.0;
  for (uint32_t i = 0; i < same.size(); ++i) sum += stacked.pmf(i, glm::vec3(500.0f), glm::vec3(0.0f));
  EXPECT_NEAR(sum, 1.0, 1e-4);
}

TEST(LightTree, InsideTheBoundingSphereImportanceIsPowerOverRadiusSquared) {
  // Inside the sphere around the box every direction is in the cone bound, so emission and
  // reception cosines are 1 for any cone, side or normal (no point here lies below or behind
  // the whole box, which the plane tests would cut).
  LightBounds b;
  b.bounds.extend(glm::vec3(-4.0f, -2.0f, -1.0f));
  b.bounds.extend(glm::vec3(4.0f, 2.0f, 1.0f));
  b.power = 3.0f;
  const float radius2 = 4.0f * 4.0f + 2.0f * 2.0f + 1.0f;
  const glm::vec3 inside[] = {glm::vec3(0.0f), glm::vec3(3.9f, 1.9f, 0.9f), glm::vec3(-4.5f, 0.0f, 0.0f)};
  for (const float cosTheta : {1.0f, 0.3f, -1.0f}) {
    for (const bool twoSided : {false, true}) {
      b.normals = {glm::vec3(0.0f, 0.0f, 1.0f), cosTheta};
      b.twoSided = twoSided;
      b.cosEmission = 0.0f;
      for (const glm::vec3& p : inside) {
        for (const glm::vec3& n : {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f), glm::normalize(glm::vec3(1, -2, 3))}) {
          EXPECT_EQ(lightImportance(b, p, n), b.power / radius2) << cosTheta << " " << twoSided;
        }
      }
      b.cosEmission = 1.0f;   // an emission cone of zero width lets nothing out
      EXPECT_EQ(lightImportance(b, glm::vec3(0.0f), glm::vec3(0.0f)), 0.0f);
    }
  }
}

TEST(LightTree, RangeLimitsTheReach) {
  LightBounds lamp;
  lamp.bounds.extend(glm::vec3(-1.0f));
  lamp.bounds.extend(glm::vec3(1.0f));
  lamp.power = 5.0f;
  lamp.normals = DirectionCone::entireSphere();
  lamp.cosEmission = -1.0f;
  lamp.range = 10.0f;
  EXPECT_GT(lightImportance(lamp, glm::vec3(10.5f, 0.0f, 0.0f), glm::vec3(0.0f)), 0.0f);   // 9.5 from the box
  EXPECT_EQ(lightImportance(lamp, glm::vec3(11.5f, 0.0f, 0.0f), glm::vec3(0.0f)), 0.0f);
  LightBounds far = lamp;
  far.range = 0.0f;   // no limit: the union has none either
  EXPECT_EQ(boundsUnion(lamp, far).range, 0.0f);
  LightBounds wider = lamp;
  wider.range = 30.0f;
  EXPECT_EQ(boundsUnion(lamp, wider).range, 30.0f);
}

TEST(LightTree, SamplingIsDeterministic) {
  const auto tris = triangleSoup(200, 8);
  const LightSampler a({}, tris, Sky{}, Bounds{}), b({}, tris, Sky{}, Bounds{});
  Random r(123);
  for (int s = 0; s < 1000; ++s) {
    const glm::vec3 p = r.inBox(200.0f), n = r.direction();
    const glm::vec4 u(r.next(), r.next(), r.next(), r.next());
    LightSample sa, sb;
    const bool oka = a.sample(p, n, u, sa), okb = b.sample(p, n, u, sb);
    ASSERT_EQ(oka, okb);
    if (!oka) continue;
    EXPECT_EQ(sa.pdf, sb.pdf);
    EXPECT_EQ(sa.lightPoint, sb.lightPoint);
    EXPECT_EQ(sa.radiance, sb.radiance);
  }
}

TEST(LightTree, KnownReachingRootChangesNoChoice) {
  // Where the caller has found the root's importance > 0, sample() and pmf() skip recomputing it
  // and must give the same emitter and the same bits.
  const auto tris = triangleSoup(300, 41);
  const LightTree tree(boundsOf(tris));
  Random r(77);
  int reached = 0;
  for (int s = 0; s < 2000; ++s) {
    const glm::vec3 p = r.inBox(200.0f), n = r.direction();
    const float u = r.next();
    if (!(tree.importance(p, n) > 0.0f)) continue;
    ++reached;
    uint32_t a = 0, b = 0;
    float pa = 0.0f, pb = 0.0f;
    const bool oka = tree.sample(p, n, u, a, pa), okb = tree.sample(p, n, u, b, pb, true);
    ASSERT_EQ(oka, okb);
    if (!oka) continue;
    EXPECT_EQ(a, b);
    EXPECT_EQ(std::bit_cast<uint32_t>(pa), std::bit_cast<uint32_t>(pb));
    EXPECT_EQ(std::bit_cast<uint32_t>(tree.pmf(a, p, n)), std::bit_cast<uint32_t>(tree.pmf(a, p, n, true)));
  }
  EXPECT_GT(reached, 1000);
}

}  // namespace
}  // namespace pa
