// Known-answer tests of the glTF importer on files the tests write themselves.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <span>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "renderer/gltf_io/gltf_builder.h"
#include "renderer/gltf_io/gltf_loader.h"

namespace pa::gltf {
namespace {

namespace fs = std::filesystem;

/// A fresh scratch directory per test.
class GltfLoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("pa_gltf_io_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path file(const std::string& name) const { return dir_ / name; }
  fs::path dir_;
};

const std::vector<glm::vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

/// One mesh with one primitive over `positions` (indexed when `indices` is non-empty).
int addMesh(ModelBuilder& builder, const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices,
            int componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, int mode = TINYGLTF_MODE_TRIANGLES) {
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = builder.addVec3(positions, true);
  if (!indices.empty()) primitive.indices = builder.addIndices(indices, componentType);
  primitive.mode = mode;
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(primitive);
  builder.model().meshes.push_back(mesh);
  return static_cast<int>(builder.model().meshes.size() - 1);
}

tinygltf::Node meshNode(int mesh) {
  tinygltf::Node node;
  node.mesh = mesh;
  return node;
}

void expectNear(const glm::vec3& actual, const glm::vec3& expected) {
  EXPECT_NEAR(actual.x, expected.x, 1e-5f);
  EXPECT_NEAR(actual.y, expected.y, 1e-5f);
  EXPECT_NEAR(actual.z, expected.z, 1e-5f);
}

/// Runs `load` and returns the runtime_error message (fails the test if nothing is thrown).
template <typename Load>
std::string errorOf(Load&& load) {
  try {
    load();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected std::runtime_error";
  return {};
}

TEST_F(GltfLoaderTest, AppliesNodeHierarchyTransforms) {
  ModelBuilder builder;
  const int mesh = addMesh(builder, kTriangle, {0, 1, 2});
  tinygltf::Node parent;
  parent.translation = {10, 0, 0};
  const int parentIndex = builder.addNode(parent);
  tinygltf::Node child = meshNode(mesh);
  child.scale = {2, 2, 2};
  child.rotation = {0, std::sqrt(0.5), 0, std::sqrt(0.5)};  // +90 degrees about +Y: x -> -z
  builder.addNode(child, parentIndex);
  builder.writeGltf(file("hierarchy.gltf"));

  const TriangleSoup soup = loadTriangles(file("hierarchy.gltf"));
  ASSERT_EQ(soup.positions.size(), 3u);
  ASSERT_EQ(soup.indices, (std::vector<uint32_t>{0, 1, 2}));
  expectNear(soup.positions[0], {10, 0, 0});
  expectNear(soup.positions[1], {10, 0, -2});
  expectNear(soup.positions[2], {10, 2, 0});
}

TEST_F(GltfLoaderTest, MatrixNodeAndInstancing) {
  ModelBuilder builder;
  const int mesh = addMesh(builder, kTriangle, {});
  builder.addNode(meshNode(mesh));
  tinygltf::Node moved = meshNode(mesh);
  moved.matrix = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 6, 7, 1};  // column-major translation
  builder.addNode(moved);
  builder.writeGltf(file("instances.gltf"));

  const GltfScene scene = loadScene(file("instances.gltf"));
  ASSERT_EQ(scene.meshes.size(), 1u);
  ASSERT_EQ(scene.instances.size(), 2u);
  EXPECT_EQ(scene.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2}));  // non-indexed -> 0..n-1
  const TriangleSoup soup = flattenTriangles(scene);
  ASSERT_EQ(soup.positions.size(), 6u);
  expectNear(soup.positions[3], {5, 6, 7});
  expectNear(soup.positions[5], {5, 7, 7});
}

TEST_F(GltfLoaderTest, AllIndexComponentTypesGiveTheSameTriangles) {
  const std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
  for (int type : {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                   TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT}) {
    ModelBuilder builder;
    builder.addNode(meshNode(addMesh(builder, quad, indices, type)));
    const fs::path path = file("indices" + std::to_string(type) + ".glb");
    builder.writeGlb(path);
    const TriangleSoup soup = loadTriangles(path);
    EXPECT_EQ(soup.indices, indices) << "componentType " << type;
    EXPECT_EQ(soup.positions.size(), 4u);
  }
}

