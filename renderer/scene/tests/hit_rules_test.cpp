// The BVH hit rule each material gets (materialHitRule, HitRule) and the answers of
// RenderScene's ray queries on one-sided surfaces: camera and bounce rays see only the front
// face, shadow rays both, alone and in camera packets, on plain and mirrored instances; and
// the same answers where the HitFilter callback decides (a mesh whose instances disagree on the
// material: HitRule::Filtered).
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/scene/world/scene_store.h"
#include "scene_builders.h"

namespace pa {
namespace {

TEST(SceneHitRules, MaterialRules) {
  MaterialDesc m;
  EXPECT_EQ(materialHitRule(m), HitRule::Opaque);
  m.twoSided = false;
  EXPECT_EQ(materialHitRule(m), HitRule::OneSided);
  for (int change = 0; change < 6; ++change) {
    MaterialDesc f = m;
    switch (change) {
      case 0: f.alphaMode = AlphaMode::Mask; break;
      case 1: f.alphaMode = AlphaMode::Blend; break;
      case 2: f.alphaMode = AlphaMode::Additive; break;
      case 3: f.sky = true; break;
      case 4: f.castsShadows = false; break;
      case 5: f.visible = false; break;
    }
    EXPECT_EQ(materialHitRule(f), HitRule::Filtered) << "change " << change;
    f.twoSided = true;
    EXPECT_EQ(materialHitRule(f), HitRule::Filtered) << "two-sided, change " << change;
  }
}

TEST(SceneHitRules, FilterRulesByKindOfRay) {
  const auto rule = [](const MaterialDesc& m, RayKind kind) {
    const FilterRule r = materialFilterRule(m, kind);
    return std::pair(r.action, r.cullBack);
  };
  using A = FilterAction;
  MaterialDesc m;
  for (const RayKind kind : {RayKind::Camera, RayKind::Bounce, RayKind::Shadow})
    EXPECT_EQ(rule(m, kind), std::pair(A::Accept, false));
  MaterialDesc oneSided = m;
  oneSided.twoSided = false;
  EXPECT_EQ(rule(oneSided, RayKind::Camera), std::pair(A::Accept, true));
  EXPECT_EQ(rule(oneSided, RayKind::Bounce), std::pair(A::Accept, true));
  EXPECT_EQ(rule(oneSided, RayKind::Shadow), std::pair(A::Accept, false));   // shadows from both faces
  MaterialDesc mask = oneSided;
  mask.alphaMode = AlphaMode::Mask;
  EXPECT_EQ(rule(mask, RayKind::Camera), std::pair(A::Mask, true));
  EXPECT_EQ(rule(mask, RayKind::Shadow), std::pair(A::Mask, false));
  MaterialDesc blend = m;
  blend.alphaMode = AlphaMode::Blend;
  EXPECT_EQ(rule(blend, RayKind::Bounce), std::pair(A::Blend, false));
  MaterialDesc additive = oneSided;   // layers work out their own face (see_through_layers)
  additive.alphaMode = AlphaMode::Additive;
  EXPECT_EQ(rule(additive, RayKind::Camera), std::pair(A::Additive, false));
  EXPECT_EQ(rule(additive, RayKind::Shadow), std::pair(A::Reject, false));
  MaterialDesc sky = additive;   // the sky before anything else
  sky.sky = true;
  sky.visible = false;
  for (const RayKind kind : {RayKind::Camera, RayKind::Bounce, RayKind::Shadow})
    EXPECT_EQ(rule(sky, kind), std::pair(A::Sky, false));
  MaterialDesc hidden = m;
  hidden.visible = false;
  EXPECT_EQ(rule(hidden, RayKind::Camera), std::pair(A::Reject, false));
  EXPECT_EQ(rule(hidden, RayKind::Shadow), std::pair(A::Accept, false));   // nodraw still casts
  hidden.castsShadows = false;
  hidden.visible = true;
  EXPECT_EQ(rule(hidden, RayKind::Shadow), std::pair(A::Reject, false));
  EXPECT_EQ(rule(hidden, RayKind::Camera), std::pair(A::Accept, false));
}

/// A one-sided square (front towards +z) placed plainly at the origin and mirrored (x -> -x, so
/// its world front faces -z) at x = 10; with `callback`, a third instance of the same mesh far
/// away overrides its material with a two-sided one, so the mesh's triangles go through the
/// HitFilter callback instead of the kernels' face culling.
struct OneSidedSquares {
  SceneStore store;
  RenderScene scene;
  explicit OneSidedSquares(bool callback) {
    MaterialDesc oneSided;
    oneSided.twoSided = false;
    test::MeshArrays square = test::quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0});
    square.setMaterial(store.addMaterial(oneSided));
    const MeshId mesh = store.addMesh(square.desc());
    store.addInstance({mesh});
    InstanceDesc mirrored{mesh};
    mirrored.objectToWorld = glm::mat4x3(glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1), glm::vec3(10, 0, 0));
    store.addInstance(mirrored);
    if (callback) {
      InstanceDesc other{mesh};
      other.objectToWorld[3] = glm::vec3(0, 100, 0);
      other.materialOverride = store.addMaterial(MaterialDesc{});
      store.addInstance(other);
    }
    scene = store.commit();
  }
};

