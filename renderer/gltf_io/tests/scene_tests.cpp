// Known-answer tests of loadScene (materials, textures, attributes, lights, cameras, extras)
// and of the glTF -> renderer description mapping.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "renderer/gltf_io/gltf_builder.h"
#include "renderer/gltf_io/gltf_loader.h"
#include "renderer/gltf_io/gltf_mapping.h"

namespace pa::gltf {
namespace {

namespace fs = std::filesystem;
using tinygltf::Value;

constexpr float kPi = 3.14159265358979f;

void expectNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance = 1e-5f) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

/// Writes the reference scene once per test into a scratch directory.
class GltfSceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = fs::temp_directory_path() /
            ("pa_gltf_scene_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
             std::to_string(::getpid()) + ".glb");
    writeReferenceScene(path_);
  }
  void TearDown() override { fs::remove(path_); }

  static void writeReferenceScene(const fs::path& path) {
    ModelBuilder builder;
    tinygltf::Model& model = builder.model();
    // 2x2 texture: red, green / blue, transparent white.
    const std::vector<uint8_t> pixels = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 0};
    const int texture = builder.addTexture("checker", 2, 2, pixels, true);

    tinygltf::Material grate;
    grate.name = "grate";
    grate.pbrMetallicRoughness.baseColorFactor = {0.5, 0.25, 1.0, 1.0};
    grate.pbrMetallicRoughness.baseColorTexture.index = texture;
    grate.pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
        Value(Value::Object{{"offset", Value(Value::Array{Value(0.5), Value(0.0)})},
                            {"scale", Value(Value::Array{Value(2.0), Value(4.0)})}});
    grate.pbrMetallicRoughness.metallicFactor = 0.25;
    grate.pbrMetallicRoughness.roughnessFactor = 0.6;
    grate.alphaMode = "MASK";
    grate.alphaCutoff = 0.3;
    grate.doubleSided = true;
    grate.emissiveFactor = {1.0, 0.5, 0.0};
    grate.extensions["KHR_materials_emissive_strength"] = Value(Value::Object{{"emissiveStrength", Value(4.0)}});
    grate.extras = Value(Value::Object{{"shader", Value(std::string("textures/base/grate"))},
                                       {"sky", Value(true)},
                                       {"stages", Value(3)}});
    model.materials.push_back(grate);

    // Primitive 0: quad with normals, normalized UNSIGNED_SHORT uvs, material 0.
    const std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const std::vector<glm::vec3> normals(4, glm::vec3(0, 0, 2));  // not unit: must be normalized
    const std::vector<uint16_t> uvs = {0, 0, 65535, 0, 65535, 65535, 0, 32768};
    tinygltf::Primitive first;
    first.attributes["POSITION"] = builder.addVec3(quad, true);
    first.attributes["NORMAL"] = builder.addVec3(normals, false);
    const int uvView = builder.addView({reinterpret_cast<const uint8_t*>(uvs.data()), uvs.size() * 2});
    first.attributes["TEXCOORD_0"] =
        builder.addAccessor(uvView, 0, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC2, 4, true);
    const std::vector<uint32_t> quadIndices = {0, 1, 2, 0, 2, 3};
    first.indices = builder.addIndices(quadIndices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE);
    first.material = 0;
    first.mode = TINYGLTF_MODE_TRIANGLES;
    // Primitive 1: triangle in the XZ plane, normalized UNSIGNED_BYTE RGB colours, no material.
    const std::vector<glm::vec3> floor = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}};
    const std::vector<uint8_t> colors = {255, 0, 0, 0, 255, 0, 0, 0, 255, 0};  // 3 x RGB + pad
    tinygltf::Primitive second;
    second.attributes["POSITION"] = builder.addVec3(floor, true);
    const int colorView = builder.addView(colors);
    second.attributes["COLOR_0"] =
        builder.addAccessor(colorView, 0, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC3, 3, true);
    second.mode = TINYGLTF_MODE_TRIANGLES;
    tinygltf::Mesh mesh;
    mesh.name = "two_primitives";
    mesh.primitives = {first, second};
    model.meshes.push_back(mesh);
    tinygltf::Node meshNode;
    meshNode.name = "geometry";
    meshNode.mesh = 0;
    meshNode.extras = Value(Value::Object{{"entity", Value(std::string("func_door"))}});
    builder.addNode(meshNode);

    // Lights: point (candela), spot (aimed down -Y by a -90 degree turn about X), directional.
    tinygltf::Light point;
    point.type = "point";
    point.color = {1.0, 0.5, 0.25};
    point.intensity = 100.0;
    point.range = 20.0;
    tinygltf::Light spot;
    spot.type = "spot";
    spot.intensity = 50.0;
    spot.spot.innerConeAngle = 0.2;
    spot.spot.outerConeAngle = 0.4;
    tinygltf::Light sun;
    sun.type = "directional";
    sun.intensity = 3.0;
    model.lights = {point, spot, sun};
    auto lightNode = [&](int light) {
      tinygltf::Node node;
      node.extensions["KHR_lights_punctual"] = Value(Value::Object{{"light", Value(light)}});
      return node;
    };
    tinygltf::Node pointNode = lightNode(0);
    pointNode.translation = {1, 2, 3};
    builder.addNode(pointNode);
    tinygltf::Node spotNode = lightNode(1);
    spotNode.translation = {0, 5, 0};
    spotNode.rotation = {-std::sqrt(0.5), 0, 0, std::sqrt(0.5)};
    builder.addNode(spotNode);
    builder.addNode(lightNode(2));

    // Camera turned +90 degrees about +Y: looks down -X.
    tinygltf::Camera camera;
    camera.type = "perspective";
    camera.name = "main";
    camera.perspective.yfov = 0.8;
    camera.perspective.aspectRatio = 16.0 / 9.0;
    camera.perspective.znear = 0.1;
    model.cameras.push_back(camera);
    tinygltf::Node cameraNode;
    cameraNode.camera = 0;
    cameraNode.translation = {0, 1, 5};
    cameraNode.rotation = {0, std::sqrt(0.5), 0, std::sqrt(0.5)};
    builder.addNode(cameraNode);

    model.scenes[0].extras = Value(Value::Object{{"sky_color", Value(Value::Array{Value(0.1), Value(0.2), Value(0.3)})},
                                                 {"sky_intensity", Value(2.0)}});
    builder.writeGlb(path);
  }

  fs::path path_;
};

