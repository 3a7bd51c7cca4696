#include "renderer/scene/lights/light_sampler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <immintrin.h>

#include <glm/geometric.hpp>

#include "renderer/scene/sampling/warp.h"

namespace pa {

using sampling::kPi;

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

double meanComponent(const glm::vec3& c) { return (double{c.r} + c.g + c.b) / 3.0; }

double analyticPower(const LightDesc& l, double sceneRadius) {
  const double i = meanComponent(l.color) * l.intensity;
  switch (l.type) {
    case LightType::Point:
    case LightType::Spot: {
      double solidAngle = 4.0 * kPi;
      if (l.type == LightType::Spot) {
        const double cosMid = 0.5 * (double{l.cosInnerAngle} + l.cosOuterAngle);
        solidAngle = 2.0 * kPi * std::max(1e-4, 1.0 - cosMid);
      }
      if (l.falloff == Falloff::Linear) {
        // Mean over [0, range] of E(d) * d^2 for E = I (1 - d / range).
        return solidAngle * i * double{l.range} * l.range / 12.0;
      }
      return solidAngle * i;
    }
    case LightType::Directional:
      return i * kPi * sceneRadius * sceneRadius;
  }
  return 0.0;
}

/// Eight floats (GCC/Clang vector extension: one AVX register, or two SSE halves).
using Lanes = float __attribute__((vector_size(32)));

Lanes load(const float* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// a > b ? a : b and a < b ? a : b lane by lane; MAXPS and MINPS give exactly that (b where
// either is NaN or both are zeros), which GCC does not see in the vector form: it compares and
// blends, two dependent instructions instead of one.
Lanes maxLanes(Lanes a, Lanes b) {
#if defined(__AVX__)
  return reinterpret_cast<Lanes>(_mm256_max_ps(reinterpret_cast<__m256>(a), reinterpret_cast<__m256>(b)));
#else
  return a > b ? a : b;
#endif
}
Lanes minLanes(Lanes a, Lanes b) {
#if defined(__AVX__)
  return reinterpret_cast<Lanes>(_mm256_min_ps(reinterpret_cast<__m256>(a), reinterpret_cast<__m256>(b)));
#else
  return a < b ? a : b;
#endif
}

Lanes sqrtLanes(Lanes v) {
#if defined(__AVX__)
  return reinterpret_cast<Lanes>(_mm256_sqrt_ps(reinterpret_cast<__m256>(v)));
#else
  for (int i = 0; i < 8; ++i) v[i] = std::sqrt(v[i]);
  return v;
#endif
}

/// Lane masks of Lanes comparisons (-1 where true).
using LaneMask = int __attribute__((vector_size(32)));

/// Bit i set where lane i of m is true.
uint32_t bitsOf(LaneMask m) {
#if defined(__AVX__)
  return uint32_t(_mm256_movemask_ps(reinterpret_cast<__m256>(m)));
#else
  uint32_t bits = 0;
  for (int i = 0; i < 8; ++i) bits |= m[i] != 0 ? 1u << i : 0u;
  return bits;
#endif
}

/// w[0] + ... + w[7] in double, as ((w0 + w4) + (w2 + w6)) + ((w1 + w5) + (w3 + w7)): what a
/// group of lamps adds to the running sum of the groups before it. Pairwise, four lanes at a
/// time: a sum lane by lane was a chain of eight dependent additions per group, half the time of
/// weighing the lamps.
double groupSum(Lanes w) {
#if defined(__AVX__)
  const __m256 v = reinterpret_cast<__m256>(w);
  const __m256d low = _mm256_cvtps_pd(_mm256_castps256_ps128(v));
  const __m256d high = _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1));
  const __m256d halves = _mm256_add_pd(low, high);   // w0 + w4, w1 + w5, w2 + w6, w3 + w7
  const __m128d pairs = _mm_add_pd(_mm256_castpd256_pd128(halves), _mm256_extractf128_pd(halves, 1));
  return _mm_cvtsd_f64(_mm_add_sd(pairs, _mm_unpackhi_pd(pairs, pairs)));
#else
  const auto d = [&](int lane) { return double{w[lane]}; };
  return ((d(0) + d(4)) + (d(2) + d(6))) + ((d(1) + d(5)) + (d(3) + d(7)));
#endif
}

