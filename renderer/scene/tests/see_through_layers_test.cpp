// See-through layers (world/see_through_layers.h): the candidates and layers a ray keeps do not
// depend on the order the traversal met them in, a triangle reported twice is one layer, and a
// camera packet gives every ray the layers it gets alone, bit for bit, in drawing order, also
// when more layers than fit cross it, many of them coincident (a shader's stages drawn as copies
// of one triangle).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

#include "renderer/core/srgb.h"
#include "renderer/scene/world/scene_store.h"
#include "renderer/scene/world/see_through_layers.h"
#include "scene_builders.h"

namespace pa {
namespace {

using Candidate = AdditiveHits::Candidate;

/// Nearest first; ties in drawing order (the later primitive of an instance first).
bool candidateBefore(const Candidate& a, const Candidate& b) {
  if (a.t != b.t) return a.t < b.t;
  if (a.overlay != b.overlay) return a.overlay < b.overlay;
  if (a.instance != b.instance) return a.instance < b.instance;
  return a.prim > b.prim;
}

TEST(SeeThroughLayers, CandidatesKeptAreTheNearestWhateverTheOrderTheyCameIn) {
  // 48 triangles at 10 distances (ties, also across the cut), on both instance tables: more
  // than the 32 kept.
  std::vector<Candidate> all;
  for (uint32_t i = 0; i < 48; ++i)
    all.push_back({1.0f + static_cast<float>(i % 10), i % 5, 100 + i, 0.25f, 0.25f, i % 3 == 0});
  std::vector<Candidate> expected = all;
  std::sort(expected.begin(), expected.end(), candidateBefore);
  expected.resize(AdditiveHits::kCandidateCapacity);
  std::vector<uint32_t> order(all.size());
  std::iota(order.begin(), order.end(), 0u);
  for (int arrangement = 0; arrangement < 4; ++arrangement) {
    SCOPED_TRACE(arrangement);
    if (arrangement == 1) std::reverse(order.begin(), order.end());
    if (arrangement >= 2) std::rotate(order.begin(), order.begin() + 17 * arrangement % 48, order.end());
    AdditiveHits hits;
    for (const uint32_t i : order) recordLayerCandidate(hits, all[i]);
    ASSERT_EQ(hits.candidateCount, AdditiveHits::kCandidateCapacity);
    std::vector<Candidate> kept(hits.candidates.begin(), hits.candidates.begin() + hits.candidateCount);
    std::sort(kept.begin(), kept.end(), candidateBefore);
    for (size_t k = 0; k < kept.size(); ++k) {
      EXPECT_EQ(kept[k].t, expected[k].t) << k;
      EXPECT_EQ(kept[k].instance, expected[k].instance) << k;
      EXPECT_EQ(kept[k].prim, expected[k].prim) << k;
      EXPECT_EQ(kept[k].overlay, expected[k].overlay) << k;
    }
  }
}

/// In front of an opaque wall at z = -10: 36 coincident additive squares at z = -4 (one mesh,
/// the stages of one shader: textured, vertex-coloured, several blends), and 4 single squares at
/// other distances; 40 layers where 32 fit.
struct LayeredWall {
  static constexpr uint32_t kStages = 36;
  SceneStore store;
  RenderScene scene;
  LayeredWall() {
    std::vector<uint8_t> pixels;
    for (uint32_t i = 0; i < 16; ++i) {
      const uint8_t v = static_cast<uint8_t>(40 + 13 * i);
      pixels.insert(pixels.end(), {v, static_cast<uint8_t>(255 - v), 90, static_cast<uint8_t>(60 + 9 * i)});
    }
    TextureDesc texture;
    texture.width = texture.height = 4;
    texture.rgba8 = pixels;
    const TextureId tex = store.addTexture(texture);
    test::addMesh(store, test::quad({-50, -50, -10}, {100, 0, 0}, {0, 100, 0}), store.addMaterial(test::diffuse(0.5f)));
    const LayerBlend blends[] = {LayerBlend::Add, LayerBlend::Over, LayerBlend::Multiply, LayerBlend::MultiplyAdd};
    test::MeshArrays stages;
    for (uint32_t s = 0; s < kStages; ++s) {
      const test::MeshArrays q = test::quad({-2, -2, -4}, {4, 0, 0}, {0, 4, 0});
      const uint32_t base = static_cast<uint32_t>(stages.positions.size());
      for (size_t k = 0; k < q.positions.size(); ++k) {
        stages.positions.push_back(q.positions[k]);
        stages.uvs.push_back(q.uvs[k] * (1.0f + 0.3f * static_cast<float>(s)));
        stages.colors.emplace_back(0.2f + 0.04f * static_cast<float>(s), 0.5f, 0.9f - 0.02f * static_cast<float>(s),
                                   0.3f + 0.1f * static_cast<float>(k));
      }
      for (const uint32_t i : q.indices) stages.indices.push_back(base + i);
      MaterialDesc m;
      m.alphaMode = AlphaMode::Additive;
      m.baseTexture = tex;
      m.baseColor = glm::vec4(0.3f + 0.02f * static_cast<float>(s));
      m.stock.layerBlend = blends[s % 4];
      const MaterialId id = store.addMaterial(m);
      stages.materials.insert(stages.materials.end(), {id, id});
    }
    store.addInstance({store.addMesh(stages.desc())});
    for (int k = 0; k < 4; ++k) {
      MaterialDesc glow;
      glow.alphaMode = AlphaMode::Additive;
      glow.baseColor = glm::vec4(0.05f * static_cast<float>(k + 1));
      glow.twoSided = k % 2 == 0;
      test::addMesh(store, test::quad({-3, -3, -2.0f - 1.7f * static_cast<float>(k)}, {6, 0, 0}, {0, 6, 0}),
                    store.addMaterial(glow));
    }
    scene = store.commit();
  }
};

TEST(SeeThroughLayers, ATriangleReportedTwiceIsOneLayer) {
  const LayeredWall wall;
  Ray ray;
  ray.origin = glm::vec3(0.0f);
  ray.dir = glm::vec3(0.1f, 0.05f, -1.0f);
  for (const bool packet : {false, true}) {
    SCOPED_TRACE(packet ? "packet" : "one ray");
    // Stage 3 of the coincident squares and the square at z = -2, each reported twice.
    const std::vector<Candidate> reported = {{4.0f, 1, 6, 0.3f, 0.2f, false}, {2.0f, 2, 0, 0.4f, 0.5f, false},
                                             {4.0f, 1, 6, 0.3f, 0.2f, false}, {2.0f, 2, 0, 0.4f, 0.5f, false}};
    std::array<TracedCameraRay, 2> rays;
    for (TracedCameraRay& r : rays) {
      r.ray = ray;
      r.found = true;
      r.hit.t = 10.0f;
      for (const Candidate& c : reported) recordLayerCandidate(r.additive, c);
      ASSERT_EQ(r.additive.candidateCount, 4u);
    }
    if (packet) {
      resolvePacketLayers(wall.scene, rays);
    } else {
      for (TracedCameraRay& r : rays) resolveRayLayers(wall.scene, r.additive, r.ray, r.hit.t);
    }
    for (const TracedCameraRay& r : rays) {
      ASSERT_EQ(r.additive.count, 2u);
      EXPECT_EQ(r.additive.entries[0].instance, 2u);
      EXPECT_EQ(r.additive.entries[1].instance, 1u);
      EXPECT_EQ(r.additive.entries[1].prim, 6u);
      EXPECT_EQ(r.additive.candidateCount, 0u);
    }
  }
}

TEST(SeeThroughLayers, ASecondPassOverFullLayersKeepsTheFirstInDrawingOrder) {
  // A ray traced twice into one AdditiveHits (the drawOnTop instances, then the world: as
  // trace::traceClosest does): the first pass fills all 32 entries with coincident stages, the
  // second brings squares in front of and behind them. The layers kept are the first 32 of all
  // in drawing order, as one pass over every layer would keep.
  const LayeredWall wall;
  Ray ray;
  ray.origin = glm::vec3(0.0f);
  ray.dir = glm::vec3(0.1f, 0.05f, -1.0f);
  constexpr float kHit = 10.0f;
  std::vector<Candidate> first, second;
  for (uint32_t stage = 0; stage < AdditiveHits::kCandidateCapacity; ++stage)
    first.push_back({4.0f, 1, 2 * stage, 0.25f, 0.25f, false});
  for (uint32_t k = 0; k < 4; ++k) second.push_back({2.0f + 1.7f * static_cast<float>(k), 2 + k, 0, 0.3f, 0.3f, false});
  const auto resolved = [&](const std::vector<std::vector<Candidate>>& passes) {
    AdditiveHits hits;
    for (const std::vector<Candidate>& pass : passes) {
      for (const Candidate& c : pass) recordLayerCandidate(hits, c);
      resolveRayLayers(wall.scene, hits, ray, kHit);
    }
    return std::vector<AdditiveHits::Entry>(hits.entries.begin(), hits.entries.begin() + hits.count);
  };
  const std::vector<AdditiveHits::Entry> stages = resolved({first});
  ASSERT_EQ(stages.size(), AdditiveHits::kCapacity);
  std::vector<AdditiveHits::Entry> expected = resolved({second});
  ASSERT_EQ(expected.size(), 4u);
  expected.insert(expected.end(), stages.begin(), stages.end());
  std::sort(expected.begin(), expected.end(), AdditiveHits::drawnBefore);
  expected.resize(AdditiveHits::kCapacity);
  const std::vector<AdditiveHits::Entry> kept = resolved({first, second});
  ASSERT_EQ(kept.size(), expected.size());
  for (size_t k = 0; k < kept.size(); ++k) {
    EXPECT_EQ(kept[k].t, expected[k].t) << k;
    EXPECT_EQ(kept[k].instance, expected[k].instance) << k;
    EXPECT_EQ(kept[k].prim, expected[k].prim) << k;
  }
}

bool sameBits(const glm::vec3& a, const glm::vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(SeeThroughLayers, PacketGivesEveryRayTheLayersItGetsAlone) {
  for (const bool display : {false, true}) {   // linear layers (traced presets) and display values (Lightmap)
  SCOPED_TRACE(display ? "display values" : "linear");
  const LayeredWall wall;
  std::array<TracedCameraRay, kMaxPacketRays> packet;
  for (uint32_t i = 0; i < kMaxPacketRays; ++i) {
    packet[i].additive.displayValues = display;
    packet[i].ray.origin = glm::vec3(0.0f);
    packet[i].ray.dir = glm::vec3(-0.3f + 0.04f * static_cast<float>(i % 4) + 0.003f * static_cast<float>(i),
                                  -0.25f + 0.05f * static_cast<float>(i / 4), -1.0f);
    if (i == 5) packet[i].ray.dir = glm::vec3(0.6f, 0.1f, -1.0f);   // beside the stages: fewer layers
  }
  std::array<TracedCameraRay, kMaxPacketRays> alone = packet;
  wall.scene.intersectCameraPacket(packet);
  uint32_t full = 0;
  for (uint32_t i = 0; i < kMaxPacketRays; ++i) {
    SCOPED_TRACE(i);
    TraceRequest request;
    request.kind = RayKind::Camera;
    AdditiveHits hits;
    hits.displayValues = display;
    request.additive = &hits;
    Hit hit;
    ASSERT_TRUE(wall.scene.intersect(alone[i].ray, hit, request));
    ASSERT_TRUE(packet[i].found);
    EXPECT_EQ(packet[i].hit.t, hit.t);
    const AdditiveHits& p = packet[i].additive;
    ASSERT_EQ(p.count, hits.count);
    full += p.count == AdditiveHits::kCapacity;
    for (uint32_t k = 0; k < p.count; ++k) {
      EXPECT_EQ(p.entries[k].t, hits.entries[k].t) << k;
      EXPECT_EQ(p.entries[k].instance, hits.entries[k].instance) << k;
      EXPECT_EQ(p.entries[k].prim, hits.entries[k].prim) << k;
      EXPECT_TRUE(sameBits(p.entries[k].color, hits.entries[k].color)) << k;
      EXPECT_TRUE(sameBits(p.entries[k].transmit, hits.entries[k].transmit)) << k;
      if (k > 0) {   // drawing order: by distance, coincident stages the later one nearer
        const AdditiveHits::Entry& a = p.entries[k - 1];
        const AdditiveHits::Entry& b = p.entries[k];
        EXPECT_TRUE(a.t < b.t || (a.t == b.t && (a.instance < b.instance || (a.instance == b.instance && a.prim > b.prim))))
            << k;
      }
    }
  }
  EXPECT_GE(full, 12u);   // most rays cross more layers than fit
  // Those keep the first 32 in drawing order: the squares at z = -2 and -3.7, then the last 30
  // of the 36 coincident stages (35 down to 6); stages 0-5 and the two squares behind are left out.
  for (uint32_t i = 0; i < kMaxPacketRays; ++i) {
    const AdditiveHits& p = packet[i].additive;
    if (p.count != AdditiveHits::kCapacity) continue;
    SCOPED_TRACE(i);
    EXPECT_EQ(p.entries[0].instance, 2u);
    EXPECT_EQ(p.entries[1].instance, 3u);
    for (uint32_t k = 2; k < p.count; ++k) {
      EXPECT_EQ(p.entries[k].instance, 1u) << k;
      EXPECT_EQ(p.entries[k].prim / 2, LayeredWall::kStages - 1 - (k - 2)) << k;   // two triangles a stage
    }
  }
  }
}

TEST(SeeThroughLayers, DisplayValueLayersAreWhatTheFramebufferIsGiven) {
  // One square over a wall: a 1x1 sRGB texture of bytes (200, 100, 30), vertex colour (linear)
  // 0.5, 0.25, 1 and alpha 0.6, an instance tint. For the Lightmap preset (displayValues) a layer
  // adds texture byte / 255 x the vertex colour's display value x the tint's, each factor
  // modulating in display values as a stock texture unit modulates by its colour. The traced
  // presets get the linear product.
  const glm::vec3 texel = glm::vec3(200.0f, 100.0f, 30.0f) / 255.0f;
  const glm::vec3 vertex(0.5f, 0.25f, 1.0f);
  const glm::vec4 tint(0.8f, 1.0f, 0.9f, 1.0f);
  const auto display = [](const glm::vec3& c) { return glm::vec3(linearToSrgb(c.x), linearToSrgb(c.y), linearToSrgb(c.z)); };
  const auto linear = [](const glm::vec3& c) { return glm::vec3(srgbToLinear(c.x), srgbToLinear(c.y), srgbToLinear(c.z)); };
  for (const LayerBlend blend : {LayerBlend::Add, LayerBlend::Multiply, LayerBlend::Modulate2x, LayerBlend::Over}) {
    SCOPED_TRACE(static_cast<int>(blend));
    SceneStore store;
    const std::vector<uint8_t> pixel = {200, 100, 30, 255};
    TextureDesc texture;
    texture.width = texture.height = 1;
    texture.rgba8 = pixel;
    const TextureId tex = store.addTexture(texture);
    test::addMesh(store, test::quad({-50, -50, -10}, {100, 0, 0}, {0, 100, 0}), store.addMaterial(test::diffuse(0.5f)));
    test::MeshArrays square = test::quad({-2, -2, -4}, {4, 0, 0}, {0, 4, 0});
    square.colors.assign(square.positions.size(), glm::vec4(vertex, 0.6f));
    MaterialDesc m;
    m.alphaMode = AlphaMode::Additive;
    m.baseTexture = tex;
    m.stock.layerBlend = blend;
    square.setMaterial(store.addMaterial(m));
    InstanceDesc instance{store.addMesh(square.desc())};
    instance.tint = tint;
    store.addInstance(instance);
    const RenderScene scene = store.commit();
    for (const bool displayValues : {false, true}) {
      SCOPED_TRACE(displayValues ? "display values" : "linear");
      TraceRequest request;
      AdditiveHits hits;
      hits.displayValues = displayValues;
      request.additive = &hits;
      Ray ray;
      ray.origin = glm::vec3(0.3f, -0.2f, 0.0f);
      ray.dir = glm::vec3(0.0f, 0.0f, -1.0f);
      Hit hit;
      ASSERT_TRUE(scene.intersect(ray, hit, request));
      ASSERT_EQ(hits.count, 1u);
      const AdditiveHits::Entry& e = hits.entries[0];
      const glm::vec3 shown = displayValues ? texel * display(vertex) * display(glm::vec3(tint))
                                            : display(linear(texel) * vertex * glm::vec3(tint));
      const glm::vec3 added = displayValues ? shown : linear(texel) * vertex * glm::vec3(tint);
      for (int c = 0; c < 3; ++c) {
        switch (blend) {
          case LayerBlend::Add: EXPECT_NEAR(e.color[c], added[c], 2e-6f) << c; EXPECT_EQ(e.transmit[c], 1.0f); break;
          case LayerBlend::Over:
            EXPECT_NEAR(e.color[c], added[c], 2e-6f) << c;
            EXPECT_NEAR(e.transmit[c], 0.4f, 1e-6f) << c;   // 1 - the vertex alpha
            break;
          case LayerBlend::Multiply: EXPECT_NEAR(e.transmit[c], shown[c], 2e-6f) << c; EXPECT_EQ(e.color[c], 0.0f); break;
          case LayerBlend::Modulate2x: EXPECT_NEAR(e.transmit[c], 2.0f * shown[c], 4e-6f) << c; break;
          default: break;
        }
      }
    }
  }
}

}  // namespace
}  // namespace pa
