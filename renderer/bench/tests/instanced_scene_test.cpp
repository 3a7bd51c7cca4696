// The bench's two-level scene (--instances): N movers besides the world, placed where the camera's
// rays see surfaces, the same hits through our Tlas and through Embree's instanced scenes.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "renderer/bench/instanced_scene.h"
#include "renderer/bvh/testing/scene_generators.h"

namespace pa::bench {
namespace {

TEST(InstancedScene, MoversAroundTheCameraHitAsInEmbree) {
  BenchScene scene = makeSyntheticScene("sphere:2000");
  scene.camera.origin = glm::vec3(0.1f, 0.2f, 0.05f);   // inside the closed sphere, as in a map
  testing::EmbreeDevice device("threads=1");
  Blas world;
  world.build(scene.mesh.input());
  testing::EmbreeScene embreeWorld(device);
  embreeWorld.addMesh(scene.mesh);
  embreeWorld.commit();
  InstancedScene two;
  buildInstancedScene(scene, world, embreeWorld, device, 12, 5, two);
  ASSERT_EQ(two.instances.size(), 13u);
  EXPECT_EQ(two.instances[0].blas, &world);

  const std::vector<Ray> rays = testing::makeRaysFromPoint(scene.camera.origin, 4096, 9);
  uint32_t moverHits = 0;
  for (const Ray& start : rays) {
    Ray ours = start, theirs = start;
    Hit ourHit, theirHit;
    const bool hitOurs = two.tlas.intersect(ours, ourHit);
    ASSERT_EQ(hitOurs, two.embreeTop->intersect(theirs, theirHit));
    ASSERT_TRUE(hitOurs) << "a ray from inside the closed world left it";
    EXPECT_NEAR(ourHit.t, theirHit.t, 1e-4f * theirHit.t);
    if (ourHit.instance == theirHit.instance && ourHit.instance != 0) ++moverHits;
    EXPECT_EQ(two.tlas.occluded(start), two.embreeTop->occluded(start));
  }
  EXPECT_GT(moverHits, 20u) << "the movers should stand where the camera's rays go";
}

}  // namespace
}  // namespace pa::bench