/// The lamp of positive weight in a group where the running sum, base plus the group's weights
/// added lane by lane, first exceeds target (the last one of positive weight if rounding, or
/// groupSum()'s other order of addition, leaves none); -1 when every weight is 0.
int laneAbove(const float* w, double base, double target) {
  double sum = 0.0;
  int last = -1;
  for (int lane = 0; lane < 8; ++lane) {
    if (w[lane] == 0.0f) continue;
    sum += double{w[lane]};
    last = lane;
    if (target < base + sum) break;
  }
  return last;
}

/// Every lane `v`.
Lanes splat(float v) {
  Lanes r;
  for (int i = 0; i < 8; ++i) r[i] = v;
  return r;
}

/// A shading point as the lamp weighing reads it, in every lane: taken once per point into
/// registers (read through the caller's references, p and n were loaded again after each
/// group's stores, which might have changed them).
struct PointLanes {
  Lanes x, y, z, nx, ny, nz;
  bool hemisphere;   ///< n is not 0: what lies below the tangent plane weighs nothing.
  PointLanes(const glm::vec3& p, const glm::vec3& n)
      : x(splat(p.x)), y(splat(p.y)), z(splat(p.z)), nx(splat(n.x)), ny(splat(n.y)), nz(splat(n.z)),
        hemisphere(n != glm::vec3(0.0f)) {}
};

/// The weights of the eight lamps of a group at p, n (localLightWeight x lampCosineFactor); false
/// (and all 0) when every lamp of the group lies wholly below the tangent plane. Lanes set in
/// `hidden` (lamps no ray from p's surroundings reached: LampVisibility) are scaled by
/// LampVisibility::kHiddenWeight. The distance falloff and the cosine are kept as fractions and
/// divided once (the same weights as the two scalar functions up to rounding).
template <class Group>
[[gnu::always_inline]] inline bool groupWeights(const Group& g, const PointLanes& p, uint8_t hidden, Lanes& out) {
  const Lanes x = load(g.x), y = load(g.y), z = load(g.z), radius = load(g.radius);
  const Lanes tx = p.x - x, ty = p.y - y, tz = p.z - z;   // light -> point
  // Nothing to reflect where the whole light lies on or below the tangent plane.
  LaneMask below{};
  Lanes height{};   // of the lamp's nearest side above the tangent plane
  if (p.hemisphere) {
    height = -(tx * p.nx + ty * p.ny + tz * p.nz) + radius;
    below = height <= 0.0f;
    if ((~bitsOf(below) & g.live) == 0) {
      out = Lanes{};
      return false;
    }
  }
  const Lanes centre = sqrtLanes(tx * tx + ty * ty + tz * tz);
  const Lanes nearest = maxLanes(centre - radius, Lanes{} + 1e-3f);
  // weight = numerator / denominator.
  Lanes numerator = load(g.strength), denominator = Lanes{} + 1.0f;
  if (g.anyLinear) {
    const Lanes linearFalloff = maxLanes(1.0f - nearest * load(g.inverseRange), Lanes{});
    numerator = g.anyInverseSquare ? (load(g.linear) != 0.0f ? numerator * linearFalloff : numerator)
                                   : numerator * linearFalloff;
  }
  if (g.anyInverseSquare) {
    const Lanes square = maxLanes(nearest * nearest, Lanes{} + 1e-8f);
    denominator = g.anyLinear ? (load(g.linear) != 0.0f ? denominator : square) : square;
  }
  if (g.anySpot) {
    // Spot lights without radius: the cone's smooth edge toward the point.
    const Lanes c = (tx * load(g.dx) + ty * load(g.dy) + tz * load(g.dz)) / centre;
    const Lanes lo = load(g.cosOuter), hi = load(g.cosInner);
    const Lanes t = (c - lo) / (hi - lo);
    const Lanes smooth = c <= lo ? Lanes{} : c >= hi ? Lanes{} + 1.0f : t * t * (3.0f - 2.0f * t);
    numerator = ((load(g.spot) != 0.0f) & (centre > 0.0f)) ? numerator * smooth : numerator;
  }
  if (p.hemisphere) {
    // lampCosineFactor: the light a lamp brings to a surface falls with the cosine toward it,
    // height / centre clamped to [kLeastLampCosine, 1], as the fraction clamp(height) / centre.
    const Lanes safeCentre = maxLanes(centre, Lanes{} + 1e-8f);
    numerator = numerator * minLanes(maxLanes(height, safeCentre * kLeastLampCosine), safeCentre);
    denominator = denominator * safeCentre;
  }
  Lanes weight = numerator / denominator;
  // Beyond a lamp's reach nothing (the maps' inverse-square lamps have none: the test is skipped).
  LaneMask none = below;
  if (g.anyRange) {
    const Lanes range = load(g.range);
    none |= (range > 0.0f) & (nearest > range);
  }
  weight = none ? Lanes{} : weight;
  if (hidden != 0) {
    const LaneMask laneBits = {1, 2, 4, 8, 16, 32, 64, 128};
    weight = (laneBits & int(hidden)) != 0 ? weight * LampVisibility::kHiddenWeight : weight;
  }
  // Only positive finite weights (NaN fails both comparisons).
  out = ((weight > 0.0f) & (weight <= std::numeric_limits<float>::max())) ? weight : Lanes{};
  return true;
}