TEST_F(GltfSceneTest, MergesPrimitivesAndFillsMissingAttributes) {
  const GltfScene scene = loadScene(path_);
  ASSERT_EQ(scene.meshes.size(), 1u);
  const GltfMesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.name, "two_primitives");
  ASSERT_EQ(mesh.positions.size(), 7u);
  EXPECT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 4, 5, 6}));
  EXPECT_EQ(mesh.triangleMaterials, (std::vector<uint32_t>{0, 0, kNone}));
  ASSERT_EQ(mesh.normals.size(), 7u);
  expectNear(mesh.normals[0], {0, 0, 1});                  // normalized from (0,0,2)
  expectNear(mesh.normals[5], {0, 1, 0});                  // computed: (0,0,1)-(0,0,0) x (1,0,0) = +Y
  ASSERT_EQ(mesh.uvs.size(), 7u);
  EXPECT_FLOAT_EQ(mesh.uvs[2].x, 1.0f);
  EXPECT_NEAR(mesh.uvs[3].y, 32768.0f / 65535.0f, 1e-6f);
  EXPECT_EQ(mesh.uvs[5], glm::vec2(0.0f));                 // primitive without uvs
  ASSERT_EQ(mesh.colors.size(), 7u);
  EXPECT_EQ(mesh.colors[0], glm::vec4(1.0f));              // primitive without colours
  EXPECT_EQ(mesh.colors[5], glm::vec4(0, 1, 0, 1));        // normalized ubyte RGB -> RGBA
}

