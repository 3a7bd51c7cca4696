// Lamp weights shared per cell (LampCell): every lamp that can light a point of the cell stays
// selectable (the estimator stays exact), the choice is a pure function of the point, its normal
// and the cell size (the memo changes no bit), and a triangle sample's pdf is its MIS pdf.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/scene/lights/light_sampler.h"

namespace pa {
namespace {

/// Uniform numbers in [0, 1) from a fixed seed.
struct Random {
  explicit Random(uint32_t seed) : engine(seed) {}
  float next() { return std::uniform_real_distribution<float>(0.0f, 1.0f)(engine); }
  std::mt19937 engine;
};

/// The unshadowed irradiance the point lights give at p on a surface facing n.
double exactIrradiance(const std::vector<LightDesc>& lights, const glm::vec3& p, const glm::vec3& n) {
  double sum = 0.0;
  for (const LightDesc& l : lights) {
    const glm::vec3 d = l.position - p;
    const float dist = glm::length(d);
    const float cosine = glm::dot(d / dist, n);
    if (cosine > 0.0f) sum += double(l.intensity) * double(distanceFalloff(l, dist)) * double(cosine);
  }
  return sum;
}

/// The mean of radiance x cosine / pdf over `count` stratified lamp choices at p, n.
double stratifiedMean(const LightSampler& sampler, const glm::vec3& p, const glm::vec3& n, const LampCell& cell,
                      int count) {
  double sum = 0.0;
  for (int i = 0; i < count; ++i) {
    const float u = (float(i) + 0.5f) / float(count);
    LightSample ls;
    if (!sampler.sample(p, n, glm::vec4(0.5f, 0.5f, 0.5f, u), ls, cell)) continue;
    sum += double(ls.radiance.x) * std::max(0.0, double(glm::dot(ls.wi, n))) / double(ls.pdf);
  }
  return sum / count;
}

/// Lamps around the floor z = 0 whose weights a careless cell would set to 0: ranged lamps
/// whose range reaches the edge of a cell but not its centre, near and far inverse-square lamps.
std::vector<LightDesc> lampsAroundAFloor() {
  std::vector<LightDesc> lights;
  const auto add = [&](glm::vec3 position, float intensity, Falloff falloff, float range) {
    LightDesc l;
    l.position = position;
    l.intensity = intensity;
    l.falloff = falloff;
    l.range = range;
    lights.push_back(l);
  };
  add({2.0f, 1.0f, 30.0f}, 900.0f, Falloff::InverseSquare, 0.0f);
  add({-40.0f, 25.0f, 60.0f}, 4000.0f, Falloff::InverseSquare, 0.0f);
  add({13.0f, -3.0f, 6.0f}, 1.0f, Falloff::Linear, 9.0f);            // reaches only part of the cells
  add({-9.0f, 7.5f, 5.0f}, 300.0f, Falloff::InverseSquare, 8.0f);    // a cut-off in the same way
  add({400.0f, 0.0f, 90.0f}, 90000.0f, Falloff::InverseSquare, 0.0f);
  return lights;
}

TEST(LampCell, EveryLampThatLightsThePointStaysSelectable) {
  const std::vector<LightDesc> lights = lampsAroundAFloor();
  const LightSampler sampler(lights, {}, Sky{}, Bounds{});
  Random r(11);
  LampCellMemo memo;
  for (const float size : {1.0f, 4.0f, 16.0f}) {
    for (int k = 0; k < 40; ++k) {
      // Points on the floor near the ranged lamps, normals a little off the floor's.
      const glm::vec3 p(-16.0f + 32.0f * r.next(), -8.0f + 16.0f * r.next(), 0.0f);
      const glm::vec3 n = glm::normalize(glm::vec3(1e-3f * (r.next() - 0.5f), 1e-3f * (r.next() - 0.5f), 1.0f));
      const double exact = exactIrradiance(lights, p, n);
      ASSERT_GT(exact, 0.0);
      const double shared = stratifiedMean(sampler, p, n, LampCell{size, &memo}, 1 << 14);
      EXPECT_NEAR(shared, exact, 2e-3 * exact) << "size " << size << " at " << p.x << ", " << p.y;
    }
  }
}

TEST(LampCell, ALampJustAboveThePlaneIsStillChosen) {
  // One lamp barely above the tangent plane at p, below it at every other bin of the plane: it is
  // the only light there, so every sample must find it.
  Random r(5);
  for (const float size : {0.5f, 2.0f, 8.0f}) {
    for (int k = 0; k < 50; ++k) {
      const glm::vec3 p(100.0f * r.next(), 100.0f * r.next(), 37.0f + 0.3f * r.next());
      const glm::vec3 n = glm::normalize(glm::vec3(2e-4f * (r.next() - 0.5f), 2e-4f * (r.next() - 0.5f), 1.0f));
      // 50 units away along the plane, 0.01 above it.
      const glm::vec3 along = glm::normalize(glm::cross(n, glm::vec3(1.0f, 0.0f, 0.0f)));
      LightDesc lamp;
      lamp.position = p + 50.0f * along + 0.01f * n;
      lamp.intensity = 100.0f;
      const LightSampler sampler(std::vector<LightDesc>{lamp}, {}, Sky{}, Bounds{});
      LightSample ls;
      EXPECT_TRUE(sampler.sample(p, n, glm::vec4(0.5f, 0.5f, 0.5f, 0.5f), ls, LampCell{size, nullptr}))
          << "size " << size;
    }
  }
}

TEST(LampCell, TheMemoAndTheOrderChangeNoBit) {
  const std::vector<LightDesc> lights = lampsAroundAFloor();
  const LightSampler sampler(lights, {}, Sky{}, Bounds{});
  Random r(3);
  std::vector<glm::vec3> points;
  for (int k = 0; k < 64; ++k) points.emplace_back(4.0f * r.next(), 4.0f * r.next(), 0.0f);   // a few cells
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  // A sample may fail (a ranged lamp chosen from a point of the cell it does not reach): then
  // it fails the same way.
  const auto samples = [&](LampCellMemo* memo, bool reversed) {
    std::vector<LightSample> out(points.size());
    for (size_t j = 0; j < points.size(); ++j) {
      const size_t i = reversed ? points.size() - 1 - j : j;
      const float u = (float(i) + 0.5f) / float(points.size());
      if (!sampler.sample(points[i], n, glm::vec4(0.5f, 0.5f, 0.5f, u), out[i], LampCell{2.0f, memo}))
        out[i].pdf = -1.0f;
    }
    return out;
  };
  LampCellMemo memo;
  const std::vector<LightSample> alone = samples(nullptr, false), forward = samples(&memo, false),
                                 backward = samples(&memo, true);
  for (size_t i = 0; i < points.size(); ++i) {
    for (const std::vector<LightSample>* other : {&forward, &backward}) {
      EXPECT_EQ(alone[i].pdf, (*other)[i].pdf) << i;
      EXPECT_EQ(alone[i].lightPoint, (*other)[i].lightPoint) << i;
      EXPECT_EQ(alone[i].radiance, (*other)[i].radiance) << i;
    }
  }
}

TEST(LampCell, SizeZeroAndSpotLampsWeighAtThePoint) {
  std::vector<LightDesc> lights = lampsAroundAFloor();
  const LightSampler plain(lights, {}, Sky{}, Bounds{});
  LightDesc spot;
  spot.type = LightType::Spot;
  spot.position = glm::vec3(0.0f, 0.0f, 50.0f);
  spot.direction = glm::vec3(0.0f, 0.0f, -1.0f);
  spot.cosInnerAngle = 0.95f;
  spot.cosOuterAngle = 0.9f;
  spot.intensity = 500.0f;
  lights.push_back(spot);
  const LightSampler withSpot(lights, {}, Sky{}, Bounds{});
  Random r(8);
  LampCellMemo memo;
  for (int k = 0; k < 200; ++k) {
    const glm::vec3 p(20.0f * r.next(), 20.0f * r.next(), 0.0f), n(0.0f, 0.0f, 1.0f);
    const glm::vec4 u(0.5f, r.next(), r.next(), r.next());
    LightSample exact, cellular;
    const bool a = plain.sample(p, n, u, exact);
    EXPECT_EQ(a, plain.sample(p, n, u, cellular, LampCell{0.0f, &memo}));
    if (a) EXPECT_EQ(exact.pdf, cellular.pdf);
    const bool b = withSpot.sample(p, n, u, exact);
    EXPECT_EQ(b, withSpot.sample(p, n, u, cellular, LampCell{4.0f, &memo}));
    if (b) EXPECT_EQ(exact.pdf, cellular.pdf);
  }
}

TEST(LampCell, TriangleSamplePdfIsTheMisPdfWithTheSameCell) {
  // Lamps and emissive triangles share the local entry: the triangles' share depends on the
  // lamps' summed weight, which the cell sets.
  std::vector<EmissiveTriangle> tris;
  Random r(21);
  for (int i = 0; i < 30; ++i) {
    EmissiveTriangle t;
    t.p0 = glm::vec3(-60.0f + 120.0f * r.next(), -60.0f + 120.0f * r.next(), 40.0f + 20.0f * r.next());
    t.e1 = glm::vec3(6.0f, 0.0f, 0.0f);
    t.e2 = glm::vec3(0.0f, 6.0f, 0.0f);
    t.normal = glm::vec3(0.0f, 0.0f, -1.0f);
    t.area = 18.0f;
    t.emission = glm::vec3(2.0f);
    tris.push_back(t);
  }
  const LightSampler sampler(lampsAroundAFloor(), tris, Sky{}, Bounds{});
  LampCellMemo memo;
  int checked = 0;
  for (int s = 0; s < 3000; ++s) {
    const glm::vec3 p(-30.0f + 60.0f * r.next(), -30.0f + 60.0f * r.next(), 0.0f), n(0.0f, 0.0f, 1.0f);
    const LampCell cell{4.0f, &memo};
    LightSample ls;
    if (!sampler.sample(p, n, glm::vec4(r.next(), r.next(), r.next(), r.next()), ls, cell)) continue;
    if (ls.light.kind != LightPoint::Kind::Triangle) continue;
    EXPECT_NEAR(ls.pdf, sampler.emissivePdf(ls.light.index, p, n, ls.lightPoint, cell), 1e-4f * ls.pdf);
    EXPECT_NEAR(ls.pdf, sampler.emissivePdf(ls.light.index, p, n, ls.lightPoint, LampCell{4.0f, nullptr}),
                1e-4f * ls.pdf);
    ++checked;
  }
  EXPECT_GT(checked, 300);
}

}  // namespace
}  // namespace pa