/// Summed area of the sky windows.
double windowArea(std::span<const glm::vec3> windows) {
  double area = 0.0;
  for (const glm::vec3& w : windows) area += double{glm::length(w)};
  return area;
}

/// Summed area of the sky windows projected across direction d (either side may face the sun).
double projectedArea(std::span<const glm::vec3> windows, const glm::vec3& d) {
  double area = 0.0;
  for (const glm::vec3& w : windows) area += std::abs(double{glm::dot(w, d)});
  return area;
}

/// Tree bounds of an emissive triangle; adds its power (category units) to `power`.
LightBounds triangleBounds(const EmissiveTriangle& t, double& power) {
  const glm::vec3 mean = t.emission * (t.texture ? glm::vec3(t.texture->average()) : glm::vec3(1.0f));
  // Peak radiant intensity (radiance x area, along the normal) for the tree; power for the category.
  const double intensity = double{t.area} * meanComponent(mean);
  LightBounds b;
  b.bounds.extend(t.p0);
  b.bounds.extend(t.p0 + t.e1);
  b.bounds.extend(t.p0 + t.e2);
  b.power = std::isfinite(intensity) && intensity > 0.0 ? float(intensity) : 0.0f;
  b.normals = {t.normal, 1.0f};
  b.cosEmission = 0.0f;   // Lambertian: up to 90 degrees from the normal
  b.twoSided = t.twoSided;
  if (b.power > 0.0f) power += kPi * double{b.power} * (t.twoSided ? 2.0 : 1.0);
  return b;
}

}  // namespace

float distanceFalloff(const LightDesc& light, float d) {
  if (light.range > 0.0f && d > light.range) return 0.0f;
  if (light.falloff == Falloff::Linear) return std::max(0.0f, 1.0f - d / light.range);
  return 1.0f / std::max(d * d, 1e-8f);
}

float spotFactor(const LightDesc& light, const glm::vec3& fromLight) {
  const float c = glm::dot(fromLight, light.direction);
  const float lo = light.cosOuterAngle;
  const float hi = light.cosInnerAngle;
  if (c <= lo) return 0.0f;
  if (c >= hi) return 1.0f;
  const float t = (c - lo) / (hi - lo);
  return t * t * (3.0f - 2.0f * t);
}

float localLightWeight(const LightDesc& light, const glm::vec3& p) {
  const float strength = float(meanComponent(light.color)) * light.intensity;
  if (!(strength > 0.0f)) return 0.0f;
  const glm::vec3 toPoint = p - light.position;
  const float centre = glm::length(toPoint);
  // The nearest any point of the light's sphere can be (falloff never grows with distance).
  const float nearest = std::max(centre - light.radius, 1e-3f);
  float weight = strength * distanceFalloff(light, nearest);
  if (light.type == LightType::Spot && light.radius == 0.0f && centre > 0.0f)
    weight *= spotFactor(light, toPoint / centre);
  return weight;
}

float lampCosineFactor(const LightDesc& light, const glm::vec3& p, const glm::vec3& n) {
  if (n == glm::vec3(0.0f)) return 1.0f;   // no surface: no factor
  const glm::vec3 toLamp = light.position - p;
  const float height = glm::dot(toLamp, n) + light.radius;
  if (!(height > 0.0f)) return 0.0f;
  return std::clamp(height / std::max(glm::length(toLamp), 1e-8f), kLeastLampCosine, 1.0f);
}

glm::vec3 emittedRadiance(const EmissiveTriangle& tri, glm::vec2 bary, bool frontSide) {
  if (!frontSide && !tri.twoSided) return glm::vec3(0.0f);
  glm::vec3 e = tri.emission;
  if (tri.texture != nullptr) {
    const glm::vec2 uv = tri.uv0 * (1.0f - bary.x - bary.y) + tri.uv1 * bary.x + tri.uv2 * bary.y;
    e *= glm::vec3(tri.texture->sample(uv, 0.0f));
  }
  return e;
}

