// EntitySlots: the same entity keeps its slot across frames, whatever the submission order.
#include <gtest/gtest.h>

#include "port/engine_glue/entity_slots.h"

namespace glue {
namespace {

TEST(EntitySlots, SameEntitiesKeepTheirSlotsWhenTheOrderChanges) {
  EntitySlots slots;
  const EntityKey rocket{5, 0, 0, 0}, player{7, 3, 0, 0};
  slots.beginFrame();
  const size_t a = slots.claim(player, {0, 0, 0});
  const size_t b = slots.claim(player, {500, 0, 0});
  const size_t c = slots.claim(rocket, {100, 100, 0});
  EXPECT_EQ(slots.size(), 3u);
  // Next frame: submitted in another order, each moved a little.
  slots.beginFrame();
  EXPECT_EQ(slots.claim(rocket, {140, 100, 0}), c);
  EXPECT_EQ(slots.claim(player, {510, 0, 0}), b);
  EXPECT_EQ(slots.claim(player, {5, 5, 0}), a);
  EXPECT_EQ(slots.size(), 3u);
}

TEST(EntitySlots, NewEntityTakesASlotThatShowedNothing) {
  EntitySlots slots;
  const EntityKey gun{1, 0, 0, 1}, player{7, 0, 0, 0}, rocket{5, 0, 0, 0};
  slots.beginFrame();
  const size_t g = slots.claim(gun, {0, 0, 0});
  const size_t p = slots.claim(player, {0, 0, 0});
  // The player is gone this frame; a rocket appears: it may not inherit the player's slot
  // (the renderer would take the player's transform for the rocket's previous one).
  slots.beginFrame();
  EXPECT_EQ(slots.claim(gun, {10, 0, 0}), g);
  const size_t r = slots.claim(rocket, {0, 0, 0});
  EXPECT_NE(r, p);
  EXPECT_FALSE(slots.claimed(p));   // shown nothing: hidden by the caller
  // Next frame the player's old slot showed nothing: a newcomer may take it.
  slots.beginFrame();
  EXPECT_EQ(slots.claim(gun, {20, 0, 0}), g);
  EXPECT_EQ(slots.claim(rocket, {40, 0, 0}), r);
  EXPECT_EQ(slots.claim(player, {900, 0, 0}), p);
}

TEST(EntitySlots, NewEntityPrefersAFreeSlotThatLastShowedItsModel) {
  // Slots are reused across models; one that last showed the same model already has a mesh of
  // that size, so taking it updates the mesh in place.
  EntitySlots slots;
  const EntityKey player{7, 0, 0, 0}, rocket{5, 0, 0, 0}, gib{9, 0, 0, 0};
  slots.beginFrame();
  const size_t p = slots.claim(player, {0, 0, 0});
  const size_t r = slots.claim(rocket, {0, 0, 0});
  slots.beginFrame();   // both gone: their slots showed nothing this frame
  slots.beginFrame();
  EXPECT_EQ(slots.claim(rocket, {900, 0, 0}), r);   // a new rocket: the old rocket's slot, not the first free
  EXPECT_EQ(slots.claim(gib, {0, 0, 0}), p);        // no slot of its model: the first free one
  EXPECT_EQ(slots.size(), 2u);
}

TEST(EntitySlots, NewEntityTakesTheSmallestFreeSlotThatHoldsItsTriangles) {
  // A slot's mesh keeps the size of the largest model it showed: a newcomer takes the smallest
  // free one that already holds it, else the largest, so that slot meshes stop growing.
  EntitySlots slots;
  const EntityKey big{1, 0, 0, 0}, medium{2, 0, 0, 0}, small{3, 0, 0, 0}, other{4, 0, 0, 0}, huge{5, 0, 0, 0};
  slots.beginFrame();
  const size_t b = slots.claim(big, {0, 0, 0}, 900);
  const size_t m = slots.claim(medium, {0, 0, 0}, 300);
  const size_t s = slots.claim(small, {0, 0, 0}, 20);
  slots.beginFrame();   // all gone
  slots.beginFrame();
  EXPECT_EQ(slots.claim(other, {0, 0, 0}, 250), m);   // fits in 300 and 900: the smaller
  EXPECT_EQ(slots.claim(huge, {0, 0, 0}, 2000), b);   // fits nowhere: the largest grows
  EXPECT_EQ(slots.claim(other, {500, 0, 0}, 10), s);
  EXPECT_EQ(slots.size(), 3u);
}

TEST(EntitySlots, FarMoveOrOtherModelIsANewEntity) {
  EntitySlots slots;
  const EntityKey a{3, 0, 0, 0}, b{4, 0, 0, 0};
  slots.beginFrame();
  const size_t first = slots.claim(a, {0, 0, 0});
  slots.beginFrame();
  EXPECT_NE(slots.claim(a, {EntitySlots::kReach * 2, 0, 0}), first);   // too far: teleported or another one
  EXPECT_NE(slots.claim(b, {0, 0, 0}), first);                          // other model
}

}  // namespace
}  // namespace glue
