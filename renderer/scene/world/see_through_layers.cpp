#include "renderer/scene/world/see_through_layers.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <tuple>
#include <utility>

#include <glm/geometric.hpp>

#include "renderer/core/srgb.h"

namespace pa {

namespace {

/// Keeps the first N items in `order` (a strict total order) of those offered, whatever the order
/// they come in: `fill` writes the new item into a free slot; when all are taken, the array is a
/// heap with the last item in `order` at its root, and `fill` replaces the root if `before(root)`
/// (the new item comes before it), which then sinks to its place. `fill` writes member by member
/// (a whole item built first and copied waits on its own stores).
template <class Item, size_t N, class Before, class Order, class Fill>
void keepFirst(std::array<Item, N>& held, uint32_t& count, Before before, Order order, Fill fill) {
  if (count < N) {
    fill(held[count++]);
    if (count == N) std::make_heap(held.begin(), held.end(), order);
    return;
  }
  if (!before(held[0])) return;
  fill(held[0]);
  for (size_t i = 0;;) {
    size_t last = i;
    for (const size_t child : {2 * i + 1, 2 * i + 2})
      if (child < N && order(held[last], held[child])) last = child;
    if (last == i) return;
    std::swap(held[i], held[last]);
    i = last;
  }
}

/// Keeps a layer's colour and what it lets through among the ray's first kCapacity in drawing
/// order (more can come only from a ray traced twice: the drawOnTop instances, then the world).
void recordAdditive(AdditiveHits& hits, float t, uint32_t instance, uint32_t prim, const glm::vec3& color,
                    const glm::vec3& transmit) {
  // A layer that adds nothing and keeps what is behind is no layer (the black margins of sprite
  // quads): it takes no slot from the ones that show.
  constexpr float kNothing = 1e-5f;
  if (glm::all(glm::lessThan(color, glm::vec3(kNothing))) &&
      glm::all(glm::lessThan(glm::abs(transmit - 1.0f), glm::vec3(kNothing))))
    return;
  using Entry = AdditiveHits::Entry;
  const Entry key{t, instance, prim, {}, {}};
  keepFirst(
      hits.entries, hits.count, [&](const Entry& held) { return AdditiveHits::drawnBefore(key, held); },
      AdditiveHits::drawnBefore, [&](Entry& slot) {
        slot.t = t;
        slot.instance = instance;
        slot.prim = prim;
        slot.color = color;
        slot.transmit = transmit;
      });
}

/// sRGB-encoded value of a non-negative linear colour (above 1 too: the dynamic-light pass). A
/// channel equal to the one before it is not encoded again (grey and white colours: one powf).
glm::vec3 displayValue(const glm::vec3& linear) {
  const glm::vec3 c = glm::max(linear, glm::vec3(0.0f));
  const float x = linearToSrgb(c.x);
  const float y = c.y == c.x ? x : linearToSrgb(c.y);
  const float z = c.z == c.y ? y : linearToSrgb(c.z);
  return {x, y, z};
}

/// A blend factor's value for a layer of display colour `src` and alpha `a`.
glm::vec3 blendFactor(BlendFactor factor, const glm::vec3& src, float a) {
  switch (factor) {
    case BlendFactor::Zero: return glm::vec3(0.0f);
    case BlendFactor::One: return glm::vec3(1.0f);
    case BlendFactor::SrcColor: return src;
    case BlendFactor::OneMinusSrcColor: return glm::vec3(1.0f) - src;
    case BlendFactor::SrcAlpha: return glm::vec3(a);
    case BlendFactor::OneMinusSrcAlpha: return glm::vec3(1.0f - a);
  }
  return glm::vec3(1.0f);
}

/// What a multiplying layer (Multiply, MultiplyInverse, MultiplyAdd, Modulate2x) of display
/// colour `src` lets through of what is behind it (StockLook::layerBlend); 1 for other blends.
glm::vec3 multiplyingTransmit(LayerBlend blend, const glm::vec3& src) {
  const glm::vec3 s = glm::max(src, glm::vec3(0.0f));
  switch (blend) {
    case LayerBlend::Multiply: return s;
    case LayerBlend::MultiplyInverse: return glm::max(1.0f - s, glm::vec3(0.0f));
    case LayerBlend::MultiplyAdd: return 1.0f + s;
    case LayerBlend::Modulate2x: return 2.0f * s;
    default: return glm::vec3(1.0f);
  }
}

/// A layer of blend factors (LayerBlend::Factors) showing display colour `shown` in [0, 1] with
/// coverage `a` in [0, 1]: what it adds in display values (shown x its source factor) and lets
/// through (its destination factor).
std::pair<glm::vec3, glm::vec3> factorsLayer(const StockLook& stock, const glm::vec3& shown, float a) {
  return {shown * blendFactor(stock.layerSrcFactor, shown, a), blendFactor(stock.layerDstFactor, shown, a)};
}

/// Records the layer of material `m` whose base colour (baseColor at full resolution) and
/// emission a ray saw at distance t: what it adds and lets through (StockLook::layerBlend);
/// nothing where it fails its alpha test.
void recordLayer(const MaterialDesc& m, const glm::vec4& base, const glm::vec3& emission, float t, uint32_t instance,
                 uint32_t prim, AdditiveHits& hits) {
  if (m.layerAlphaTest && (m.alphaInvert ? base.a >= m.alphaCutoff : base.a < m.alphaCutoff)) return;
  glm::vec3 added = glm::vec3(base) + emission;
  glm::vec3 transmit(1.0f);
  switch (m.stock.layerBlend) {
    case LayerBlend::Add: break;
    case LayerBlend::Over: transmit = glm::vec3(1.0f - std::clamp(base.a, 0.0f, 1.0f)); break;
    case LayerBlend::Factors: {
      // The layer adds encode(added) x srcFactor in display values: back to linear.
      const auto [shown, through] =
          factorsLayer(m.stock, glm::min(displayValue(added), glm::vec3(1.0f)), std::clamp(base.a, 0.0f, 1.0f));
      added = {srgbToLinear(shown.x), srgbToLinear(shown.y), srgbToLinear(shown.z)};
      transmit = through;
      break;
    }
    default:   // multiplying blends
      transmit = multiplyingTransmit(m.stock.layerBlend, displayValue(glm::vec3(base)));
      added = glm::vec3(0.0f);
      break;
  }
  recordAdditive(hits, t, instance, prim, added, transmit);
}

/// recordLayer for AdditiveHits::displayValues: `base` is the layer's colour in display values
/// (its texture as stored x display-value vertex colour and factors) with its linear alpha, as a
/// stock framebuffer receives it; `emission` (linear) is added to it as recordLayer adds it.
/// Inlined into the crossing loop: a call passed `base` through the stack once per crossing.
[[gnu::always_inline]] inline void recordDisplayLayer(const MaterialDesc& m, const glm::vec4& base,
                                                      const glm::vec3& emission, float t, uint32_t instance,
                                                      uint32_t prim, AdditiveHits& hits) {
  if (m.layerAlphaTest && (m.alphaInvert ? base.a >= m.alphaCutoff : base.a < m.alphaCutoff)) return;
  const glm::vec3 src(base);
  glm::vec3 added = src;
  if (emission != glm::vec3(0.0f)) {   // an emissive layer (rare): the sum in linear values, shown
    const glm::vec3 clamped = glm::clamp(src, 0.0f, 1.0f);
    added = displayValue(glm::vec3(srgbToLinear(clamped.x), srgbToLinear(clamped.y), srgbToLinear(clamped.z)) + emission);
  }
  glm::vec3 transmit(1.0f);
  switch (m.stock.layerBlend) {
    case LayerBlend::Add: break;
    case LayerBlend::Over: transmit = glm::vec3(1.0f - std::clamp(base.a, 0.0f, 1.0f)); break;
    case LayerBlend::Factors:
      std::tie(added, transmit) = factorsLayer(m.stock, glm::clamp(added, 0.0f, 1.0f), std::clamp(base.a, 0.0f, 1.0f));
      break;
    default:   // multiplying blends
      transmit = multiplyingTransmit(m.stock.layerBlend, src);
      added = glm::vec3(0.0f);
      break;
  }
  recordAdditive(hits, t, instance, prim, added, transmit);
}

/// One ray crossing an additive triangle in front of its closest hit.
struct Crossing {
  float t, u, v;
  const Ray* ray;
  AdditiveHits* hits;
};

/// What every crossing of one triangle reads: its material, corners' uvs, colours and wobble,
/// its winding (one-sided layers, emission's side).
struct LayerTriangle {
  const RenderInstance* instance;
  const MaterialRecord* material;
  uint32_t prim;
  bool oneSided, hasUvs, hasColors, wobbles;
  glm::vec3 winding;          ///< Unnormalised winding normal (world space).
  glm::vec3 emittingNormal;   ///< Unit winding normal, (0, 0, 1) when degenerate.
  glm::vec2 uv[3];
  glm::vec4 color[3];
  glm::vec2 wobble[3];        ///< UvWobble::offsetAt the corners.
  // AdditiveHits::displayValues: the display values of what multiplies the texture.
  glm::vec3 displayColor[3];  ///< The corners' vertex colours (where they tint the base).
  glm::vec3 displayFactor;    ///< The material's base colour x the instance's tint.
};

/// The parts of triangle `prim` of `inst` that its layers read (in display values too with `display`).
LayerTriangle layerTriangle(const RenderScene& scene, const RenderInstance& inst, uint32_t prim, bool display) {
  const MeshGeometry& g = inst.mesh->geometry;
  const MaterialRecord& material = scene.materialOf(inst, prim);
  const MaterialDesc& desc = material.desc;
  LayerTriangle tri{};
  tri.instance = &inst;
  tri.material = &material;
  tri.prim = prim;
  const uint32_t corner[3] = {g.indices[3 * size_t{prim}], g.indices[3 * size_t{prim} + 1], g.indices[3 * size_t{prim} + 2]};
  tri.oneSided = !desc.twoSided;
  if (tri.oneSided || material.emits) {
    tri.winding = scene.windingNormal(inst, prim);
    const float len = glm::length(tri.winding);
    tri.emittingNormal = len > 0.0f ? tri.winding / len : glm::vec3(0.0f, 0.0f, 1.0f);
  }
  tri.hasUvs = !g.uvs.empty();
  tri.hasColors = !g.colors.empty();
  tri.wobbles = desc.uvWobble.amplitude != 0.0f;
  for (int k = 0; k < 3; ++k) {
    if (tri.hasUvs) tri.uv[k] = g.uvs[corner[k]];
    if (tri.hasColors) tri.color[k] = g.colors[corner[k]];
    if (tri.wobbles) tri.wobble[k] = desc.uvWobble.offsetAt(g.positions[corner[k]]);
  }
  if (display) {
    tri.displayFactor = displayValue(glm::vec3(desc.baseColor) * glm::vec3(inst.tint));
    if (tri.hasColors && !desc.stock.useVertexLight && desc.vertexColorTints)
      for (int k = 0; k < 3; ++k)   // a sprite's corners share one colour: encoded once
        tri.displayColor[k] = k > 0 && glm::vec3(tri.color[k]) == glm::vec3(tri.color[k - 1])
                                  ? tri.displayColor[k - 1]
                                  : displayValue(glm::vec3(tri.color[k]));
  }
  return tri;
}

/// The layers of one triangle for each of its crossings, recorded in the crossing's hits.
void evaluateCrossings(const RenderScene& scene, const LayerTriangle& tri, uint32_t instance, bool overlay,
                       std::span<const Crossing> crossings) {
  const MaterialRecord& material = *tri.material;
  const MaterialDesc& m = material.desc;
  if (m.baseTexCoords != TexCoordSource::Mesh) {   // uvs that depend on the ray: surfaceAt works them out
    for (const Crossing& c : crossings) {
      if (tri.oneSided && glm::dot(tri.winding, c.ray->dir) > 0.0f) continue;
      const SurfaceHit s = scene.surfaceAt(Hit{c.t, c.u, c.v, tri.prim, instance}, overlay, *c.ray, SurfaceParts::LayerColour);
      const glm::vec4 base = scene.baseColor(s, 0.0f);
      const glm::vec3 emission = scene.emission(s, glm::dot(s.geometricNormal, c.ray->dir) < 0.0f);
      if (c.hits->displayValues)
        recordDisplayLayer(m, glm::vec4(displayValue(glm::vec3(base)), base.a), emission, c.t, instance, tri.prim, *c.hits);
      else
        recordLayer(m, base, emission, c.t, instance, tri.prim, *c.hits);
    }
    return;
  }
  const glm::vec4 tint = tri.instance->tint;
  // baseFactor's vertex colour: its RGB only where it tints the base.
  const bool colorTints = !m.stock.useVertexLight && m.vertexColorTints;
  // A texture read as stored where its bytes are display values; else read linear and encoded.
  const bool storedTexture = material.base != nullptr && material.base->srgb();
  for (const Crossing& c : crossings) {
    const glm::vec3& d = c.ray->dir;
    if (tri.oneSided && glm::dot(tri.winding, d) > 0.0f) continue;
    const float w0 = 1.0f - c.u - c.v;
    // surfaceAt's uvs, vertex colour and emissive uv (SurfaceParts::LayerColour), as it forms them.
    glm::vec2 meshUv(0.0f);
    if (tri.hasUvs) meshUv = w0 * tri.uv[0] + c.u * tri.uv[1] + c.v * tri.uv[2];
    glm::vec2 uv = m.uvTransform * glm::vec3(meshUv, 1.0f);
    if (tri.wobbles) uv += w0 * tri.wobble[0] + c.u * tri.wobble[1] + c.v * tri.wobble[2];
    glm::vec4 vertex(1.0f);
    if (tri.hasColors) {
      const glm::vec4 &c0 = tri.color[0], &c1 = tri.color[1], &c2 = tri.color[2];
      vertex.a = std::fma(c.v, c2.a, std::fma(c.u, c1.a, w0 * c0.a));
      if (colorTints && !c.hits->displayValues)
        for (int k = 0; k < 3; ++k) vertex[k] = std::fma(c.v, c2[k], std::fma(w0, c0[k], c.u * c1[k]));
    }
    if (!m.vertexAlphaTints) vertex.a = 1.0f;
    glm::vec3 emission(0.0f);
    if (material.emits && (m.twoSided || glm::dot(tri.emittingNormal, d) < 0.0f)) {
      emission = m.emission;
      if (material.emissive != nullptr) {
        const glm::vec2 emissiveUv = m.emissiveOwnUv ? m.emissiveUvTransform * glm::vec3(meshUv, 1.0f) : uv;
        emission *= glm::vec3(material.emissive->sampleFull(emissiveUv));
      }
    }
    if (!c.hits->displayValues) {
      glm::vec4 base = m.baseColor * vertex * tint;
      if (material.base != nullptr) base *= material.base->sampleFull(uv);
      recordLayer(m, base, emission, c.t, instance, tri.prim, *c.hits);
      continue;
    }
    // Display values: texture x vertex colour x factor, each as the framebuffer receives it.
    glm::vec4 base(tri.displayFactor, m.baseColor.a * vertex.a * tint.a);
    if (colorTints && tri.hasColors) {
      const glm::vec3 &c0 = tri.displayColor[0], &c1 = tri.displayColor[1], &c2 = tri.displayColor[2];
      for (int k = 0; k < 3; ++k) base[k] *= std::fma(c.v, c2[k], std::fma(w0, c0[k], c.u * c1[k]));
    }
    if (storedTexture) {
      base *= material.base->sampleFullStored(uv);
    } else if (material.base != nullptr) {
      const glm::vec4 texel = material.base->sampleFull(uv);
      base *= glm::vec4(displayValue(glm::vec3(texel)), texel.a);
    }
    recordDisplayLayer(m, base, emission, c.t, instance, tri.prim, *c.hits);
  }
}

/// Two candidates of one triangle (a triangle the traversal reported twice).
bool sameTriangle(const AdditiveHits::Candidate& a, const AdditiveHits::Candidate& b) {
  return a.prim == b.prim && a.instance == b.instance && a.overlay == b.overlay;
}

/// Candidates nearest first, ties in drawing order (AdditiveHits::drawnBefore), the world's before
/// the drawOnTop instances'.
bool nearerCandidate(const AdditiveHits::Candidate& a, const AdditiveHits::Candidate& b) {
  if (a.t != b.t) return a.t < b.t;
  if (a.overlay != b.overlay) return a.overlay < b.overlay;
  if (a.instance != b.instance) return a.instance < b.instance;
  return a.prim > b.prim;
}

/// Sorts the entries into drawing order: a full array is a heap (keepFirst), the others are in
/// the order recorded (insertion sort: a few, often in order already).
void sortEntries(AdditiveHits& hits) {
  if (hits.count == AdditiveHits::kCapacity) {
    std::sort_heap(hits.entries.begin(), hits.entries.end(), AdditiveHits::drawnBefore);
    return;
  }
  for (uint32_t i = 1; i < hits.count; ++i) {
    const AdditiveHits::Entry e = hits.entries[i];
    uint32_t j = i;
    for (; j > 0 && AdditiveHits::drawnBefore(e, hits.entries[j - 1]); --j)
      hits.entries[j] = hits.entries[j - 1];
    hits.entries[j] = e;
  }
}

}  // namespace

void recordLayerCandidate(AdditiveHits& hits, const AdditiveHits::Candidate& c) {
  using Candidate = AdditiveHits::Candidate;
  // The candidates kept are the layers drawn first.
  const auto nearer = [](const Candidate& a, const Candidate& b) { return nearerCandidate(a, b); };
  keepFirst(
      hits.candidates, hits.candidateCount, [&](const Candidate& held) { return nearer(c, held); }, nearer,
      [&](Candidate& slot) {
        slot.t = c.t;
        slot.instance = c.instance;
        slot.prim = c.prim;
        slot.u = c.u;
        slot.v = c.v;
        slot.overlay = c.overlay;
      });
}

void resolveRayLayers(const RenderScene& scene, AdditiveHits& hits, const Ray& ray, float tEnd) {
  // A full array left by an earlier pass of the same ray (trace::traceClosest's drawOnTop pass) is
  // in drawing order (sortEntries); keepFirst takes a full array for a heap with the last at its root.
  if (hits.count == AdditiveHits::kCapacity)
    std::make_heap(hits.entries.begin(), hits.entries.end(), AdditiveHits::drawnBefore);
  for (uint32_t i = 0; i < hits.candidateCount; ++i) {
    const AdditiveHits::Candidate& c = hits.candidates[i];
    if (!(c.t < tEnd)) continue;   // behind the closest hit: never shown
    if (std::any_of(hits.candidates.begin(), hits.candidates.begin() + i, [&](const AdditiveHits::Candidate& e) {
          return sameTriangle(e, c);
        }))
      continue;   // reported twice
    const RenderInstance& inst = scene.instancesOf(c.overlay)[c.instance];
    const Crossing crossing{c.t, c.u, c.v, &ray, &hits};
    evaluateCrossings(scene, layerTriangle(scene, inst, c.prim, hits.displayValues), c.instance, c.overlay,
                      {&crossing, 1});
  }
  hits.candidateCount = 0;
  sortEntries(hits);
}

void resolvePacketLayers(const RenderScene& scene, std::span<TracedCameraRay> rays) {
  const uint32_t rayCount = static_cast<uint32_t>(std::min<size_t>(rays.size(), kMaxPacketRays));
  if (std::all_of(rays.begin(), rays.begin() + rayCount,
                  [](const TracedCameraRay& r) { return r.additive.candidateCount == 0; }))
    return;   // nothing crossed (most packets): no tables to clear
  // The rays' candidates in front of their hits grouped by triangle (a hash of the triangle to
  // its group), then each group's crossings worked out together.
  constexpr uint32_t kMaxPending = kMaxPacketRays * AdditiveHits::kCandidateCapacity;
  constexpr uint32_t kSlotBits = 10;   // twice kMaxPending slots
  static_assert((1u << kSlotBits) >= 2 * kMaxPending);
  std::array<uint16_t, 1u << kSlotBits> slots{};   // group + 1; 0: empty
  std::array<const AdditiveHits::Candidate*, kMaxPending> groupKey;
  std::array<uint16_t, kMaxPending + 1> groupStart;   // zeroed as the groups are made
  groupStart[0] = 0;
  std::array<uint8_t, kMaxPending> groupLastRay;   // the last ray added to each group
  constexpr uint8_t kNoRay = 0xff;
  struct Pending {
    const AdditiveHits::Candidate* candidate;
    uint16_t ray, group;
  };
  std::array<Pending, kMaxPending> pending;
  uint32_t count = 0, groups = 0;
  for (uint32_t r = 0; r < rayCount; ++r) {
    const TracedCameraRay& ray = rays[r];
    const float tEnd = ray.found ? ray.hit.t : std::numeric_limits<float>::infinity();
    for (uint32_t i = 0; i < ray.additive.candidateCount; ++i) {
      const AdditiveHits::Candidate& c = ray.additive.candidates[i];
      if (!(c.t < tEnd)) continue;   // behind the closest hit: never shown
      const uint64_t key = (uint64_t{c.instance} << 33) ^ (uint64_t{c.prim} << 1) ^ uint64_t{c.overlay};
      uint32_t slot = static_cast<uint32_t>((key * 0x9e3779b97f4a7c15ull) >> (64 - kSlotBits));
      while (slots[slot] != 0) {
        if (sameTriangle(*groupKey[slots[slot] - 1u], c)) break;
        slot = (slot + 1) & ((1u << kSlotBits) - 1);
      }
      if (slots[slot] == 0) {
        groupKey[groups] = &c;
        groupStart[groups + 1] = 0;
        groupLastRay[groups] = kNoRay;
        slots[slot] = static_cast<uint16_t>(++groups);
      }
      const uint16_t group = static_cast<uint16_t>(slots[slot] - 1u);
      if (groupLastRay[group] == r) continue;   // reported twice
      groupLastRay[group] = static_cast<uint8_t>(r);
      ++groupStart[group + 1u];
      pending[count++] = {&c, static_cast<uint16_t>(r), group};
    }
  }
  for (uint32_t g = 0; g < groups; ++g) groupStart[g + 1] += groupStart[g];
  // Each group's crossings together, in ray order (a ray crosses a triangle once).
  std::array<Crossing, kMaxPending> crossings;
  std::array<uint16_t, kMaxPending> filled;
  std::copy(groupStart.begin(), groupStart.begin() + groups, filled.begin());
  for (uint32_t i = 0; i < count; ++i) {
    const Pending& p = pending[i];
    TracedCameraRay& ray = rays[p.ray];
    crossings[filled[p.group]++] = {p.candidate->t, p.candidate->u, p.candidate->v, &ray.ray, &ray.additive};
  }
  // The groups nearest first (by their first crossing, in drawing order): the rays of a packet
  // mostly see the same layers in the same order, so each ray's entries come in drawing order and
  // sortEntries finds them sorted.
  std::array<uint16_t, kMaxPending> byDistance;
  for (uint32_t g = 0; g < groups; ++g) {
    uint32_t j = g;
    for (; j > 0 && nearerCandidate(*groupKey[g], *groupKey[byDistance[j - 1]]); --j) byDistance[j] = byDistance[j - 1];
    byDistance[j] = static_cast<uint16_t>(g);
  }
  for (uint32_t k = 0; k < groups; ++k) {
    const uint32_t g = byDistance[k];
    const AdditiveHits::Candidate& key = *groupKey[g];
    const RenderInstance& inst = scene.instancesOf(key.overlay)[key.instance];
    const std::span<const Crossing> group{crossings.data() + groupStart[g], size_t{groupStart[g + 1]} - groupStart[g]};
    // A packet's rays are traced for one preset: all of them want display values or none.
    evaluateCrossings(scene, layerTriangle(scene, inst, key.prim, group.front().hits->displayValues), key.instance,
                      key.overlay, group);
  }
  for (uint32_t r = 0; r < rayCount; ++r) {
    rays[r].additive.candidateCount = 0;
    sortEntries(rays[r].additive);
  }
}

}  // namespace pa