LightSampler::LightSampler(std::span<const LightDesc> lights, std::vector<EmissiveTriangle> triangles,
                           const Sky& sky, const Bounds& sceneBounds, std::span<const glm::vec3> skyWindows)
    : analytic_(lights.begin(), lights.end()), triangles_(std::move(triangles)) {
  buildTables(sky, sceneBounds, skyWindows);
}

void LightSampler::rebuild(std::span<const LightDesc> lights, std::span<const EmissiveTriangle> triangles,
                           const Sky& sky, const Bounds& sceneBounds, std::span<const glm::vec3> skyWindows) {
  analytic_.assign(lights.begin(), lights.end());
  triangles_.assign(triangles.begin(), triangles.end());
  buildTables(sky, sceneBounds, skyWindows);
}

void LightSampler::buildTables(const Sky& sky, const Bounds& sceneBounds, std::span<const glm::vec3> skyWindows) {
  skyEntry_ = localEntry_ = UINT32_MAX;
  localLights_.clear();
  environmentEntries_.clear();
  environmentShare_ = 0.0;
  visibility_.reset();
  lampVisibility_.reset();
  const double radius =
      sceneBounds.empty() ? 1.0 : std::max(1e-3, 0.5 * double{glm::length(sceneBounds.max - sceneBounds.min)});
  std::vector<double>& power = power_;
  power.clear();
  power.reserve(analytic_.size() + 2);
  std::vector<LightBounds>& emitters = emitters_;
  emitters.clear();
  emitters.reserve(triangles_.size());
  double localPower = 0.0;
  for (const EmissiveTriangle& t : triangles_) emitters.push_back(triangleBounds(t, localPower));
  for (uint32_t i = 0; i < analytic_.size(); ++i) {
    const LightDesc& l = analytic_[i];
    if (l.type == LightType::Directional) {
      // A floor keeps every sun selectable (unbiased) should light leave by other ways.
      const double open = analyticPower(l, radius);
      power.push_back(skyWindows.empty()
                          ? open
                          : std::max(1e-6 * open, meanComponent(l.color) * l.intensity *
                                                      projectedArea(skyWindows, l.direction)));
      continue;
    }
    power.push_back(0.0);   // chosen through the local entry
    const double p = analyticPower(l, radius);
    if (!(std::isfinite(p) && p > 0.0)) continue;   // dark (a pooled light switched off): weight 0 everywhere
    localLights_.push_back(i);
    localPower += p;
  }
  lampGroups_.assign((localLights_.size() + 7) / 8, LampGroup{});
  for (size_t k = 0; k < localLights_.size(); ++k) {
    const LightDesc& l = analytic_[localLights_[k]];
    LampGroup& g = lampGroups_[k / 8];
    const size_t lane = k % 8;
    g.x[lane] = l.position.x, g.y[lane] = l.position.y, g.z[lane] = l.position.z;
    g.radius[lane] = l.radius;
    g.strength[lane] = float(meanComponent(l.color)) * l.intensity;
    g.range[lane] = l.range;
    g.inverseRange[lane] = l.range > 0.0f ? 1.0f / l.range : kInfinity;   // no reach: the linear falloff is 0
    g.linear[lane] = l.falloff == Falloff::Linear ? 1.0f : 0.0f;
    g.spot[lane] = l.type == LightType::Spot && l.radius == 0.0f ? 1.0f : 0.0f;
    g.dx[lane] = l.direction.x, g.dy[lane] = l.direction.y, g.dz[lane] = l.direction.z;
    g.cosOuter[lane] = l.cosOuterAngle, g.cosInner[lane] = l.cosInnerAngle;
    g.live |= 1u << lane;
    (l.falloff == Falloff::Linear ? g.anyLinear : g.anyInverseSquare) = true;
    g.anyRange = g.anyRange || l.range > 0.0f;
    g.anySpot = g.anySpot || g.spot[lane] != 0.0f;
  }
  emissiveTree_.rebuild(emitters);
  if ((!emissiveTree_.empty() || !localLights_.empty()) && localPower > 0.0) {
    localEntry_ = static_cast<uint32_t>(power.size());
    power.push_back(localPower);
  }
  // Assigned in place: the sky's sampling tables keep their memory from one commit to the next.
  if (sky.black())
    sky_ = Sky{};
  else
    sky_ = sky;
  if (!sky.black()) {
    skyEntry_ = static_cast<uint32_t>(power.size());
    // Radiance L over a hemisphere through area A carries pi L A.
    const double disc = kPi * radius * radius;
    const double area = skyWindows.empty() ? disc : std::max(1e-6 * disc, windowArea(skyWindows));
    power.push_back(kPi * meanComponent(sky.average()) * area);
  }
  table_.rebuild(power);
  std::vector<double>& environmentPower = environmentPower_;
  environmentPower.clear();
  for (uint32_t entry = 0; entry < table_.size(); ++entry) {
    const bool sun = entry < analytic_.size() && analytic_[entry].type == LightType::Directional;
    if ((!sun && entry != skyEntry_) || !(table_.pdf(entry) > 0.0f)) continue;
    environmentEntries_.push_back(entry);
    environmentPower.push_back(table_.pdf(entry));
    environmentShare_ += table_.pdf(entry);
  }
  environmentTable_.rebuild(environmentPower);
  if (environmentTable_.empty()) environmentShare_ = 0.0;
}

