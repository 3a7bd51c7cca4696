// Known-answer tests of motion for meshes whose vertices change between frames (a dynamic mesh
// updated in place, as vertex-animated models are), on small scenes built here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "motion_checks.h"
#include "scene_builders.h"

namespace pa {
namespace {

using test::lookAt;
using test::pixelsPerUnitAt10;
using test::settingsFor;

/// A grey floor and a small dynamic quad above it, looked at from straight above.
struct MovingVertices {
  Renderer r;
  MeshId mesh = kNoId;
  InstanceId instance = kNoId;
  InstanceDesc desc;
  MaterialId grey = kNoId;
  explicit MovingVertices(uint32_t threads = 2, bool dynamic = true) : r(RendererConfig{threads}) {
    grey = r.addMaterial(test::diffuse(0.5f));
    test::addMesh(r, test::quad({-6, -6, 0}, {12, 0, 0}, {0, 12, 0}), grey);
    test::MeshArrays q = box(glm::vec3(0.0f));
    MeshDesc d = q.desc();
    d.dynamic = dynamic;
    mesh = r.addMesh(d);
    desc = InstanceDesc{mesh};
    instance = r.addInstance(desc);
    r.commit();
  }
  /// The quad's arrays with every vertex moved by `offset` (object space).
  test::MeshArrays box(glm::vec3 offset) const {
    test::MeshArrays q = test::quad(glm::vec3(-0.5f, -0.5f, 0.01f) + offset, {1, 0, 0}, {0, 1, 0});
    q.setMaterial(grey);
    return q;
  }
  /// Replaces the quad's vertices (same count and indices: the renderer refits).
  void moveVertices(glm::vec3 offset, bool dynamic = true) {
    const test::MeshArrays q = box(offset);
    MeshDesc d = q.desc();
    d.dynamic = dynamic;
    r.updateMesh(mesh, d);
    r.commit();
  }
  static Camera top() { return lookAt({0, 0, 10}, {0, 0, 0}, 40.0f); }
};

TEST(VertexMotion, MovedVerticesUnderAStillCameraGiveTheirScreenMotion) {
  MovingVertices scene;
  const uint32_t size = 64;
  RenderSettings s = settingsFor(Integrator::Lightmap, size, 1);
  s.accumulate = false;
  scene.r.render(MovingVertices::top(), s);
  scene.moveVertices({0.0f, 1.0f, 0.0f});   // one unit along +Y, the instance's transform unchanged
  const FrameView f = scene.r.render(MovingVertices::top(), s);
  // The quad's pixels point back to where it was, one unit away; the floor's do not move.
  test::expectMotionOnlyOn(f, scene.instance, pixelsPerUnitAt10(size), 30, 1000);
}

TEST(VertexMotion, VertexMotionAndInstanceMotionCompose) {
  // The vertices move by (0, 1, 0) in object space and the instance by (0.5, 0, 0): the hit was
  // sqrt(1.25) units away, and the same motion done by the transform alone gives the same vector.
  MovingVertices scene;
  const uint32_t size = 64;
  RenderSettings s = settingsFor(Integrator::Lightmap, size, 1);
  s.accumulate = false;
  scene.r.render(MovingVertices::top(), s);
  scene.desc.objectToWorld[3] = glm::vec3(0.5f, 0.0f, 0.0f);
  scene.r.setInstance(scene.instance, scene.desc);
  scene.moveVertices({0.0f, 1.0f, 0.0f});
  const FrameView f = scene.r.render(MovingVertices::top(), s);
  const std::vector<glm::vec2> composed(f.motion.begin(), f.motion.end());
  const std::vector<InstanceId> ids(f.instance.begin(), f.instance.end());

  MovingVertices rigid;
  rigid.r.render(MovingVertices::top(), s);
  rigid.desc.objectToWorld[3] = glm::vec3(0.5f, 1.0f, 0.0f);
  rigid.r.setInstance(rigid.instance, rigid.desc);
  rigid.r.commit();
  const FrameView g = rigid.r.render(MovingVertices::top(), s);
  const float expected = std::sqrt(1.25f) * pixelsPerUnitAt10(size);
  size_t onQuad = 0;
  for (size_t i = 0; i < composed.size(); ++i) {
    if (ids[i] != scene.instance) continue;
    ++onQuad;
    EXPECT_NEAR(glm::length(composed[i]), expected, 0.02f * expected) << i;
    ASSERT_EQ(g.instance[i], rigid.instance) << i;
    EXPECT_NEAR(composed[i].x, g.motion[i].x, 1e-3f) << i;
    EXPECT_NEAR(composed[i].y, g.motion[i].y, 1e-3f) << i;
  }
  EXPECT_GT(onQuad, 30u);
}

TEST(VertexMotion, ChangedTopologyOrAStaticMeshUpdateIsDisoccluded) {
  const uint32_t size = 48;
  RenderSettings s = settingsFor(Integrator::Lightmap, size, 1);
  s.accumulate = false;
  const auto quadPixels = [](const FrameView& f, InstanceId id, size_t& withMotion) {
    size_t n = 0;
    withMotion = 0;
    for (size_t i = 0; i < f.motion.size(); ++i) {
      if (f.instance[i] != id) continue;
      ++n;
      if (std::isfinite(f.motion[i].x)) ++withMotion;
    }
    return n;
  };
  {   // another vertex count: no previous position
    MovingVertices scene;
    scene.r.render(MovingVertices::top(), s);
    test::MeshArrays q = scene.box(glm::vec3(0.0f));
    q.positions.push_back({0, 0, 0.01f});   // one more vertex, the same triangles
    q.uvs.push_back({0, 0});
    MeshDesc d = q.desc();
    d.dynamic = true;
    scene.r.updateMesh(scene.mesh, d);
    scene.r.commit();
    size_t withMotion = 0;
    EXPECT_GT(quadPixels(scene.r.render(MovingVertices::top(), s), scene.instance, withMotion), 20u);
    EXPECT_EQ(withMotion, 0u);
    // The frame after, unchanged again: motion (0) is back.
    EXPECT_GT(quadPixels(scene.r.render(MovingVertices::top(), s), scene.instance, withMotion), 20u);
    EXPECT_GT(withMotion, 20u);
  }
  {   // a mesh not marked dynamic keeps no copy of its vertices: an update is a disocclusion
    MovingVertices scene(2, false);
    scene.r.render(MovingVertices::top(), s);
    scene.moveVertices({0.0f, 0.5f, 0.0f}, false);
    size_t withMotion = 0;
    EXPECT_GT(quadPixels(scene.r.render(MovingVertices::top(), s), scene.instance, withMotion), 20u);
    EXPECT_EQ(withMotion, 0u);
  }
  {   // the vertices moved in an earlier frame only: this frame's motion is 0, not that move
    MovingVertices scene;
    scene.r.render(MovingVertices::top(), s);
    scene.moveVertices({0.0f, 1.0f, 0.0f});
    scene.r.render(MovingVertices::top(), s);
    const FrameView f = scene.r.render(MovingVertices::top(), s);
    size_t onQuad = 0;
    for (size_t i = 0; i < f.motion.size(); ++i) {
      if (f.instance[i] != scene.instance) continue;
      ++onQuad;
      ASSERT_TRUE(std::isfinite(f.motion[i].x)) << i;
      EXPECT_LT(glm::length(f.motion[i]), 1e-3f) << i;
    }
    EXPECT_GT(onQuad, 20u);
  }
}

TEST(VertexMotion, TemporalImageIsTheSameWithOneAndTwoThreads) {
  const auto run = [](uint32_t threads) {
    MovingVertices scene(threads);
    LightDesc light;
    light.position = {2, -2, 3};
    light.intensity = 6.0f;
    scene.r.addLight(light);
    scene.r.commit();
    RenderSettings s = settingsFor(Integrator::Path, 40, 1, 2);
    s.accumulate = false;
    s.denoise = true;
    s.temporal = true;
    FrameView f;
    for (uint32_t frame = 0; frame < 4; ++frame) {
      s.seed = frame;
      scene.moveVertices({0.2f * static_cast<float>(frame), 0.0f, 0.0f});
      f = scene.r.render(MovingVertices::top(), s);
    }
    return std::vector<glm::vec3>(f.radiance.begin(), f.radiance.end());
  };
  const auto one = run(1), two = run(2);
  ASSERT_EQ(one.size(), two.size());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), one.size() * sizeof(glm::vec3)), 0);
}

}  // namespace
}  // namespace pa