TEST_F(GltfSceneTest, ReadsMaterialTextureAndExtras) {
  const GltfScene scene = loadScene(path_);
  ASSERT_EQ(scene.images.size(), 1u);
  ASSERT_EQ(scene.images[0].width, 2u);
  ASSERT_EQ(scene.images[0].rgba8.size(), 16u);
  EXPECT_EQ(scene.images[0].rgba8[4 + 1], 255);            // second pixel green
  EXPECT_EQ(scene.images[0].rgba8[15], 0);                 // last pixel transparent
  ASSERT_EQ(scene.textures.size(), 1u);
  EXPECT_EQ(scene.textures[0].wrap, Wrap::Clamp);
  ASSERT_EQ(scene.materials.size(), 1u);
  const GltfMaterial& material = scene.materials[0];
  EXPECT_EQ(material.name, "grate");
  EXPECT_EQ(material.baseColorFactor, glm::vec4(0.5f, 0.25f, 1.0f, 1.0f));
  EXPECT_EQ(material.baseColorTexture, 0u);
  EXPECT_EQ(material.alphaMode, AlphaMode::Mask);
  EXPECT_FLOAT_EQ(material.alphaCutoff, 0.3f);
  expectNear(material.emissive, {4.0f, 2.0f, 0.0f});       // factor x emissive_strength
  EXPECT_TRUE(material.doubleSided);
  EXPECT_FLOAT_EQ(material.metallic, 0.25f);
  EXPECT_FLOAT_EQ(material.roughness, 0.6f);
  // uv' = T * R * S * uv: (1, 1) -> (2 + 0.5, 4).
  const glm::vec2 uv = material.baseColorUvTransform * glm::vec3(1.0f, 1.0f, 1.0f);
  EXPECT_NEAR(uv.x, 2.5f, 1e-6f);
  EXPECT_NEAR(uv.y, 4.0f, 1e-6f);
  EXPECT_EQ(material.extras.at("shader"), "textures/base/grate");
  EXPECT_EQ(material.extras.at("sky"), "true");
  EXPECT_EQ(material.extras.at("stages"), "3");
  ASSERT_EQ(scene.instances.size(), 1u);
  EXPECT_EQ(scene.instances[0].extras.at("entity"), "func_door");
  EXPECT_EQ(scene.sceneExtras.at("sky_color"), "[0.1,0.2,0.3]");
}

TEST_F(GltfSceneTest, PlacesLightsAndCameras) {
  LoadOptions options;
  options.lightUnitScale = 0.5f;
  const GltfScene scene = loadScene(path_, options);
  ASSERT_EQ(scene.lights.size(), 3u);
  const GltfLight& point = scene.lights[0];
  EXPECT_EQ(point.type, LightType::Point);
  expectNear(point.position, {1, 2, 3});
  expectNear(point.color, {1.0f, 0.5f, 0.25f});
  EXPECT_FLOAT_EQ(point.intensity, 50.0f);                 // 100 cd x 0.5
  EXPECT_FLOAT_EQ(point.range, 20.0f);
  const GltfLight& spot = scene.lights[1];
  EXPECT_EQ(spot.type, LightType::Spot);
  expectNear(spot.position, {0, 5, 0});
  expectNear(spot.direction, {0, -1, 0});
  EXPECT_FLOAT_EQ(spot.outerConeAngle, 0.4f);
  const GltfLight& sun = scene.lights[2];
  EXPECT_EQ(sun.type, LightType::Directional);
  expectNear(sun.direction, {0, 0, -1});
  EXPECT_FLOAT_EQ(sun.intensity, 1.5f);

  ASSERT_EQ(scene.cameras.size(), 1u);
  const GltfCamera& camera = scene.cameras[0];
  EXPECT_EQ(camera.name, "main");
  expectNear(camera.origin, {0, 1, 5});
  expectNear(camera.forward, {-1, 0, 0});
  expectNear(camera.left, {0, 0, 1});
  expectNear(camera.up, {0, 1, 0});
  EXPECT_FLOAT_EQ(camera.yfov, 0.8f);
  EXPECT_NEAR(camera.aspectRatio, 16.0f / 9.0f, 1e-6f);
}