std::vector<glm::vec3> LightSampler::sunDirections() const {
  std::vector<glm::vec3> directions;
  sunDirections(directions);
  return directions;
}

void LightSampler::sunDirections(std::vector<glm::vec3>& out) const {
  out.clear();
  // Analytic light i is table entry i; a sun that carries no power (intensity or colour 0, as a
  // pooled light switched off) lights nothing and is left out.
  for (uint32_t i = 0; i < analytic_.size(); ++i)
    if (analytic_[i].type == LightType::Directional && table_.pdf(i) > 0.0f) out.push_back(analytic_[i].direction);
}

void LightSampler::setLampVisibility(std::shared_ptr<const LampVisibility> visibility) {
  lampVisibility_.reset();
  bool any = false;
  for (size_t k = 0; k < localLights_.size(); ++k) {
    LampGroup& g = lampGroups_[k / 8];
    const uint8_t bit = uint8_t(1u << (k % 8));
    g.mapped = uint8_t(g.mapped & ~bit);
    if (visibility == nullptr || k >= visibility->lamps().size()) continue;
    if (!LampVisibility::sameLamp(analytic_[localLights_[k]], visibility->lamps()[k])) continue;
    g.mapped = uint8_t(g.mapped | bit);
    any = true;
  }
  if (any) lampVisibility_ = std::move(visibility);
}

void LightSampler::localLamps(std::vector<LightDesc>& out) const {
  out.clear();
  for (const uint32_t i : localLights_) out.push_back(analytic_[i]);
}

float LightSampler::entryProbability(uint32_t entry, const glm::vec3& p, const glm::vec3& n) const {
  const float own = table_.pdf(entry);
  const double kept = environmentScale(p, n);
  if (kept >= 1.0) return own;
  // The environment entries keep that fraction of their probability, all renormalised.
  const double norm = 1.0 - environmentShare_ + kept * environmentShare_;
  const bool environment = entry != localEntry_;
  return float(double(own) * (environment ? kept : 1.0) / norm);
}