TEST_F(GltfLoaderTest, ConvertsStripsAndFans) {
  const std::vector<glm::vec3> strip = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}};
  ModelBuilder builder;
  builder.addNode(meshNode(addMesh(builder, strip, {0, 1, 2, 3, 4}, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                   TINYGLTF_MODE_TRIANGLE_STRIP)));
  builder.addNode(meshNode(addMesh(builder, strip, {}, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_MODE_TRIANGLE_FAN)));
  builder.writeGltf(file("strips.gltf"));

  const GltfScene scene = loadScene(file("strips.gltf"));
  ASSERT_EQ(scene.meshes.size(), 2u);
  // Strip: {0,1,2}, {1,3,2}, {2,3,4}: every triangle wound like the first.
  EXPECT_EQ(scene.meshes[0].indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 2, 3, 4}));
  // Fan (glTF order {v[i+1], v[i+2], v[0]}).
  EXPECT_EQ(scene.meshes[1].indices, (std::vector<uint32_t>{1, 2, 0, 2, 3, 0, 3, 4, 0}));
}

TEST_F(GltfLoaderTest, MirroredInstanceKeepsFrontFaces) {
  ModelBuilder builder;
  const int mesh = addMesh(builder, kTriangle, {0, 1, 2});
  tinygltf::Node mirrored = meshNode(mesh);
  mirrored.scale = {-1, 1, 1};
  builder.addNode(mirrored);
  builder.writeGltf(file("mirror.gltf"));
  const TriangleSoup soup = loadTriangles(file("mirror.gltf"));
  ASSERT_EQ(soup.indices.size(), 3u);
  const glm::vec3 normal = glm::cross(soup.positions[soup.indices[1]] - soup.positions[soup.indices[0]],
                                      soup.positions[soup.indices[2]] - soup.positions[soup.indices[0]]);
  EXPECT_GT(normal.z, 0.0f);  // same facing (+Z) as the unmirrored triangle
}

TEST_F(GltfLoaderTest, MissingFileIsAClearError) {
  const std::string message = errorOf([&] { loadTriangles(file("nope.gltf")); });
  EXPECT_NE(message.find("nope.gltf"), std::string::npos) << message;
  EXPECT_NE(message.find("cannot open"), std::string::npos) << message;
}

std::vector<std::byte> readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const auto* p = reinterpret_cast<const std::byte*>(text.data());
  return {p, p + text.size()};
}

TEST_F(GltfLoaderTest, LoadsFromMemoryLikeFromAFile) {
  ModelBuilder builder;
  builder.addNode(meshNode(addMesh(builder, kTriangle, {0, 1, 2})));
  builder.writeGlb(file("tri.glb"));
  builder.writeGltf(file("tri.gltf"));
  for (const char* name : {"tri.glb", "tri.gltf"}) {
    const GltfScene fromFile = loadScene(file(name));
    const GltfScene fromMemory = loadSceneFromMemory(readBytes(file(name)), name);
    ASSERT_EQ(fromMemory.meshes.size(), 1u) << name;
    EXPECT_EQ(fromMemory.meshes[0].positions, fromFile.meshes[0].positions) << name;
    EXPECT_EQ(fromMemory.meshes[0].indices, fromFile.meshes[0].indices) << name;
    EXPECT_EQ(fromMemory.instances.size(), fromFile.instances.size()) << name;
  }
  const std::vector<std::byte> glb = readBytes(file("tri.glb"));
  const std::string message = errorOf([&] { loadSceneFromMemory(std::span(glb).first(30), "cut.glb"); });
  EXPECT_NE(message.find("cut.glb: truncated GLB"), std::string::npos) << message;
}

TEST_F(GltfLoaderTest, InMemoryInputReadsNoExternalFileUnlessGivenAFolder) {
  ModelBuilder builder;
  builder.addNode(meshNode(addMesh(builder, kTriangle, {0, 1, 2})));
  builder.writeGltf(file("tri.gltf"));
  // The same buffer as an external file beside the JSON.
  std::ifstream in(file("tri.gltf"));
  std::string json{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const size_t uri = json.find("data:application/octet-stream;base64,");
  ASSERT_NE(uri, std::string::npos);
  const size_t end = json.find('"', uri);
  tinygltf::Model& model = builder.model();
  std::ofstream(file("tri.bin"), std::ios::binary)
      .write(reinterpret_cast<const char*>(model.buffers[0].data.data()), static_cast<std::streamsize>(model.buffers[0].data.size()));
  json.replace(uri, end - uri, "tri.bin");
  const auto* p = reinterpret_cast<const std::byte*>(json.data());
  const std::vector<std::byte> bytes(p, p + json.size());
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_);  // tri.bin is even in the working directory: still not read
  const std::string message = errorOf([&] { loadSceneFromMemory(bytes, "external.gltf"); });
  fs::current_path(cwd);
  EXPECT_NE(message.find("File not found : tri.bin"), std::string::npos) << message;  // our FileExists says no
  EXPECT_EQ(loadSceneFromMemory(bytes, "external.gltf", dir_).meshes.size(), 1u);
}