TEST_F(GltfSceneTest, MapsToRendererDescriptions) {
  const GltfScene scene = loadScene(path_);
  const MaterialDesc material = toMaterialDesc(scene.materials[0], {TextureId{7}});
  EXPECT_EQ(material.baseTexture, 7u);
  EXPECT_EQ(material.alphaMode, pa::AlphaMode::Mask);
  EXPECT_FLOAT_EQ(material.alphaCutoff, 0.3f);
  EXPECT_TRUE(material.twoSided);
  EXPECT_TRUE(material.sky);                               // from extras
  EXPECT_FALSE(material.mirror);
  EXPECT_NEAR(material.specular, 0.04f + 0.96f * 0.25f, 1e-6f);
  expectNear(material.emission, {4.0f, 2.0f, 0.0f});

  const LightDesc spot = toLightDesc(scene.lights[1]);
  EXPECT_EQ(spot.type, pa::LightType::Spot);
  EXPECT_NEAR(spot.cosInnerAngle, std::cos(0.2f), 1e-6f);
  EXPECT_NEAR(spot.cosOuterAngle, std::cos(0.4f), 1e-6f);
  EXPECT_FLOAT_EQ(spot.intensity, 50.0f);

  const SkyDesc sky = toSkyDesc(scene.sceneExtras);
  expectNear(sky.color, {0.1f, 0.2f, 0.3f});
  EXPECT_FLOAT_EQ(sky.intensity, 2.0f);

  // 90 degree vertical fov on a 2:1 image: horizontal = 2 atan(2 tan 45) = 126.87 degrees.
  GltfCamera square = scene.cameras[0];
  square.yfov = kPi / 2;
  const Camera camera = toCamera(square, 2.0f);
  EXPECT_NEAR(camera.fovY, 90.0f, 1e-4f);
  EXPECT_NEAR(camera.fovX, 126.8699f, 1e-3f);
  expectNear(camera.forward, {-1, 0, 0});
}

TEST_F(GltfSceneTest, GeometryOnlyLoadSkipsImages) {
  LoadOptions options;
  options.decodeImages = false;
  const GltfScene scene = loadScene(path_, options);
  ASSERT_EQ(scene.images.size(), 1u);
  EXPECT_TRUE(scene.images[0].rgba8.empty());
  EXPECT_EQ(scene.materials[0].baseColorTexture, kNone);   // texture without pixels is dropped
}

TEST(GltfSparse, SparseAccessorOverridesBaseValues) {
  const fs::path path = fs::temp_directory_path() / ("pa_gltf_sparse_" + std::to_string(::getpid()) + ".gltf");
  ModelBuilder builder;
  const std::vector<glm::vec3> base = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = builder.addVec3(base, false);
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  const std::vector<uint8_t> sparseIndices = {2, 0, 0, 0};
  const std::vector<glm::vec3> sparseValues = {{0, 5, 0}};
  tinygltf::Accessor& accessor = builder.model().accessors[0];
  accessor.sparse.isSparse = true;
  accessor.sparse.count = 1;
  const int indexView = builder.addView(sparseIndices);
  const int valueView = builder.addView({reinterpret_cast<const uint8_t*>(sparseValues.data()), 12});
  tinygltf::Accessor& again = builder.model().accessors[0];
  again.sparse.indices.bufferView = indexView;
  again.sparse.indices.byteOffset = 0;
  again.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  again.sparse.values.bufferView = valueView;
  again.sparse.values.byteOffset = 0;
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(primitive);
  builder.model().meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  builder.addNode(node);
  builder.writeGltf(path);
  const TriangleSoup soup = loadTriangles(path);
  fs::remove(path);
  ASSERT_EQ(soup.positions.size(), 3u);
  expectNear(soup.positions[2], {0, 5, 0});
  expectNear(soup.positions[1], {1, 0, 0});
}

