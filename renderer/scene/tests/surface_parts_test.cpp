// RenderScene::surfaceAt with SurfaceParts::LayerColour (what the hit filter reads of each
// additive layer a camera ray crosses) against SurfaceParts::All: the members a layer's colour
// reads have the same bits, the rest is left out. SurfaceParts::NoShadingNormal and a
// TriangleMemo give All's bits (the memo whatever triangles and parts came before).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "renderer/scene/world/render_scene.h"
#include "renderer/scene/world/scene_store.h"
#include "scene_builders.h"

namespace pa {
namespace {

template <class T>
bool sameBits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

/// A sphere whose vertices carry colours, alphas, normals and lightmap uvs of their own.
struct LayerMesh : test::MeshArrays {
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> lightmapUvs;
  MeshDesc desc() const { return meshDescOf(*this, materials); }
};

LayerMesh layerSphere() {
  LayerMesh m;
  static_cast<test::MeshArrays&>(m) = test::sphere({0.3f, -0.2f, 0.1f}, 1.7f, 9, 13);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const float k = static_cast<float>(i);
    m.colors.emplace_back(0.13f + 0.011f * k, 0.71f - 0.004f * k, 0.37f + 0.002f * k, 0.93f - 0.003f * k);
    m.normals.push_back(glm::normalize(m.positions[i] + glm::vec3(0.1f * std::sin(k), 0.2f, -0.1f)));
    m.lightmapUvs.emplace_back(0.01f * k, 1.0f - 0.007f * k);
  }
  return m;
}

/// Three spheres of additive materials: vertex-lit, tinted by vertex colours with an emissive
/// uv of its own, and environment mapped with a one-sided glow (the scene points into `store`).
RenderScene layerScene(SceneStore& store) {
  std::vector<uint8_t> pixels;
  for (int i = 0; i < 8 * 8; ++i) pixels.insert(pixels.end(), {uint8_t(31 * i), uint8_t(255 - 3 * i), uint8_t(7 * i), uint8_t(4 * i)});
  const TextureId texture = store.addTexture({8, 8, pixels});   // sRGB, mipmapped

  MaterialDesc vertexLit;   // an effect on an entity lit by the light grid (the game's plasma rings)
  vertexLit.alphaMode = AlphaMode::Additive;
  vertexLit.baseTexture = texture;
  vertexLit.stock.useVertexLight = true;
  vertexLit.uvTransform = glm::mat3x2(1.3f, 0.2f, -0.1f, 0.9f, 0.25f, -0.5f);
  vertexLit.emission = {0.2f, 0.3f, 0.4f};
  vertexLit.emissiveTexture = texture;
  MaterialDesc tinted = vertexLit;   // vertex colours that tint the base
  tinted.stock.useVertexLight = false;
  tinted.stock.layerBlend = LayerBlend::Over;
  tinted.emissiveOwnUv = true;
  tinted.emissiveUvTransform = glm::mat3x2(0.5f, 0.0f, 0.1f, 2.0f, 0.3f, 0.0f);
  tinted.emission = glm::vec3(0.0f);   // no glow: no winding normal either
  tinted.emissiveTexture = kNoId;
  MaterialDesc reflecting = vertexLit;   // base uvs from the ray (environment mapped), one-sided glow
  reflecting.baseTexCoords = TexCoordSource::ReflectionSphere;
  reflecting.stock.useVertexLight = false;
  reflecting.twoSided = false;

  LayerMesh mesh = layerSphere();
  for (const MaterialDesc& material : {vertexLit, tinted, reflecting}) {
    mesh.setMaterial(store.addMaterial(material));
    const glm::mat4 place = glm::rotate(glm::translate(glm::mat4(1.0f), {4.0f, 1.0f, -2.0f}), 0.7f, glm::vec3(0.3f, 1.0f, 0.2f));
    store.addInstance({store.addMesh(mesh.desc()), glm::mat4x3(place)});
  }
  return store.commit();
}

/// The ray both tests look along (the reflecting sphere's uvs come from it).
Ray viewRay() {
  Ray ray;
  ray.origin = {-3.0f, 0.5f, 2.0f};
  ray.dir = glm::normalize(glm::vec3(1.0f, 0.1f, -0.4f));
  return ray;
}

/// A hit on triangle `prim` of world instance `instance` at barycentrics `bary`.
Hit hitAt(uint32_t instance, uint32_t prim, glm::vec2 bary) {
  Hit hit;
  hit.instance = instance;
  hit.prim = prim;
  hit.u = bary.x;
  hit.v = bary.y;
  return hit;
}

TEST(SurfaceParts, LayerColourHasTheBitsOfAllInWhatALayerReads) {
  SceneStore store;
  const RenderScene scene = layerScene(store);
  ASSERT_EQ(scene.world.size(), 3u);
  const Ray ray = viewRay();
  uint32_t checked = 0;
  for (uint32_t instance = 0; instance < 3; ++instance) {
    const bool litByVertices = instance == 0;
    const bool glows = instance != 1;
    const uint32_t triangles = scene.world[instance].mesh->geometry.triangleCount();
    for (uint32_t prim = 0; prim < triangles; prim += 3) {
      for (const glm::vec2 bary : {glm::vec2(0.1f, 0.2f), glm::vec2(0.33f, 0.61f), glm::vec2(0.7f, 0.05f)}) {
        const Hit hit = hitAt(instance, prim, bary);
        for (const bool alongRay : {false, true}) {
          const SurfaceHit all = alongRay ? scene.surfaceAt(hit, false, ray) : scene.surfaceAt(hit, false);
          const SurfaceHit layer = alongRay ? scene.surfaceAt(hit, false, ray, SurfaceParts::LayerColour)
                                            : scene.surfaceAt(hit, false, SurfaceParts::LayerColour);
          SCOPED_TRACE(testing::Message() << "instance " << instance << ", prim " << prim << ", along ray " << alongRay);
          EXPECT_TRUE(sameBits(all.position, layer.position));
          EXPECT_TRUE(sameBits(all.uv, layer.uv));
          EXPECT_TRUE(sameBits(all.emissiveUv, layer.emissiveUv));
          EXPECT_TRUE(sameBits(all.uvArea, layer.uvArea));
          EXPECT_TRUE(sameBits(all.vertexColor.a, layer.vertexColor.a));
          if (glows) {
            EXPECT_TRUE(sameBits(all.geometricNormal, layer.geometricNormal));
          } else {   // left out: nothing reads them
            EXPECT_EQ(layer.geometricNormal, glm::vec3(0.0f, 0.0f, 1.0f));
            EXPECT_EQ(layer.worldArea, 0.0f);
          }
          EXPECT_EQ(layer.shadingNormal, layer.geometricNormal);
          EXPECT_EQ(layer.lightmapUv, glm::vec2(0.0f));
          // What the hit filter makes of a layer: its colour and glow, on the side it faces.
          EXPECT_TRUE(sameBits(scene.baseColor(all, 0.0f), scene.baseColor(layer, 0.0f)));
          const bool front = glm::dot(all.geometricNormal, ray.dir) < 0.0f;
          EXPECT_TRUE(sameBits(scene.emission(all, front), scene.emission(layer, front)));
          EXPECT_TRUE(sameBits(scene.emission(all, !front), scene.emission(layer, !front)));
          if (litByVertices) {
            EXPECT_EQ(glm::vec3(layer.vertexColor), glm::vec3(1.0f));   // no baked light computed
            EXPECT_NE(glm::vec3(all.vertexColor), glm::vec3(1.0f));
          } else {
            EXPECT_TRUE(sameBits(all.vertexColor, layer.vertexColor));
          }
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 300u);
}

/// Every member of two surface hits has the same bits, the shading normal aside.
void expectSameBitsButShadingNormal(const SurfaceHit& a, const SurfaceHit& b) {
  EXPECT_EQ(a.instance, b.instance);
  EXPECT_EQ(a.material, b.material);
  EXPECT_EQ(a.prim, b.prim);
  EXPECT_TRUE(sameBits(a.bary, b.bary));
  EXPECT_TRUE(sameBits(a.position, b.position));
  EXPECT_TRUE(sameBits(a.geometricNormal, b.geometricNormal));
  EXPECT_TRUE(sameBits(a.uv, b.uv));
  EXPECT_TRUE(sameBits(a.emissiveUv, b.emissiveUv));
  EXPECT_TRUE(sameBits(a.lightmapUv, b.lightmapUv));
  EXPECT_TRUE(sameBits(a.shineUv, b.shineUv));
  EXPECT_TRUE(sameBits(a.shineUvArea, b.shineUvArea));
  EXPECT_TRUE(sameBits(a.vertexColor, b.vertexColor));
  EXPECT_TRUE(sameBits(a.worldArea, b.worldArea));
  EXPECT_TRUE(sameBits(a.uvArea, b.uvArea));
}

TEST(SurfaceParts, NoShadingNormalAndTheTriangleMemoKeepAllsBits) {
  SceneStore store;
  const RenderScene scene = layerScene(store);
  ASSERT_EQ(scene.world.size(), 3u);
  const Ray ray = viewRay();
  TriangleMemo memo;
  uint32_t checked = 0, shaded = 0;
  for (uint32_t instance = 0; instance < 3; ++instance) {
    const uint32_t triangles = scene.world[instance].mesh->geometry.triangleCount();
    // Each triangle twice in a row (the memo kept), then one visited before (the memo refilled).
    for (const uint32_t prim : {0u, 0u, 5u, 5u, 0u, 17u, triangles - 1, 5u}) {
      for (const glm::vec2 bary : {glm::vec2(0.1f, 0.2f), glm::vec2(0.33f, 0.61f), glm::vec2(0.7f, 0.05f)}) {
        const Hit hit = hitAt(instance, prim, bary);
        SCOPED_TRACE(testing::Message() << "instance " << instance << ", prim " << prim);
        for (const SurfaceParts parts : {SurfaceParts::All, SurfaceParts::NoShadingNormal, SurfaceParts::LayerColour}) {
          const SurfaceHit alone = scene.surfaceAt(hit, false, ray, parts);
          const SurfaceHit remembered = scene.surfaceAt(hit, false, ray, parts, &memo);
          expectSameBitsButShadingNormal(alone, remembered);
          EXPECT_TRUE(sameBits(alone.shadingNormal, remembered.shadingNormal));
        }
        const SurfaceHit all = scene.surfaceAt(hit, false, ray);
        const SurfaceHit shown = scene.surfaceAt(hit, false, ray, SurfaceParts::NoShadingNormal, &memo);
        expectSameBitsButShadingNormal(all, shown);
        EXPECT_EQ(shown.shadingNormal, shown.geometricNormal);
        shaded += all.shadingNormal != all.geometricNormal;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 72u);
  EXPECT_GT(shaded, 60u);   // the spheres' normals are their own, not the winding one
}

}  // namespace
}  // namespace pa