TEST_F(GltfLoaderTest, GarbageJsonIsAClearError) {
  std::ofstream(file("garbage.gltf")) << "{ \"asset\": { \"version\": \"2.0\" }, \"meshes\": [ ";
  const std::string message = errorOf([&] { loadTriangles(file("garbage.gltf")); });
  EXPECT_NE(message.find("garbage.gltf"), std::string::npos) << message;
}

TEST_F(GltfLoaderTest, TruncatedGlbIsAClearError) {
  ModelBuilder builder;
  builder.addNode(meshNode(addMesh(builder, kTriangle, {0, 1, 2})));
  builder.writeGlb(file("whole.glb"));
  const uintmax_t size = fs::file_size(file("whole.glb"));
  for (uintmax_t keep : {uintmax_t{10}, size / 2, size - 4}) {
    fs::copy_file(file("whole.glb"), file("cut.glb"), fs::copy_options::overwrite_existing);
    fs::resize_file(file("cut.glb"), keep);
    const std::string message = errorOf([&] { loadTriangles(file("cut.glb")); });
    EXPECT_NE(message.find("truncated GLB"), std::string::npos) << "kept " << keep << ": " << message;
    EXPECT_NE(message.find("cut.glb"), std::string::npos) << message;
  }
}

TEST_F(GltfLoaderTest, OutOfRangeAccessorIsAClearError) {
  ModelBuilder builder;
  builder.addNode(meshNode(addMesh(builder, kTriangle, {0, 1, 2})));
  builder.model().meshes[0].primitives[0].attributes["POSITION"] = 99;
  builder.writeGltf(file("accessor.gltf"));
  const std::string message = errorOf([&] { loadTriangles(file("accessor.gltf")); });
  EXPECT_NE(message.find("accessor.gltf"), std::string::npos) << message;
  EXPECT_NE(message.find("99"), std::string::npos) << message;
}

TEST_F(GltfLoaderTest, AccessorOverrunningItsViewIsAClearError) {
  ModelBuilder builder;
  builder.addNode(meshNode(addMesh(builder, kTriangle, {0, 1, 2})));
  builder.model().accessors[0].count = 4;  // view holds 3 vec3
  builder.writeGltf(file("overrun.gltf"));
  const std::string message = errorOf([&] { loadTriangles(file("overrun.gltf")); });
  EXPECT_NE(message.find("meshes[0].primitives[0] POSITION (accessors[0])"), std::string::npos) << message;
  EXPECT_NE(message.find("overrun bufferViews[0]"), std::string::npos) << message;
}

TEST_F(GltfLoaderTest, BadBufferViewIsAClearError) {
  ModelBuilder builder;
  builder.addNode(meshNode(addMesh(builder, kTriangle, {0, 1, 2})));
  builder.model().bufferViews[0].byteOffset = 1000000;
  builder.writeGltf(file("view.gltf"));
  const std::string message = errorOf([&] { loadTriangles(file("view.gltf")); });
  EXPECT_NE(message.find("view.gltf"), std::string::npos) << message;
  EXPECT_NE(message.find("bufferView"), std::string::npos) << message;
}

TEST_F(GltfLoaderTest, IndexBeyondVertexCountIsAClearError) {
  ModelBuilder builder;
  builder.addNode(meshNode(addMesh(builder, kTriangle, {0, 1, 7})));
  builder.writeGltf(file("index.gltf"));
  const std::string message = errorOf([&] { loadTriangles(file("index.gltf")); });
  EXPECT_NE(message.find("index 7 at position 2 >= vertex count 3"), std::string::npos) << message;
}

TEST_F(GltfLoaderTest, OverflowingTransformIsAClearError) {
  ModelBuilder builder;
  tinygltf::Node parent;
  parent.scale = {1e30, 1e30, 1e30};
  const int parentIndex = builder.addNode(parent);
  tinygltf::Node child = meshNode(addMesh(builder, kTriangle, {}));
  child.scale = {1e30, 1e30, 1e30};
  builder.addNode(child, parentIndex);
  builder.writeGltf(file("huge.gltf"));
  const std::string message = errorOf([&] { loadTriangles(file("huge.gltf")); });
  EXPECT_NE(message.find("nodes[1]: world transform overflows"), std::string::npos) << message;
}

TEST_F(GltfLoaderTest, NodeCycleIsAClearError) {
  ModelBuilder builder;
  const int a = builder.addNode(meshNode(addMesh(builder, kTriangle, {})));
  const int b = builder.addNode(tinygltf::Node{}, a);
  builder.model().nodes[static_cast<size_t>(b)].children.push_back(a);
  builder.writeGltf(file("cycle.gltf"));
  const std::string message = errorOf([&] { loadTriangles(file("cycle.gltf")); });
  EXPECT_NE(message.find("cycle"), std::string::npos) << message;
}

}  // namespace
}  // namespace pa::gltf
