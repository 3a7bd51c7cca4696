// Portal surfaces: the planes found in a map and the engine's mirror / portal-camera mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "port/engine_glue/portals.h"
#include "port/engine_glue/tests/portal_fixtures.h"
#include "port/q3formats/bsp/tests/bsp_writer.h"
#include "port/q3formats/shader/shader_library.h"
#include "port/q3formats/vfs/game_filesystem.h"
#include "port/q3formats/world/world_scene.h"
#include "port/scene_bridge/scene_bridge.h"
#include "renderer/scene/renderer.h"

namespace glue {
namespace {

glm::vec3 mapPoint(const pa::PortalDesc& p, const glm::vec3& x) { return p.transform * glm::vec4(x, 1.0f); }
glm::vec3 mapDirection(const pa::PortalDesc& p, const glm::vec3& d) { return glm::mat3(p.transform) * d; }

bool near(const glm::vec3& a, const glm::vec3& b) { return glm::distance(a, b) < 1e-4f; }

using testing::portalEntity;

TEST(Portals, PlanesOfPortalFacesOfTheWorldModelOnce) {
  auto w = q3::testing::sampleMap();   // floor quad and patch use shader 0, the door (*1) too
  w.addQuad({glm::vec3(300, 0, 0), {400, 0, 0}, {300, 100, 0}, {400, 100, 0}}, {0, 0, 1});   // coplanar
  w.models[0].numSurfaces = 2;   // keep the door out; the new quad is listed by no model
  const std::vector<std::byte> bytes = w.build();
  const q3::BspFile bsp = q3::parseBsp(bytes, "maps/portals.bsp");
  const auto planes = findPortalPlanes(bsp, {true, false});
  ASSERT_EQ(planes.size(), 1u);   // the floor; the patch has no plane
  EXPECT_TRUE(near(planes[0].normal, {0, 0, 1}));
  EXPECT_FLOAT_EQ(planes[0].dist, 0.0f);
  EXPECT_TRUE(findPortalPlanes(bsp, {false, true}).empty());
  // q3map stores no face normal on nolightmap faces (all of OpenArena's portals): the plane
  // comes from the first triangle, clockwise seen from the front.
  w.surfaces[0].lightmapVecs[2] = glm::vec3(0.0f);
  const q3::BspFile noNormal = q3::parseBsp(w.build(), "maps/nonormal.bsp");
  const auto fromTriangle = findPortalPlanes(noNormal, {true, false});
  ASSERT_EQ(fromTriangle.size(), 1u);
  EXPECT_TRUE(near(fromTriangle[0].normal, {0, 0, 1}));
  EXPECT_TRUE(findPortalPlanes(bsp, {}).empty());
}

TEST(Portals, MirrorEntityReflectsAboutThePlane) {
  const PortalPlane floor{{0, 0, 1}, 0};
  const q3abi::refEntity_t mirror = portalEntity({10, 10, 5}, {10, 10, 5});
  const auto portal = portalFor(floor, std::span(&mirror, 1), 0);
  ASSERT_TRUE(portal);
  EXPECT_TRUE(near(mapPoint(*portal, {3, 4, 7}), {3, 4, -7}));
  EXPECT_TRUE(near(mapDirection(*portal, {1, 2, -3}), {1, 2, 3}));
}

TEST(Portals, CameraEntityMapsTheSurfaceFrameToTheCamera) {
  // A wall portal on x = 0 seen from +x; the camera is at (100, 200, 50) looking along +x.
  const PortalPlane wall{{1, 0, 0}, 0};
  q3abi::refEntity_t camera = portalEntity({2, 5, 5}, {100, 200, 50});
  auto portal = portalFor(wall, std::span(&camera, 1), 0);
  ASSERT_TRUE(portal);
  // The entity's point, dropped onto the plane, is the camera; looking in is looking along axis[0].
  EXPECT_TRUE(near(mapPoint(*portal, {0, 5, 5}), {100, 200, 50}));
  EXPECT_TRUE(near(mapDirection(*portal, {-1, 0, 0}), {1, 0, 0}));
  // The engine's surface axes for normal +x are +y and +z; they go to -axis[1] and axis[2].
  EXPECT_TRUE(near(mapPoint(*portal, {0, 6, 5}), {100, 199, 50}));
  EXPECT_TRUE(near(mapPoint(*portal, {0, 5, 6}), {100, 200, 51}));

  // skinNum rolls the view by that many degrees about the camera's forward axis.
  camera.skinNum = 90;
  portal = portalFor(wall, std::span(&camera, 1), 0);
  ASSERT_TRUE(portal);
  EXPECT_TRUE(near(mapPoint(*portal, {0, 6, 5}), {100, 200, 51}));
  // oldframe + frame: spinning at `frame` degrees per second (90 at t = 1 s).
  camera.skinNum = 0;
  camera.oldframe = 1;
  camera.frame = 90;
  portal = portalFor(wall, std::span(&camera, 1), 1000);
  ASSERT_TRUE(portal);
  EXPECT_TRUE(near(mapPoint(*portal, {0, 6, 5}), {100, 200, 51}));
}

TEST(Portals, OnlyNearbyPortalEntitiesWithUsableAxesCount) {
  const PortalPlane wall{{1, 0, 0}, 0};
  std::vector<q3abi::refEntity_t> entities = {portalEntity({65, 0, 0}, {100, 0, 0})};   // too far
  EXPECT_FALSE(portalFor(wall, entities, 0));
  entities[0].origin[0] = 63;
  EXPECT_TRUE(portalFor(wall, entities, 0));
  entities[0].reType = q3abi::RT_MODEL;
  EXPECT_FALSE(portalFor(wall, entities, 0));
  // The first one within reach decides, whatever follows.
  entities = {portalEntity({-10, 0, 0}, {-10, 0, 0}), portalEntity({0, 0, 0}, {100, 0, 0})};
  const auto first = portalFor(wall, entities, 0);
  ASSERT_TRUE(first);
  EXPECT_TRUE(near(mapPoint(*first, {3, 0, 0}), {-3, 0, 0}));   // the mirror
  // Degenerate or non-finite axes give no portal (and nothing the renderer would refuse).
  entities = {portalEntity({0, 0, 0}, {100, 0, 0})};
  entities[0].axis[1][1] = 0.0f;
  EXPECT_FALSE(portalFor(wall, entities, 0));
  entities[0].axis[1][1] = std::nanf("");
  EXPECT_FALSE(portalFor(wall, entities, 0));
}

TEST(Portals, ViewsHandTheRendererThePortalsOfThisFrame) {
  PortalViews views = testing::mirrorFloorViews();   // the floor at z = 0
  ASSERT_EQ(views.planes().size(), 1u);

  // The tracer's view of it: a half-grey mirror floor under a lamp ceiling, seen from above.
  // A mirror reflects the lamp tinted (0.5); through a mirror portal it shows it as it is (1).
  pa::Renderer renderer({1});
  pa::MaterialDesc mirrorMaterial;
  mirrorMaterial.baseColor = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  mirrorMaterial.mirror = true;
  pa::MaterialDesc lamp;
  lamp.baseColor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  lamp.emission = glm::vec3(1.0f);
  const pa::MaterialId materials[2] = {renderer.addMaterial(mirrorMaterial), renderer.addMaterial(lamp)};
  const glm::vec3 positions[8] = {{-50, -50, 0}, {50, -50, 0}, {50, 50, 0}, {-50, 50, 0},
                                  {-50, -50, 10}, {50, -50, 10}, {50, 50, 10}, {-50, 50, 10}};
  const uint32_t indices[12] = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6};
  const pa::MaterialId perTriangle[4] = {materials[0], materials[0], materials[1], materials[1]};
  pa::MeshDesc mesh;
  mesh.positions = positions;
  mesh.indices = indices;
  mesh.materials = perTriangle;
  pa::InstanceDesc instance;
  instance.mesh = renderer.addMesh(mesh);
  renderer.addInstance(instance);
  pa::Camera camera;
  camera.origin = {0, 0, 5};
  camera.forward = {0, 0, -1};
  camera.left = {0, 1, 0};
  camera.up = {1, 0, 0};
  camera.fovX = camera.fovY = 10.0f;
  pa::RenderSettings settings;
  settings.width = settings.height = 2;
  settings.integrator = pa::Integrator::Lightmap;
  settings.tonemap = pa::Tonemap::Clamp;
  auto seen = [&] {
    renderer.commit();
    return renderer.render(camera, settings).radiance[0].g;
  };
  EXPECT_NEAR(seen(), 0.5f, 1e-5f);   // Lightmap look of a mirror without portal: its albedo
  const q3abi::refEntity_t mirror = portalEntity({10, 10, 5}, {10, 10, 5});
  views.update(std::span(&mirror, 1), 0, renderer);
  EXPECT_NEAR(seen(), 1.0f, 1e-5f);   // the lamp, reflected by the portal
  views.update({}, 0, renderer);      // the entity is gone: no portal any more
  EXPECT_NEAR(seen(), 0.5f, 1e-5f);
}

/// The cgame's RT_PORTALSURFACE entity for a misc_portal_surface aimed at a misc_portal_camera
/// (CG_Portal): axis[0] the camera's direction, axis[1] minus the engine's perpendicular,
/// skinNum the camera's roll in degrees.
q3abi::refEntity_t cgamePortal(const glm::vec3& surface, const glm::vec3& camera, const glm::vec3& forward,
                               float rollDegrees) {
  q3abi::refEntity_t e = portalEntity(surface, camera);
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::fabs(forward[k]) < std::fabs(forward[axis])) axis = k;
  glm::vec3 e1(0.0f);
  e1[axis] = 1.0f;
  const glm::vec3 left = -glm::normalize(e1 - glm::dot(e1, forward) * forward);
  const glm::vec3 up = glm::cross(forward, left);
  for (int k = 0; k < 3; ++k) {
    e.axis[0][k] = forward[k];
    e.axis[1][k] = left[k];
    e.axis[2][k] = up[k];
  }
  e.skinNum = static_cast<int>(rollDegrees);
  return e;
}

