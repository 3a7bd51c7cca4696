// RenderSettings::accumulateThroughEdits: a still view of a world that keeps changing (play in
// the reference preset) keeps accumulating. Edits restart only the pixels that show them; light
// edits are averaged over the frames; edits that may change any pixel restart everything.
#include <gtest/gtest.h>

#include <vector>

#include "scene_builders.h"

namespace pa {
namespace {

using test::lookAt;
using test::settingsFor;

constexpr uint32_t kSize = 16;
constexpr float kItemAlbedo = 0.25f;

/// Floor and back wall lit by one point light only (no sky, no emitters: radiance is linear in
/// the light's intensity).
struct Room {
  TextureId texture = kNoId;
  LightId light = kNoId;
  LightDesc lightDesc;
};

Room buildRoom(Renderer& r) {
  Room room;
  static constexpr uint8_t kWhite[4] = {255, 255, 255, 255};
  TextureDesc white;
  white.width = white.height = 1;
  white.rgba8 = kWhite;
  room.texture = r.addTexture(white);
  MaterialDesc wall = test::diffuse(0.7f);
  wall.baseTexture = room.texture;
  const MaterialId grey = r.addMaterial(wall);
  test::addMesh(r, test::quad({-3, -3, 0}, {6, 0, 0}, {0, 6, 0}), grey);
  test::addMesh(r, test::quad({-3, 3, 0}, {6, 0, 0}, {0, 0, 4}), grey);
  room.lightDesc.position = {1, -2, 3};
  room.lightDesc.intensity = 5.0f;
  room.light = r.addLight(room.lightDesc);
  r.commit();
  return room;
}

Camera camera() { return lookAt({0, -6, 2}, {0, 0, 1}, 50.0f); }

RenderSettings throughEdits() {
  RenderSettings s = settingsFor(Integrator::Direct, kSize, 1, 1);
  s.accumulateThroughEdits = true;
  return s;
}

/// A small plate in front of the back wall that only camera rays see (it changes no other
/// pixel's light, so those pixels can be compared exactly with a room without it).
InstanceDesc addItem(Renderer& r, InstanceId& id) {
  MaterialDesc m = test::diffuse(kItemAlbedo);
  const MaterialId material = r.addMaterial(m);
  test::MeshArrays plate = test::quad({-2.5f, 1, 0.5f}, {2, 0, 0}, {0, 0, 2});
  plate.setMaterial(material);
  InstanceDesc item;
  item.mesh = r.addMesh(plate.desc());
  item.mask = kMaskCamera;
  id = r.addInstance(item);
  r.commit();
  return item;
}

bool showsItem(const FrameView& f, size_t i) { return f.albedo[i] == glm::vec3(kItemAlbedo); }

TEST(AccumulateThroughEdits, AMovedInstanceRestartsOnlyThePixelsThatShowIt) {
  Renderer r({2});
  buildRoom(r);
  InstanceId itemId = kNoId;
  InstanceDesc item = addItem(r, itemId);
  Renderer plain({2});   // the same room without the item
  buildRoom(plain);
  const RenderSettings s = throughEdits();
  r.render(camera(), s);
  r.render(camera(), s);
  const FrameView before = r.render(camera(), s);
  std::vector<bool> showedBefore(before.albedo.size()), mixedBefore(before.albedo.size());
  for (size_t i = 0; i < showedBefore.size(); ++i) {
    showedBefore[i] = showsItem(before, i);
    mixedBefore[i] = !showedBefore[i] && before.albedo[i] != glm::vec3(0.7f);   // an edge pixel
  }
  item.objectToWorld[3] = glm::vec3(3.0f, 0, 0);   // to the other side of the view
  r.setInstance(itemId, item);
  r.commit();
  const FrameView after = r.render(camera(), s);
  EXPECT_EQ(after.accumulatedFrames, 4u);
  FrameView expected;
  for (int i = 0; i < 4; ++i) expected = plain.render(camera(), s);
  size_t untouched = 0, nowShown = 0, uncovered = 0;
  for (size_t i = 0; i < after.radiance.size(); ++i) {
    const bool shows = after.albedo[i] != glm::vec3(0.7f);   // the item in some sample now
    if (!showedBefore[i] && !mixedBefore[i] && !shows) {
      ++untouched;   // four frames of the room, exactly as without the item
      EXPECT_EQ(after.radiance[i], expected.radiance[i]) << "pixel " << i;
    } else if (showsItem(after, i) && !showedBefore[i] && !mixedBefore[i]) {
      ++nowShown;   // restarted: the item alone, no wall history
      EXPECT_EQ(after.albedo[i], glm::vec3(kItemAlbedo)) << "pixel " << i;
      EXPECT_EQ(after.variance[i], 0.0f) << "pixel " << i;   // one sample
    } else if (showedBefore[i] && !shows) {
      ++uncovered;   // restarted: the wall alone, no item history
      EXPECT_EQ(after.albedo[i], glm::vec3(0.7f)) << "pixel " << i;
    }
  }
  EXPECT_GT(untouched, kSize * kSize / 2);
  EXPECT_GT(nowShown, 4u);
  EXPECT_GT(uncovered, 4u);
}

TEST(AccumulateThroughEdits, ASurfaceThatMovesALittleKeepsItsHistory) {
  // The view weapon's idle drift, a bobbing item: the pixel still shows the same surface.
  Renderer r({2});
  buildRoom(r);
  InstanceId itemId = kNoId;
  InstanceDesc item = addItem(r, itemId);
  const RenderSettings s = throughEdits();
  r.render(camera(), s);
  r.render(camera(), s);
  const FrameView before = r.render(camera(), s);
  const std::vector<glm::vec3> albedoBefore(before.albedo.begin(), before.albedo.end());
  item.objectToWorld[3] = glm::vec3(0.001f, 0, 0.001f);
  r.setInstance(itemId, item);
  r.commit();
  const FrameView after = r.render(camera(), s);
  EXPECT_EQ(after.accumulatedFrames, 4u);
  size_t kept = 0;
  for (size_t i = 0; i < after.radiance.size(); ++i) {
    if (albedoBefore[i] != glm::vec3(kItemAlbedo) || !showsItem(after, i)) continue;
    ++kept;   // four samples of the item: a spread between them (one sample alone has none)
    EXPECT_GT(after.variance[i], 0.0f) << "pixel " << i;
  }
  EXPECT_GT(kept, 8u);
}

TEST(AccumulateThroughEdits, ALightEditIsAveragedOverTheFrames) {
  Renderer r({2});
  Room room = buildRoom(r);
  Renderer plain({2});
  buildRoom(plain);
  const RenderSettings s = throughEdits();
  FrameView four, five;
  for (int i = 0; i < 4; ++i) r.render(camera(), s);
  for (int i = 0; i < 4; ++i) four = plain.render(camera(), s);
  const std::vector<glm::vec3> meanOfFour(four.radiance.begin(), four.radiance.end());
  five = plain.render(camera(), s);
  room.lightDesc.intensity *= 2.0f;   // the fifth frame sees the light twice as bright
  r.setLight(room.light, room.lightDesc);
  r.commit();
  const FrameView f = r.render(camera(), s);
  EXPECT_EQ(f.accumulatedFrames, 5u);
  // Frame 5 alone is 5 x mean5 - 4 x mean4 at the old intensity; doubled, the mean of five becomes
  // mean5 + (5 mean5 - 4 mean4) / 5.
  for (size_t i = 0; i < f.radiance.size(); ++i) {
    const glm::vec3 expected = 2.0f * five.radiance[i] - 0.8f * meanOfFour[i];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f.radiance[i][c], expected[c], 1e-5f + 1e-5f * expected[c]) << i;
  }
}

TEST(AccumulateThroughEdits, EditsThatMayChangeAnyPixelRestartEverything) {
  Renderer r({2});
  const Room room = buildRoom(r);
  const RenderSettings s = throughEdits();
  r.render(camera(), s);
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 2u);
  r.commit();   // nothing changed
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 3u);
  static constexpr uint8_t kGrey[4] = {128, 128, 128, 255};
  TextureDesc grey;
  grey.width = grey.height = 1;
  grey.rgba8 = kGrey;
  r.updateTexture(room.texture, grey);
  r.commit();
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 1u);
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 2u);
  RenderSettings plain = s;   // switching the mode starts again
  plain.accumulateThroughEdits = false;
  EXPECT_EQ(r.render(camera(), plain).accumulatedFrames, 1u);
}

TEST(AccumulateThroughEdits, SettingTheSameValuesChangesNothing) {
  Renderer r({2});
  Room room = buildRoom(r);
  RenderSettings s = settingsFor(Integrator::Direct, kSize, 1, 1);   // any edit would restart
  r.render(camera(), s);
  r.setLight(room.light, room.lightDesc);
  r.setMaterial(0, [] {
    MaterialDesc wall = test::diffuse(0.7f);
    wall.baseTexture = 0;
    return wall;
  }());
  r.setPortals({});
  r.commit();
  EXPECT_EQ(r.render(camera(), s).accumulatedFrames, 2u);
}

}  // namespace
}  // namespace pa