/// Whether a ray from `fromAbove` at the square at x (world front +z if !mirrored) of the given
/// kind must hit it: shadow rays always, the others only on the world front face.
bool expectedHit(RayKind kind, bool fromAbove, bool mirrored) {
  return kind == RayKind::Shadow || fromAbove != mirrored;
}

const char* name(RayKind kind) {
  return kind == RayKind::Camera ? "camera" : kind == RayKind::Bounce ? "bounce" : "shadow";
}

TEST(SceneHitRules, OneSidedSquaresByRayKind) {
  for (const bool callback : {false, true}) {
    SCOPED_TRACE(callback ? "through the callback" : "culled in the kernels");
    const OneSidedSquares squares(callback);
    const RenderScene& scene = squares.scene;
    EXPECT_EQ(scene.world[0].mesh->rules[0], callback ? HitRule::Filtered : HitRule::OneSided);
    for (const bool mirrored : {false, true}) {
      const float x = mirrored ? 10.0f : 0.0f;
      for (const bool fromAbove : {true, false}) {
        for (const RayKind kind : {RayKind::Camera, RayKind::Bounce, RayKind::Shadow}) {
          SCOPED_TRACE(std::string(mirrored ? "mirrored, " : "plain, ") + (fromAbove ? "from above, " : "from below, ") +
                       name(kind));
          Ray ray;
          ray.origin = glm::vec3(x + 0.2f, 0.1f, fromAbove ? 3.0f : -3.0f);
          ray.dir = glm::vec3(x - 0.1f, 0.3f, 0.0f) - ray.origin;
          TraceRequest request;
          request.kind = kind;
          Ray traced = ray;
          Hit hit;
          const bool expected = expectedHit(kind, fromAbove, mirrored);
          EXPECT_EQ(scene.intersect(traced, hit, request), expected);
          if (expected) {
            EXPECT_EQ(hit.instance, mirrored ? 1u : 0u);
          }
          EXPECT_EQ(scene.occluded(ray, request), expected);
        }
      }
      // Camera packets: rays from above and below mixed in one call.
      std::array<TracedCameraRay, kMaxPacketRays> rays;
      for (uint32_t i = 0; i < kMaxPacketRays; ++i) {
        const bool fromAbove = i % 4 != 3;
        rays[i].ray.origin = glm::vec3(x, 0.0f, fromAbove ? 3.0f : -3.0f);
        rays[i].ray.dir = glm::vec3(x - 0.5f + 0.06f * i, 0.4f - 0.05f * i, 0.0f) - rays[i].ray.origin;
      }
      scene.intersectCameraPacket(rays);
      for (uint32_t i = 0; i < kMaxPacketRays; ++i)
        EXPECT_EQ(rays[i].found, expectedHit(RayKind::Camera, i % 4 != 3, mirrored)) << "packet ray " << i;
    }
  }
}

}  // namespace
}  // namespace pa