TEST(PortalsRealMap, TheWindowShowsWhatTheRemoteCameraSees) {
  // oa_dm5: a misc_portal_surface at (1096, 200, 256) on the face x = 1104 (seen from -x),
  // aimed at a misc_portal_camera at (1312, -944, 248) looking along -x, rolled 180 degrees.
  const std::filesystem::path dir = "/usr/share/games/openarena/baseoa";
  if (!std::filesystem::exists(dir / "pak1-maps.pk3")) GTEST_SKIP() << "OpenArena data not installed";
  const q3::GameFileSystem game(dir);
  const auto bytes = game.readFile("maps/oa_dm5.bsp");
  ASSERT_TRUE(bytes);
  const q3::BspFile bsp = q3::parseBsp(*bytes, "maps/oa_dm5.bsp");
  q3::ShaderLibrary shaders;
  shaders.addScriptsInEngineOrder(game.listFiles("scripts", ".shader"),
                                  [&](const std::string& path) { return game.readFile(path); });
  q3::WorldBuildOptions options;
  options.loadTextures = false;   // flat colours: the test compares geometry seen, not looks
  const q3::WorldScene scene = q3::buildWorldScene(
      bsp, shaders, [&](std::string_view path) { return game.readFile(path); }, options);
  PortalViews views;
  views.load(bsp, scene);
  EXPECT_EQ(views.planes().size(), 4u);   // two back-to-back windows, each a pair of faces

  pa::Renderer renderer({2});
  pa::bridge::showSkyAndFog(pa::bridge::uploadWorld(scene, renderer), renderer);
  const glm::vec3 cameraAt(1312, -944, 248);
  const q3abi::refEntity_t portal = cgamePortal({1096, 200, 256}, cameraAt, {-1, 0, 0}, 180.0f);
  views.update(std::span(&portal, 1), 0, renderer);
  renderer.commit();

  // What a narrow view from the corridor sees through the window, pixel by pixel, must be what
  // the same rays see when they start at the remote camera: the portal's own mapping.
  const PortalPlane window{{-1, 0, 0}, -1104};
  const auto desc = portalFor(window, std::span(&portal, 1), 0);
  ASSERT_TRUE(desc);
  EXPECT_TRUE(near(mapPoint(*desc, {1104, 200, 256}), cameraAt));
  // The viewer stands half a unit in front of the window, so the mapped viewpoint is half a unit
  // behind the remote camera, in the open (a viewer farther away maps into the wall behind it).
  pa::Camera viewer;
  viewer.origin = {1103.5f, 200, 256};
  viewer.fovX = viewer.fovY = 40.0f;
  pa::Camera remote = viewer;
  remote.origin = mapPoint(*desc, viewer.origin);
  remote.forward = mapDirection(*desc, viewer.forward);
  remote.left = mapDirection(*desc, viewer.left);
  remote.up = mapDirection(*desc, viewer.up);
  pa::RenderSettings settings;
  settings.width = settings.height = 8;
  settings.integrator = pa::Integrator::Lightmap;
  const pa::FrameView seen = renderer.render(viewer, settings);
  const std::vector<glm::vec3> through(seen.radiance.begin(), seen.radiance.end());
  const pa::FrameView direct = renderer.render(remote, settings);
  float difference = 0.0f, signal = 0.0f;
  for (size_t i = 0; i < through.size(); ++i) {
    difference += glm::distance(through[i], direct.radiance[i]);
    signal += glm::length(direct.radiance[i]);
  }
  EXPECT_GT(signal, 0.0f);
  EXPECT_LT(difference, 1e-3f * signal);
  // Without the portal entity the window is the mirror material again: another picture.
  views.update({}, 0, renderer);
  renderer.commit();
  const pa::FrameView mirrored = renderer.render(viewer, settings);
  float changed = 0.0f;
  for (size_t i = 0; i < through.size(); ++i) changed += glm::distance(through[i], mirrored.radiance[i]);
  EXPECT_GT(changed, 0.05f * signal);
}

}  // namespace
}  // namespace glue