bool LightSampler::sample(const glm::vec3& p, const glm::vec3& n, const glm::vec4& u, LightSample& out,
                          bool skyRadiance) const {
  if (table_.empty()) return false;
  uint32_t entry;
  float selection;
  if (const float scale = environmentScale(p, n); scale < 1.0f) {
    // Sun and sky hard to reach from here: the local emitters take what they give up.
    const double kept = double(scale) * environmentShare_;
    const float environment = float(kept / (1.0 - environmentShare_ + kept));
    if (u.x < environment) {
      const uint32_t k = environmentTable_.sample(std::min(u.x / environment, 0x1.fffffep-1f));
      entry = environmentEntries_[k];
      selection = environment * environmentTable_.pdf(k);
    } else {
      entry = localEntry_;
      selection = 1.0f - environment;
    }
  } else {
    entry = table_.sample(u.x);
    selection = table_.pdf(entry);
  }
  if (!(selection > 0.0f)) return false;
  const glm::vec2 uv(u.y, u.z);
  bool ok;
  if (entry == localEntry_) {
    // u.w is free here (only the sky's cell choice uses it): it picks the kind, then the emitter.
    LampPrefix prefix;   // uninitialised: localSplit() writes what pickLocalLight() reads
    const LocalSplit split = localSplit(p, n, &prefix);
    float uw = std::min(u.w, 0x1.fffffep-1f);
    if (uw < split.emissive) {
      uint32_t triangle = 0;
      float withinTree = 0.0f;
      // split.emissive > 0: the tree's root importance, summed by localSplit(), is > 0.
      if (!emissiveTree_.sample(p, n, uw / split.emissive, triangle, withinTree, true)) return false;
      selection *= split.emissive * withinTree;
      ok = sampleTriangle(triangles_[triangle], p, uv, out);
      out.light.index = triangle;
    } else {
      uint32_t light = 0;
      float withinLamps = 0.0f;
      uw = (uw - split.emissive) / (1.0f - split.emissive);
      if (!pickLocalLight(p, n, uw, split.lampWeight, &prefix, light, withinLamps)) return false;
      selection *= (1.0f - split.emissive) * withinLamps;
      ok = sampleAnalytic(analytic_[light], p, uv, out);
      out.light = {LightPoint::Kind::Lamp, light, glm::vec3(uv, 0.0f)};
    }
  } else if (entry < analytic_.size()) {
    ok = sampleAnalytic(analytic_[entry], p, uv, out);
    out.light = {LightPoint::Kind::Sun, entry, glm::vec3(uv, 0.0f)};
  } else if (entry == skyEntry_) {
    glm::vec3 wi;
    float pdf;
    if (sky_.importanceSampled()) {
      if (!sky_.sample(glm::vec3(u.w, u.y, u.z), wi, pdf)) return false;
    } else {
      wi = sampling::Frame(n).toWorld(sampling::cosineHemisphere(uv));
      pdf = std::max(0.0f, glm::dot(wi, n)) * sampling::kInvPi;
    }
    if (!(pdf > 0.0f)) return false;
    out = {};
    out.wi = wi;
    out.distance = kInfinity;
    if (skyRadiance) out.radiance = sky_.lightingRadiance(wi);
    out.pdf = pdf;
    out.environment = true;
    out.light = {LightPoint::Kind::Sky, 0, wi};
    out.jacobian = 4.0f * kPi;
    ok = true;
  } else {
    return false;
  }
  if (!ok) return false;
  out.pdf *= selection;
  return out.pdf > 0.0f;
}

LightSampler::LocalSplit LightSampler::localSplit(const glm::vec3& p, const glm::vec3& n, LampPrefix* prefix) const {
  // The running sum over the lamps is kept per group (groupSum): one addition chains the groups.
  LocalSplit split;
  double lamps = 0.0;
  const uint32_t buffered = prefix != nullptr ? std::min<uint32_t>(lampGroups_.size(), kBufferedLamps / 8) : 0;
  uint32_t g = 0;
  Lanes w;
  const PointLanes point(p, n);
  const HiddenRow hidden = hiddenRow(p, n);
  const LampGroup* groups = lampGroups_.data();
  const uint32_t groupCount = static_cast<uint32_t>(lampGroups_.size());
  // The stored groups' weights first, then their running sums (a group of zeros adds +0): in one
  // loop each group's sum waited on its weights, and the weighing of the next group on the sum.
  for (; g < buffered; ++g) {
    groupWeights(groups[g], point, hidden.lanes(g, groups[g].mapped), w);
    std::memcpy(prefix->weight + 8 * g, &w, sizeof w);
  }
  for (uint32_t k = 0; k < buffered; ++k) {
    lamps += groupSum(load(prefix->weight + 8 * k));
    prefix->groupEnd[k] = lamps;
  }
  if (prefix != nullptr) prefix->count = 8 * buffered;
  for (; g < groupCount; ++g)
    if (groupWeights(groups[g], point, hidden.lanes(g, groups[g].mapped), w)) lamps += groupSum(w);
  const double triangles = emissiveTree_.empty() ? 0.0 : double{emissiveTree_.importance(p, n)};
  split.lampWeight = lamps;
  const double total = lamps + triangles;
  split.emissive = total > 0.0 ? float(triangles / total) : 0.0f;
  if (total > 0.0 && lamps == 0.0) split.emissive = 1.0f;
  return split;
}

