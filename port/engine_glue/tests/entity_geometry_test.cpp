// Known answers for the camera-facing geometry of effects and for polygon fans.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "port/engine_glue/entity_geometry.h"
#include "port/engine_glue/scene.h"
#include "port/q3formats/model/md3.h"

namespace glue {
namespace {

q3abi::refEntity_t entity(int type) {
  q3abi::refEntity_t e{};
  e.reType = type;
  e.shaderRGBA[0] = e.shaderRGBA[1] = e.shaderRGBA[2] = e.shaderRGBA[3] = 255;
  e.customShader = 7;
  return e;
}

TEST(EntityGeometry, SpriteIsAViewerFacingSquareOfTwiceTheRadius) {
  auto e = entity(q3abi::RT_SPRITE);
  e.origin[0] = 100;
  e.radius = 10;
  const Viewer viewer{{0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  GeometryBatch batch;
  ASSERT_TRUE(appendEffect(e, viewer, batch));
  ASSERT_EQ(batch.positions.size(), 4u);
  EXPECT_EQ(batch.triangles(), 2u);
  EXPECT_EQ(batch.positions[0], glm::vec3(100, 10, 10));    // +left +up: top-left, uv (0,0)
  EXPECT_EQ(batch.positions[2], glm::vec3(100, -10, -10));  // -left -up: bottom-right, uv (1,1)
  EXPECT_EQ(batch.uvs[2], glm::vec2(1, 1));
  EXPECT_EQ(batch.triangleShaders[0], 7);
  EXPECT_NEAR(std::fabs(batch.normals[0].x), 1.0f, 1e-6f);   // faces the viewer along x
  EXPECT_EQ(batch.colors[0], glm::vec4(1.0f));
}

TEST(EntityGeometry, RotatedSpriteTurnsInTheViewPlane) {
  auto e = entity(q3abi::RT_SPRITE);
  e.radius = 1;
  e.rotation = 90;
  e.origin[0] = 5;
  const Viewer viewer{{0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  GeometryBatch batch;
  ASSERT_TRUE(appendEffect(e, viewer, batch));
  // left' = up, up' = -left: the first corner (left' + up') is (0, -1, 1) from the origin.
  EXPECT_NEAR(batch.positions[0].y, -1.0f, 1e-5f);
  EXPECT_NEAR(batch.positions[0].z, 1.0f, 1e-5f);
}

TEST(EntityGeometry, RailCoreSpansOldOriginToOriginWithItsWidth) {
  auto e = entity(q3abi::RT_RAIL_CORE);
  e.oldorigin[0] = 0;
  e.origin[0] = 100;
  const Viewer viewer{{50, 0, 100}, {0, 1, 0}, {0, 0, 1}};   // above the beam
  GeometryBatch batch;
  ASSERT_TRUE(appendEffect(e, viewer, batch));
  ASSERT_EQ(batch.positions.size(), 4u);
  EXPECT_NEAR(glm::distance(batch.positions[0], batch.positions[3]), 6.0f, 1e-4f);   // r_railCoreWidth
  EXPECT_NEAR(glm::distance(batch.positions[0], batch.positions[1]), 100.0f, 1e-4f);
  EXPECT_NEAR(std::fabs(batch.normals[0].z), 1.0f, 1e-5f);   // turned towards the viewer above
}

TEST(EntityGeometry, ModelsAndPortalsAreNotEffects) {
  GeometryBatch batch;
  const Viewer viewer;
  EXPECT_FALSE(appendEffect(entity(q3abi::RT_MODEL), viewer, batch));
  EXPECT_FALSE(appendEffect(entity(q3abi::RT_PORTALSURFACE), viewer, batch));
  auto degenerate = entity(q3abi::RT_SPRITE);
  degenerate.radius = 0;
  EXPECT_FALSE(appendEffect(degenerate, viewer, batch));
  EXPECT_TRUE(batch.positions.empty());
}

TEST(EntityGeometry, PolygonsBecomeTriangleFansWithTheirColours) {
  SceneFrame scene;
  q3abi::polyVert_t verts[5]{};
  for (int i = 0; i < 5; ++i) {
    verts[i].xyz[0] = float(i);
    verts[i].xyz[1] = float(i * i);
    verts[i].modulate[0] = 255;
    verts[i].modulate[3] = 128;
  }
  ASSERT_TRUE(scene.addPolys(3, 5, verts, 1));
  GeometryBatch batch;
  appendPolys(scene.polys(), scene.polyVerts(), Viewer{}, {}, batch);
  EXPECT_EQ(batch.triangles(), 3u);
  EXPECT_EQ(batch.positions[4], glm::vec3(4, 16, 0));   // where the game put it
  EXPECT_EQ(batch.indices[3], 0u);   // every triangle starts at the first vertex
  EXPECT_EQ(batch.triangleShaders[2], 3);
  EXPECT_FLOAT_EQ(batch.colors[0].r, 1.0f);
  EXPECT_FLOAT_EQ(batch.colors[0].g, 0.0f);
  EXPECT_NEAR(batch.colors[0].a, 128.0f / 255.0f, 1e-6f);
}

TEST(EntityGeometry, DecalPolygonsMoveTowardsTheViewerAlongTheirSightLines) {
  // Two quads in the wall plane x = 100, seen from the origin: a mark (shader 7, polygonOffset)
  // and another polygon (shader 8).
  SceneFrame scene;
  q3abi::polyVert_t verts[4]{};
  const float corners[4][3] = {{100, -10, -10}, {100, 10, -10}, {100, 10, 10}, {100, -10, 10}};
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k) verts[i].xyz[k] = corners[i][k];
  ASSERT_TRUE(scene.addPolys(7, 4, verts, 1));
  ASSERT_TRUE(scene.addPolys(8, 4, verts, 1));
  GeometryBatch batch;
  const Viewer viewer{{0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  appendPolys(scene.polys(), scene.polyVerts(), viewer, [](int32_t shader) { return shader == 7; }, batch);
  ASSERT_EQ(batch.positions.size(), 8u);
  for (int i = 0; i < 4; ++i) {
    const glm::vec3 wall(corners[i][0], corners[i][1], corners[i][2]);
    const glm::vec3 mark = batch.positions[size_t(i)];
    EXPECT_EQ(batch.positions[size_t(i) + 4], wall);   // not a decal: left where it is
    // In front of the wall by kDecalLift of its distance, on the same line of sight.
    EXPECT_NEAR(glm::length(mark), (1.0f - kDecalLift) * glm::length(wall), 1e-4f);
    EXPECT_NEAR(glm::length(glm::cross(glm::normalize(mark), glm::normalize(wall))), 0.0f, 1e-6f);
    EXPECT_LT(mark.x, 100.0f - 0.09f);
  }
}

TEST(EntityGeometry, AutospriteSurfacesBecomeViewerFacingQuads) {
  // One frame, one surface: a quad lying flat (z = 0) of half-diagonal 10 * sqrt 2 around (5, 0, 0).
  q3::Md3Model model;
  model.frames.resize(1);
  q3::Md3Surface surface;
  surface.numVerts = 4;
  surface.positions = {{{15, 10, 0}}, {{-5, 10, 0}}, {{-5, -10, 0}}, {{15, -10, 0}}};
  surface.normals.assign(4, {{0, 0, 1}});
  surface.texCoords.assign(4, {{0, 0}});
  surface.triangles = {{{0, 1, 2}}, {{0, 2, 3}}};
  model.surfaces.push_back(surface);
  auto e = entity(q3abi::RT_MODEL);
  e.axis[0][0] = e.axis[1][1] = e.axis[2][2] = 1;
  const Viewer viewer{{-100, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  GeometryBatch flat, sprite;
  appendMd3(model, e, {3}, flat);
  EXPECT_EQ(flat.positions[0], glm::vec3(15, 10, 0));
  appendMd3(model, e, {3}, sprite, {true}, spriteAxesFor(e, viewer));
  ASSERT_EQ(sprite.positions.size(), 4u);
  EXPECT_EQ(sprite.triangles(), 2u);
  EXPECT_EQ(sprite.triangleShaders[0], 3);
  // Radius 10 * sqrt 2 * 0.707 ~ 10: the quad stands up facing -X, centred on (5, 0, 0).
  EXPECT_NEAR(sprite.positions[0].x, 5.0f, 1e-4f);
  EXPECT_NEAR(sprite.positions[0].y, 10.0f * 1.41421356f * 0.707f, 1e-3f);
  EXPECT_NEAR(sprite.positions[0].z, 10.0f * 1.41421356f * 0.707f, 1e-3f);
  EXPECT_EQ(sprite.uvs[2], glm::vec2(1, 1));
}

TEST(EntityGeometry, SpriteAxesAreTheViewerAxesInModelSpace) {
  auto e = entity(q3abi::RT_MODEL);
  // Entity turned 90 degrees about Z and scaled 2x: model x = world y.
  e.axis[0][1] = 2;
  e.axis[1][0] = -2;
  e.axis[2][2] = 2;
  e.nonNormalizedAxes = 1;
  const Viewer viewer{{0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const SpriteAxes axes = spriteAxesFor(e, viewer);
  EXPECT_NEAR(axes.left.x, 1.0f, 1e-6f);   // world left (+Y) is model +X
  EXPECT_NEAR(axes.left.y, 0.0f, 1e-6f);
  EXPECT_NEAR(axes.up.z, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace glue
