// Heap allocations of the portal views' per-frame update, counted as the module counts its own
// (this file is part of engine_glue_memory_tests: allocation_hooks.cpp and the --wrap options).
// Once warm, a frame that hands over the same portal, or another one, allocates nothing.
#include <cstdint>

#include <gtest/gtest.h>
#include <glm/vec3.hpp>

#include "port/engine_glue/allocation_counter.h"
#include "port/engine_glue/portals.h"
#include "port/engine_glue/tests/portal_fixtures.h"
#include "renderer/scene/renderer.h"

namespace glue {
namespace {

TEST(PortalMemory, UpdatesOfAWarmPortalViewAllocateNothing) {
  PortalViews views = testing::mirrorFloorViews();
  ASSERT_EQ(views.planes().size(), 1u);
  pa::Renderer renderer({1});
  const q3abi::refEntity_t first = testing::portalEntity({10, 10, 5}, {10, 10, 5});
  const q3abi::refEntity_t second = testing::portalEntity({10, 10, 5}, {40, 10, 5});
  for (int frame = 0; frame < 4; ++frame) {   // warm: both buffers and the renderer's copy grown
    views.update(std::span(&first, 1), 0, renderer);
    views.update(std::span(&second, 1), 0, renderer);
  }
  const uint64_t before = allocationCount();
  for (int frame = 0; frame < 8; ++frame) views.update(std::span(&first, 1), 0, renderer);   // the same each frame
  for (int frame = 0; frame < 8; ++frame)   // another portal each frame
    views.update(frame % 2 == 0 ? std::span(&second, 1) : std::span(&first, 1), 0, renderer);
  views.update({}, 0, renderer);   // gone
  views.update(std::span(&first, 1), 0, renderer);
  EXPECT_EQ(allocationCount() - before, 0u);
}

}  // namespace
}  // namespace glue