bool LightSampler::pickLocalLight(const glm::vec3& p, const glm::vec3& n, float u, double total,
                                  const LampPrefix* prefix, uint32_t& index, float& probability) const {
  // Inverts the running sum of the weights localSplit() summed: the group by binary search over
  // the stored group ends, the lamp by walking that group; beyond the stored groups the weights
  // are recomputed (nothing is kept per sample).
  if (!(total > 0.0)) return false;
  const double target = double(u) * total;
  double base = 0.0;
  float chosenWeight = 0.0f;
  uint32_t g = 0;
  if (prefix != nullptr && prefix->count > 0) {
    const uint32_t groups = prefix->count / 8;
    // The first group whose end exceeds the target holds a lamp of positive weight (groups of
    // zero weight end where the one before did), the lamp a walk over the weights stops at.
    g = uint32_t(std::upper_bound(prefix->groupEnd, prefix->groupEnd + groups, target) - prefix->groupEnd);
    if (g < groups) {
      const int lane = laneAbove(prefix->weight + 8 * g, g > 0 ? prefix->groupEnd[g - 1] : 0.0, target);
      if (lane < 0) return false;   // cannot happen: the group's end exceeds the one before
      index = localLights_[8 * g + uint32_t(lane)];
      probability = float(double(prefix->weight[8 * g + uint32_t(lane)]) / total);
      return probability > 0.0f;
    }
    // Beyond the stored lamps: the last stored one of positive weight catches rounding at the top end.
    for (uint32_t j = prefix->count; j-- > 0;) {
      if (prefix->weight[j] == 0.0f) continue;
      index = localLights_[j];
      chosenWeight = prefix->weight[j];
      break;
    }
    base = prefix->groupEnd[groups - 1];
  }
  alignas(32) float w[8];
  if (g < lampGroups_.size()) {   // beyond the stored groups (the point and its row only then)
    const PointLanes point(p, n);
    const HiddenRow hidden = hiddenRow(p, n);
    for (; g < lampGroups_.size(); ++g) {
      Lanes weights;
      if (!groupWeights(lampGroups_[g], point, hidden.lanes(g, lampGroups_[g].mapped), weights)) continue;
      std::memcpy(w, &weights, sizeof w);
      const int lane = laneAbove(w, base, target);
      if (lane < 0) continue;
      index = localLights_[8 * g + uint32_t(lane)];   // the last light with weight catches rounding at the top end
      chosenWeight = w[lane];
      base += groupSum(weights);
      if (target < base) break;
    }
  }
  if (!(chosenWeight > 0.0f)) return false;
  probability = float(double(chosenWeight) / total);
  return probability > 0.0f;
}

bool LightSampler::pickLamp(const glm::vec3& p, const glm::vec3& n, float u, bool reuseWeights, uint32_t& index,
                            float& probability) const {
  LampPrefix prefix;
  const LocalSplit split = localSplit(p, n, reuseWeights ? &prefix : nullptr);
  return pickLocalLight(p, n, u, split.lampWeight, reuseWeights ? &prefix : nullptr, index, probability);
}

bool LightSampler::sampleAnalytic(const LightDesc& l, const glm::vec3& p, const glm::vec2& u,
                                  LightSample& out) const {
  out = {};
  out.delta = true;
  out.pdf = 1.0f;
  const glm::vec3 power = l.color * l.intensity;
  if (l.type == LightType::Directional) {
    const glm::vec3 toSun = -l.direction;
    out.wi = l.angularRadius > 0.0f
                 ? sampling::Frame(toSun).toWorld(sampling::uniformCone(u, std::cos(l.angularRadius)))
                 : toSun;
    out.distance = kInfinity;
    out.radiance = power;
    out.environment = true;
    return true;
  }
  glm::vec3 q = l.position;
  if (l.radius > 0.0f) q += l.radius * sampling::uniformSphere(u);
  const glm::vec3 d = q - p;
  const float dist = glm::length(d);
  if (!(dist > 0.0f)) return false;
  out.wi = d / dist;
  out.distance = dist;
  out.lightPoint = q;
  float factor = distanceFalloff(l, dist);
  if (l.type == LightType::Spot) factor *= spotFactor(l, -out.wi);
  if (!(factor > 0.0f)) return false;
  out.radiance = power * factor;
  return true;
}

bool LightSampler::sampleTriangle(const EmissiveTriangle& tri, const glm::vec3& p, const glm::vec2& u,
                                  LightSample& out) const {
  return connectTriangle(tri, p, sampling::uniformTriangle(u), out);
}

