#pragma once
// pa::gltf::ModelBuilder: writes glTF 2.0 files from typed arrays (test fixtures, the bundled
// default scene, converters). A thin layer over tinygltf::Model: all data goes to buffer 0.
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <tiny_gltf.h>

namespace pa::gltf {

/// Accumulates a tinygltf::Model; helpers return glTF indices.
class ModelBuilder {
 public:
  ModelBuilder();

  /// The model being built (free to edit directly, e.g. for malformed test files).
  tinygltf::Model& model() { return model_; }

  /// Appends bytes (4-byte aligned) to buffer 0 as a new bufferView.
  int addView(std::span<const uint8_t> bytes, size_t byteStride = 0, int target = 0);
  /// Adds an accessor over an existing view.
  int addAccessor(int view, size_t byteOffset, int componentType, int type, size_t count, bool normalized = false);

  /// Float VEC3 accessor with min/max (POSITION, NORMAL).
  int addVec3(std::span<const glm::vec3> values, bool withBounds);
  /// Float VEC2 accessor (TEXCOORD_0).
  int addVec2(std::span<const glm::vec2> values);
  /// Float VEC4 accessor (COLOR_0).
  int addVec4(std::span<const glm::vec4> values);
  /// Index accessor stored as UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT (values must fit).
  int addIndices(std::span<const uint32_t> indices, int componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);

  /// Embeds an RGBA8 image (encoded as PNG when written) and a texture using it; returns the texture.
  int addTexture(const std::string& name, uint32_t width, uint32_t height, std::span<const uint8_t> rgba8,
                 bool clamp = false);

  /// Adds a node to scene 0's root list (or as a child of `parent`); returns the node index.
  int addNode(tinygltf::Node node, int parent = -1);

  /// Writes a .gltf (JSON, buffers and images embedded as base64 data URIs).
  void writeGltf(const std::filesystem::path& path);
  /// Writes a binary .glb.
  void writeGlb(const std::filesystem::path& path);

 private:
  void write(const std::filesystem::path& path, bool binary);
  tinygltf::Model model_;
};

}  // namespace pa::gltf
