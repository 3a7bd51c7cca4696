// Writes the seed corpus of the glTF fuzzer: small files built by code with ModelBuilder (no
// game data), each as .gltf (JSON, base64 buffers) and .glb: every primitive mode the importer
// converts, index widths, interleaved and quantized attributes, sparse accessors, textures with
// samplers and KHR_texture_transform, emissive strength, lights, cameras, mirrored instances,
// lightmap extras and a second scene.
#include <filesystem>
#include <string>
#include <vector>

#include "renderer/gltf_io/gltf_builder.h"

namespace {

using pa::gltf::ModelBuilder;
using tinygltf::Value;

const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};

int addMesh(ModelBuilder& b, tinygltf::Primitive primitive) {
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(std::move(primitive));
  b.model().meshes.push_back(std::move(mesh));
  return static_cast<int>(b.model().meshes.size()) - 1;
}

tinygltf::Primitive quadPrimitive(ModelBuilder& b, int indexType, int mode = TINYGLTF_MODE_TRIANGLES) {
  tinygltf::Primitive p;
  p.attributes["POSITION"] = b.addVec3(kQuad, true);
  p.mode = mode;
  const std::vector<uint32_t> triangles = {0, 1, 2, 0, 2, 3}, strip = {0, 1, 3, 2}, fan = {0, 1, 2, 3};
  p.indices = b.addIndices(mode == TINYGLTF_MODE_TRIANGLES ? triangles : mode == TINYGLTF_MODE_TRIANGLE_STRIP ? strip : fan,
                           indexType);
  return p;
}

void meshNode(ModelBuilder& b, int mesh, std::vector<double> scale = {}) {
  tinygltf::Node node;
  node.mesh = mesh;
  node.scale = std::move(scale);
  b.addNode(node);
}