bool LightSampler::connectTriangle(const EmissiveTriangle& tri, const glm::vec3& p, const glm::vec2& bary,
                                   LightSample& out) const {
  const glm::vec3 q = tri.p0 + bary.x * tri.e1 + bary.y * tri.e2;
  const glm::vec3 d = q - p;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return false;
  const float dist = std::sqrt(dist2);
  const glm::vec3 wi = d / dist;
  const float cosLight = -glm::dot(wi, tri.normal);
  if (cosLight == 0.0f) return false;
  const glm::vec3 radiance = emittedRadiance(tri, bary, cosLight > 0.0f);
  if (radiance == glm::vec3(0.0f)) return false;
  out = {};
  out.wi = wi;
  out.distance = dist;
  out.radiance = radiance;
  out.pdf = dist2 / (tri.area * std::abs(cosLight));
  out.delta = !tri.hittable;
  out.lightPoint = q;
  out.lightNormal = cosLight > 0.0f ? tri.normal : -tri.normal;
  out.light = {LightPoint::Kind::Triangle, 0, glm::vec3(bary, 0.0f)};
  out.jacobian = 1.0f / out.pdf;
  return std::isfinite(out.pdf) && out.pdf > 0.0f;
}

bool LightSampler::evaluate(const LightPoint& light, const glm::vec3& p, const glm::vec3& n, LightSample& out) const {
  switch (light.kind) {
    case LightPoint::Kind::Lamp: {
      // sample() picks a lamp only through the local entry, in proportion to its weight at p, n.
      if (localEntry_ == UINT32_MAX || light.index >= analytic_.size()) return false;
      const LightDesc& l = analytic_[light.index];
      if (l.type == LightType::Directional) return false;
      if (!(localLightWeight(l, p) > 0.0f)) return false;
      if (n != glm::vec3(0.0f) && glm::dot(l.position - p, n) + l.radius <= 0.0f) return false;
      if (!sampleAnalytic(l, p, glm::vec2(light.where), out)) return false;
      break;
    }
    case LightPoint::Kind::Sun: {
      if (light.index >= analytic_.size() || analytic_[light.index].type != LightType::Directional) return false;
      if (!(entryProbability(light.index, p, n) > 0.0f)) return false;
      if (!sampleAnalytic(analytic_[light.index], p, glm::vec2(light.where), out)) return false;
      break;
    }
    case LightPoint::Kind::Triangle: {
      // emissiveSelection() > 0 without the lamps' sum: the local entry and the tree's branch
      // probabilities are all that can be 0 (the tree's pmf is 0 where its root's importance is).
      if (light.index >= triangles_.size() || localEntry_ == UINT32_MAX ||
          !(emissiveTree_.pmf(light.index, p, n) > 0.0f))
        return false;
      if (!connectTriangle(triangles_[light.index], p, glm::vec2(light.where), out)) return false;
      break;
    }
    case LightPoint::Kind::Sky: {
      if (!(skyPdf(p, n, light.where) > 0.0f)) return false;
      out = {};
      out.wi = light.where;
      out.distance = kInfinity;
      out.radiance = sky_.lightingRadiance(light.where);
      out.environment = true;
      out.jacobian = 4.0f * kPi;
      break;
    }
    default:
      return false;
  }
  out.light = light;
  return out.radiance != glm::vec3(0.0f);
}

float LightSampler::emissiveSelection(uint32_t index, const glm::vec3& p, const glm::vec3& n) const {
  if (localEntry_ == UINT32_MAX || index >= triangles_.size()) return 0.0f;
  const LocalSplit split = localSplit(p, n);
  if (!(split.emissive > 0.0f)) return 0.0f;
  return entryProbability(localEntry_, p, n) * split.emissive * emissiveTree_.pmf(index, p, n, true);
}

float LightSampler::emissivePdf(uint32_t index, const glm::vec3& p, const glm::vec3& n, const glm::vec3& q) const {
  if (index >= triangles_.size()) return 0.0f;
  const EmissiveTriangle& tri = triangles_[index];
  const glm::vec3 d = q - p;
  const float dist2 = glm::dot(d, d);
  const float cosLight = std::abs(glm::dot(d, tri.normal)) / std::sqrt(dist2);
  if (!(cosLight > 0.0f) || !(tri.area > 0.0f)) return 0.0f;
  return emissiveSelection(index, p, n) * dist2 / (tri.area * cosLight);
}

float LightSampler::skyPdf(const glm::vec3& p, const glm::vec3& n, const glm::vec3& wi) const {
  if (skyEntry_ == UINT32_MAX) return 0.0f;
  const float directional =
      sky_.importanceSampled() ? sky_.pdf(wi) : std::max(0.0f, glm::dot(wi, n)) * sampling::kInvPi;
  return entryProbability(skyEntry_, p, n) * directional;
}

}  // namespace pa
