// Portal surfaces: the planes found in a map and the engine's mirror / portal-camera mapping.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "port/engine_glue/portals.h"
#include "port/q3formats/bsp/tests/bsp_writer.h"
#include "port/q3formats/world/world_scene.h"
#include "renderer/scene/renderer.h"

namespace glue {
namespace {

glm::vec3 mapPoint(const pa::PortalDesc& p, const glm::vec3& x) { return p.transform * glm::vec4(x, 1.0f); }
glm::vec3 mapDirection(const pa::PortalDesc& p, const glm::vec3& d) { return glm::mat3(p.transform) * d; }

bool near(const glm::vec3& a, const glm::vec3& b) { return glm::distance(a, b) < 1e-4f; }

q3abi::refEntity_t portalEntity(const glm::vec3& origin, const glm::vec3& camera) {
  q3abi::refEntity_t e{};
  e.reType = q3abi::RT_PORTALSURFACE;
  for (int k = 0; k < 3; ++k) {
    e.origin[k] = origin[k];
    e.oldorigin[k] = camera[k];
    e.axis[k][k] = 1.0f;   // camera looking along +x, left +y, up +z
  }
  return e;
}

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
  auto w = q3::testing::sampleMap();   // shader 0 ("textures/test/floor"): the floor at z = 0
  const q3::BspFile bsp = q3::parseBsp(w.build(), "maps/portals.bsp");
  q3::WorldScene scene;
  scene.materials.resize(2);
  scene.materials[0].shaderName = "textures/test/floor";
  scene.materials[0].mirror = true;
  scene.materials[1].shaderName = "textures/test/fog";
  PortalViews views;
  views.load(bsp, scene);
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

}  // namespace
}  // namespace glue
