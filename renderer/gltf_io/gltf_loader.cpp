// tinygltf::Model -> GltfScene: meshes (primitives merged), node traversal with world
// transforms, materials, textures, KHR_lights_punctual lights and perspective cameras.
#include "renderer/gltf_io/gltf_loader.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "renderer/gltf_io/gltf_accessor.h"
#include "renderer/gltf_io/gltf_materials.h"
#include "renderer/gltf_io/gltf_model_reader.h"

namespace pa::gltf {
namespace {

using detail::readFloats;
using detail::readIndices;
using detail::convertExtras;
using detail::convertMaterials;

/// Deepest node hierarchy accepted (guards against stack exhaustion on hostile files).
constexpr int kMaxNodeDepth = 256;

/// Extensions whose presence in extensionsRequired we can honour.
const std::set<std::string>& supportedRequiredExtensions() {
  static const std::set<std::string> supported = {
      "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_texture_transform",
      "KHR_mesh_quantization"};
  return supported;
}

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

std::string indexed(const char* array, size_t index) {
  return std::string(array) + "[" + std::to_string(index) + "]";
}

glm::vec3 toVec3(const std::vector<float>& values, size_t i) {
  return {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
}

/// The triangle list of one primitive (strips and fans converted, degenerate triangles dropped).
std::vector<uint32_t> triangulate(const std::vector<uint32_t>& vertices, int mode, const std::string& what) {
  std::vector<uint32_t> triangles;
  auto push = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (a == b || b == c || a == c) return;
    triangles.insert(triangles.end(), {a, b, c});
  };
  const size_t n = vertices.size();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    if (n % 3 != 0) fail(what + ": triangle list of " + std::to_string(n) + " indices is not a multiple of 3");
    for (size_t i = 0; i + 2 < n; i += 3) push(vertices[i], vertices[i + 1], vertices[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    // glTF: triangle i = {v[i], v[i + 1 + i%2], v[i + 2 - i%2]} keeps a consistent winding.
    for (size_t i = 0; i + 2 < n; ++i)
      push(vertices[i], vertices[i + 1 + i % 2], vertices[i + 2 - i % 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (size_t i = 0; i + 2 < n; ++i) push(vertices[i + 1], vertices[i + 2], vertices[0]);
  }
  return triangles;
}

/// Area-weighted smooth normals for the vertices of `mesh` flagged in `needsNormal`.
void fillMissingNormals(GltfMesh& mesh, const std::vector<bool>& needsNormal) {
  std::vector<glm::vec3> accumulated(mesh.positions.size(), glm::vec3(0.0f));
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const glm::vec3 faceNormal =
        glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    accumulated[a] += faceNormal;
    accumulated[b] += faceNormal;
    accumulated[c] += faceNormal;
  }
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    if (!needsNormal[v]) continue;
    const float length = glm::length(accumulated[v]);
    mesh.normals[v] = length > 0.0f ? accumulated[v] / length : glm::vec3(0.0f, 1.0f, 0.0f);
  }
}

/// A primitive's baked lightmap, from its extras (assets_converter's convention).
struct PrimitiveLightmap {
  uint32_t texture = kNone;
  std::string uvAttribute;
};

PrimitiveLightmap primitiveLightmap(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                    const std::string& what, std::vector<std::string>& warnings) {
  PrimitiveLightmap lightmap;
  if (!primitive.extras.IsObject()) return lightmap;
  const tinygltf::Value& texture = primitive.extras.Get("lightmapTexture");
  if (!texture.IsNumber()) return lightmap;
  const double index = texture.GetNumberAsDouble();
  const tinygltf::Value& texCoord = primitive.extras.Get("lightmapTexCoord");
  const double set = texCoord.IsNumber() ? texCoord.GetNumberAsDouble() : 1.0;
  if (!(index >= 0.0 && index < static_cast<double>(model.textures.size())) || !(set >= 0.0 && set < 16.0)) {
    warnings.push_back(what + ": extras lightmapTexture/lightmapTexCoord out of range, lightmap ignored");
    return lightmap;
  }
  lightmap.uvAttribute = "TEXCOORD_" + std::to_string(static_cast<int>(set));
  if (!primitive.attributes.count(lightmap.uvAttribute)) {
    warnings.push_back(what + ": lightmap without " + lightmap.uvAttribute + ", lightmap ignored");
    return lightmap;
  }
  lightmap.texture = static_cast<uint32_t>(index);
  return lightmap;
}

GltfMesh convertMesh(const tinygltf::Model& model, size_t meshIndex, std::vector<std::string>& warnings) {
  const tinygltf::Mesh& source = model.meshes[meshIndex];
  GltfMesh mesh;
  mesh.name = source.name;
  std::vector<bool> hasNormal;
  bool anyNormals = false, anyUvs = false, anyColors = false, anyLightmaps = false;
  for (size_t p = 0; p < source.primitives.size(); ++p) {
    const tinygltf::Primitive& primitive = source.primitives[p];
    const std::string what = indexed("meshes", meshIndex) + "." + indexed("primitives", p);
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        primitive.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      warnings.push_back(what + ": mode " + std::to_string(primitive.mode) + " (points/lines) skipped");
      continue;
    }
    const auto positionIt = primitive.attributes.find("POSITION");
    if (positionIt == primitive.attributes.end()) {
      warnings.push_back(what + ": no POSITION attribute, skipped");
      continue;
    }
    if (!primitive.targets.empty()) warnings.push_back(what + ": morph targets ignored (base shape used)");
    if (primitive.material < -1 || primitive.material >= static_cast<int>(model.materials.size()))
      fail(what + ".material " + std::to_string(primitive.material) + " out of range (file has " +
           std::to_string(model.materials.size()) + " materials)");

    int components = 0;
    const std::vector<float> positions = readFloats(model, positionIt->second, {3}, components, what + " POSITION");
    const size_t vertexCount = positions.size() / 3;
    if (mesh.positions.size() + vertexCount > 0xfffffff0u) fail(what + ": too many vertices");
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size());

    std::vector<uint32_t> vertexOrder;
    if (primitive.indices >= 0) {
      vertexOrder = readIndices(model, primitive.indices, what + " indices");
      for (size_t i = 0; i < vertexOrder.size(); ++i)
        if (vertexOrder[i] >= vertexCount)
          fail(what + " indices (accessors[" + std::to_string(primitive.indices) + "]): index " +
               std::to_string(vertexOrder[i]) + " at position " + std::to_string(i) + " >= vertex count " +
               std::to_string(vertexCount));
    } else {
      vertexOrder.resize(vertexCount);
      for (size_t i = 0; i < vertexCount; ++i) vertexOrder[i] = static_cast<uint32_t>(i);
    }
    const std::vector<uint32_t> triangles = triangulate(vertexOrder, primitive.mode, what);

    auto attribute = [&](const char* name, std::initializer_list<int> allowed, int& componentsOut) {
      std::vector<float> values;
      const auto it = primitive.attributes.find(name);
      if (it == primitive.attributes.end()) return values;
      values = readFloats(model, it->second, allowed, componentsOut, what + " " + name);
      if (values.size() / static_cast<size_t>(componentsOut) != vertexCount)
        fail(what + " " + name + ": " + std::to_string(values.size() / componentsOut) +
             " elements, POSITION has " + std::to_string(vertexCount));
      return values;
    };
    const PrimitiveLightmap lightmap = primitiveLightmap(model, primitive, what, warnings);
    int normalComponents = 0, uvComponents = 0, colorComponents = 0, lightmapComponents = 0;
    const std::vector<float> normals = attribute("NORMAL", {3}, normalComponents);
    const std::vector<float> uvs = attribute("TEXCOORD_0", {2}, uvComponents);
    const std::vector<float> colors = attribute("COLOR_0", {3, 4}, colorComponents);
    std::vector<float> lightmapUvs;
    if (lightmap.texture != kNone) lightmapUvs = attribute(lightmap.uvAttribute.c_str(), {2}, lightmapComponents);

    for (size_t v = 0; v < vertexCount; ++v) {
      mesh.positions.push_back(toVec3(positions, v));
      glm::vec3 normal(0.0f);
      if (!normals.empty()) normal = toVec3(normals, v);
      const float length = glm::length(normal);
      hasNormal.push_back(length > 1e-12f);
      mesh.normals.push_back(length > 1e-12f ? normal / length : glm::vec3(0.0f));
      mesh.uvs.push_back(uvs.empty() ? glm::vec2(0.0f) : glm::vec2(uvs[2 * v], uvs[2 * v + 1]));
      glm::vec4 color(1.0f);
      if (!colors.empty()) {
        const float* c = &colors[v * static_cast<size_t>(colorComponents)];
        color = glm::vec4(c[0], c[1], c[2], colorComponents == 4 ? c[3] : 1.0f);
      }
      mesh.colors.push_back(color);
      mesh.lightmapUvs.push_back(lightmapUvs.empty() ? glm::vec2(0.0f)
                                                      : glm::vec2(lightmapUvs[2 * v], lightmapUvs[2 * v + 1]));
    }
    anyNormals |= !normals.empty();
    anyUvs |= !uvs.empty();
    anyColors |= !colors.empty();
    anyLightmaps |= !lightmapUvs.empty();
    const uint32_t material = primitive.material < 0 ? kNone : static_cast<uint32_t>(primitive.material);
    for (size_t i = 0; i < triangles.size(); ++i) mesh.indices.push_back(base + triangles[i]);
    mesh.triangleMaterials.insert(mesh.triangleMaterials.end(), triangles.size() / 3, material);
    mesh.triangleLightmaps.insert(mesh.triangleLightmaps.end(), triangles.size() / 3,
                                  lightmapUvs.empty() ? kNone : lightmap.texture);
  }
  if (!anyNormals) mesh.normals.clear();
  else if (std::find(hasNormal.begin(), hasNormal.end(), false) != hasNormal.end()) {
    std::vector<bool> needsNormal(hasNormal.size());
    for (size_t v = 0; v < hasNormal.size(); ++v) needsNormal[v] = !hasNormal[v];
    fillMissingNormals(mesh, needsNormal);
  }
  if (!anyUvs) mesh.uvs.clear();
  if (!anyColors) mesh.colors.clear();
  if (!anyLightmaps) {
    mesh.lightmapUvs.clear();
    mesh.triangleLightmaps.clear();
  }
  return mesh;
}

/// Local transform of a node: its matrix, or translation * rotation * scale.
glm::dmat4 localTransform(const tinygltf::Node& node, const std::string& what) {
  for (double v : node.matrix)
    if (!std::isfinite(v)) fail(what + ".matrix has a non-finite value");
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) fail(what + ".matrix has " + std::to_string(node.matrix.size()) + " values (need 16)");
    glm::dmat4 m(1.0);
    for (int column = 0; column < 4; ++column)
      for (int row = 0; row < 4; ++row) m[column][row] = node.matrix[static_cast<size_t>(column * 4 + row)];
    return m;
  }
  auto check = [&](const std::vector<double>& values, size_t size, const char* field) {
    if (!values.empty() && values.size() != size)
      fail(what + "." + field + " has " + std::to_string(values.size()) + " values (need " + std::to_string(size) + ")");
    for (double v : values)
      if (!std::isfinite(v)) fail(what + "." + field + " has a non-finite value");
  };
  check(node.translation, 3, "translation");
  check(node.rotation, 4, "rotation");
  check(node.scale, 3, "scale");
  glm::dmat4 m(1.0);
  if (!node.translation.empty()) m[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
  if (!node.rotation.empty()) {
    glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    const double length = glm::length(q);
    if (!(length > 1e-12)) fail(what + ".rotation is a zero quaternion");
    m = m * glm::dmat4(glm::mat3_cast(q / length));
  }
  if (!node.scale.empty()) m = m * glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

glm::mat4x3 toAffine(const glm::dmat4& m) {
  glm::mat4x3 out;
  for (int column = 0; column < 4; ++column) out[column] = glm::vec3(m[column]);
  return out;
}

/// Walks the node hierarchy and fills instances, cameras and lights.
class SceneBuilder {
 public:
  SceneBuilder(const tinygltf::Model& model, const LoadOptions& options, GltfScene& scene)
      : model_(model), options_(options), scene_(scene), onPath_(model.nodes.size(), false) {}

  void visit(int nodeIndex, const glm::dmat4& parent, int depth, const std::string& from) {
    if (nodeIndex < 0 || static_cast<size_t>(nodeIndex) >= model_.nodes.size())
      fail(from + ": node " + std::to_string(nodeIndex) + " out of range (file has " +
           std::to_string(model_.nodes.size()) + " nodes)");
    const size_t index = static_cast<size_t>(nodeIndex);
    const std::string what = indexed("nodes", index);
    if (onPath_[index]) fail(what + ": node hierarchy has a cycle");
    if (depth > kMaxNodeDepth) fail(what + ": node hierarchy deeper than " + std::to_string(kMaxNodeDepth));
    const tinygltf::Node& node = model_.nodes[index];
    const glm::dmat4 world = parent * localTransform(node, what);
    for (int column = 0; column < 4; ++column)
      for (int row = 0; row < 3; ++row)
        if (!std::isfinite(static_cast<float>(world[column][row])))
          fail(what + ": world transform overflows (non-finite in single precision)");
    onPath_[index] = true;
    if (node.mesh >= 0) addInstance(node, world, what);
    else if (node.mesh < -1) fail(what + ".mesh " + std::to_string(node.mesh) + " out of range");
    if (node.camera != -1) addCamera(node, world, what);
    addLight(node, world, what);
    if (node.skin >= 0) scene_.warnings.push_back(what + ": skinning ignored (bind pose used)");
    for (int child : node.children) visit(child, world, depth + 1, what + ".children");
    onPath_[index] = false;
  }

 private:
  void addInstance(const tinygltf::Node& node, const glm::dmat4& world, const std::string& what) {
    if (static_cast<size_t>(node.mesh) >= model_.meshes.size())
      fail(what + ".mesh " + std::to_string(node.mesh) + " out of range (file has " +
           std::to_string(model_.meshes.size()) + " meshes)");
    GltfInstance instance;
    instance.nodeName = node.name;
    instance.mesh = static_cast<uint32_t>(node.mesh);
    instance.objectToWorld = toAffine(world);
    instance.extras = convertExtras(node.extras);
    scene_.instances.push_back(std::move(instance));
  }

  void addCamera(const tinygltf::Node& node, const glm::dmat4& world, const std::string& what) {
    if (node.camera < 0 || static_cast<size_t>(node.camera) >= model_.cameras.size())
      fail(what + ".camera " + std::to_string(node.camera) + " out of range (file has " +
           std::to_string(model_.cameras.size()) + " cameras)");
    const tinygltf::Camera& source = model_.cameras[static_cast<size_t>(node.camera)];
    if (source.type != "perspective") {
      scene_.warnings.push_back(what + ": camera type \"" + source.type + "\" not supported, skipped");
      return;
    }
    const double yfov = source.perspective.yfov;
    if (!(yfov > 1e-4 && yfov < 3.14)) fail(indexed("cameras", static_cast<size_t>(node.camera)) +
                                            ".perspective.yfov " + std::to_string(yfov) + " out of (0, pi)");
    // glTF cameras look down local -Z with +Y up; orthonormalize against scale/shear.
    const glm::dvec3 forward = -glm::dvec3(world[2]);
    const glm::dvec3 upHint = glm::dvec3(world[1]);
    const glm::dvec3 right = glm::cross(forward, upHint);
    if (!(glm::length(forward) > 1e-12) || !(glm::length(right) > 1e-12)) {
      scene_.warnings.push_back(what + ": camera transform is degenerate, skipped");
      return;
    }
    GltfCamera camera;
    camera.name = !source.name.empty() ? source.name : node.name;
    camera.yfov = static_cast<float>(yfov);
    const double aspect = source.perspective.aspectRatio;
    camera.aspectRatio = std::isfinite(aspect) && aspect > 0.0 ? static_cast<float>(aspect) : 0.0f;
    camera.origin = glm::vec3(world[3]);
    camera.forward = glm::vec3(glm::normalize(forward));
    camera.left = -glm::vec3(glm::normalize(right));
    camera.up = glm::normalize(glm::cross(glm::vec3(glm::normalize(right)), camera.forward));
    scene_.cameras.push_back(std::move(camera));
  }

  void addLight(const tinygltf::Node& node, const glm::dmat4& world, const std::string& what) {
    const auto extension = node.extensions.find("KHR_lights_punctual");
    if (extension == node.extensions.end()) return;
    const tinygltf::Value& lightRef = extension->second.Get("light");
    if (!lightRef.IsNumber()) fail(what + ".extensions.KHR_lights_punctual.light is missing");
    const double lightIndex = lightRef.GetNumberAsDouble();
    if (!(lightIndex >= 0 && lightIndex < static_cast<double>(model_.lights.size())))
      fail(what + ".extensions.KHR_lights_punctual.light " + std::to_string(lightIndex) +
           " out of range (file has " + std::to_string(model_.lights.size()) + " lights)");
    const tinygltf::Light& source = model_.lights[static_cast<size_t>(lightIndex)];
    const std::string lightName = "KHR_lights_punctual.lights[" + std::to_string(static_cast<size_t>(lightIndex)) + "]";
    GltfLight light;
    light.name = !source.name.empty() ? source.name : node.name;
    if (source.type == "point") light.type = LightType::Point;
    else if (source.type == "spot") light.type = LightType::Spot;
    else if (source.type == "directional") light.type = LightType::Directional;
    else fail(lightName + ".type \"" + source.type + "\" is not point, spot or directional");
    if (!source.color.empty()) {
      if (source.color.size() != 3) fail(lightName + ".color needs 3 values");
      light.color = glm::vec3(source.color[0], source.color[1], source.color[2]);
    }
    light.intensity = static_cast<float>(source.intensity) * options_.lightUnitScale;
    light.range = static_cast<float>(source.range);
    light.innerConeAngle = static_cast<float>(source.spot.innerConeAngle);
    light.outerConeAngle = static_cast<float>(source.spot.outerConeAngle);
    const bool finite = std::isfinite(light.intensity) && std::isfinite(light.range) &&
                        std::isfinite(light.innerConeAngle) && std::isfinite(light.outerConeAngle) &&
                        std::isfinite(light.color.x) && std::isfinite(light.color.y) && std::isfinite(light.color.z);
    if (!finite || light.intensity < 0.0f || light.range < 0.0f)
      fail(lightName + ": non-finite or negative intensity/range/colour");
    if (light.type == LightType::Spot &&
        !(light.innerConeAngle >= 0.0f && light.innerConeAngle < light.outerConeAngle && light.outerConeAngle <= 1.5708f))
      fail(lightName + ".spot: need 0 <= innerConeAngle < outerConeAngle <= pi/2");
    light.position = glm::vec3(world[3]);
    const glm::dvec3 direction = -glm::dvec3(world[2]);
    if (!(glm::length(direction) > 1e-12)) {
      scene_.warnings.push_back(what + ": light transform is degenerate, skipped");
      return;
    }
    light.direction = glm::vec3(glm::normalize(direction));
    scene_.lights.push_back(std::move(light));
  }

  const tinygltf::Model& model_;
  const LoadOptions& options_;
  GltfScene& scene_;
  std::vector<bool> onPath_;
};

/// Root nodes of the scene to import (all parentless nodes when the file has no scenes).
std::vector<int> rootNodes(const tinygltf::Model& model, const LoadOptions& options, GltfScene& scene) {
  int sceneIndex = options.scene >= 0 ? options.scene : std::max(model.defaultScene, 0);
  if (model.scenes.empty()) {
    if (options.scene > 0) fail("scene " + std::to_string(options.scene) + " requested, file has no scenes");
    std::vector<bool> isChild(model.nodes.size(), false);
    for (const tinygltf::Node& node : model.nodes)
      for (int child : node.children)
        if (child >= 0 && static_cast<size_t>(child) < model.nodes.size()) isChild[static_cast<size_t>(child)] = true;
    std::vector<int> roots;
    for (size_t i = 0; i < model.nodes.size(); ++i)
      if (!isChild[i]) roots.push_back(static_cast<int>(i));
    return roots;
  }
  if (static_cast<size_t>(sceneIndex) >= model.scenes.size())
    fail("scene " + std::to_string(sceneIndex) + " out of range (file has " + std::to_string(model.scenes.size()) +
         " scenes)");
  const tinygltf::Scene& source = model.scenes[static_cast<size_t>(sceneIndex)];
  scene.sceneExtras = convertExtras(source.extras);
  // Metadata may also sit on the root nodes (assets_converter's map node): merge, scene first.
  for (int root : source.nodes)
    if (root >= 0 && static_cast<size_t>(root) < model.nodes.size())
      scene.sceneExtras.merge(convertExtras(model.nodes[static_cast<size_t>(root)].extras));
  return source.nodes;
}

/// Turns a parsed model into a scene; errors are prefixed with `name`.
GltfScene convertModel(const tinygltf::Model& model, const std::string& name, const LoadOptions& options,
                       GltfScene scene) {
  try {
    for (const std::string& extension : model.extensionsRequired)
      if (!supportedRequiredExtensions().count(extension))
        fail("requires unsupported extension " + extension);
    convertMaterials(model, options, scene);
    scene.meshes.reserve(model.meshes.size());
    for (size_t m = 0; m < model.meshes.size(); ++m) scene.meshes.push_back(convertMesh(model, m, scene.warnings));
    SceneBuilder builder(model, options, scene);
    for (int root : rootNodes(model, options, scene)) builder.visit(root, glm::dmat4(1.0), 0, "scene.nodes");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
  return scene;
}

}  // namespace

GltfScene loadScene(const std::filesystem::path& path, const LoadOptions& options) {
  GltfScene scene;
  const tinygltf::Model model = detail::readModel(path, options.decodeImages, scene.warnings);
  return convertModel(model, path.string(), options, std::move(scene));
}

GltfScene loadSceneFromMemory(std::span<const std::byte> bytes, const std::string& name,
                              const std::filesystem::path& baseDir, const LoadOptions& options) {
  GltfScene scene;
  const std::span<const unsigned char> raw(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
  const tinygltf::Model model = detail::readModel(raw, name, baseDir, options.decodeImages, scene.warnings);
  return convertModel(model, name, options, std::move(scene));
}

TriangleSoup flattenTriangles(const GltfScene& scene) {
  TriangleSoup soup;
  soup.warnings = scene.warnings;
  for (const GltfInstance& instance : scene.instances) {
    const GltfMesh& mesh = scene.meshes.at(instance.mesh);
    const uint32_t base = static_cast<uint32_t>(soup.positions.size());
    const glm::mat4x3& m = instance.objectToWorld;
    for (const glm::vec3& p : mesh.positions) soup.positions.push_back(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3]);
    // A mirroring transform flips the winding; swap two corners to keep front faces front.
    const bool mirrored = glm::determinant(glm::mat3(m)) < 0.0f;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      soup.indices.push_back(base + mesh.indices[t]);
      soup.indices.push_back(base + mesh.indices[t + (mirrored ? 2 : 1)]);
      soup.indices.push_back(base + mesh.indices[t + (mirrored ? 1 : 2)]);
    }
  }
  return soup;
}

TriangleSoup loadTriangles(const std::filesystem::path& path) {
  LoadOptions options;
  options.decodeImages = false;
  return flattenTriangles(loadScene(path, options));
}

}  // namespace pa::gltf
