// Hostile input: deterministic mutations of valid files must either load or throw
// std::runtime_error (never crash, hang or throw anything else). Run under ASan/UBSan in CI.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "renderer/gltf_io/gltf_builder.h"
#include "renderer/gltf_io/gltf_loader.h"

namespace pa::gltf {
namespace {

namespace fs = std::filesystem;

/// A small but feature-rich file: indexed mesh with normals/uvs, texture, material, light, camera.
std::string referenceFile(bool binary) {
  ModelBuilder builder;
  const std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<glm::vec2> uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const std::vector<uint32_t> indices = {0, 1, 2, 0, 2, 3};
  const std::vector<uint8_t> pixels(4 * 4 * 4, 200);
  tinygltf::Material material;
  material.pbrMetallicRoughness.baseColorTexture.index = builder.addTexture("t", 4, 4, pixels);
  builder.model().materials.push_back(material);
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = builder.addVec3(quad, true);
  primitive.attributes["NORMAL"] = builder.addVec3(std::vector<glm::vec3>(4, glm::vec3(0, 0, 1)), false);
  primitive.attributes["TEXCOORD_0"] = builder.addVec2(uvs);
  primitive.indices = builder.addIndices(indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  primitive.material = 0;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(primitive);
  builder.model().meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.translation = {1, 2, 3};
  const int parent = builder.addNode(node);
  tinygltf::Light light;
  light.type = "spot";
  builder.model().lights.push_back(light);
  tinygltf::Node lightNode;
  lightNode.extensions["KHR_lights_punctual"] = tinygltf::Value(tinygltf::Value::Object{{"light", tinygltf::Value(0)}});
  builder.addNode(lightNode, parent);
  tinygltf::Camera camera;
  camera.type = "perspective";
  camera.perspective.yfov = 1.0;
  builder.model().cameras.push_back(camera);
  tinygltf::Node cameraNode;
  cameraNode.camera = 0;
  builder.addNode(cameraNode);
  const fs::path path = fs::temp_directory_path() / ("pa_gltf_reference_" + std::to_string(::getpid()) + (binary ? ".glb" : ".gltf"));
  binary ? builder.writeGlb(path) : builder.writeGltf(path);
  std::ifstream in(path, std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  fs::remove(path);
  return bytes;
}

/// Loads `bytes` as a file; true if it loaded, false if it threw runtime_error.
bool loads(const std::string& bytes, const fs::path& path) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  try {
    loadScene(path);
    return true;
  } catch (const std::runtime_error&) {
    return false;
  }
}

void mutateAndLoad(bool binary) {
  const std::string original = referenceFile(binary);
  const fs::path path = fs::temp_directory_path() / ("pa_gltf_mutant_" + std::to_string(::getpid()) + (binary ? ".glb" : ".gltf"));
  ASSERT_TRUE(loads(original, path));
  std::mt19937 random(binary ? 1234u : 5678u);
  int loaded = 0;
  const int kMutants = 400;
  for (int i = 0; i < kMutants; ++i) {
    std::string mutant = original;
    const int edits = 1 + static_cast<int>(random() % 4);
    for (int e = 0; e < edits; ++e) {
      const size_t at = random() % mutant.size();
      switch (random() % 4) {
        case 0: mutant[at] = static_cast<char>(random()); break;                      // byte flip
        case 1: mutant[at] = static_cast<char>('0' + random() % 10); break;           // digit (JSON numbers)
        case 2: mutant.resize(at); break;                                             // truncation
        default: mutant.insert(at, 1, static_cast<char>("9-e.,[]{}\""[random() % 10])); break;
      }
      if (mutant.empty()) mutant = "x";
    }
    loaded += loads(mutant, path);
  }
  fs::remove(path);
  // Both outcomes must occur: the mutations are neither all harmless nor all fatal.
  EXPECT_GT(loaded, 0);
  EXPECT_LT(loaded, kMutants);
}

TEST(GltfRobustness, MutatedGlbLoadsOrThrowsRuntimeError) { mutateAndLoad(true); }
TEST(GltfRobustness, MutatedGltfLoadsOrThrowsRuntimeError) { mutateAndLoad(false); }

}  // namespace
}  // namespace pa::gltf