/// Textured, lit, with camera and light (the importer's main paths).
void full(ModelBuilder& b) {
  const std::vector<uint8_t> pixels(4 * 4 * 4, 200);
  tinygltf::Material material;
  material.pbrMetallicRoughness.baseColorTexture.index = b.addTexture("t", 4, 4, pixels, true);
  material.pbrMetallicRoughness.baseColorTexture.extensions["KHR_texture_transform"] =
      Value(Value::Object{{"offset", Value(Value::Array{Value(0.5), Value(0.0)})}, {"rotation", Value(0.3)},
                          {"scale", Value(Value::Array{Value(2.0), Value(2.0)})}});
  material.emissiveFactor = {1, 0.5, 0};
  material.extensions["KHR_materials_emissive_strength"] = Value(Value::Object{{"emissiveStrength", Value(4.0)}});
  material.alphaMode = "MASK";
  b.model().materials.push_back(material);
  tinygltf::Primitive p = quadPrimitive(b, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  p.attributes["NORMAL"] = b.addVec3(std::vector<glm::vec3>(4, glm::vec3(0, 0, 1)), false);
  p.attributes["TEXCOORD_0"] = b.addVec2(std::vector<glm::vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  p.attributes["COLOR_0"] = b.addVec4(std::vector<glm::vec4>(4, glm::vec4(1, 0.5f, 0.25f, 1)));
  p.material = 0;
  tinygltf::Node node;
  node.mesh = addMesh(b, p);
  node.translation = {1, 2, 3};
  node.rotation = {0, 0.7071, 0, 0.7071};
  const int parent = b.addNode(node);
  tinygltf::Light light;
  light.type = "spot";
  light.intensity = 100;
  b.model().lights.push_back(light);
  tinygltf::Node lightNode;
  lightNode.extensions["KHR_lights_punctual"] = Value(Value::Object{{"light", Value(0)}});
  b.addNode(lightNode, parent);
  tinygltf::Camera camera;
  camera.type = "perspective";
  camera.perspective.yfov = 1.0;
  camera.perspective.znear = 0.1;
  b.model().cameras.push_back(camera);
  tinygltf::Node cameraNode;
  cameraNode.camera = 0;
  cameraNode.matrix = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 5, 5, 1};
  b.addNode(cameraNode);
}

/// Strip and fan, byte indices, and a mirrored instance.
void modes(ModelBuilder& b) {
  meshNode(b, addMesh(b, quadPrimitive(b, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_MODE_TRIANGLE_STRIP)));
  meshNode(b, addMesh(b, quadPrimitive(b, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_MODE_TRIANGLE_FAN)), {-1, 1, 1});
  tinygltf::Primitive unindexed;
  unindexed.attributes["POSITION"] = b.addVec3(std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, true);
  meshNode(b, addMesh(b, unindexed));
}

/// Interleaved positions/uvs in one strided view, quantized (normalized short) uvs, a sparse accessor.
void layouts(ModelBuilder& b) {
  std::vector<uint8_t> bytes;
  auto put = [&bytes](const void* p, size_t n) {
    bytes.insert(bytes.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + n);
  };
  for (int v = 0; v < 4; ++v) {
    put(&kQuad[v], sizeof(glm::vec3));
    const int16_t uv[2] = {static_cast<int16_t>(v & 1 ? 32767 : 0), static_cast<int16_t>(v & 2 ? 32767 : 0)};
    put(uv, sizeof(uv));
  }
  const int view = b.addView(bytes, 16, TINYGLTF_TARGET_ARRAY_BUFFER);
  tinygltf::Primitive p;
  p.attributes["POSITION"] = b.addAccessor(view, 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 4);
  b.model().accessors.back().minValues = {0, 0, 0};
  b.model().accessors.back().maxValues = {1, 1, 0};
  p.attributes["TEXCOORD_0"] = b.addAccessor(view, 12, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC2, 4, true);
  p.indices = b.addIndices(std::vector<uint32_t>{0, 1, 2, 0, 2, 3}, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  const std::vector<uint16_t> sparseIndices = {1};
  const std::vector<float> sparseValues = {2, 0, 0};
  const int normals = b.addVec3(std::vector<glm::vec3>(4, glm::vec3(0, 0, 1)), false);
  const int indicesView = b.addView({reinterpret_cast<const uint8_t*>(sparseIndices.data()), 2});
  const int valuesView = b.addView({reinterpret_cast<const uint8_t*>(sparseValues.data()), 12});
  tinygltf::Accessor& sparse = b.model().accessors[static_cast<size_t>(normals)];
  sparse.sparse.isSparse = true;
  sparse.sparse.count = 1;
  sparse.sparse.indices.bufferView = indicesView;
  sparse.sparse.indices.byteOffset = 0;  // tinygltf 2.7 leaves the sparse offsets uninitialised
  sparse.sparse.values.byteOffset = 0;
  sparse.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  sparse.sparse.values.bufferView = valuesView;
  p.attributes["NORMAL"] = normals;
  b.model().extensionsUsed = {"KHR_mesh_quantization"};
  b.model().extensionsRequired = {"KHR_mesh_quantization"};
  meshNode(b, addMesh(b, p));
}

/// Lightmap extras as written by assets_converter, and a second scene.
void lightmapAndScenes(ModelBuilder& b) {
  const std::vector<uint8_t> pixels(2 * 2 * 4, 90);
  const int lightmap = b.addTexture("lm", 2, 2, pixels);
  tinygltf::Primitive p = quadPrimitive(b, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  p.attributes["TEXCOORD_1"] = b.addVec2(std::vector<glm::vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  p.extras = Value(Value::Object{{"lightmapTexture", Value(lightmap)}, {"lightmapTexCoord", Value(1)}});
  const int mesh = addMesh(b, p);
  meshNode(b, mesh);
  tinygltf::Node other;
  other.mesh = mesh;
  b.model().nodes.push_back(other);
  tinygltf::Scene second;
  second.nodes = {static_cast<int>(b.model().nodes.size()) - 1};
  b.model().scenes.push_back(second);
  b.model().scenes[0].extras = Value(Value::Object{{"map", Value(std::string("seed"))}});
  tinygltf::Light sun;
  sun.type = "directional";
  tinygltf::Light point;
  point.type = "point";
  point.range = 10;
  b.model().lights = {sun, point};
  tinygltf::Node sunNode;
  sunNode.extensions["KHR_lights_punctual"] = Value(Value::Object{{"light", Value(0)}});
  b.addNode(sunNode);
  tinygltf::Camera ortho;
  ortho.type = "orthographic";
  ortho.orthographic.xmag = ortho.orthographic.ymag = 2;
  ortho.orthographic.zfar = 100;
  b.model().cameras.push_back(ortho);
  tinygltf::Node cameraNode;
  cameraNode.camera = 0;
  b.addNode(cameraNode);
}

void writeBoth(const std::filesystem::path& dir, const std::string& name, void (*build)(ModelBuilder&)) {
  ModelBuilder json, binary;
  build(json);
  build(binary);
  json.writeGltf(dir / (name + ".gltf"));
  binary.writeGlb(dir / (name + ".glb"));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 2;  // output folder
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  writeBoth(dir, "full", &full);
  writeBoth(dir, "modes", &modes);
  writeBoth(dir, "layouts", &layouts);
  writeBoth(dir, "lightmap_scenes", &lightmapAndScenes);
  return 0;
}