TEST(GltfConverterConventions, ReadsLightmapsAndQuakeExtras) {
  const fs::path path = fs::temp_directory_path() / ("pa_gltf_lightmap_" + std::to_string(::getpid()) + ".glb");
  ModelBuilder builder;
  const std::vector<uint8_t> pixels = {64, 32, 16, 255};
  const int lightmap = builder.addTexture("lightmap 0", 1, 1, pixels, true);
  tinygltf::Material material;
  material.extras = Value(Value::Object{
      {"quake", Value(Value::Object{{"shader", Value(std::string("textures/sfx/sky"))},
                                    {"sky", Value(true)},
                                    {"blend", Value(std::string("add"))},
                                    {"lightmapStageScale", Value(2.0)}})}});
  builder.model().materials.push_back(material);
  const std::vector<glm::vec3> triangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<glm::vec2> uv0 = {{0, 0}, {1, 0}, {0, 1}};
  const std::vector<glm::vec2> uv1 = {{0.25f, 0.5f}, {0.75f, 0.5f}, {0.25f, 1.0f}};
  tinygltf::Primitive lit;
  lit.attributes["POSITION"] = builder.addVec3(triangle, true);
  lit.attributes["TEXCOORD_0"] = builder.addVec2(uv0);
  lit.attributes["TEXCOORD_1"] = builder.addVec2(uv1);
  lit.material = 0;
  lit.mode = TINYGLTF_MODE_TRIANGLES;
  lit.extras = Value(Value::Object{{"lightmapTexture", Value(lightmap)}, {"lightmapTexCoord", Value(1)}});
  tinygltf::Primitive unlit = lit;
  unlit.extras = Value();
  tinygltf::Mesh mesh;
  mesh.primitives = {lit, unlit};
  builder.model().meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  builder.addNode(node);
  // assets_converter keeps the map metadata on the root node, not on the scene.
  builder.model().nodes[0].extras = Value(Value::Object{
      {"quake", Value(Value::Object{{"lightmapOverbrightScale", Value(4.0)},
                                    {"sky", Value(Value::Object{{"color", Value(Value::Array{Value(1.0), Value(0.5), Value(0.25)})}})}})}});
  builder.writeGlb(path);
  const GltfScene scene = loadScene(path);
  fs::remove(path);

  ASSERT_EQ(scene.meshes.size(), 1u);
  const GltfMesh& loaded = scene.meshes[0];
  ASSERT_EQ(loaded.lightmapUvs.size(), 6u);
  EXPECT_EQ(loaded.lightmapUvs[1], glm::vec2(0.75f, 0.5f));
  EXPECT_EQ(loaded.lightmapUvs[4], glm::vec2(0.0f));                 // primitive without a lightmap
  EXPECT_EQ(loaded.triangleLightmaps, (std::vector<uint32_t>{0, kNone}));
  EXPECT_EQ(scene.materials[0].extras.at("quake.shader"), "textures/sfx/sky");  // nested keys flattened

  const MaterialDesc desc = toMaterialDesc(scene.materials[0], {});
  EXPECT_TRUE(desc.sky);
  EXPECT_EQ(desc.alphaMode, pa::AlphaMode::Additive);
  expectNear(toSkyDesc(scene.sceneExtras).color, {1.0f, 0.5f, 0.25f});
  EXPECT_FLOAT_EQ(lightmapBrightness(scene.sceneExtras), 4.0f);
  EXPECT_FLOAT_EQ(lightmapStageScale(scene.materials[0]), 2.0f);   // a doubling lightmap stage
  GltfMaterial plain;
  EXPECT_FLOAT_EQ(lightmapStageScale(plain), 1.0f);
  plain.extras["quake.lightmapStageScale"] = "nan";
  EXPECT_FLOAT_EQ(lightmapStageScale(plain), 1.0f);
}

TEST(GltfConverterConventions, BrightenLightmapSaturatesKeepingHue) {
  const std::vector<uint8_t> pixels = {64, 32, 16, 0, 100, 50, 10, 7};
  const std::vector<uint8_t> bright = brightenLightmap(pixels, 4.0f);
  EXPECT_EQ(bright, (std::vector<uint8_t>{255, 128, 64, 255, 255, 128, 26, 255}));  // 400,200,40 -> fit to 255
}

}  // namespace
}  // namespace pa::gltf
