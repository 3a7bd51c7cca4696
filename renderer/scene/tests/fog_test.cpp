// Fog volumes: the opacity curve, ray clipping, and known answers through pa::Renderer in
// every integrator (camera rays, eye-space depth in the Lightmap look, shadow rays, glow).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "renderer/scene/media/fog_volumes.h"
#include "renderer/scene/tests/scene_builders.h"
#include "renderer/scene/textures/texture.h"

namespace pa::test {
namespace {

/// Planes of the axis-aligned box [mins, maxs] (outward normals).
std::vector<glm::vec4> boxPlanes(const glm::vec3& mins, const glm::vec3& maxs) {
  return {{1, 0, 0, maxs.x},  {-1, 0, 0, -mins.x}, {0, 1, 0, maxs.y},
          {0, -1, 0, -mins.y}, {0, 0, 1, maxs.z},  {0, 0, -1, -mins.z}};
}

float expectedOpacity(float length, float depth) { return std::sqrt(length / depth - 1.0f / 64.0f); }

glm::vec3 centrePixel(const FrameView& f) { return f.radiance[(f.height / 2) * f.width + f.width / 2]; }

/// A white full-bright wall (Lightmap: base x 1) facing -X at x = 10, camera at the origin looking +X.
struct WallScene {
  Renderer renderer{RendererConfig{2}};
  std::vector<glm::vec4> planes;
  WallScene() {
    MeshArrays wall = quad({10, 50, -50}, {0, -100, 0}, {0, 0, 100});
    wall.setMaterial(renderer.addMaterial(diffuse(1.0f)));
    const MeshId mesh = renderer.addMesh(wall.desc());
    InstanceDesc instance;
    instance.mesh = mesh;
    renderer.addInstance(instance);
  }
  void setFog(const glm::vec3& mins, const glm::vec3& maxs, const glm::vec3& color, float depth) {
    planes = boxPlanes(mins, maxs);
    FogVolumeDesc fog;
    fog.planes = planes;
    fog.color = color;
    fog.depthForOpaque = depth;
    renderer.setFogVolumes(std::span<const FogVolumeDesc>(&fog, 1));
  }
  FrameView render(Integrator integrator, float fov, uint32_t size = 9) {
    renderer.commit();
    RenderSettings s = settingsFor(integrator, size, 1, 0);
    s.accumulate = false;
    return renderer.render(lookAt({0, 0, 0}, {1, 0, 0}, fov), s);
  }
};

TEST(FogVolume, OpacityCurveFollowsTheStockFogTable) {
  EXPECT_FLOAT_EQ(fogOpacity(0.0f, 100.0f), 0.0f);
  EXPECT_FLOAT_EQ(fogOpacity(100.0f / 64.0f, 100.0f), 0.0f);   // the fog starts 1/64 in
  EXPECT_FLOAT_EQ(fogOpacity(50.0f, 100.0f), expectedOpacity(50.0f, 100.0f));
  EXPECT_FLOAT_EQ(fogOpacity(1000.0f, 100.0f), 1.0f);
  EXPECT_FLOAT_EQ(fogOpacity(std::numeric_limits<float>::infinity(), 100.0f), 1.0f);
  EXPECT_FLOAT_EQ(fogOpacity(std::nanf(""), 100.0f), 0.0f);
}

TEST(FogVolume, IntervalOfARayThroughABox) {
  const std::vector<glm::vec4> planes = boxPlanes({0, 0, 0}, {1, 1, 1});
  FogVolumeDesc desc;
  desc.planes = planes;
  const FogVolume box = makeFogVolume(desc, "box");
  float t0 = 0, t1 = 0;
  ASSERT_TRUE(fogInterval(box, {-5, 0.5f, 0.5f}, {2, 0, 0}, 100.0f, t0, t1));   // t in units of |dir| = 2
  EXPECT_FLOAT_EQ(t0, 2.5f);
  EXPECT_FLOAT_EQ(t1, 3.0f);
  ASSERT_TRUE(fogInterval(box, {0.5f, 0.5f, 0.5f}, {0, 0, 1}, 0.25f, t0, t1));   // starts inside, ends inside
  EXPECT_FLOAT_EQ(t0, 0.0f);
  EXPECT_FLOAT_EQ(t1, 0.25f);
  EXPECT_FALSE(fogInterval(box, {-5, 2, 0.5f}, {1, 0, 0}, 100.0f, t0, t1));     // passes beside it
  EXPECT_FALSE(fogInterval(box, {-5, 0.5f, 0.5f}, {1, 0, 0}, 4.0f, t0, t1));    // stops before it
  EXPECT_FALSE(fogInterval(box, {-5, 0.5f, 0.5f}, {-1, 0, 0}, 100.0f, t0, t1)); // points away
}

TEST(FogVolume, BoxHoldsABoundedVolumeAndOnlySegmentsThatMissItSkipIt) {
  const std::vector<glm::vec4> cube = boxPlanes({-1, 2, 3}, {4, 5, 7});
  FogVolumeDesc desc;
  desc.planes = cube;
  const FogVolume box = makeFogVolume(desc, "box");
  ASSERT_TRUE(box.boxed);
  for (int a = 0; a < 3; ++a) {   // the box with a margin of about 1e-3 of its coordinates
    EXPECT_LT(box.boxMin[a], glm::vec3(-1, 2, 3)[a]);
    EXPECT_GT(box.boxMin[a], glm::vec3(-1, 2, 3)[a] - 0.05f);
    EXPECT_GT(box.boxMax[a], glm::vec3(4, 5, 7)[a]);
    EXPECT_LT(box.boxMax[a], glm::vec3(4, 5, 7)[a] + 0.05f);
  }
  // A tetrahedron (a slanted face): its box holds its four corners.
  const std::vector<glm::vec4> tetra = {{-1, 0, 0, 0}, {0, -1, 0, 0}, {0, 0, -1, 0}, {1, 1, 1, 2}};
  desc.planes = tetra;
  const FogVolume wedge = makeFogVolume(desc, "tetrahedron");
  ASSERT_TRUE(wedge.boxed);
  EXPECT_NEAR(wedge.boxMax.x, 2.0f, 0.01f);
  EXPECT_NEAR(wedge.boxMin.y, 0.0f, 0.01f);
  // Open volumes (a box missing a side, a half-space) and volumes of many planes get no box.
  const std::vector<glm::vec4> open(cube.begin(), cube.begin() + 5);
  desc.planes = open;
  EXPECT_FALSE(makeFogVolume(desc, "open box").boxed);
  desc.planes = std::span<const glm::vec4>(cube.data(), 1);
  EXPECT_FALSE(makeFogVolume(desc, "half-space").boxed);
  std::vector<glm::vec4> many = cube;
  for (size_t i = many.size(); i <= kMaxBoxedFogPlanes; ++i) many.push_back({1, 0, 0, 4.0f + float(i)});   // redundant
  desc.planes = many;
  EXPECT_FALSE(makeFogVolume(desc, "many planes").boxed);
  // Segments about both volumes, many grazing their faces, edges and corners: the same crossings
  // with the box as clipped plane by plane.
  for (const FogVolume* volume : {&box, &wedge}) {
    FogVolume unboxed = *volume;
    unboxed.boxed = false;
    const glm::vec3 centre = 0.5f * (volume->boxMin + volume->boxMax), half = 0.5f * (volume->boxMax - volume->boxMin);
    uint32_t state = 12345u, crossed = 0;
    const auto next = [&] {
      state = state * 1664525u + 1013904223u;
      return float(state >> 8) / float(1u << 24) * 2.0f - 1.0f;   // [-1, 1)
    };
    for (int i = 0; i < 20000; ++i) {
      const glm::vec3 origin = centre + 2.5f * half * glm::vec3(next(), next(), next());
      glm::vec3 target = centre + 1.2f * half * glm::vec3(next(), next(), next());
      if (i % 3 == 0) target[i % 9 / 3] = (i % 2 ? volume->boxMin : volume->boxMax)[i % 9 / 3];   // on a face plane
      const float tEnd = 0.5f + 1.5f * (next() + 1.0f);
      const FogSegment a(std::span(volume, 1), origin, target - origin, tEnd, 1.0f);
      const FogSegment b(std::span(&unboxed, 1), origin, target - origin, tEnd, 1.0f);
      ASSERT_EQ(a.transmittance(), b.transmittance()) << i;
      ASSERT_EQ(a.glow(), b.glow()) << i;
      crossed += a.empty() ? 0 : 1;
    }
    EXPECT_GT(crossed, 2000u);   // many segments cross the volume, many miss it
    EXPECT_LT(crossed, 18000u);
  }
}

TEST(FogVolume, SegmentComposesVolumesFrontToBack) {
  const std::vector<glm::vec4> nearPlanes = boxPlanes({1, -1, -1}, {3, 1, 1});
  const std::vector<glm::vec4> farPlanes = boxPlanes({5, -1, -1}, {9, 1, 1});
  FogVolumeDesc a{nearPlanes, {1, 0, 0}, 4.0f};
  FogVolumeDesc b{farPlanes, {0, 0, 1}, 8.0f};
  const std::vector<FogVolume> volumes = {makeFogVolume(b, "far"), makeFogVolume(a, "near")};   // any order
  const FogSegment segment(volumes, {0, 0, 0}, {1, 0, 0}, 20.0f, 1.0f);
  const float an = expectedOpacity(2.0f, 4.0f), af = expectedOpacity(4.0f, 8.0f);
  EXPECT_NEAR(segment.transmittance(), (1 - an) * (1 - af), 1e-6f);
  EXPECT_NEAR(segment.glow().r, an, 1e-6f);
  EXPECT_NEAR(segment.glow().b, (1 - an) * af, 1e-6f);
  EXPECT_NEAR(segment.transmittanceTo(4.0f), 1 - an, 1e-6f);
  EXPECT_FLOAT_EQ(segment.transmittanceTo(0.5f), 1.0f);
}

/// What FogSegment's endInsideOnly counts, from fogInterval alone: the volume holds the end of
/// origin + t dir, t in [0, tEnd] (within the end slack of 1e-4 tEnd; an infinite end when the
/// ray never leaves).
bool holdsEnd(const FogVolume& v, const glm::vec3& origin, const glm::vec3& dir, float tEnd) {
  float t0 = 0, t1 = 0;
  if (!fogInterval(v, origin, dir, tEnd, t0, t1)) return false;
  return std::isfinite(tEnd) ? t1 + 1e-4f * std::max(1.0f, tEnd) >= tEnd : std::isinf(t1);
}

/// fogMayHoldEndsIn for the ends of a set of segments, as RenderScene::markFogFreeEnds asks it.
bool mayHoldAny(std::span<const FogVolume> volumes, std::span<const glm::vec3> origins, std::span<const glm::vec3> dirs,
                std::span<const float> tEnds) {
  glm::vec3 lo(1e30f), hi(-1e30f);
  float maxT = 0.0f, maxDir = 0.0f;
  for (size_t i = 0; i < origins.size(); ++i) {
    lo = glm::min(lo, origins[i] + tEnds[i] * dirs[i]);
    hi = glm::max(hi, origins[i] + tEnds[i] * dirs[i]);
    maxT = std::max(maxT, tEnds[i]);
    maxDir = std::max(maxDir, std::fabs(dirs[i].x) + std::fabs(dirs[i].y) + std::fabs(dirs[i].z));
  }
  return fogMayHoldEndsIn(volumes, lo, hi, fogEndAllowance(lo, hi, maxT, maxDir));
}

TEST(FogVolume, EndTestRulesOutVolumesThatCannotHoldTheEnds) {
  FogVolumeDesc boxDesc;
  const std::vector<glm::vec4> unitBox = boxPlanes({0, 0, 0}, {1, 1, 1});
  boxDesc.planes = unitBox;
  const std::vector<FogVolume> one = {makeFogVolume(boxDesc, "box")};
  const auto may = [&](const glm::vec3& origin, const glm::vec3& dir, float tEnd) {
    return mayHoldAny(one, std::span(&origin, 1), std::span(&dir, 1), std::span(&tEnd, 1));
  };
  EXPECT_TRUE(may({-5, 0.5f, 0.5f}, {1, 0, 0}, 5.5f));    // ends inside
  EXPECT_TRUE(may({-5, 0.5f, 0.5f}, {1, 0, 0}, 6.0f));    // ends on the far side
  EXPECT_FALSE(may({-5, 0.5f, 0.5f}, {1, 0, 0}, 8.0f));   // passes through, ends beyond
  EXPECT_FALSE(may({-5, 0.5f, 0.5f}, {1, 0, 0}, 2.0f));   // stops before it
  EXPECT_FALSE(fogMayHoldEndsIn({}, {0, 0, 0}, {1, 1, 1}, 1.0f));   // no volumes

  // Packets of 16 rays from one origin toward ends scattered about a spot near the boundaries of
  // a box far from the origin (as in a map) and of a slanted wedge, from near and far, with unit
  // and longer directions: when the test rules the volume out, no ray of the packet ends in it
  // (as fogInterval and FogSegment count it), and it rules out most packets clearly outside.
  const std::vector<glm::vec4> farBoxPlanes = boxPlanes({2000, -3000, 100}, {2300, -2800, 180});
  const std::vector<glm::vec4> wedgePlanes = {{0.2f, 0.98f, 0, 40}, {0.3f, -0.95f, 0, 10}, {-1, 0, 0, 0},
                                              {0, 0, 1, 50},        {0, 0, -1, 50},         {0.99f, 0.14f, 0.0f, 300}};
  FogVolumeDesc farBox;
  farBox.planes = farBoxPlanes;
  FogVolumeDesc wedge;
  wedge.planes = wedgePlanes;
  uint32_t state = 12345;
  const auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / 16777216.0f;
  };
  uint32_t ruledOut = 0, clearlyOutside = 0, held = 0, rays = 0;
  for (const FogVolumeDesc* desc : {&farBox, &wedge}) {
    const std::vector<FogVolume> volumes = {makeFogVolume(*desc, "volume")};
    const FogVolume& v = volumes[0];
    const glm::vec3 lo = desc == &farBox ? glm::vec3(2000, -3000, 100) : glm::vec3(-10, -60, -60);
    const glm::vec3 hi = desc == &farBox ? glm::vec3(2300, -2800, 180) : glm::vec3(320, 60, 60);
    for (int packet = 0; packet < 4000; ++packet) {
      const glm::vec3 size = hi - lo;
      glm::vec3 spot = lo + glm::vec3(next() * 1.4f - 0.2f, next() * 1.4f - 0.2f, next() * 1.4f - 0.2f) * size;
      if (packet % 2 == 0) {   // on a face of the box, within a unit either side
        const int axis = packet / 2 % 3;
        spot[axis] = (next() < 0.5f ? lo[axis] : hi[axis]) + (next() - 0.5f) * 2.0f;
      }
      const glm::vec3 origin = spot + glm::vec3(next() - 0.5f, next() - 0.5f, next() - 0.5f) *
                                          (packet % 4 < 2 ? 200.0f : 8000.0f);
      const float spread = packet % 3 == 0 ? 0.01f : 3.0f;   // tight packets and wide ones
      std::array<glm::vec3, 16> origins, dirs;
      std::array<float, 16> tEnds;
      bool anyHeld = false, allOutside = true;
      for (int i = 0; i < 16; ++i) {
        const glm::vec3 end = spot + glm::vec3(next() - 0.5f, next() - 0.5f, next() - 0.5f) * spread;
        const float scale = packet % 5 == 0 ? 1.0f : 0.25f + 4.0f * next();
        origins[i] = origin;
        dirs[i] = glm::normalize(end - origin) * scale;
        tEnds[i] = glm::length(end - origin) / scale;
        const bool holds = holdsEnd(v, origins[i], dirs[i], tEnds[i]);
        EXPECT_EQ(FogSegment(volumes, origins[i], dirs[i], tEnds[i], 1.0f, true).empty(), !holds);
        anyHeld = anyHeld || holds;
        held += holds;
        ++rays;
        bool outside = false;
        for (const glm::vec4& plane : v.planes)
          outside = outside || glm::dot(glm::vec3(plane), origins[i] + tEnds[i] * dirs[i]) - plane.w > 10.0f;
        allOutside = allOutside && outside;
      }
      const bool mayHold = mayHoldAny(volumes, origins, dirs, tEnds);
      ASSERT_TRUE(mayHold || !anyHeld) << "packet " << packet;
      ruledOut += !mayHold;
      clearlyOutside += allOutside;
    }
  }
  EXPECT_GT(held, rays / 20);
  EXPECT_GT(clearlyOutside, 2000u);
  EXPECT_GE(ruledOut, clearlyOutside * 9 / 10);
}

TEST(FogVolume, DisplaySpaceBlendMixesEncodedValues) {
  const glm::vec3 out = blendInDisplaySpace({srgbToLinear(0.2f), 4.0f, 0.0f}, 0.25f, glm::vec3(srgbToLinear(0.6f)));
  EXPECT_NEAR(out.r, srgbToLinear(0.75f * 0.2f + 0.25f * 0.6f), 1e-6f);
  EXPECT_NEAR(out.g, srgbToLinear(0.75f * 1.0f + 0.25f * 0.6f), 1e-6f);   // behind clamped to 1
  EXPECT_NEAR(out.b, srgbToLinear(0.25f * 0.6f), 1e-6f);
}

TEST(FogVolume, InvalidVolumesAreRejectedWithTheirIndex) {
  Renderer renderer(RendererConfig{1});
  std::vector<glm::vec4> planes = boxPlanes({0, 0, 0}, {1, 1, 1});
  FogVolumeDesc fog{planes, {0.5f, 0.5f, 0.5f}, 100.0f};
  auto expectError = [&](const FogVolumeDesc& bad, const std::string& fragment) {
    const FogVolumeDesc both[2] = {fog, bad};
    try {
      renderer.setFogVolumes(both);
      FAIL() << "accepted: " << fragment;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("volume 1"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  std::vector<glm::vec4> nanPlane = planes;
  nanPlane[2].y = std::nanf("");
  expectError({nanPlane, fog.color, 100.0f}, "plane 2 is not finite");
  std::vector<glm::vec4> zeroPlane = planes;
  zeroPlane[3] = glm::vec4(0, 0, 0, 1);
  expectError({zeroPlane, fog.color, 100.0f}, "plane 3 has a zero normal");
  expectError({planes, fog.color, 0.0f}, "depthForOpaque");
  expectError({planes, fog.color, std::numeric_limits<float>::infinity()}, "depthForOpaque");
  expectError({planes, {-1, 0, 0}, 100.0f}, "color");
  expectError({{}, fog.color, 100.0f}, "no planes");
  renderer.setFogVolumes(std::span<const FogVolumeDesc>(&fog, 1));   // a valid one is still taken
  EXPECT_NO_THROW(renderer.commit());
}

TEST(FogVolume, CameraRayThroughAFogSlabBlendsTowardItsColour) {
  for (const Integrator integrator : {Integrator::Lightmap, Integrator::Path}) {
    WallScene scene;
    scene.setFog({6, -100, -100}, {12, 100, 100}, {1, 0, 0}, 8.0f);   // the last 4 units before the wall
    const glm::vec3 c = centrePixel(scene.render(integrator, 1.0f));
    const float a = expectedOpacity(4.0f, 8.0f);
    if (integrator == Integrator::Lightmap) {
      EXPECT_NEAR(c.r, 1.0f, 1e-3f);              // (1 - a) * white + a * red, on display values
      EXPECT_NEAR(c.g, srgbToLinear(1.0f - a), 1e-3f);
      EXPECT_NEAR(c.b, srgbToLinear(1.0f - a), 1e-3f);
    } else {
      EXPECT_NEAR(c.r, a, 1e-3f);                 // the wall is unlit: only the glow
      EXPECT_NEAR(c.g, 0.0f, 1e-6f);
    }
  }
}

TEST(FogVolume, RayThatMissesTheVolumeIsUnchanged) {
  WallScene scene;
  scene.setFog({2, 20, -100}, {6, 100, 100}, {1, 0, 0}, 8.0f);   // off to the side
  const glm::vec3 c = centrePixel(scene.render(Integrator::Lightmap, 1.0f));
  EXPECT_LT(glm::length(c - glm::vec3(1.0f)), 1e-4f);   // unfogged (display-value product: sRGB round trip)
}

TEST(FogVolume, LightmapLookMeasuresEyeSpaceDepthOthersTrueLength) {
  // A slab square to the view axis: every pixel has 4 units of eye-space depth inside it.
  WallScene scene;
  scene.setFog({6, -100, -100}, {12, 100, 100}, {0, 0, 0}, 8.0f);
  const FrameView lightmap = scene.render(Integrator::Lightmap, 90.0f, 3);
  const float a = expectedOpacity(4.0f, 8.0f);
  for (const glm::vec3& c : lightmap.radiance) EXPECT_NEAR(c.g, srgbToLinear(1.0f - a), 2e-3f);
  // Path: unlit wall behind black fog is black, so test the glow of a white fog instead:
  scene.setFog({6, -100, -100}, {12, 100, 100}, {1, 1, 1}, 8.0f);
  const FrameView path = scene.render(Integrator::Path, 90.0f, 31);
  const glm::vec3 corner = path.radiance[0];   // pixel (0, 0): a ray about 50 degrees off axis
  const glm::vec3 centre = centrePixel(path);
  EXPECT_NEAR(centre.g, a, 2e-3f);
  EXPECT_GT(corner.g, centre.g + 0.02f);       // a longer way through the slab
}

TEST(FogVolume, LightmapLookFogsOnlySurfacesInsideTheVolume) {
  // Eye inside a fog box whose far side stops short of the wall: stock draws the wall unfogged.
  WallScene scene;
  scene.setFog({-5, -100, -100}, {6, 100, 100}, {0, 0, 0}, 8.0f);
  EXPECT_LT(glm::length(centrePixel(scene.render(Integrator::Lightmap, 1.0f)) - glm::vec3(1.0f)), 1e-4f);
  // The same box reaching the wall: fogged by the eye-space depth inside (10 units).
  scene.setFog({-5, -100, -100}, {10, 100, 100}, {0, 0, 0}, 20.0f);
  EXPECT_NEAR(centrePixel(scene.render(Integrator::Lightmap, 1.0f)).g, srgbToLinear(1.0f - expectedOpacity(10.0f, 20.0f)),
              1e-3f);
}

TEST(FogVolume, LightmapPacketsOutsideEveryVolumeSkipTheClippingWithTheSameImage) {
  // A fog box around part of the wall (its corner in view): packets of camera rays whose hits all
  // lie clearly outside it skip FogSegment (RenderScene::markFogFreeEnds); rays traced one by one
  // clip every segment. Both give the same bits, fogged pixels and clear ones alike.
  WallScene scene;
  scene.setFog({8, -100, -100}, {12, 1.5f, 2.5f}, {0.2f, 0.4f, 0.9f}, 6.0f);
  scene.renderer.commit();
  RenderSettings s = settingsFor(Integrator::Lightmap, 48, 1, 0);
  s.accumulate = false;
  s.pixelCentres = true;
  const Camera camera = lookAt({0, 0, 0}, {1, 0, 0}, 60.0f);
  s.cameraPackets = true;
  const std::vector<glm::vec3> packets(scene.renderer.render(camera, s).radiance.begin(),
                                       scene.renderer.render(camera, s).radiance.end());
  s.cameraPackets = false;
  const FrameView single = scene.renderer.render(camera, s);
  ASSERT_EQ(packets.size(), single.radiance.size());
  uint32_t fogged = 0, clear = 0, differ = 0;
  for (size_t i = 0; i < packets.size(); ++i) {
    differ += std::memcmp(&packets[i], &single.radiance[i], sizeof(glm::vec3)) != 0;
    (packets[i].r < 0.99f ? fogged : clear) += 1;
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(fogged, 200u);
  EXPECT_GT(clear, 200u);
}

TEST(FogVolume, ViewFromInsideGlowsUpToTheBoundaryExceptInTheStockLook) {
  Renderer renderer(RendererConfig{1});
  const std::vector<glm::vec4> planes = boxPlanes({-5, -5, -5}, {5, 5, 5});
  const FogVolumeDesc fog{planes, {0.2f, 0.4f, 0.8f}, 10.0f};
  renderer.setFogVolumes(std::span<const FogVolumeDesc>(&fog, 1));
  renderer.commit();
  const float a = expectedOpacity(5.0f, 10.0f);
  for (const Integrator integrator : {Integrator::Lightmap, Integrator::Direct, Integrator::Path}) {
    RenderSettings s = settingsFor(integrator, 5, 1, 2);
    if (integrator == Integrator::Lightmap) {   // the stock look never fogs the sky
      EXPECT_EQ(centrePixel(renderer.render(lookAt({0, 0, 0}, {1, 0, 0}, 1.0f), s)), glm::vec3(0.0f));
      continue;
    }
    const glm::vec3 c = centrePixel(renderer.render(lookAt({0, 0, 0}, {1, 0, 0}, 1.0f), s));
    EXPECT_NEAR(c.r, 0.2f * a, 1e-3f);
    EXPECT_NEAR(c.b, 0.8f * a, 1e-3f);
  }
}

TEST(FogVolume, ShadowRaysLoseWhatTheFogHides) {
  // Floor at z = 0 lit by a point light at (20, 0, 10); fog fills x in [10, 30] (the light's
  // half of the shadow ray) but not the camera's view straight down at the origin.
  auto render = [](bool withFog) {
    Renderer renderer(RendererConfig{1});
    MeshArrays floor = quad({-50, -50, 0}, {100, 0, 0}, {0, 100, 0});
    floor.setMaterial(renderer.addMaterial(diffuse(0.5f)));
    InstanceDesc instance;
    instance.mesh = renderer.addMesh(floor.desc());
    renderer.addInstance(instance);
    LightDesc light;
    light.position = {20, 0, 10};
    light.intensity = 100.0f;
    renderer.addLight(light);
    const std::vector<glm::vec4> planes = boxPlanes({10, -50, -1}, {30, 50, 20});
    const FogVolumeDesc fog{planes, {1, 1, 1}, 20.0f};
    if (withFog) renderer.setFogVolumes(std::span<const FogVolumeDesc>(&fog, 1));
    renderer.commit();
    RenderSettings s = settingsFor(Integrator::Direct, 5, 4, 1);
    return centrePixel(renderer.render(lookAt({0, 0, 10}, {0, 0, 0}, 1.0f), s));
  };
  const glm::vec3 clear = render(false);
  const glm::vec3 fogged = render(true);
  ASSERT_GT(clear.g, 0.0f);
  const float inside = 0.5f * std::sqrt(20.0f * 20.0f + 10.0f * 10.0f);   // from x = 10 to the light
  EXPECT_NEAR(fogged.g / clear.g, 1.0f - expectedOpacity(inside, 20.0f), 2e-3f);
}

}  // namespace
}  // namespace pa::test
