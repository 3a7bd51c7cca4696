// Heap allocations of dynamic-mesh updates, counted as the module counts its own (this test
// links allocation_hooks.cpp and the same --wrap options): a slot mesh given the memory of the
// largest one (Renderer::reserveMeshLike, what the glue does for every entity slot) takes a model
// of that size without allocating, where a mesh without it allocates.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>
#include <glm/vec3.hpp>

#include "port/engine_glue/allocation_counter.h"
#include "renderer/scene/renderer.h"

namespace {

/// A cells x cells grid of quads (2 triangles each) in the z = height plane.
struct Grid {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;
  std::vector<pa::MaterialId> materials;

  Grid(uint32_t cells, float height) {
    for (uint32_t y = 0; y <= cells; ++y)
      for (uint32_t x = 0; x <= cells; ++x) positions.emplace_back(float(x), float(y), height + 0.01f * float(x % 3));
    for (uint32_t y = 0; y < cells; ++y) {
      for (uint32_t x = 0; x < cells; ++x) {
        const uint32_t a = y * (cells + 1) + x, b = a + 1, c = a + cells + 1, d = c + 1;
        indices.insert(indices.end(), {a, b, d, a, d, c});
      }
    }
    materials.assign(indices.size() / 3, 0);
  }
  pa::MeshDesc desc() const {
    pa::MeshDesc mesh;
    mesh.positions = positions;
    mesh.indices = indices;
    mesh.materials = materials;
    mesh.dynamic = true;
    return mesh;
  }
};

/// Allocations made by update(), counted by the module's counter.
template <class Update>
uint64_t allocationsOf(const Update& update) {
  const uint64_t before = glue::allocationCount();
  update();
  return glue::allocationCount() - before;
}

TEST(MeshMemory, ASlotMeshReservedLikeTheLargestTakesItsModelWithoutAllocating) {
  pa::Renderer renderer({1});
  renderer.addMaterial(pa::MaterialDesc{});
  const Grid large(40, 0.0f), largeMoved(40, 1.0f), small(3, 0.0f), smallMoved(3, 1.0f);
  const pa::MeshId largest = renderer.addMesh(large.desc());
  const pa::MeshId reserved = renderer.addMesh(small.desc());
  const pa::MeshId unreserved = renderer.addMesh(small.desc());
  for (const pa::MeshId mesh : {largest, reserved, unreserved}) renderer.addInstance({mesh});
  renderer.commit();
  renderer.updateMesh(largest, largeMoved.desc());   // rebuilt, as slot meshes are in play
  renderer.commit();
  renderer.reserveMeshLike(reserved, largest);
  // Warm the scene's own per-commit arrays with small updates of both meshes.
  for (const Grid* grid : {&smallMoved, &small}) {
    renderer.updateMesh(reserved, grid->desc());
    renderer.updateMesh(unreserved, grid->desc());
    renderer.commit();
  }

  // The large model shown in the reserved mesh: copied, its BVH built, committed.
  EXPECT_EQ(allocationsOf([&] {
              renderer.updateMesh(reserved, large.desc());
              renderer.commit();
            }),
            0u);
  // And moved (a refit), then back to a small model and the large one again (rebuilds).
  EXPECT_EQ(allocationsOf([&] {
              renderer.updateMesh(reserved, largeMoved.desc());
              renderer.commit();
              renderer.updateMesh(reserved, small.desc());
              renderer.commit();
              renderer.updateMesh(reserved, large.desc());
              renderer.commit();
            }),
            0u);
  // Without the reservation the same update grows the mesh's arrays and BVH memory.
  EXPECT_GT(allocationsOf([&] {
              renderer.updateMesh(unreserved, large.desc());
              renderer.commit();
            }),
            4u);
}

TEST(MeshMemory, ReservingLikeAnUncommittedOrTheSameMeshIsHarmless) {
  pa::Renderer renderer({1});
  renderer.addMaterial(pa::MaterialDesc{});
  const Grid small(2, 0.0f), large(10, 0.0f);
  const pa::MeshId a = renderer.addMesh(small.desc());
  const pa::MeshId b = renderer.addMesh(large.desc());
  renderer.reserveMeshLike(a, b);   // b not committed yet: its pending arrays' size
  renderer.reserveMeshLike(a, a);
  renderer.addInstance({a});
  renderer.addInstance({b});
  EXPECT_NO_THROW(renderer.commit());
  renderer.updateMesh(a, large.desc());
  EXPECT_NO_THROW(renderer.commit());
  EXPECT_THROW(renderer.reserveMeshLike(a, 99), pa::SceneError);
}

}  // namespace
