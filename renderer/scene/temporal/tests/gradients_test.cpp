// Known-answer tests of the temporal gradients (temporal/gradients.h): the estimator on its own,
// then through pa::Renderer on small scenes built here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "motion_checks.h"
#include "renderer/scene/temporal/gradients.h"
#include "scene_builders.h"

namespace pa {
namespace {

using temporal::GBuffer;
using temporal::GradientConfig;
using temporal::GradientEstimator;
using test::bytesOf;
using test::lookAt;
using test::settingsFor;

/// A G-buffer of w x h whose every pixel moved by `motion` since last frame.
GBuffer movedBy(uint32_t w, uint32_t h, glm::vec2 motion) {
  GBuffer g;
  g.resize(w, h);
  std::fill(g.motion.begin(), g.motion.end(), motion);
  return g;
}

/// One frame of the estimator whose first samples all had luminance `value`.
void recordFrame(GradientEstimator& e, uint32_t w, uint32_t h, float value) {
  e.beginFrame(w, h);
  std::fill(e.sampleLuminance().begin(), e.sampleLuminance().end(), value);
  e.endFrame();
}

const auto kPixelCentre = [](uint32_t, uint32_t) { return glm::vec2(0.5f); };

TEST(GradientEstimator, WithoutLastFrameNothingIsTracedAndNothingDropped) {
  GradientEstimator e(GradientConfig{3, 1, 2.0f});
  e.beginFrame(12, 9);
  EXPECT_FALSE(e.havePrevious());
  e.plan(movedBy(12, 9, {0, 0}), 7, kPixelCentre);
  for (const temporal::GradientTarget& t : e.targets()) EXPECT_FALSE(t.valid);
  EXPECT_TRUE(e.historyDrop().empty());   // before resolve()
  e.resolve();
  ASSERT_EQ(e.historyDrop().size(), 12u * 9u);
  for (float d : e.historyDrop()) EXPECT_EQ(d, 0.0f);
  EXPECT_EQ(e.strataX(), 4u);
  EXPECT_EQ(e.strataY(), 3u);
}

TEST(GradientEstimator, TargetsFollowTheMotionBackAndStayInsideTheirStratum) {
  GradientEstimator e(GradientConfig{3, 1, 2.0f});
  recordFrame(e, 30, 30, 1.0f);
  e.beginFrame(30, 30);
  e.plan(movedBy(30, 30, {-3.0f, 1.0f}), 11, kPixelCentre);   // last frame it was 3 left, 1 down
  size_t valid = 0;
  for (uint32_t sy = 0; sy < e.strataY(); ++sy) {
    for (uint32_t sx = 0; sx < e.strataX(); ++sx) {
      const temporal::GradientTarget& t = e.targets()[size_t{sy} * e.strataX() + sx];
      if (!t.valid) continue;
      ++valid;
      // The chosen pixel (x, y) lies in the stratum; its sample at x + 0.5 came from x - 2.5.
      EXPECT_GE(t.x + 3, sx * 3);
      EXPECT_LT(t.x + 3, sx * 3 + 3);
      EXPECT_GE(t.y, sy * 3 + 1);
      EXPECT_LT(t.y, sy * 3 + 4);
    }
  }
  EXPECT_GT(valid, 80u);   // all but the strata whose pixel came from outside the image
  // Another frame seed picks other pixels in some strata.
  const std::vector<temporal::GradientTarget> first(e.targets().begin(), e.targets().end());
  e.plan(movedBy(30, 30, {-3.0f, 1.0f}), 12, kPixelCentre);
  size_t moved = 0;
  for (size_t k = 0; k < first.size(); ++k) moved += first[k].x != e.targets()[k].x || first[k].y != e.targets()[k].y;
  EXPECT_GT(moved, 50u);
}

TEST(GradientEstimator, UnchangedSamplesDropNothingAndDarkenedOnesDropTheirShare) {
  // 36 x 12 pixels: 12 x 4 strata. The left half's samples come back unchanged, the right
  // half's at 3/4 of their value (a quarter of the light went; gain 2: half the history).
  GradientEstimator e(GradientConfig{3, 1, 2.0f});
  recordFrame(e, 36, 12, 2.0f);
  e.beginFrame(36, 12);
  e.plan(movedBy(36, 12, {0, 0}), 5, kPixelCentre);
  for (size_t k = 0; k < e.targets().size(); ++k) {
    ASSERT_TRUE(e.targets()[k].valid);
    e.record(k, e.targets()[k].x < 18 ? 2.0f : 1.5f);
  }
  e.resolve();
  const std::span<const float> strata = e.strataDrop();
  for (uint32_t sy = 0; sy < 4; ++sy) {
    for (uint32_t sx = 0; sx < 12; ++sx) {
      const float d = strata[size_t{sy} * 12 + sx];
      if (sx <= 4) EXPECT_EQ(d, 0.0f) << sx;                    // pooled over left strata only
      else if (sx >= 7) EXPECT_NEAR(d, 0.5f, 1e-6f) << sx;      // right strata only: 2 |2 - 1.5| / 2
      else EXPECT_GT(d, 0.0f) << sx;                            // the border pools both sides
    }
  }
  // Each pixel takes its stratum's share.
  const std::span<const float> drop = e.historyDrop();
  for (uint32_t y = 0; y < 12; ++y)
    for (uint32_t x = 0; x < 36; ++x) EXPECT_EQ(drop[size_t{y} * 36 + x], strata[size_t{y / 3} * 12 + x / 3]);
}

TEST(GradientEstimator, AnotherSizeForgetsLastFrame) {
  GradientEstimator e;
  recordFrame(e, 12, 12, 1.0f);
  e.beginFrame(12, 12);
  EXPECT_TRUE(e.havePrevious());
  e.beginFrame(15, 12);
  EXPECT_FALSE(e.havePrevious());
  e.reset();
  e.beginFrame(15, 12);
  EXPECT_FALSE(e.havePrevious());
}

TEST(GradientEstimator, AnotherStratumForgetsLastFrameAndCutsOtherStrata) {
  GradientEstimator e(GradientConfig{3, 1, 2.0f});
  recordFrame(e, 16, 16, 1.0f);
  e.configure(GradientConfig{3, 1, 2.0f});   // the same parameters: nothing forgotten
  e.beginFrame(16, 16);
  EXPECT_TRUE(e.havePrevious());
  EXPECT_EQ(e.strataX(), 6u);
  e.configure(GradientConfig{4, 1, 2.0f});
  EXPECT_EQ(e.config().stratum, 4u);
  e.beginFrame(16, 16);
  EXPECT_FALSE(e.havePrevious());
  EXPECT_EQ(e.strataX(), 4u);
  EXPECT_EQ(e.targets().size(), 16u);
  e.configure(GradientConfig{1, 9, -1.0f});   // clamped to 2 strata pixels, radius 4, gain 0
  EXPECT_EQ(e.config().stratum, 2u);
  EXPECT_EQ(e.config().filterRadius, 4u);
  EXPECT_EQ(e.config().gain, 0.0f);
}

/// The floor of addFloorWithTwoLamps (the left lamp can be changed) with a back wall and a sphere
/// under the right lamp that casts a shadow.
struct LampRoom {
  Renderer r;
  LightId left = kNoId;
  LightDesc leftDesc;
  explicit LampRoom(uint32_t threads = 2) : r(RendererConfig{threads}) {
    left = test::addFloorWithTwoLamps(r, leftDesc);
    const MaterialId grey = r.addMaterial(test::diffuse(0.6f));
    test::addMesh(r, test::quad({-8, 4, 0}, {16, 0, 0}, {0, 0, 5}), grey);
    test::addMesh(r, test::sphere({3.5f, 1, 1}, 0.8f, 12, 24), grey);
    r.commit();
  }
  /// Looks down at the floor from the -Y side: film +x is world +x; frames move it sideways.
  static Camera camera(uint32_t frame) {
    const float dx = 0.05f * static_cast<float>(frame);
    return lookAt({dx, -3, 9}, {dx, 0, 0}, 100.0f);
  }
};

RenderSettings temporalSettings(Integrator integrator, bool gradients) {
  RenderSettings s = settingsFor(integrator, 48, 1, 2);
  s.accumulate = false;
  s.denoise = true;
  s.temporal = true;
  s.temporalGradients = gradients;
  return s;
}

TEST(TemporalGradients, StillLightingUnderCameraMotionDropsNothing) {
  // Last frame's samples traced again from this frame's scene give the same values bit for bit:
  // no gradient anywhere, so the frames are those of the temporal stage without gradients.
  for (const Integrator integrator : {Integrator::Direct, Integrator::Path}) {
    LampRoom with, without;
    for (uint32_t frame = 0; frame < 5; ++frame) {
      RenderSettings s = temporalSettings(integrator, true);
      s.seed = frame;
      const FrameView f = with.r.render(LampRoom::camera(frame), s);
      ASSERT_EQ(f.historyDrop.empty(), frame == 0);
      size_t nonzero = 0;
      for (float d : f.historyDrop) nonzero += d != 0.0f;
      EXPECT_EQ(nonzero, 0u) << "frame " << frame;
      const std::vector<uint8_t> image = bytesOf(f.radiance);
      s.temporalGradients = false;
      const FrameView g = without.r.render(LampRoom::camera(frame), s);
      EXPECT_TRUE(g.historyDrop.empty());
      EXPECT_EQ(bytesOf(g.radiance), image) << "frame " << frame;
    }
  }
}

TEST(TemporalGradients, WeaponMovingWithTheCameraDropsNothing) {
  // A camera-only overlay drawn on top (the first-person weapon) placed in front of a camera that
  // moves half a unit a frame: last frame's camera rays no longer find it where they did, which
  // is no change of lighting.
  LampRoom room;
  test::MeshArrays gun = test::quad({-0.5f, 0, -0.5f}, {1, 0, 0}, {0, 0, 1});
  gun.setMaterial(room.r.addMaterial(test::diffuse(0.6f)));
  InstanceDesc weapon{room.r.addMesh(gun.desc())};
  weapon.mask = kMaskCamera;
  weapon.drawOnTop = true;
  const InstanceId id = room.r.addInstance(weapon);
  RenderSettings s = temporalSettings(Integrator::Direct, true);
  size_t onWeapon = 0;
  for (uint32_t frame = 0; frame < 5; ++frame) {
    const float x = -2.0f + 0.5f * static_cast<float>(frame);
    const Camera camera = lookAt({x, -6, 2}, {x, 0, 1}, 60.0f);
    weapon.objectToWorld[3] = camera.origin + 2.0f * camera.forward - 0.6f * camera.up;   // low in the view
    room.r.setInstance(id, weapon);
    room.r.commit();
    s.seed = frame;
    const FrameView f = room.r.render(camera, s);
    for (size_t i = 0; i < f.historyDrop.size(); ++i) {
      EXPECT_EQ(f.historyDrop[i], 0.0f) << "frame " << frame << " pixel " << i;
      onWeapon += f.instance[i] == id;
    }
  }
  EXPECT_GT(onWeapon, 400u);
}

TEST(TemporalGradients, SwitchedOffLampDropsTheHistoryWhereItLitAndNowhereElse) {
  LampRoom room;
  RenderSettings s = temporalSettings(Integrator::Direct, true);
  std::vector<float> lit;
  for (uint32_t frame = 0; frame < 12; ++frame) {
    s.seed = frame;
    const FrameView f = room.r.render(LampRoom::camera(frame), s);
    lit.assign(f.radiance.size(), 0.0f);
    for (size_t i = 0; i < f.radiance.size(); ++i) lit[i] = f.radiance[i].g;
  }
  LightDesc off = room.leftDesc;
  off.intensity = 0.0f;
  room.r.setLight(room.left, off);
  room.r.commit();
  s.seed = 12;
  const FrameView f = room.r.render(LampRoom::camera(12), s);
  ASSERT_EQ(f.historyDrop.size(), 48u * 48u);
  // The left lamp lights the floor at world x in [-7.2, -0.8], the right one at x in [0.8, 7.2]:
  // columns left of 20 (world x < -1.2) saw only the left lamp, those from 34 on (x > 5.4) at most
  // the right one.
  size_t leftChecked = 0, rightChecked = 0;
  for (uint32_t y = 8; y < 40; ++y) {
    for (uint32_t x = 4; x < 44; ++x) {
      const size_t i = size_t{y} * 48 + x;
      if (x < 20 && lit[i] > 0.05f) {
        EXPECT_GT(f.historyDrop[i], 0.8f) << x << "," << y;
        ++leftChecked;
      } else if (x >= 34) {
        EXPECT_EQ(f.historyDrop[i], 0.0f) << x << "," << y;
        ++rightChecked;
      }
    }
  }
  EXPECT_GT(leftChecked, 100u);
  EXPECT_GT(rightChecked, 100u);
}

TEST(TemporalGradients, DimmedLampLeavesNoLagBehind) {
  // A lamp dimmed to a third. The gradients drop the whole history under it (a change by half or
  // more, GradientConfig::gain 2), and the frame after shows the new light as a frame without
  // history does, not a blend with the old light.
  const auto dim = [](LampRoom& room) {
    LightDesc d = room.leftDesc;
    d.intensity /= 3.0f;
    room.r.setLight(room.left, d);
    room.r.commit();
  };
  LampRoom room;
  RenderSettings s = temporalSettings(Integrator::Direct, true);
  FrameView before;
  for (uint32_t frame = 0; frame < 16; ++frame) {
    s.seed = frame;
    before = room.r.render(LampRoom::camera(0), s);
  }
  // The floor well inside the left lamp's reach: left of the middle, above a third of the peak.
  std::vector<size_t> lit;
  float peak = 0.0f;
  for (uint32_t y = 0; y < 48; ++y)
    for (uint32_t x = 0; x < 20; ++x) peak = std::max(peak, before.radiance[size_t{y} * 48 + x].g);
  for (uint32_t y = 0; y < 48; ++y)
    for (uint32_t x = 0; x < 20; ++x)
      if (before.radiance[size_t{y} * 48 + x].g > peak / 3.0f) lit.push_back(size_t{y} * 48 + x);
  ASSERT_GT(lit.size(), 40u);
  const auto meanLit = [&](const FrameView& f) {
    double sum = 0.0;
    for (const size_t i : lit) sum += f.radiance[i].g;
    return sum / static_cast<double>(lit.size());
  };
  dim(room);
  s.seed = 16;
  const FrameView after = room.r.render(LampRoom::camera(0), s);
  for (const size_t i : lit) EXPECT_EQ(after.historyDrop[i], 1.0f) << i;
  const double seen = meanLit(after);
  LampRoom fresh;   // the dimmed lamp from the start: the same frame with no history
  dim(fresh);
  const double truth = meanLit(fresh.r.render(LampRoom::camera(0), s));
  ASSERT_GT(truth, 0.0);
  EXPECT_NEAR(seen / truth, 1.0, 0.02);
}

TEST(TemporalGradients, SameFramesWithOneAndTwoThreads) {
  const auto run = [](uint32_t threads) {
    LampRoom room(threads);
    RenderSettings s = temporalSettings(Integrator::Path, true);
    FrameView f;
    for (uint32_t frame = 0; frame < 4; ++frame) {
      if (frame == 2) {   // a change for the gradients to see
        LightDesc dim = room.leftDesc;
        dim.intensity = 3.0f;
        room.r.setLight(room.left, dim);
        room.r.commit();
      }
      s.seed = frame;
      f = room.r.render(LampRoom::camera(frame), s);
    }
    std::vector<uint8_t> out = bytesOf(f.radiance);
    const std::vector<uint8_t> drop = bytesOf(f.historyDrop);
    out.insert(out.end(), drop.begin(), drop.end());
    return out;
  };
  EXPECT_EQ(run(1), run(2));
}

}  // namespace
}  // namespace pa
