#pragma once
// Plain data produced by the glTF 2.0 importer (pa::gltf::loadScene): meshes, materials,
// decoded images, textures, lights, cameras and node instances with world transforms.
// Coordinates are kept exactly as in the file (glTF: Y up, metres); nothing here knows
// about tinygltf or the renderer.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/mat3x2.hpp>
#include <glm/mat4x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace pa::gltf {

/// "No index" marker for optional references (material, texture, image).
inline constexpr uint32_t kNone = 0xffffffffu;

/// Free-form `extras` of a glTF object as text: nested objects are flattened into dotted keys
/// ({"quake": {"shader": "x"}} -> "quake.shader" = "x"); strings verbatim, booleans
/// "true"/"false", numbers in decimal, arrays as JSON text.
using Extras = std::map<std::string, std::string>;

/// One glTF mesh with all its triangle primitives merged. Optional arrays are empty or
/// hold one entry per vertex; missing attributes of some primitives are filled
/// (normals computed smooth, uvs zero, colours white).
struct GltfMesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;              ///< TEXCOORD_0.
  std::vector<glm::vec4> colors;           ///< COLOR_0, linear RGBA.
  std::vector<uint32_t> indices;           ///< 3 per triangle, all < positions.size().
  std::vector<uint32_t> triangleMaterials; ///< One per triangle: index into materials or kNone.
  /// Baked-light texture coordinates (the TEXCOORD_n named by a primitive's extras
  /// "lightmapTexCoord", default 1); empty when no primitive has a lightmap.
  std::vector<glm::vec2> lightmapUvs;
  /// One per triangle when lightmapUvs is set: index into textures (primitive extras
  /// "lightmapTexture", as written by assets_converter) or kNone.
  std::vector<uint32_t> triangleLightmaps;
};

/// Texture addressing, from the glTF sampler.
enum class Wrap : uint8_t { Repeat, Clamp };

/// Decoded image: RGBA8, row-major from the top row. Empty (0x0) if it could not be decoded.
struct GltfImage {
  std::string name;
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<uint8_t> rgba8;
};

/// A glTF texture: an image plus addressing mode.
struct GltfTexture {
  uint32_t image = kNone;   ///< Index into images, kNone if the texture has no usable image.
  Wrap wrap = Wrap::Repeat;
};

/// How a material's alpha is used (glTF alphaMode).
enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

/// glTF metallic-roughness material, reduced to what pa::Renderer models.
struct GltfMaterial {
  std::string name;
  glm::vec4 baseColorFactor{1.0f};        ///< Linear RGBA.
  uint32_t baseColorTexture = kNone;      ///< Index into textures.
  glm::mat3x2 baseColorUvTransform{1.0f}; ///< KHR_texture_transform of the base colour texture.
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;
  glm::vec3 emissive{0.0f};               ///< emissiveFactor x KHR_materials_emissive_strength x lightUnitScale.
  uint32_t emissiveTexture = kNone;       ///< Index into textures.
  bool doubleSided = false;
  float metallic = 1.0f;
  float roughness = 1.0f;
  Extras extras;
};

/// KHR_lights_punctual light kinds.
enum class LightType : uint8_t { Point, Spot, Directional };

/// A placed KHR_lights_punctual light in world space. Intensity is the file's value
/// (point/spot: candela, directional: lux) times LoadOptions::lightUnitScale.
struct GltfLight {
  std::string name;
  LightType type = LightType::Point;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float range = 0.0f;             ///< 0 = infinite.
  float innerConeAngle = 0.0f;    ///< Spot, radians.
  float outerConeAngle = 0.785398f;
  glm::vec3 position{0.0f};       ///< World position (point, spot).
  glm::vec3 direction{0.0f, 0.0f, -1.0f}; ///< World direction the light travels (spot axis, sun rays).
};

/// A placed perspective camera. Axes are orthonormal, in world space.
struct GltfCamera {
  std::string name;
  float yfov = 0.8f;              ///< Vertical field of view, radians.
  float aspectRatio = 0.0f;       ///< width / height; 0 = not given (use the viewport's).
  glm::vec3 origin{0.0f};
  glm::vec3 forward{0.0f, 0.0f, -1.0f};
  glm::vec3 left{-1.0f, 0.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
};

/// One node that references a mesh, with its world transform.
struct GltfInstance {
  std::string nodeName;
  uint32_t mesh = kNone;          ///< Index into meshes.
  glm::mat4x3 objectToWorld{1.0f};
  Extras extras;                  ///< The node's extras.
};

/// Everything the importer understood, plus warnings for what it skipped.
struct GltfScene {
  std::vector<GltfMesh> meshes;
  std::vector<GltfInstance> instances;
  std::vector<GltfMaterial> materials;
  std::vector<GltfTexture> textures;
  std::vector<GltfImage> images;
  std::vector<GltfLight> lights;
  std::vector<GltfCamera> cameras;   ///< In node order of the scene traversal.
  /// Extras of the glTF scene (e.g. "sky_color"), then of its root nodes for keys not yet
  /// present (assets_converter keeps map metadata such as "quake.sky.color" on the root node).
  Extras sceneExtras;
  std::vector<std::string> warnings; ///< Unsupported features that were skipped.
};

/// World-space triangle soup (all instances flattened).
struct TriangleSoup {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> indices;     ///< 3 per triangle.
  std::vector<std::string> warnings;
};

}  // namespace pa::gltf
