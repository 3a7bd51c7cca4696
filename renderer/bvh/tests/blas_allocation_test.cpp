// Blases that dynamic meshes use in play allocate nothing once reserved: reserveLike and a
// rebuild keep the memory that the next build and the first refit need. Its own program: it
// counts every operator new of the process (plain and aligned).
#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/bvh/bvh.h"
#include "renderer/bvh/wide16_bvh.h"
#include "renderer/bvh/testing/scene_generators.h"

namespace {
std::atomic<uint64_t> allocations{0};
}  // namespace

void* operator new(std::size_t bytes) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(bytes == 0 ? 1 : bytes)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
// Over-aligned arrays (the wide layouts' nodes and packs) come through the aligned forms.
void* operator new(std::size_t bytes, std::align_val_t alignment) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  const auto align = static_cast<std::size_t>(alignment);
  if (void* p = std::aligned_alloc(align, (bytes + align - 1) / align * align + (bytes == 0 ? align : 0))) return p;
  throw std::bad_alloc();
}
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace pa {
namespace {

/// operator new calls made by body.
template <class Body>
uint64_t allocationsDuring(Body&& body) {
  const uint64_t before = allocations.load();
  body();
  return allocations.load() - before;
}

/// The mesh's vertices moved a little (same topology), as an animated model's next frame.
std::vector<glm::vec3> moved(const testing::TestMesh& mesh, float by) {
  std::vector<glm::vec3> out = mesh.positions;
  for (glm::vec3& p : out) p += glm::vec3(by, 0.5f * by, -by);
  return out;
}

TEST(BlasAllocations, ReservedLikeAPoolSlotShowingASmallerMeshBuildsAndRefitsWithoutAllocating) {
  // The example held a large mesh and now shows a small one (a pooled model slot reused): the
  // memory reserved follows the most it held, not what it holds now.
  const testing::TestMesh large = testing::makeTriangleSoup(4000, 31);
  const testing::TestMesh small = testing::makeTriangleSoup(50, 32);
  Blas example;
  example.build(large.input());
  example.build(large.input());   // rebuilt: keeps its build memory
  example.build(small.input());
  Blas reserved;
  reserved.reserveLike(example);
  const std::vector<glm::vec3> next = moved(large, 0.01f);
  EXPECT_EQ(allocationsDuring([&] { reserved.build(large.input()); }), 0u);
  EXPECT_EQ(allocationsDuring([&] { reserved.refit(next); }), 0u);
  EXPECT_EQ(reserved.triangleCount(), 4000u);
}

TEST(BlasAllocations, ARebuiltBlasRefitsWithoutAllocating) {
  // The largest slot is not reserved like another: its second build keeps the memory, and its
  // first refit then allocates nothing either.
  const testing::TestMesh mesh = testing::makeTriangleSoup(3000, 33);
  Blas blas;
  blas.build(mesh.input());
  blas.build(mesh.input());
  const std::vector<glm::vec3> next = moved(mesh, 0.02f);
  EXPECT_EQ(allocationsDuring([&] { blas.refit(next); }), 0u);
  EXPECT_EQ(allocationsDuring([&] { blas.refit(mesh.positions); }), 0u);
}

TEST(BlasAllocations, RefitsOfADeformingMeshAllocateNothing) {
  // Each refit plans the collapse to the wide layout again over the moved boxes and may choose
  // other leaves than the build did (more nodes, more small packs): a kept Blas has room for any.
  const testing::TestMesh mesh = testing::makeTriangleSoup(3000, 34);
  std::vector<uint32_t> widths{8};
  if (bvh_detail::wide16Available()) widths.push_back(16);
  for (const uint32_t width : widths) {
    BvhBuildConfig config;
    config.nodeWidth = width;
    Blas blas;
    blas.build(mesh.input(), config);
    blas.build(mesh.input(), config);
    uint32_t state = 12345u;
    const auto jitter = [&state] {   // in [-1, 1)
      state = state * 1664525u + 1013904223u;
      return static_cast<float>(state >> 8) / static_cast<float>(1u << 23) - 1.0f;
    };
    for (int frame = 0; frame < 30; ++frame) {
      std::vector<glm::vec3> next = mesh.positions;
      const float amplitude = 0.002f * static_cast<float>(frame % 10);
      for (glm::vec3& p : next) p += amplitude * glm::vec3(jitter(), jitter(), jitter());
      EXPECT_EQ(allocationsDuring([&] { blas.refit(next); }), 0u) << "width " << width << " frame " << frame;
    }
  }
}

}  // namespace
}  // namespace pa
