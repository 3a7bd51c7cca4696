// Writes renderer/cli/scenes/default_arena.gltf: a small arena-like room (glTF 2.0, Y up, metres)
// that exercises the importer and the renderer: checker-textured floor, plaster walls with a
// window to the sky, instanced pillars, a masked grate, an emissive ceiling panel, a point light,
// a sun, a glossy metal sphere and a camera.
// Usage: pa-make-default-arena OUT.gltf
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/gltf_io/gltf_builder.h"

namespace {

using pa::gltf::ModelBuilder;
using tinygltf::Value;

constexpr float kPi = 3.14159265358979f;

/// Triangle geometry of one primitive being assembled.
struct Geometry {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> indices;
};

/// Adds the parallelogram origin, origin+u, origin+u+v, origin+v, facing cross(u, v);
/// uvs are metres along u and v times uvPerMetre.
void addQuad(Geometry& g, glm::vec3 origin, glm::vec3 u, glm::vec3 v, float uvPerMetre) {
  const uint32_t base = static_cast<uint32_t>(g.positions.size());
  const glm::vec3 normal = glm::normalize(glm::cross(u, v));
  const float lu = glm::length(u) * uvPerMetre, lv = glm::length(v) * uvPerMetre;
  const glm::vec3 corners[4] = {origin, origin + u, origin + u + v, origin + v};
  const glm::vec2 uvs[4] = {{0, lv}, {lu, lv}, {lu, 0}, {0, 0}};
  for (int i = 0; i < 4; ++i) {
    g.positions.push_back(corners[i]);
    g.normals.push_back(normal);
    g.uvs.push_back(uvs[i]);
  }
  g.indices.insert(g.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

/// Axis-aligned box centred on the origin with outward faces.
void addBox(Geometry& g, glm::vec3 h, float uvPerMetre) {
  addQuad(g, {h.x, -h.y, h.z}, {0, 0, -2 * h.z}, {0, 2 * h.y, 0}, uvPerMetre);
  addQuad(g, {-h.x, -h.y, -h.z}, {0, 0, 2 * h.z}, {0, 2 * h.y, 0}, uvPerMetre);
  addQuad(g, {-h.x, -h.y, h.z}, {2 * h.x, 0, 0}, {0, 2 * h.y, 0}, uvPerMetre);
  addQuad(g, {h.x, -h.y, -h.z}, {-2 * h.x, 0, 0}, {0, 2 * h.y, 0}, uvPerMetre);
  addQuad(g, {-h.x, h.y, h.z}, {2 * h.x, 0, 0}, {0, 0, -2 * h.z}, uvPerMetre);
  addQuad(g, {-h.x, -h.y, -h.z}, {2 * h.x, 0, 0}, {0, 0, 2 * h.z}, uvPerMetre);
}

/// UV sphere around the origin, triangles wound outward.
void addSphere(Geometry& g, float radius, int segments, int rings) {
  const uint32_t base = static_cast<uint32_t>(g.positions.size());
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPi * static_cast<float>(i) / static_cast<float>(rings);
    for (int j = 0; j <= segments; ++j) {
      const float phi = 2.0f * kPi * static_cast<float>(j) / static_cast<float>(segments);
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
      g.positions.push_back(radius * n);
      g.normals.push_back(n);
      g.uvs.push_back({static_cast<float>(j) / segments, static_cast<float>(i) / rings});
    }
  }
  const uint32_t stride = static_cast<uint32_t>(segments + 1);
  for (uint32_t i = 0; i < static_cast<uint32_t>(rings); ++i)
    for (uint32_t j = 0; j < static_cast<uint32_t>(segments); ++j) {
      const uint32_t a = base + i * stride + j, b = a + stride, c = b + 1, d = a + 1;
      for (const auto& t : {std::array<uint32_t, 3>{a, b, c}, std::array<uint32_t, 3>{a, c, d}}) {
        const glm::vec3 p0 = g.positions[t[0]], p1 = g.positions[t[1]], p2 = g.positions[t[2]];
        const glm::vec3 n = glm::cross(p1 - p0, p2 - p0);
        if (glm::length(n) < 1e-9f) continue;  // pole slivers
        const bool outward = glm::dot(n, p0 + p1 + p2) > 0.0f;
        g.indices.insert(g.indices.end(), {t[0], outward ? t[1] : t[2], outward ? t[2] : t[1]});
      }
    }
}

tinygltf::Primitive toPrimitive(ModelBuilder& builder, const Geometry& g, int material) {
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = builder.addVec3(g.positions, true);
  primitive.attributes["NORMAL"] = builder.addVec3(g.normals, false);
  primitive.attributes["TEXCOORD_0"] = builder.addVec2(g.uvs);
  const bool small = g.positions.size() <= 0xffff;
  primitive.indices = builder.addIndices(g.indices, small ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT
                                                          : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  primitive.material = material;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  return primitive;
}

int addMesh(ModelBuilder& builder, const char* name, std::vector<tinygltf::Primitive> primitives) {
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives = std::move(primitives);
  builder.model().meshes.push_back(std::move(mesh));
  return static_cast<int>(builder.model().meshes.size() - 1);
}

int addMaterial(ModelBuilder& builder, const char* name, glm::vec4 color, float metallic, float roughness,
                int texture = -1) {
  tinygltf::Material material;
  material.name = name;
  material.pbrMetallicRoughness.baseColorFactor = {color.r, color.g, color.b, color.a};
  material.pbrMetallicRoughness.metallicFactor = metallic;
  material.pbrMetallicRoughness.roughnessFactor = roughness;
  material.pbrMetallicRoughness.baseColorTexture.index = texture;
  material.doubleSided = true;
  builder.model().materials.push_back(std::move(material));
  return static_cast<int>(builder.model().materials.size() - 1);
}

tinygltf::Node node(const char* name, int mesh, glm::vec3 translation) {
  tinygltf::Node n;
  n.name = name;
  n.mesh = mesh;
  n.translation = {translation.x, translation.y, translation.z};
  return n;
}

/// Quaternion (x, y, z, w) rotating by `angle` radians about the unit `axis`.
std::vector<double> rotation(glm::vec3 axis, float angle) {
  const float s = std::sin(0.5f * angle);
  return {axis.x * s, axis.y * s, axis.z * s, std::cos(0.5f * angle)};
}

void buildArena(ModelBuilder& builder) {
  // Textures: an 8x8 checker (floor) and a grate of 2-pixel bars every 8 pixels (alpha 0 between).
  std::vector<uint8_t> checker(64 * 64 * 4), grate(32 * 32 * 4);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool light = ((x / 8) + (y / 8)) % 2 == 0;
      uint8_t* p = &checker[static_cast<size_t>(y * 64 + x) * 4];
      p[0] = light ? 205 : 55, p[1] = light ? 200 : 58, p[2] = light ? 190 : 68, p[3] = 255;
    }
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const bool bar = x % 8 < 2 || y % 8 < 2;
      uint8_t* p = &grate[static_cast<size_t>(y * 32 + x) * 4];
      p[0] = 120, p[1] = 125, p[2] = 135, p[3] = bar ? 255 : 0;
    }
  const int checkerTexture = builder.addTexture("checker", 64, 64, checker);
  const int grateTexture = builder.addTexture("grate", 32, 32, grate);

  const int floorMaterial = addMaterial(builder, "floor_checker", glm::vec4(1.0f), 0.0f, 0.8f, checkerTexture);
  const int wallMaterial = addMaterial(builder, "wall_plaster", {0.75f, 0.72f, 0.66f, 1.0f}, 0.0f, 0.9f);
  const int ceilingMaterial = addMaterial(builder, "ceiling", {0.8f, 0.8f, 0.8f, 1.0f}, 0.0f, 0.9f);
  const int pillarMaterial = addMaterial(builder, "pillar_stone", {0.55f, 0.22f, 0.16f, 1.0f}, 0.0f, 0.7f);
  const int grateMaterial = addMaterial(builder, "grate_metal", glm::vec4(1.0f), 0.6f, 0.5f, grateTexture);
  builder.model().materials[static_cast<size_t>(grateMaterial)].alphaMode = "MASK";
  builder.model().materials[static_cast<size_t>(grateMaterial)].alphaCutoff = 0.5;
  const int steelMaterial = addMaterial(builder, "steel", {0.9f, 0.9f, 0.92f, 1.0f}, 1.0f, 0.25f);
  const int panelMaterial = addMaterial(builder, "light_panel", {0.9f, 0.9f, 0.9f, 1.0f}, 0.0f, 0.5f);
  tinygltf::Material& panel = builder.model().materials[static_cast<size_t>(panelMaterial)];
  panel.emissiveFactor = {1.0, 0.85, 0.6};
  panel.doubleSided = false;
  panel.extensions["KHR_materials_emissive_strength"] = Value(Value::Object{{"emissiveStrength", Value(6.0)}});
  panel.extras = Value(Value::Object{{"shader", Value(std::string("arena/light_panel"))}});
  builder.model().extensionsUsed.push_back("KHR_materials_emissive_strength");

  // Room 12 x 4 x 12 m; the -Z wall has a 3 x 1.8 m window.
  Geometry floor, walls, ceiling;
  addQuad(floor, {-6, 0, 6}, {12, 0, 0}, {0, 0, -12}, 0.5f);
  addQuad(ceiling, {-6, 4, -6}, {12, 0, 0}, {0, 0, 12}, 0.5f);
  addQuad(walls, {6, 0, -6}, {0, 0, 12}, {0, 4, 0}, 0.5f);
  addQuad(walls, {-6, 0, 6}, {0, 0, -12}, {0, 4, 0}, 0.5f);
  addQuad(walls, {6, 0, 6}, {-12, 0, 0}, {0, 4, 0}, 0.5f);
  addQuad(walls, {-6, 0, -6}, {4.5f, 0, 0}, {0, 4, 0}, 0.5f);
  addQuad(walls, {1.5f, 0, -6}, {4.5f, 0, 0}, {0, 4, 0}, 0.5f);
  addQuad(walls, {-1.5f, 0, -6}, {3, 0, 0}, {0, 1.2f, 0}, 0.5f);
  addQuad(walls, {-1.5f, 3, -6}, {3, 0, 0}, {0, 1, 0}, 0.5f);
  const int room = addMesh(builder, "room", {toPrimitive(builder, floor, floorMaterial),
                                             toPrimitive(builder, walls, wallMaterial),
                                             toPrimitive(builder, ceiling, ceilingMaterial)});
  builder.addNode(node("room", room, {0, 0, 0}));

  // Four instances of one pillar mesh under a parent node.
  Geometry pillarGeometry;
  addBox(pillarGeometry, {0.3f, 2.0f, 0.3f}, 1.0f);
  const int pillar = addMesh(builder, "pillar", {toPrimitive(builder, pillarGeometry, pillarMaterial)});
  const int pillars = builder.addNode(node("pillars", -1, {0, 2, 0}));
  builder.addNode(node("pillar_nw", pillar, {-3, 0, -3}), pillars);
  builder.addNode(node("pillar_ne", pillar, {3, 0, -3}), pillars);
  builder.addNode(node("pillar_sw", pillar, {-3, 0, 3}), pillars);
  builder.addNode(node("pillar_se", pillar, {3, 0, 3}), pillars);

  Geometry grateGeometry;
  addQuad(grateGeometry, {0, 0, 2.7f}, {0, 0, -5.4f}, {0, 1.5f, 0}, 1.5f);
  const int grateMesh = addMesh(builder, "grate", {toPrimitive(builder, grateGeometry, grateMaterial)});
  builder.addNode(node("grate", grateMesh, {-3, 0, 0}));

  Geometry sphere;
  addSphere(sphere, 0.7f, 32, 16);
  const int ball = addMesh(builder, "steel_sphere", {toPrimitive(builder, sphere, steelMaterial)});
  builder.addNode(node("steel_sphere", ball, {1.5f, 0.7f, -1.0f}));

  Geometry panelGeometry;
  addQuad(panelGeometry, {-1, 0, -1}, {2, 0, 0}, {0, 0, 2}, 1.0f);
  const int panelMesh = addMesh(builder, "light_panel", {toPrimitive(builder, panelGeometry, panelMaterial)});
  builder.addNode(node("light_panel", panelMesh, {0, 3.95f, 0}));

  // Lights: a warm point light and a sun shining in through the window.
  tinygltf::Light lamp;
  lamp.name = "lamp";
  lamp.type = "point";
  lamp.color = {1.0, 0.8, 0.6};
  lamp.intensity = 30.0;
  tinygltf::Light sun;
  sun.name = "sun";
  sun.type = "directional";
  sun.color = {1.0, 0.95, 0.85};
  sun.intensity = 1.5;
  builder.model().lights = {lamp, sun};
  tinygltf::Node lampNode = node("lamp", -1, {-2.0f, 2.6f, 1.5f});
  lampNode.extensions["KHR_lights_punctual"] = Value(Value::Object{{"light", Value(0)}});
  builder.addNode(lampNode);
  // The sun travels along local -Z: turn -Z to (0, -sin 30, cos 30), i.e. -150 degrees about +X,
  // so it heads +Z through the window, 30 degrees below the horizon.
  tinygltf::Node sunNode = node("sun", -1, {0, 10, -20});
  sunNode.rotation = rotation({1, 0, 0}, -150.0f * kPi / 180.0f);
  sunNode.extensions["KHR_lights_punctual"] = Value(Value::Object{{"light", Value(1)}});
  builder.addNode(sunNode);

  // Camera near the +Z wall, looking down -Z at the window, pitched 8 degrees down.
  tinygltf::Camera camera;
  camera.name = "overview";
  camera.type = "perspective";
  camera.perspective.yfov = 60.0 * kPi / 180.0;
  camera.perspective.aspectRatio = 16.0 / 9.0;
  camera.perspective.znear = 0.05;
  builder.model().cameras.push_back(camera);
  tinygltf::Node cameraNode = node("camera", -1, {0.0f, 1.8f, 5.2f});
  cameraNode.camera = 0;
  cameraNode.rotation = rotation({1, 0, 0}, -8.0f * kPi / 180.0f);
  builder.addNode(cameraNode);

  builder.model().scenes[0].name = "default_arena";
  builder.model().scenes[0].extras = Value(Value::Object{
      {"sky_color", Value(Value::Array{Value(0.55), Value(0.7), Value(1.0)})}, {"sky_intensity", Value(1.0)}});
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "Usage: %s OUT.gltf\n", argv[0]);
    return 2;
  }
  try {
    ModelBuilder builder;
    buildArena(builder);
    builder.writeGltf(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
    return 1;
  }
  return 0;
}
